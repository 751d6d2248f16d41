//! Silhouettes, shadow volumes and penumbra wedges, evaluated on the CPU (Forest, Barthe &
//! Paulin, "Realistic Soft Shadows by Penumbra-Wedges Blending", 2006): the oracle that the wgpu
//! back end must reproduce, and the renderer on machines without a GPU.
#![warn(missing_docs)]

pub mod blend;
pub mod clip;
pub mod depth_complexity;
mod light_centre;
pub mod potential;
mod region;
pub mod render;
pub mod samples;
mod sectors;
pub mod shadow_volume;
pub mod silhouette;
pub mod terminator;
pub mod wedge;
pub mod wedge_grid;

pub use depth_complexity::{DepthComplexity, SamplePattern};
pub use penumbra_geom as geom;
pub use penumbra_geom::Technique;
pub use render::{CpuRenderer, Volumes};
