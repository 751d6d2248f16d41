//! The wgpu back end of penumbra: one module and one WGSL file per pass (Forest et al. 2006, section 4).
//!
//! The device (any adapter, hardware first, Mesa's lavapipe otherwise), the depth pre-pass, the
//! z-fail stencil pass of the shadow volumes, the penumbra-wedge pass, the blend pass and the
//! resolve: `hard`, additive `wedges` and Forest et al.'s `wedges-blend`, each checked against the
//! CPU oracle of `penumbra-volumes`. And the shadow-map techniques of the other papers
//! ([`shadow_maps`]): `pcf`, `pcss`, `fractional-disk`, `mdsm` and `gaussian`.
//!
//! Two ways in: [`GpuRenderer::render`] renders a scene once and reads V back; [`GpuScene`]
//! holds a scene on an application's own device and records each frame's passes into its
//! command encoder and its own target ([`GBuffer`] and [`FrameCamera`] say what it needs).
#![warn(missing_docs)]

pub mod complexity;
pub mod constants;
pub mod context;
pub mod frame;
pub mod gpu_scene;
pub mod light_frustum;
pub mod passes;
pub mod readback;
mod record;
mod render_once;
pub mod renderer;
pub mod scene_data;
pub mod shadow_inputs;
pub mod shadow_maps;
pub mod timing;

pub use context::{GpuContext, GpuError};
pub use frame::{CameraError, FrameCamera};
pub use gpu_scene::{FrameInputs, GpuScene, Uploads};
pub use passes::depth::GBuffer;
pub use penumbra_volumes as volumes;
pub use renderer::{GpuRenderer, PassTimes};
pub use shadow_maps::ShadowMapRenderer;
/// The wgpu this crate is built with: an application's device must come from the same version.
pub use wgpu;
