//! A [`GpuScene`]'s depth-complexity sampling: its settings, its edge list and its reports, kept
//! by [`super::complexity_state`], which records the passes.

use super::complexity_state::{ComplexityReport, SceneParts};
use super::{FrameInputs, GpuScene};
use crate::context::GpuError;
use crate::frame_uniforms::FrameCamera;
use crate::passes::depth::GBuffer;
use crate::timing::Timer;

impl GpuScene {
    /// Light samples per pixel of depth-complexity sampling (`N x N`).
    pub fn light_samples(&self) -> u32 {
        self.complexity.light_samples()
    }

    /// Takes `samples` light samples per pixel in depth-complexity sampling from the next frame
    /// on: a perfect square up to [`MAX_SAMPLES`](crate::MAX_SAMPLES) (1024), in the correlated
    /// multi-jittered pattern of the CPU oracle (`penumbra_volumes::SamplePattern`).
    pub fn set_light_samples(&mut self, samples: u32) -> Result<(), GpuError> {
        self.complexity.set_light_samples(samples)
    }

    /// Records the depth pre-pass and the edge-list pass of the depth-complexity frame `inputs`
    /// into `gbuffer`, and nothing else: submitted, [`GpuScene::complexity_report`] then sizes
    /// the list for that frame before it is recorded, so that even the first frame fits.
    pub fn record_edge_lists(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &FrameInputs,
        gbuffer: &GBuffer,
    ) -> Result<(), GpuError> {
        self.record_depth(encoder, &inputs.camera, gbuffer)?;
        self.record_complexity(encoder, &inputs.camera, gbuffer, None, &Timer::disabled())
    }

    /// Entries the depth-complexity edge list holds; 0 until the first frame sized it (64 per
    /// tile of 8 x 8 pixels).
    pub fn edge_list_capacity(&self) -> u32 {
        self.complexity.list_capacity()
    }

    /// Makes the depth-complexity edge list hold `entries` from the next frame on. Frames grow
    /// it as they need ([`GpuScene::complexity_report`]); this sets where it starts.
    pub fn set_edge_list_capacity(&mut self, entries: u32) {
        self.complexity.set_list_capacity(entries);
    }

    /// Potential silhouette edges of the current light and transforms and all edges of the
    /// meshes; `(0, 0)` until a depth-complexity frame needed them.
    pub fn potential_edges(&self) -> (usize, usize) {
        self.complexity.potential_edges()
    }

    /// After the last depth-complexity frame was submitted: waits for it and reads its report,
    /// growing the edge list to what the frame needed when it overflowed (a quarter more, so
    /// that a frame that needs a little more does not overflow again). `None` when no
    /// depth-complexity frame was recorded since the last call.
    pub fn complexity_report(&mut self) -> Result<Option<ComplexityReport>, GpuError> {
        self.complexity.report(&self.ctx)
    }

    /// Bytes of the counting pass's buffer that the last depth-complexity frame's buffers
    /// hold: what [`count_buffer_bytes`](crate::count_buffer_bytes) gives for its size and
    /// samples on this device. `None` before the first frame.
    pub fn count_buffer_bytes(&self) -> Option<u64> {
        self.complexity.count_buffer_bytes()
    }

    /// The loop iterations an invocation of the counting pass may take before its pixel is
    /// reported as cut short: [`SOFTWARE_LOOP_BUDGET`](crate::SOFTWARE_LOOP_BUDGET) on a CPU
    /// adapter (llvmpipe), unlimited on a GPU.
    pub fn loop_budget(&self) -> u32 {
        self.complexity.loop_budget()
    }

    /// Sets [`GpuScene::loop_budget`] (for a software device with another limit).
    pub fn set_loop_budget(&mut self, iterations: u32) {
        self.complexity.set_loop_budget(iterations);
    }

    /// Entries of a pixel's work (its tile's potential edges, then the triangles through the
    /// light's plane) that one dispatch of the counting pass takes: as many as keep an
    /// invocation within [`DISPATCH_ITERATIONS`](crate::DISPATCH_ITERATIONS) loop iterations at
    /// the scene's samples, whatever the scene; 0 until a depth-complexity frame built the
    /// scene's edges. The pass records as many dispatches as the longest possible work needs.
    pub fn edges_per_dispatch(&self) -> u32 {
        self.complexity.edges_per_dispatch()
    }

    /// Makes one dispatch of the counting pass take `entries` of a pixel's work from the next
    /// frame on (0: [`GpuScene::edges_per_dispatch`]'s own): fewer take more dispatches, with
    /// the same image.
    pub fn set_edges_per_dispatch(&mut self, entries: u32) {
        self.complexity.set_edges_per_dispatch(entries);
    }

    /// Makes the counting pass keep the state and counts of at most `rows` image rows at once
    /// from the next frame on, in bands from the top (0: as many as one storage binding of
    /// the device holds, the whole image at most; at least 4): less memory, more dispatches,
    /// the same image. A frame refuses with [`GpuError::TooLarge`] where not even 4 rows fit.
    pub fn set_count_band_rows(&mut self, rows: u32) {
        self.complexity.set_most_band_rows(rows);
    }

    /// Makes the counting pass read the stencil count of pixel `[x, y]` two above what the
    /// shadow volumes' rasterisation left there, from the next frame on (`None`: none), as a
    /// crack between two volumes' faces can make it: a test that such a count is found and
    /// counted again, not left to darken the pixel.
    pub fn set_stencil_error(&mut self, pixel: Option<[u32; 2]>) {
        self.complexity.set_stencil_error(pixel);
    }

    /// Records the passes of depth-complexity sampling for `camera` into `target`; without a
    /// target, only the edge lists, for [`GpuScene::complexity_report`] to size the list.
    pub(super) fn record_complexity(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        camera: &FrameCamera,
        gbuffer: &GBuffer,
        target: Option<&wgpu::TextureView>,
        timer: &Timer,
    ) -> Result<(), GpuError> {
        let parts = SceneParts {
            ctx: &self.ctx,
            pipelines: &self.pipelines,
            frame: &self.frame,
            light: self.light.rect(),
            warp: self.light.warp(),
            meshes: &self.meshes,
            uploads: &mut self.uploads,
        };
        self.complexity
            .record(parts, encoder, camera, gbuffer, target, timer)
    }
}
