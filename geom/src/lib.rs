//! Geometry of penumbra: meshes and their half-edge structure, scene files, the camera and the
//! rectangular light, ray casting, the ray-cast visibility reference, the exact point evaluator
//! and visibility images.
#![warn(missing_docs)]

pub mod exact;
pub mod light;
pub mod rng;

pub use light::RectLight;
pub use rng::Rng;
