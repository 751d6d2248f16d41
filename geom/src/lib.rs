//! Geometry of penumbra: meshes and their half-edge structure, scenes (made in code or read from
//! scene files), the camera and the rectangular light, ray casting, the ray-cast visibility
//! reference, the exact point evaluator, visibility images with their files and metrics, and the shaded
//! preview.
//!
//! Every public name is here at the crate root; the modules are private.
#![warn(missing_docs)]
#![warn(unnameable_types)]

mod boxtree;
mod bvh_build;
mod camera;
mod channels;
mod colour_map;
mod corners;
mod distant;
mod exact;
mod gltf;
mod gltf_buffers;
#[cfg(test)]
mod gltf_tests;
mod halfedge;
mod image;
mod image_files;
mod input;
mod interrupt;
mod light;
mod light_error;
#[cfg(test)]
mod light_error_tests;
mod lights;
mod limits;
mod lit_scene;
mod memory;
mod mesh;
mod mesh_files;
#[cfg(test)]
mod mesh_files_tests;
mod mesh_format;
mod metrics;
mod obj;
mod output;
mod ply;
#[cfg(test)]
mod ply_tests;
mod range;
mod raycast;
mod reference;
mod rng;
mod scene;
mod scene_error;
mod scene_file;
mod scene_file_lights;
#[cfg(test)]
mod scene_file_lights_tests;
mod scene_values;
mod shaded;
mod technique;
mod tracer;

pub use boxtree::{BoxTree, Plane};
pub use camera::{Camera, CameraError};
pub use channels::{Channel, LIGHTS_ATTRIBUTE, VisibilityChannels, is_visibility_channel};
pub use colour_map::colour_map;
pub use distant::{DistantLight, Warp};
pub use exact::{ExactVisibility, LIGHT_SQUARE_AREA, clip_step, exact_visibility};
pub use halfedge::{Edge, EdgeKind, HalfEdge, HalfEdgeList, HalfEdgeMesh, InvariantError, NO_TWIN};
pub use image::{ImageError, VisibilityImage};
pub use image_files::{CHANNEL, PngColor, write_exr_channel, write_png_bytes};
pub use interrupt::{Interrupter, Interruption};
pub use light::RectLight;
pub use light_error::LightError;
pub use lights::{
    Light, LightNameError, MAX_LIGHT_NAME, NamedLight, check_light_name, check_light_names,
    default_light_name, light_channel,
};
pub use limits::{MAX_COORDINATE, MAX_FOV_DEG, MIN_FOV_DEG, UNIT_TOLERANCE, within_coordinates};
pub use lit_scene::{DistantView, LitScene, PLANE_SNAP};
pub use memory::available_memory;
pub use mesh::{MeshError, TriangleMesh};
pub use mesh_format::MeshFormat;
pub use metrics::{Comparison, ERROR_THRESHOLD, Metrics, PENUMBRA, compare, heatmap};
pub use output::{check_writable, output_target, remove_temporaries_in_progress, write_atomically};
pub use range::RangeError;
pub use raycast::{Hit, Rays, SceneBvh, WatertightRay};
pub use reference::{LightSamples, REFERENCE_SEED, Reference};
pub use rng::Rng;
pub use scene::{Scene, SceneMesh};
pub use scene_error::SceneError;
pub use shaded::{SHADED_AMBIENT, SHADED_BACKGROUND, ShadedImage, shaded_value, srgb_byte};
pub use technique::{Technique, UnknownTechnique};
pub use tracer::{
    PLANE_HOLDS, SHADOW_EPSILON, SurfacePoint, TOUCH_EPSILON, Tracer, TracerGeometry,
    segment_meets_plane,
};
