//! What a render gives back: the image, the GPU's pass times, where it ran, and what makes the
//! image wrong though it rendered.

use std::fmt;

use penumbra_geom::{LitScene, Technique, VisibilityImage};
use penumbra_gpu::{PassCounters, PassTimes};

use crate::backend::Placement;
use crate::runs::Runs;

/// A rendered image, with where it was made.
pub struct Frame {
    /// The visibility image.
    pub image: VisibilityImage,
    /// The GPU passes' times, where the device has timestamp queries.
    pub times: Option<PassTimes>,
    /// What each GPU pass did, where [`crate::Renderer::set_counters`] asked for it.
    pub counters: Option<PassCounters>,
    /// `gpu: <adapter>` or `cpu`, and what the technique used (samples, edges, wedges).
    pub detail: String,
    /// What makes the image wrong though it rendered.
    pub warnings: Vec<Warning>,
}

/// What makes an image wrong though it rendered.
#[derive(Clone, Debug, PartialEq)]
pub enum Warning {
    /// A mesh whose cut by the light's plane holds the light's centre
    /// ([`penumbra_volumes::encloses_light_centre`]), under a technique that builds
    /// its shadow from that centre (hard, wedges, shadow maps).
    HoldsLightCentre {
        /// The mesh's index in the scene.
        mesh: usize,
        /// The mesh's name (its file, or the name it was given in code).
        name: String,
        /// The technique.
        technique: Technique,
    },
    /// A render on the GPU of a scene with a triangle wider than
    /// [`crate::backend::MAX_GPU_EXTENT_RATIO`] times the eye's distance to the light's centre,
    /// beyond which the GPU's 32-bit floats misplace shadows.
    GpuExtent {
        /// [`crate::backend::extent_ratio`] of the scene.
        ratio: f64,
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
            Warning::GpuExtent { ratio, technique } => write!(
                f,
                "a triangle {ratio:.1e} times as wide as the eye is far from the light's centre: \
                 the GPU's 32-bit floats may misplace {technique}'s shadows beyond {:.0e} \
                 (see docs/scene-format.md); the CPU's techniques have no such limit",
                crate::backend::MAX_GPU_EXTENT_RATIO
            ),
        }
    }
}

/// The warnings of a frame of `technique` rendered where `placement` says: each mesh whose cut
/// by the light's plane holds the light's centre, for the techniques built from the light's
/// centre (hard, wedges, shadow maps); on the GPU, a triangle wider than its floats hold
/// (`extent`, the scene's [`crate::backend::extent_ratio`] where already measured).
pub(crate) fn warnings(
    scene: &LitScene,
    technique: Technique,
    placement: Placement,
    extent: Option<f64>,
) -> Vec<Warning> {
    let mut out = Vec::new();
    if placement == Placement::Gpu {
        let ratio = extent.unwrap_or_else(|| crate::backend::extent_ratio(scene));
        if ratio > crate::backend::MAX_GPU_EXTENT_RATIO {
            out.push(Warning::GpuExtent { ratio, technique });
        }
    }
    if !(technique.is_volume() || Runs::of(technique) == Runs::GpuOnly) {
        return out;
    }
    out.extend(
        scene
            .meshes
            .iter()
            .enumerate()
            .filter(|(_, m)| {
                penumbra_volumes::encloses_light_centre(
                    &m.mesh.positions,
                    &m.mesh.triangles,
                    &scene.light,
                )
            })
            .map(|(mesh, m)| Warning::HoldsLightCentre {
                mesh,
                name: m.source.display().to_string(),
                technique,
            }),
    );
    out
}
