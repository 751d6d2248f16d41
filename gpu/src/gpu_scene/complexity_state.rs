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
//! light and transforms, the frame's buffers, and its settings.

use crate::counters::{Pass, Traffic};
use std::ops::Range;

use penumbra_geom::{HalfEdgeMesh, RectLight, Warp};
use penumbra_volumes::PotentialEdges;
use penumbra_volumes::Silhouette;
use penumbra_volumes::{ShadowVolume, VolumeVertex};

use super::complexity::{ComplexityReport, SOFTWARE_LOOP_BUDGET};
use super::complexity_receivers::{ReceiverInputs, ReceiverTargets};
use super::meshes::{StoredMesh, world};
use super::uploads::Uploads;
use crate::constants::{COUNT_GROUP, MAX_AXIS, TILE};
use crate::context::{GpuContext, GpuError};
use crate::frame::FrameCamera;
use crate::passes::complexity::{ComplexityParams, gpu_edges, light_triangles, neighbours};
use crate::passes::count::{
    band_rows, chunks, count_bytes, edges_per_dispatch, storage_binding_limit,
};
use crate::passes::depth::GBuffer;
use crate::passes::resolve::ResolveInput;
use crate::passes::{FrameBindings, bind_group, buffer};
use crate::pipelines::Pipelines;
use crate::timing::Timer;

/// Light samples per axis of a new scene (256 samples per pixel).
const DEFAULT_AXIS: u32 = 16;

/// Entries of the edge list per tile of a new scene, before any frame told how many it needs.
const FIRST_ENTRIES_PER_TILE: u32 = 64;

/// What depth-complexity sampling keeps of a scene for the current light and transforms.
pub(super) struct ComplexityScene {
    /// The open-rule shadow volumes' vertices (as `scene_data::volume_vertices`) and each mesh's
    /// range.
    volume: wgpu::Buffer,
    volume_ranges: Vec<(u32, Range<u32>)>,
    edges: wgpu::Buffer,
    faces: wgpu::Buffer,
    crossings: wgpu::Buffer,
    triangles: wgpu::Buffer,
    edge_count: u32,
    crossing_count: u32,
    triangle_count: u32,
    /// Most faces on one potential edge (the counting pass's work per edge grows with it).
    max_faces: u32,
    /// Potential silhouette edges, and all edges, for reports.
    pub(super) potential: usize,
    pub(super) all_edges: usize,
}

/// The per-frame buffers of depth-complexity sampling at one image size and list capacity.
pub(super) struct ComplexityFrame {
    size: (u32, u32),
    capacity: u32,
    /// Samples per axis and dispatches of the counting pass the buffers are made for.
    per_axis: u32,
    chunks: u32,
    /// Rows whose state and counts the counting pass keeps at once.
    band_rows: u32,
    tile_ranges: wgpu::Buffer,
    list: wgpu::Buffer,
    demand: wgpu::Buffer,
    demand_readback: wgpu::Buffer,
    params: wgpu::Buffer,
    /// V, then each pixel's state and counts between the counting pass's dispatches.
    visibility: wgpu::Buffer,
    /// The indirect arguments of the counting pass's chunk dispatches.
    args: wgpu::Buffer,
    /// What the receivers' checks draw (`super::complexity_receivers`).
    receivers: ReceiverTargets,
    /// Whether the last recorded frame's report awaits [`ComplexityState::report`].
    pending: bool,
}

/// Tiles per row and rows of tiles of an image of `size` pixels.
fn tiles((w, h): (u32, u32)) -> (u32, u32) {
    (w.div_ceil(TILE), h.div_ceil(TILE))
}

impl ComplexityScene {
    /// Builds and uploads what the passes read of `meshes` lit by `light`; and the bytes
    /// uploaded.
    fn build(
        device: &wgpu::Device,
        meshes: &[StoredMesh],
        light: &RectLight,
        warp: Option<&Warp>,
    ) -> (Self, u64) {
        let stored = meshes;
        let (meshes, world) = world(stored, warp);
        let c = light.center;
        let mut vol: Vec<[f32; 4]> = Vec::new();
        let mut volume_ranges = Vec::with_capacity(meshes.len());
        let half_edge: Vec<HalfEdgeMesh> = meshes.iter().map(HalfEdgeMesh::build).collect();
        let triangles = light_triangles(light, &world, &neighbours(&half_edge));
        for (mi, (mesh, stored)) in half_edge.iter().zip(stored).enumerate() {
            // Every triangle casts, facing the centre either way: the stencil then counts each
            // triangle the segment to the centre crosses.
            let sil = Silhouette::build_as(mesh, c, false);
            let volume = ShadowVolume::build(mesh, &sil, c);
            let start = vol.len() as u32;
            for (t, _) in &volume.triangles {
                vol.extend(t.iter().map(|&v| {
                    match v {
                        VolumeVertex::Finite(i) => {
                            let [x, y, z] = stored.stored[i as usize];
                            [x, y, z, 1.0]
                        }
                        VolumeVertex::Infinite(i) => (mesh.positions[i as usize] - c)
                            .as_vec3()
                            .extend(0.0)
                            .to_array(),
                    }
                }));
            }
            volume_ranges.push((mi as u32, start..vol.len() as u32));
        }
        let potential = PotentialEdges::build_half_edge(&half_edge, light);
        let (edges, faces, crossings) = gpu_edges(&potential);
        let storage = wgpu::BufferUsages::STORAGE;
        let bytes = std::mem::size_of_val(vol.as_slice())
            + std::mem::size_of_val(edges.as_slice())
            + std::mem::size_of_val(faces.as_slice())
            + std::mem::size_of_val(crossings.as_slice())
            + std::mem::size_of_val(triangles.as_slice());
        let data = ComplexityScene {
            volume: buffer(device, "open volumes", &vol, wgpu::BufferUsages::VERTEX),
            volume_ranges,
            edges: buffer(device, "potential edges", &edges, storage),
            faces: buffer(device, "edge faces", &faces, storage),
            crossings: buffer(device, "light crossings", &crossings, storage),
            triangles: buffer(device, "light-space triangles", &triangles, storage),
            edge_count: edges.len() as u32,
            crossing_count: crossings.len() as u32,
            triangle_count: triangles.len() as u32,
            max_faces: potential
                .edges
                .iter()
                .map(|e| e.face_count)
                .max()
                .unwrap_or(0),
            potential: potential.edges.len(),
            all_edges: potential.all_edges,
        };
        (data, bytes as u64)
    }
}

impl ComplexityFrame {
    /// What the edge-list pass binds: it reads the receivers' positions, the edges, faces and
    /// parameters, and writes the tiles' ranges, the list and its demand.
    fn edge_list_traffic(&self, data: &ComplexityScene, gbuffer: &GBuffer) -> Traffic {
        Traffic::new()
            .reads(&gbuffer.position)
            .reads(&data.edges)
            .reads(&data.faces)
            .reads(&self.params)
            .writes(&self.tile_ranges)
            .writes(&self.list)
            .updates(&self.demand)
    }

    /// What the counting pass binds: it reads the receivers, their stencil counts, the
    /// edges, faces, crossings, triangles, the tiles' lists, the parameters and its dispatches'
    /// arguments, and updates V with each pixel's state and counts between dispatches.
    fn count_traffic(&self, data: &ComplexityScene, gbuffer: &GBuffer) -> Traffic {
        Traffic::new()
            .reads(&gbuffer.position)
            .reads(&gbuffer.depth)
            .reads(&data.edges)
            .reads(&data.faces)
            .reads(&data.crossings)
            .reads(&data.triangles)
            .reads(&self.tile_ranges)
            .reads(&self.list)
            .reads(&self.params)
            .reads(&self.args)
            .updates(&self.demand)
            .updates(&self.visibility)
    }

    fn new(
        device: &wgpu::Device,
        size: (u32, u32),
        capacity: u32,
        (per_axis, chunks, band_rows): (u32, u32, u32),
    ) -> Self {
        let (tx, ty) = tiles(size);
        let make = |label, bytes: u64, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes.max(4),
                usage,
                mapped_at_creation: false,
            })
        };
        let storage = wgpu::BufferUsages::STORAGE;
        let copy = wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC;
        ComplexityFrame {
            size,
            capacity,
            per_axis,
            chunks,
            band_rows,
            tile_ranges: make("tile ranges", 8 * (tx * ty) as u64, storage),
            list: make("edge list", 4 * capacity as u64, storage),
            demand: make("depth-complexity report", 32, storage | copy),
            demand_readback: make(
                "depth-complexity report readback",
                16,
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            ),
            params: make(
                "depth-complexity params",
                std::mem::size_of::<ComplexityParams>() as u64,
                wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            ),
            visibility: make(
                "visibility",
                count_bytes(size, per_axis, band_rows),
                storage,
            ),
            args: make(
                "count arguments",
                12 * chunks as u64,
                storage | wgpu::BufferUsages::INDIRECT,
            ),
            receivers: ReceiverTargets::new(device, size),
            pending: false,
        }
    }
}

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
                &data.volume,
                &data.volume_ranges,
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

impl ComplexityFrame {
    /// Group 1 of both compute passes (`passes::complexity::inputs_layout`).
    fn inputs(
        &self,
        device: &wgpu::Device,
        p: &Pipelines,
        data: &ComplexityScene,
        gbuffer: &GBuffer,
        candidate: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        bind_group(
            device,
            "depth-complexity inputs",
            &p.complexity_layout,
            &[
                wgpu::BindingResource::TextureView(&gbuffer.position_view),
                wgpu::BindingResource::TextureView(&gbuffer.stencil_view),
                data.edges.as_entire_binding(),
                data.faces.as_entire_binding(),
                data.crossings.as_entire_binding(),
                self.tile_ranges.as_entire_binding(),
                self.list.as_entire_binding(),
                self.demand.as_entire_binding(),
                self.params.as_entire_binding(),
                self.visibility.as_entire_binding(),
                data.triangles.as_entire_binding(),
                wgpu::BindingResource::TextureView(candidate),
            ],
        )
    }
}
