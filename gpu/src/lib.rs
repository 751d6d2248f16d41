//! The wgpu back end of penumbra: one module and one WGSL file per pass (Forest et al. 2006, section 4).
//!
//! The device (any adapter, hardware first, Mesa's lavapipe otherwise), the depth pre-pass, the
//! z-fail stencil pass of the shadow volumes, the penumbra-wedge pass, the blend pass and the
//! resolve: `hard`, additive `wedges` and Forest et al.'s `wedges-blend`, each checked against the
//! CPU oracle of `penumbra-volumes`; depth-complexity sampling; and the shadow-map techniques of
//! the other papers ([`ShadowMapRenderer`]): `pcf`, `pcss`, `fractional-disk`, `mdsm` and
//! `gaussian`.
//!
//! Every renderer is built once per device, its pipelines shared by every scene it renders:
//! [`GpuRenderer::render`] renders a scene once by a volume technique and reads V back
//! ([`GpuRenderer::render_depth_complexity`] by depth-complexity sampling);
//! [`ShadowMapRenderer::render`] does so by one shadow-map technique; [`GpuScene`] holds a scene
//! on an application's own device and records each frame's passes into its command encoder and
//! its own target ([`GBuffer`] and [`FrameCamera`] say what it needs).
//!
//! Every public name is here, at the crate root; the modules are private.
#![warn(missing_docs)]

mod blend_units;
mod constants;
mod context;
mod counters;
mod frame_uniforms;
mod gpu_scene;
mod passes;
mod pipelines;
mod readback;
mod renderer;
mod scene_data;
mod shadow_maps;
mod timing;

#[cfg(test)]
mod docs_tests;

pub use constants::{DISPATCH_ITERATIONS, MAX_SAMPLES, MAX_TAPS};
pub use context::{
    GpuContext, GpuError, OPTIONAL_FEATURES, REQUIRED_FEATURES, quiet_device_select,
    required_features, required_limits,
};
pub use counters::{PassCounters, PassCounts, Statistics};
pub use frame_uniforms::{CameraError, FrameCamera};
pub use gpu_scene::{
    ComplexityReport, FrameInputs, GpuScene, SOFTWARE_LOOP_BUDGET, ShadowBuilder, Uploads,
    WedgePass,
};
pub use passes::count::{count_buffer_bytes, storage_binding_limit};
pub use passes::depth::{GBuffer, visibility_target};
pub use passes::{DEPTH_FORMAT, NORMAL_FORMAT, POSITION_FORMAT, VISIBILITY_FORMAT};
pub use pipelines::GpuRenderer;
pub use readback::{read_r32f, read_texels};
pub use renderer::ComplexityImage;
pub use shadow_maps::{
    CORE_SLOPE, LightFrustum, MAX_SLOPE, ShadowMapRenderer, ShadowUniforms, Window,
    multi_pass_kernel, windows,
};
pub use timing::{PassTimes, Rendered};
/// The wgpu this crate is built with: an application's device must come from the same version.
pub use wgpu;
