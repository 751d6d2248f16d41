//! penumbra: physically based soft shadows built from geometry.
//!
//! This facade re-exports the workspace's crates, in the order data flows through them:
//! [`geom`] (meshes, scenes, rays, the references), [`volumes`] (silhouettes, shadow volumes,
//! penumbra wedges on the CPU) and [`gpu`] (the wgpu passes).
#![warn(missing_docs)]

pub use penumbra_geom as geom;
pub use penumbra_gpu as gpu;
pub use penumbra_volumes as volumes;
