//! The volume techniques' pipelines on one device ([`GpuRenderer`]): built once, shared by
//! every [`crate::GpuScene`] made with it (`gpu_scene/`) and by the one-shot renders
//! (`renderer.rs`).

use std::sync::Arc;

use crate::context::{GpuContext, GpuError};
use crate::passes::{
    blend::BlendPass,
    blend_tiles::BlendTilesPass,
    build::BuildPass,
    candidates::CandidatePass,
    complexity::{ComplexityPass, inputs_layout},
    count::CountPass,
    depth::DepthPass,
    frame_layout,
    resolve::ResolvePass,
    stencil::StencilPass,
    wedge::WedgePass,
    wedge_tiles::WedgeTilesPass,
};

/// The pipelines of every pass, built once per device.
pub(crate) struct Pipelines {
    pub(crate) frame_layout: wgpu::BindGroupLayout,
    pub(crate) depth: DepthPass,
    pub(crate) stencil: StencilPass,
    /// The shadows built on the GPU.
    pub(crate) build: BuildPass,
    pub(crate) wedge: WedgePass,
    /// `wedges`' tiled wedge pass.
    pub(crate) wedge_tiles: WedgeTilesPass,
    pub(crate) blend: BlendPass,
    /// `wedges-blend`'s tiled pass.
    pub(crate) blend_tiles: BlendTilesPass,
    pub(crate) resolve: ResolvePass,
    /// Depth-complexity sampling's group 1 and its compute passes.
    pub(crate) complexity_layout: wgpu::BindGroupLayout,
    pub(crate) edge_lists: ComplexityPass,
    pub(crate) count: CountPass,
    /// Its receiver candidates.
    pub(crate) candidates: CandidatePass,
}

/// The volume techniques' pipelines on one device. Cloning it is cheap: the pipelines are
/// shared.
///
/// ```no_run
/// // An application's own device, made with what the passes need.
/// # async fn device() -> (wgpu::Device, wgpu::Queue) { unimplemented!() }
/// # pollster::block_on(async {
/// let (device, queue) = device().await;
/// let renderer = penumbra::gpu::GpuRenderer::new(&device, &queue)?;
/// # Ok::<(), penumbra::gpu::GpuError>(())
/// # }).unwrap();
/// ```
#[derive(Clone)]
pub struct GpuRenderer {
    ctx: GpuContext,
    pipelines: Arc<Pipelines>,
    counters: bool,
    wedge_pass: Option<crate::WedgePass>,
}

impl GpuRenderer {
    /// Builds the pipelines on an application's `device` (made with
    /// [`crate::context::REQUIRED_FEATURES`] and [`crate::context::required_limits`]); the
    /// renderer keeps clones of both handles.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Result<Self, GpuError> {
        Ok(Self::with_context(&GpuContext::from_device(device, queue)?))
    }

    /// Builds the pipelines on `ctx`'s device.
    pub fn with_context(ctx: &GpuContext) -> Self {
        let device = &ctx.device;
        let frame_layout = frame_layout(device);
        let resolve = ResolvePass::new(device, &frame_layout);
        let wedge = WedgePass::new(device, &frame_layout, &resolve.receiver_layout);
        let complexity_layout = inputs_layout(device);
        let pipelines = Pipelines {
            edge_lists: ComplexityPass::edge_lists(device, &frame_layout, &complexity_layout),
            count: CountPass::new(device, &frame_layout, &complexity_layout),
            candidates: CandidatePass::new(device, &frame_layout),
            complexity_layout,
            depth: DepthPass::new(device, &frame_layout),
            stencil: StencilPass::new(device, &frame_layout, ctx.unclipped_depth),
            build: BuildPass::new(device),
            blend: BlendPass::new(device, &frame_layout),
            blend_tiles: BlendTilesPass::new(device),
            wedge,
            wedge_tiles: WedgeTilesPass::new(device, &frame_layout),
            resolve,
            frame_layout,
        };
        GpuRenderer {
            ctx: ctx.clone(),
            pipelines: Arc::new(pipelines),
            counters: false,
            wedge_pass: None,
        }
    }

    /// Whether [`GpuRenderer::render_timed`] and [`GpuRenderer::render_depth_complexity`] count
    /// what each pass does ([`crate::PassCounters`]); off by default.
    pub fn set_counters(&mut self, on: bool) {
        self.counters = on;
    }

    /// Whether they do.
    pub fn counters(&self) -> bool {
        self.counters
    }

    /// How its one-shot renders of `wedges` and `wedges-blend` evaluate the wedges; `None` (the
    /// default): the faster on its device ([`crate::WedgePass::for_device`]).
    pub fn set_wedge_pass(&mut self, pass: Option<crate::WedgePass>) {
        self.wedge_pass = pass;
    }

    /// The pass asked for, if any.
    pub fn wedge_pass(&self) -> Option<crate::WedgePass> {
        self.wedge_pass
    }

    /// The device and queue it renders with.
    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// The pipelines, which every [`crate::GpuScene`] made with it shares.
    pub(crate) fn pipelines(&self) -> &Arc<Pipelines> {
        &self.pipelines
    }
}
