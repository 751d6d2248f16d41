//! Geometry of penumbra: meshes and their half-edge structure, scene files, the camera and the
//! rectangular light, ray casting, the ray-cast visibility reference, the exact point evaluator
//! and visibility images.
#![warn(missing_docs)]

pub mod boxtree;
pub mod bvh_build;
pub mod camera;
pub mod exact;
pub mod halfedge;
pub mod image;
pub mod input;
pub mod light;
pub mod memory;
pub mod mesh;
mod output;
pub mod range;
pub mod raycast;
pub mod reference;
pub mod rng;
pub mod scene;
pub mod scene_values;
pub mod technique;
pub mod union;

pub use camera::Camera;
pub use halfedge::HalfEdgeMesh;
pub use image::VisibilityImage;
pub use light::RectLight;
pub use mesh::TriangleMesh;
pub use reference::{SurfacePoint, Tracer};
pub use rng::Rng;
pub use scene::{Scene, SceneError};
pub use technique::Technique;
