//! penumbra: physically based soft shadows built from geometry.
//!
//! This facade re-exports the workspace's crates, in the order data flows through them:
//! [`geom`] (meshes, scenes, rays, the references), [`volumes`] (silhouettes, shadow volumes,
//! penumbra wedges on the CPU) and [`gpu`] (the wgpu passes).
//!
//! The front door is [`Renderer`]: give it a [`Scene`] (loaded from a scene file, see
//! `docs/scene-format.md`) and a [`Technique`], get a [`VisibilityImage`] (the share of the
//! light each pixel's surface point sees; `write_exr`, `write_png`).
#![warn(missing_docs)]

mod render;

pub use glam;
pub use penumbra_geom as geom;
pub use penumbra_geom::{Scene, Technique, VisibilityImage};
pub use penumbra_gpu as gpu;
pub use penumbra_volumes as volumes;
pub use render::{Backend, Frame, RenderError, RenderOptions, Renderer};
