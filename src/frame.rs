//! What a render gives back: the image, the GPU's pass times, where it ran, and what makes the
//! image wrong though it rendered.

use std::fmt;

use penumbra_geom::{Scene, Technique, VisibilityImage};
use penumbra_gpu::PassTimes;

use crate::runs::Runs;

/// A rendered image, with where it was made.
pub struct Frame {
    /// The visibility image.
    pub image: VisibilityImage,
    /// The GPU passes' times, where the device has timestamp queries.
    pub times: Option<PassTimes>,
    /// `gpu: <adapter>` or `cpu`, and what the technique used (samples, edges, wedges).
    pub detail: String,
    /// What makes the image wrong though it rendered.
    pub warnings: Vec<Warning>,
}

/// What makes an image wrong though it rendered.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Warning {
    /// A mesh whose cut by the light's plane holds the light's centre
    /// ([`penumbra_volumes::render::encloses_light_centre`]), under a technique that builds
    /// its shadow from that centre (hard, wedges, shadow maps).
    HoldsLightCentre {
        /// The mesh's index in the scene.
        mesh: usize,
        /// The mesh's name (its file, or the name it was given in code).
        name: String,
        /// The technique.
        technique: Technique,
    },
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::HoldsLightCentre {
                mesh,
                name,
                technique,
            } => write!(
                f,
                "mesh {mesh} ({name}) holds the light's centre where the light's plane cuts it: {technique} \
                 builds its shadow from that centre and cannot be right here (see docs/accuracy.md); \
                 depth-complexity is exact there for its samples"
            ),
        }
    }
}

/// The warnings of a frame of `technique`: each mesh whose cut by the light's plane holds the
/// light's centre, for the techniques built from the light's centre (hard, wedges, shadow
/// maps).
pub(crate) fn warnings(scene: &Scene, technique: Technique) -> Vec<Warning> {
    if !(technique.is_volume() || Runs::of(technique) == Runs::GpuOnly) {
        return Vec::new();
    }
    scene
        .meshes
        .iter()
        .enumerate()
        .filter(|(_, m)| {
            penumbra_volumes::render::encloses_light_centre(
                &m.mesh.positions,
                &m.mesh.triangles,
                &scene.light,
            )
        })
        .map(|(mesh, m)| Warning::HoldsLightCentre {
            mesh,
            name: m.source.display().to_string(),
            technique,
        })
        .collect()
}
