//! Silhouettes, shadow volumes and penumbra wedges, evaluated on the CPU (Forest, Barthe &
//! Paulin, "Realistic Soft Shadows by Penumbra-Wedges Blending", 2006): the oracle that the wgpu
//! back end must reproduce, and the renderer on machines without a GPU.
//!
//! What the GPU needs of a scene is [`Volumes`] (per mesh an [`Occluder`]: its half-edges,
//! [`Silhouette`] and [`ShadowVolume`]; the [`Wedge`]s) and, for depth-complexity sampling, the
//! [`PotentialEdges`]. The CPU renderers are [`CpuRenderer`] (the volume techniques) and
//! [`DepthComplexity`]; both are built from a scene once and render with their options.
//!
//! Every public name is here at the crate root; the modules are private.
#![warn(missing_docs)]
#![warn(unnameable_types)]

mod blend;
mod candidates;
mod clip;
mod cpu_renderer;
mod depth_complexity;
mod depth_complexity_image;
mod light_centre;
mod potential;
mod pyramid_grid;
mod region;
mod samples;
mod sectors;
mod sensors;
mod shadow_volume;
mod silhouette;
mod sun_series;
mod terminator;
mod volumes;
mod wedge;
mod wedge_grid;
mod wedge_integral;
mod wedge_reach;

#[cfg(test)]
mod depth_complexity_tests;
#[cfg(test)]
mod wedge_tests;

pub use clip::Rect;
pub use cpu_renderer::CpuRenderer;
pub use depth_complexity::{DepthComplexity, PointVisibility, Scratch, THIN_LIGHT};
pub use depth_complexity_image::{GRID_FROM_EDGES, TILE};
pub use light_centre::{
    Enclosure, NEAR_LIGHT, enclosure, in_front_of, near_light, passes_through_light, winds_around,
};
pub use potential::{EdgeFace, LightCrossing, PotentialEdge, PotentialEdges};
pub use samples::SamplePattern;
pub use sensors::{SensorSamples, SensorVisibility};
pub use shadow_volume::{FaceKind, OpenVolume, ShadowVolume, VolumeVertex, caps, side};
pub use silhouette::{Silhouette, SilhouetteEdge};
pub use sun_series::SunSeries;
pub use terminator::{front_share, outward_sign};
pub use volumes::{GeometryCounts, Occluder, Volumes};
pub use wedge::Wedge;
pub use wedge_grid::{ReceiverCells, WedgeGrid};
pub use wedge_integral::EdgeIntegral;
pub use wedge_reach::{WedgeFrustum, receiver_box, wedge_bounds, wedge_box, wedge_frustum};
