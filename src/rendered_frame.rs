//! What a render gives back: the image, the GPU's pass times, where it ran, and what makes the
//! image wrong though it rendered.

use std::fmt;

use penumbra_geom::{HalfEdgeMesh, LitScene, Technique, VisibilityImage};
use penumbra_gpu::{PassCounters, PassTimes};
use penumbra_volumes::Enclosure;

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
    /// A closed mesh around the light's centre with the eye outside it
    /// ([`penumbra_volumes::Enclosure::Sealed`]: a lamp shut in a box, seen from outside), under
    /// a soft technique built from that centre (wedges, shadow maps). A room around the light
    /// and the eye is right; `hard` is taken from the hard reference here.
    SealedLight {
        /// The mesh's index in the scene.
        mesh: usize,
        /// The mesh's name (its file, or the name it was given in code).
        name: String,
        /// The technique.
        technique: Technique,
    },
    /// A mesh that passes through the light's own rectangle
    /// ([`penumbra_volumes::passes_through_light`]), under a soft technique built from the
    /// silhouette seen from the light's centre (wedges, shadow maps), which is far from the
    /// silhouette seen from the rest of the light there.
    ThroughLight {
        /// The mesh's index in the scene.
        mesh: usize,
        /// The mesh's name (its file, or the name it was given in code).
        name: String,
        /// The technique.
        technique: Technique,
    },
    /// A mesh within a quarter of the light's size of the light, in front of it
    /// ([`penumbra_volumes::near_light`]: a lamp in a recess, a shade), under a shadow-map
    /// technique: such a blocker casts penumbrae many times the light's width, wider than the
    /// maps' filters reach.
    NearLight {
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
            Warning::SealedLight {
                mesh,
                name,
                technique,
            } => write!(
                f,
                "mesh {mesh} ({name}) closes round the light's centre and the eye is outside it: \
                 {technique} builds its shadow from that centre, and is right for a light inside \
                 a closed mesh only with the eye inside it too (a room lit from its ceiling; see \
                 docs/accuracy.md); hard, depth-complexity and the reference are exact here"
            ),
            Warning::ThroughLight {
                mesh,
                name,
                technique,
            } => write!(
                f,
                "mesh {mesh} ({name}) passes through the light's rectangle: {technique} builds \
                 its shadow from the silhouette seen from the light's centre, which is far from \
                 the one seen from the rest of the light here (see docs/accuracy.md); hard, \
                 depth-complexity and the reference are exact here"
            ),
            Warning::NearLight {
                mesh,
                name,
                technique,
            } => write!(
                f,
                "mesh {mesh} ({name}) comes within a quarter of the light's size of the light, in front of \
                 it (a lamp in a recess or a shade): {technique} takes each penumbra's width \
                 from a shadow map's blocker depth, and a blocker this near the light casts \
                 penumbrae wider than the map's filters reach (see docs/shadow-maps.md); \
                 wedges-blend, depth-complexity and the reference are right here"
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

/// The warnings of a frame of `technique` rendered where `placement` says: for the soft
/// techniques built from the light's centre (wedges, shadow maps), each closed mesh that shuts
/// the light's centre in from the eye (`sealing`, [`sealing_meshes`]) and each other mesh that
/// passes through the light's rectangle, and for the shadow maps each other mesh near the light
/// in front of it; on the GPU, a triangle wider
/// than its floats hold (`extent`, the scene's [`crate::backend::extent_ratio`] where already
/// measured).
pub(crate) fn warnings(
    scene: &LitScene,
    technique: Technique,
    (placement, sealing): (Placement, &[usize]),
    extent: Option<f64>,
) -> Vec<Warning> {
    let mut out = Vec::new();
    if placement == Placement::Gpu {
        let ratio = extent.unwrap_or_else(|| crate::backend::extent_ratio(scene));
        if ratio > crate::backend::MAX_GPU_EXTENT_RATIO {
            out.push(Warning::GpuExtent { ratio, technique });
        }
    }
    let soft = matches!(technique, Technique::Wedges | Technique::WedgesBlend)
        || Runs::of(technique) == Runs::GpuOnly;
    if !soft {
        return out;
    }
    for (mesh, m) in scene.meshes.iter().enumerate() {
        let name = m.source.display().to_string();
        let tris = (0..m.mesh.triangles.len()).map(|t| m.mesh.triangle(t));
        if sealing.contains(&mesh) {
            out.push(Warning::SealedLight {
                mesh,
                name,
                technique,
            });
        } else if scene.distant.is_none()
            && penumbra_volumes::passes_through_light(tris.clone(), &scene.light)
        {
            out.push(Warning::ThroughLight {
                mesh,
                name,
                technique,
            });
        } else if scene.distant.is_none()
            && technique.is_shadow_map()
            && penumbra_volumes::near_light(tris, &scene.light)
        {
            out.push(Warning::NearLight {
                mesh,
                name,
                technique,
            });
        }
    }
    out
}

/// The closed meshes of `scene` that shut its lamp in from the eye
/// ([`penumbra_volumes::Enclosure::Sealed`]); none under a distant light.
pub(crate) fn sealing_meshes(scene: &LitScene) -> Vec<usize> {
    if scene.distant.is_some() {
        return Vec::new();
    }
    let sealed = |m: &penumbra_geom::SceneMesh| {
        let mesh = &m.mesh;
        let tris = (0..mesh.triangles.len()).map(|t| mesh.triangle(t));
        penumbra_volumes::enclosure(tris, &scene.light, scene.camera.eye) == Enclosure::Sealed
            && penumbra_volumes::outward_sign(mesh, &HalfEdgeMesh::build(mesh)) != 0.0
    };
    (scene.meshes.iter().enumerate())
        .filter(|(_, m)| sealed(m))
        .map(|(i, _)| i)
        .collect()
}
