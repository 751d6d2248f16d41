//! Depth-complexity sampling on the GPU (Forest, Barthe & Paulin, "Accurate Shadows by Depth
//! Complexity Sampling", 2008), recorded by a [`super::GpuScene`]: exact soft shadows, equal to the CPU
//! oracle (`penumbra_volumes::depth_complexity`) sample for sample up to `f32` rounding.
//!
//! After the depth pre-pass, a frame takes four passes:
//!
//! 1. **stencil**: the z-fail count of shadow volumes built by the open-mesh rule for every mesh
//!    (each triangle facing the light's centre either way casts), which is `D(P, c)`, the number
//!    of triangles between the receiver and the light's centre: the oracle's convention, on open,
//!    closed and non-manifold meshes alike. The stencil holds it modulo 256;
//! 2. **edge lists** (compute, one workgroup per tile of `TILE x TILE` pixels): the potential
//!    silhouette edges that the tile's receivers' views of the light may meet, in one range of a
//!    list per tile;
//! 3. **count** (compute, one invocation per pixel): the centre's count plus each listed edge's
//!    change to the `N x N` samples it separates from the centre, and V, into a buffer;
//! 4. **resolve**: V into the application's target.
//!
//! The list is a storage buffer sized from an earlier frame's demand. A frame that needs more
//! loses nothing: the counting pass reads every edge for the tiles whose range did not fit, and
//! [`super::GpuScene::complexity_report`] reads the demand back after the frame and grows the list.
//!
//! [`ComplexityState`] is all a scene keeps for it: what it built of the scene for the current
//! light and transforms and the frame's buffers (`super::complexity_buffers`), and its
//! settings; [`ComplexityReport`] is what a frame reports once it has run.

use penumbra_geom::{RectLight, Warp};

use super::complexity_buffers::{ComplexityFrame, ComplexityScene, tiles};
use super::complexity_receivers::ReceiverInputs;
use super::meshes::StoredMesh;
use super::uploads::Uploads;
use crate::constants::{COUNT_GROUP, MAX_AXIS};
use crate::context::{GpuContext, GpuError};
use crate::counters::{Pass, Traffic};
use crate::frame_uniforms::FrameCamera;
use crate::passes::complexity::ComplexityParams;
use crate::passes::count::{
    band_rows, chunks, count_bytes, edges_per_dispatch, storage_binding_limit,
};
use crate::passes::depth::GBuffer;
use crate::passes::resolve::ResolveInput;
use crate::passes::stencil::VolumeDraws;
use crate::passes::{FrameBindings, bind_group};
use crate::pipelines::Pipelines;
use crate::timing::Timer;

/// Loop iterations an invocation of the counting pass may take on a software device before its
/// pixel counts as cut short. Mesa's llvmpipe (lavapipe) ends every loop of an invocation once
/// they have run 65,535 iterations in all (`LP_MAX_TGSI_LOOP_ITERATIONS`), silently; the
/// counting pass counts its loops' iterations (an upper bound of llvmpipe's count, which does
/// not see the loops its compiler unrolls) and reports the pixels that may have reached that
/// limit ([`ComplexityReport::cut_short`]).
pub const SOFTWARE_LOOP_BUDGET: u32 = 65_000;

/// What a depth-complexity frame reports once it has run
/// ([`GpuScene::complexity_report`](super::GpuScene::complexity_report)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ComplexityReport {
    /// Entries the frame's edge list needed.
    pub demand: u32,
    /// Whether that was more than it held: the tiles that did not fit read every edge (the
    /// image is the same, only slower) and the list has grown for the next frames.
    pub overflowed: bool,
    /// Pixels whose counting took more loop iterations than a software device runs (see
    /// [`SOFTWARE_LOOP_BUDGET`]): their V may be wrong. Always 0 on a hardware GPU, and on a
    /// software one unless a receiver's own work outgrows the budget (a budget set below
    /// what the counting pass's bounded dispatches take).
    pub cut_short: u32,
    /// Pixels whose work (their tile's edges and the crossings) the counting pass's
    /// dispatches did not finish: their V is wrong. Found exactly, by each pixel; 0 unless a
    /// frame records fewer dispatches than the longest possible work needs, which none does.
    pub unfinished: u32,
}

/// Light samples per axis of a new scene (256 samples per pixel).
const DEFAULT_AXIS: u32 = 16;

/// Entries of the edge list per tile of a new scene, before any frame told how many it needs.
const FIRST_ENTRIES_PER_TILE: u32 = 64;

/// Everything a scene keeps for depth-complexity sampling.
pub(super) struct ComplexityState {
    /// What it built of the scene for the current light and transforms (`None`: not yet, or
    /// they changed since).
    scene: Option<ComplexityScene>,
    /// The frame's buffers at the last frame's size and list capacity.
    frame: Option<ComplexityFrame>,
    /// Light samples per axis, `N`.
    samples_per_axis: u32,
    /// Entries of the edge list from the next frame on (0: not yet sized).
    list_capacity: u32,
    /// Loop iterations an invocation may take before its pixel is reported cut short.
    loop_budget: u32,
    /// Entries of a pixel's work per dispatch of the counting pass in place of
    /// [`edges_per_dispatch`]'s (0: that).
    chunk_override: u32,
    /// The most rows the counting pass keeps state for at once (0: as many as fit).
    most_band_rows: u32,
    /// The pixel whose stencil count the counting pass reads two too many (tests).
    stencil_error: Option<[u32; 2]>,
}

/// What recording a depth-complexity frame reads of its scene, and where it counts its uploads.
pub(super) struct SceneParts<'a> {
    pub(super) ctx: &'a GpuContext,
    pub(super) pipelines: &'a Pipelines,
    /// The frame's group 0, written for this frame.
    pub(super) frame: &'a wgpu::BindGroup,
    pub(super) light: &'a RectLight,
    /// A distant light's warp, which the meshes are rendered through.
    pub(super) warp: Option<&'a Warp>,
    pub(super) meshes: &'a [StoredMesh],
    pub(super) uploads: &'a mut Uploads,
}

impl ComplexityState {
    /// The state of a new scene on a device of `device_type`: [`SOFTWARE_LOOP_BUDGET`] on a
    /// CPU adapter, no budget on a GPU.
    pub(super) fn new(device_type: wgpu::DeviceType) -> Self {
        ComplexityState {
            scene: None,
            frame: None,
            samples_per_axis: DEFAULT_AXIS,
            list_capacity: 0,
            loop_budget: if device_type == wgpu::DeviceType::Cpu {
                SOFTWARE_LOOP_BUDGET
            } else {
                u32::MAX
            },
            chunk_override: 0,
            most_band_rows: 0,
            stencil_error: None,
        }
    }

    /// Drops what was built for the old light or transforms.
    pub(super) fn light_changed(&mut self) {
        self.scene = None;
    }

    pub(super) fn light_samples(&self) -> u32 {
        self.samples_per_axis * self.samples_per_axis
    }

    pub(super) fn set_light_samples(&mut self, samples: u32) -> Result<(), GpuError> {
        let n = (samples as f64).sqrt().round() as u32;
        if samples == 0 || n * n != samples || n > MAX_AXIS {
            return Err(GpuError::LightSamples {
                samples,
                most: MAX_AXIS * MAX_AXIS,
            });
        }
        self.samples_per_axis = n;
        Ok(())
    }

    pub(super) fn list_capacity(&self) -> u32 {
        self.list_capacity
    }

    pub(super) fn set_list_capacity(&mut self, entries: u32) {
        self.list_capacity = entries.max(1);
    }

    pub(super) fn potential_edges(&self) -> (usize, usize) {
        self.scene
            .as_ref()
            .map_or((0, 0), |c| (c.potential, c.all_edges))
    }

    pub(super) fn loop_budget(&self) -> u32 {
        self.loop_budget
    }

    pub(super) fn set_loop_budget(&mut self, iterations: u32) {
        self.loop_budget = iterations;
    }

    /// Entries of a pixel's work one dispatch of the counting pass takes (0 until a frame
    /// built the scene's edges).
    pub(super) fn edges_per_dispatch(&self) -> u32 {
        match (self.chunk_override, &self.scene) {
            (0, Some(data)) => edges_per_dispatch(self.samples_per_axis, data.max_faces),
            (0, None) => 0,
            (k, _) => k,
        }
    }

    pub(super) fn set_edges_per_dispatch(&mut self, entries: u32) {
        self.chunk_override = entries;
    }

    /// Bytes of the counting pass's buffer (V, the pixels' state and counts) of the last
    /// frame's buffers; `None` before the first frame.
    pub(super) fn count_buffer_bytes(&self) -> Option<u64> {
        self.frame.as_ref().map(|f| f.visibility.size())
    }

    pub(super) fn set_stencil_error(&mut self, pixel: Option<[u32; 2]>) {
        self.stencil_error = pixel;
    }

    pub(super) fn set_most_band_rows(&mut self, rows: u32) {
        self.most_band_rows = if rows == 0 { 0 } else { rows.max(COUNT_GROUP) };
    }

    /// Waits for the last frame and reads its report, growing the list when it overflowed (a
    /// quarter more than it needed); `None` when no frame was recorded since the last call.
    pub(super) fn report(
        &mut self,
        ctx: &GpuContext,
    ) -> Result<Option<ComplexityReport>, GpuError> {
        let Some(frame) = self.frame.as_mut().filter(|f| f.pending) else {
            return Ok(None);
        };
        frame.pending = false;
        let bytes = crate::readback::map_read(ctx, &frame.demand_readback)?;
        let word = |k: usize| u32::from_le_bytes(bytes[4 * k..4 * k + 4].try_into().expect("4"));
        let report = ComplexityReport {
            demand: word(0),
            overflowed: word(0) > frame.capacity,
            cut_short: word(1),
            unfinished: word(3),
        };
        if report.overflowed {
            self.list_capacity = report.demand.saturating_add(report.demand / 4);
        }
        Ok(Some(report))
    }

    /// Builds what the frame of `size` pixels needs and is not there yet: the scene's part, the
    /// list's first size, the frame's buffers. An error when V or the list would not fit one
    /// storage binding of the device.
    fn prepare(&mut self, parts: &mut SceneParts<'_>, size: (u32, u32)) -> Result<(), GpuError> {
        let device = &parts.ctx.device;
        if self.scene.is_none() {
            let (data, bytes) =
                ComplexityScene::build(device, parts.meshes, parts.light, parts.warp);
            parts.uploads.shadows += bytes;
            self.scene = Some(data);
        }
        let (tx, ty) = tiles(size);
        if self.list_capacity == 0 {
            self.list_capacity = (tx * ty).saturating_mul(FIRST_ENTRIES_PER_TILE);
        }
        // The counting pass's buffer and the list are storage buffers: each must fit one
        // binding. The former keeps as many rows' state and counts at once as fit.
        let limit = storage_binding_limit(&device.limits());
        let n = self.samples_per_axis;
        let rows = band_rows(size, n, limit, self.most_band_rows);
        let list_bytes = 4 * self.list_capacity as u64;
        let (Some(rows), true) = (rows, list_bytes <= limit) else {
            return Err(GpuError::TooLarge {
                size,
                bytes: count_bytes(size, n, size.1.min(COUNT_GROUP)).max(list_bytes),
                entries: self.list_capacity,
                limit,
            });
        };
        let data = self.scene.as_ref().expect("built above");
        let chunks = chunks(
            data.edge_count,
            data.crossing_count,
            self.edges_per_dispatch(),
            data.triangle_count,
        );
        let shape = (self.samples_per_axis, chunks, rows);
        if self.frame.as_ref().is_none_or(|f| {
            f.size != size
                || f.capacity != self.list_capacity
                || (f.per_axis, f.chunks, f.band_rows) != shape
        }) {
            self.frame = Some(ComplexityFrame::new(
                device,
                size,
                self.list_capacity,
                shape,
            ));
        }
        Ok(())
    }

    /// Records the passes of depth-complexity sampling (the module's documentation lists them)
    /// for `camera`, reading `gbuffer`; without a target, only the edge lists, for
    /// [`ComplexityState::report`] to size the list.
    pub(super) fn record(
        &mut self,
        mut parts: SceneParts<'_>,
        encoder: &mut wgpu::CommandEncoder,
        camera: &FrameCamera,
        gbuffer: &GBuffer,
        target: Option<&wgpu::TextureView>,
        timer: &Timer,
    ) -> Result<(), GpuError> {
        let size = camera.size;
        self.prepare(&mut parts, size)?;
        let chunk = self.edges_per_dispatch();
        let (tx, ty) = tiles(size);
        let data = self.scene.as_ref().expect("built in prepare");
        let frame = self.frame.as_mut().expect("made in prepare");
        let mut params = ComplexityParams {
            edges: data.edge_count,
            crossings: data.crossing_count,
            capacity: frame.capacity,
            per_axis: self.samples_per_axis,
            tiles_x: tx,
            triangles: data.triangle_count,
            budget: self.loop_budget,
            chunk,
            chunks: frame.chunks,
            band_rows: frame.band_rows,
            recount_all: u32::from(data.room),
            stencil_error: self
                .stencil_error
                .filter(|&[x, y]| x < size.0 && y < size.1)
                .map_or(0, |[x, y]| 1 + y * size.0 + x),
            ..Default::default()
        };
        params.set_camera(camera, parts.light);
        let (device, p) = (&parts.ctx.device, parts.pipelines);
        parts
            .ctx
            .queue
            .write_buffer(&frame.params, 0, bytemuck::bytes_of(&params));
        parts.uploads.frame += std::mem::size_of::<ComplexityParams>() as u64;
        let position = p.resolve.receivers(device, gbuffer);
        let bindings = FrameBindings {
            frame: parts.frame,
            depth: &gbuffer.depth_view,
            position: &position,
        };
        if target.is_some() {
            p.stencil.record(
                encoder,
                bindings,
                VolumeDraws::Vertices {
                    vertices: &data.volume,
                    ranges: &data.volume_ranges,
                },
                timer.pass(
                    Pass::Stencil,
                    Traffic::new().reads(&data.volume).updates(&gbuffer.depth),
                ),
            );
        }
        if target.is_some() {
            let inputs = ReceiverInputs {
                frame: parts.frame,
                params: &frame.params,
                triangles: (&data.triangles, data.triangle_count),
            };
            frame.receivers.record(encoder, (device, p), inputs, timer);
        }
        let group = frame.inputs(device, p, data, gbuffer, &frame.receivers.candidates());
        encoder.clear_buffer(&frame.demand, 0, None);
        p.edge_lists.record(
            encoder,
            (parts.frame, &group),
            (tx, ty),
            timer.pass(Pass::EdgeLists, frame.edge_list_traffic(data, gbuffer)),
        );
        frame.pending = true;
        let Some(target) = target else {
            encoder.copy_buffer_to_buffer(&frame.demand, 0, &frame.demand_readback, 0, 16);
            return Ok(());
        };
        let args = bind_group(
            device,
            "count arguments",
            &p.count.args_layout,
            &[frame.args.as_entire_binding()],
        );
        p.count.record(
            encoder,
            (parts.frame, &group, &args),
            (&frame.args, frame.chunks),
            (size, frame.band_rows),
            timer.pass(Pass::Count, frame.count_traffic(data, gbuffer)),
        );
        encoder.copy_buffer_to_buffer(&frame.demand, 0, &frame.demand_readback, 0, 16);
        let v = bind_group(
            device,
            "visibility buffer",
            &p.resolve.final_layout,
            &[wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: &frame.visibility,
                offset: 0,
                size: wgpu::BufferSize::new(4 * size.0 as u64 * size.1 as u64),
            })],
        );
        p.resolve.record(
            encoder,
            bindings,
            ResolveInput::Visibility(&v),
            target,
            timer.pass(
                Pass::Resolve,
                gbuffer
                    .receivers_read()
                    .reads(&frame.visibility)
                    .writes(target),
            ),
        );
        Ok(())
    }
}
