//! Depth-complexity sampling on the GPU (Forest, Barthe & Paulin, "Accurate Shadows by Depth
//! Complexity Sampling", 2008), recorded by a [`GpuScene`]: exact soft shadows, equal to the CPU
//! oracle (`penumbra_volumes::DepthComplexity`) sample for sample up to `f32` rounding.
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
//! [`GpuScene::complexity_report`] reads the demand back after the frame and grows the list.

use std::ops::Range;

use penumbra_geom::{HalfEdgeMesh, Technique};
use penumbra_volumes::PotentialEdges;
use penumbra_volumes::Silhouette;
use penumbra_volumes::{ShadowVolume, VolumeVertex};

use crate::constants::{COUNT_GROUP, MAX_AXIS, TILE};
use crate::context::GpuError;
use crate::gpu_scene::{FrameInputs, GpuScene};
use crate::passes::complexity::{ComplexityParams, gpu_edges, light_triangles, neighbours};
use crate::passes::depth::GBuffer;
use crate::passes::resolve::ResolveInput;
use crate::passes::{FrameBindings, bind_group, buffer};
use crate::timing::{Pass, Timer};

/// Light samples per axis of a new [`GpuScene`] (256 samples per pixel).
pub const DEFAULT_AXIS: u32 = 16;

/// Entries of the edge list per tile of a new [`GpuScene`], before any frame told how many it
/// needs.
pub const FIRST_ENTRIES_PER_TILE: u32 = 64;

/// What depth-complexity sampling keeps of a scene for the current light and transforms.
pub(crate) struct ComplexityScene {
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
    /// Potential silhouette edges, and all edges, for reports.
    pub(crate) potential: usize,
    pub(crate) all_edges: usize,
}

/// The per-frame buffers of depth-complexity sampling at one image size and list capacity.
pub(crate) struct ComplexityFrame {
    size: (u32, u32),
    capacity: u32,
    tile_ranges: wgpu::Buffer,
    list: wgpu::Buffer,
    demand: wgpu::Buffer,
    demand_readback: wgpu::Buffer,
    params: wgpu::Buffer,
    visibility: wgpu::Buffer,
    /// Whether the last recorded frame's report awaits [`GpuScene::complexity_report`].
    pending: bool,
}

/// Tiles per row and rows of tiles of an image of `size` pixels.
fn tiles((w, h): (u32, u32)) -> (u32, u32) {
    (w.div_ceil(TILE), h.div_ceil(TILE))
}

/// Bytes of the buffers of a frame of `size` pixels with an edge list of `capacity` entries: V
/// (4 per pixel), a range per tile (8), the list (4 per entry), the frame's report and its
/// readback (16).
pub fn frame_bytes(size: (u32, u32), capacity: u32) -> u64 {
    let (tx, ty) = tiles(size);
    4 * size.0 as u64 * size.1 as u64 + 8 * (tx * ty) as u64 + 4 * capacity as u64 + 16
}

/// Loop iterations an invocation of the counting pass may take on a software device before its
/// pixel counts as cut short. Mesa's llvmpipe (lavapipe) ends every loop of an invocation once
/// they have run 65,535 iterations in all (`LP_MAX_TGSI_LOOP_ITERATIONS`), silently; the
/// counting pass counts its loops' iterations (an upper bound of llvmpipe's count, which does
/// not see the loops its compiler unrolls) and reports the pixels that may have reached that
/// limit ([`ComplexityReport::cut_short`]).
pub const SOFTWARE_LOOP_BUDGET: u32 = 65_000;

/// A depth-complexity image rendered once ([`crate::GpuRenderer::render_depth_complexity`]).
pub struct ComplexityImage {
    /// V.
    pub image: penumbra_geom::VisibilityImage,
    /// The GPU time of each pass, where the device has timestamp queries.
    pub times: Option<crate::PassTimes>,
    /// Potential silhouette edges of the scene's light.
    pub potential_edges: usize,
    /// All edges of the scene's meshes.
    pub all_edges: usize,
    /// Entries of the edge list the frame needed (`(tile, edge)` pairs), and the list's size.
    pub list_entries: u32,
    /// Entries the list held.
    pub list_capacity: u32,
}

/// What a depth-complexity frame reports once it has run ([`GpuScene::complexity_report`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ComplexityReport {
    /// Entries the frame's edge list needed.
    pub demand: u32,
    /// Whether that was more than it held: the tiles that did not fit read every edge (the
    /// image is the same, only slower) and the list has grown for the next frames.
    pub overflowed: bool,
    /// Pixels whose counting took more loop iterations than a software device runs (see
    /// [`SOFTWARE_LOOP_BUDGET`]): their V may be wrong. Always 0 on a hardware GPU.
    pub cut_short: u32,
}

impl ComplexityScene {
    fn build(scene: &GpuScene) -> (Self, u64) {
        let device = &scene.ctx.device;
        let (meshes, world) = scene.world();
        let c = scene.light.center;
        let mut vol: Vec<[f32; 4]> = Vec::new();
        let mut volume_ranges = Vec::with_capacity(meshes.len());
        let half_edge: Vec<HalfEdgeMesh> = meshes.iter().map(HalfEdgeMesh::build).collect();
        let triangles = light_triangles(&scene.light, &world, &neighbours(&half_edge));
        for (mi, (mesh, stored)) in half_edge.iter().zip(&scene.meshes).enumerate() {
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
        let potential = PotentialEdges::build_half_edge(&half_edge, &scene.light);
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
            potential: potential.edges.len(),
            all_edges: potential.all_edges,
        };
        (data, bytes as u64)
    }
}

impl ComplexityFrame {
    fn new(device: &wgpu::Device, size: (u32, u32), capacity: u32) -> Self {
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
            tile_ranges: make("tile ranges", 8 * (tx * ty) as u64, storage),
            list: make("edge list", 4 * capacity as u64, storage),
            demand: make("depth-complexity report", 8, storage | copy),
            demand_readback: make(
                "depth-complexity report readback",
                8,
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            ),
            params: make(
                "depth-complexity params",
                std::mem::size_of::<ComplexityParams>() as u64,
                wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            ),
            visibility: make("visibility", 4 * size.0 as u64 * size.1 as u64, storage),
            pending: false,
        }
    }
}

impl GpuScene {
    /// Light samples per pixel of depth-complexity sampling (`N x N`).
    pub fn light_samples(&self) -> u32 {
        self.samples_per_axis * self.samples_per_axis
    }

    /// Takes `samples` light samples per pixel in depth-complexity sampling from the next frame
    /// on: a perfect square up to [`crate::constants::MAX_SAMPLES`] (1024), in the correlated
    /// multi-jittered pattern of the CPU oracle (`penumbra_volumes::SamplePattern`).
    pub fn set_light_samples(&mut self, samples: u32) -> Result<(), GpuError> {
        let n = (samples as f64).sqrt().round() as u32;
        if samples == 0 || n * n != samples || n > MAX_AXIS {
            return Err(GpuError::Frame(format!(
                "{samples} light samples: depth-complexity sampling on the GPU takes a perfect \
                 square up to {} (the CPU takes up to 65536)",
                MAX_AXIS * MAX_AXIS
            )));
        }
        self.samples_per_axis = n;
        Ok(())
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
        self.record_complexity(encoder, inputs, gbuffer, None, &Timer::disabled())
    }

    /// Entries the depth-complexity edge list holds; 0 until the first frame sized it
    /// ([`FIRST_ENTRIES_PER_TILE`] per tile).
    pub fn edge_list_capacity(&self) -> u32 {
        self.list_capacity
    }

    /// Makes the depth-complexity edge list hold `entries` from the next frame on. Frames grow
    /// it as they need ([`GpuScene::complexity_report`]); this sets where it starts.
    pub fn set_edge_list_capacity(&mut self, entries: u32) {
        self.list_capacity = entries.max(1);
    }

    /// Potential silhouette edges of the current light and transforms and all edges of the
    /// meshes; `(0, 0)` until a depth-complexity frame needed them.
    pub fn potential_edges(&self) -> (usize, usize) {
        self.complexity
            .as_ref()
            .map_or((0, 0), |c| (c.potential, c.all_edges))
    }

    /// After the last depth-complexity frame was submitted: waits for it and reads its report,
    /// growing the edge list to what the frame needed when it overflowed (a quarter more, so
    /// that a frame that needs a little more does not overflow again). `None` when no
    /// depth-complexity frame was recorded since the last call.
    pub fn complexity_report(&mut self) -> Result<Option<ComplexityReport>, GpuError> {
        let Some(frame) = self.complexity_frame.as_mut().filter(|f| f.pending) else {
            return Ok(None);
        };
        frame.pending = false;
        let bytes = crate::readback::map_read(&self.ctx, &frame.demand_readback)?;
        let word = |k: usize| u32::from_le_bytes(bytes[4 * k..4 * k + 4].try_into().expect("4"));
        let report = ComplexityReport {
            demand: word(0),
            overflowed: word(0) > frame.capacity,
            cut_short: word(1),
        };
        if report.overflowed {
            self.list_capacity = report.demand.saturating_add(report.demand / 4);
        }
        Ok(Some(report))
    }

    /// The loop iterations an invocation of the counting pass may take before its pixel is
    /// reported as cut short: [`SOFTWARE_LOOP_BUDGET`] on a CPU adapter (llvmpipe), unlimited
    /// on a GPU.
    pub fn loop_budget(&self) -> u32 {
        self.loop_budget
    }

    /// Sets [`GpuScene::loop_budget`] (for a software device with another limit).
    pub fn set_loop_budget(&mut self, iterations: u32) {
        self.loop_budget = iterations;
    }

    /// Records the passes of depth-complexity sampling (the module's documentation lists them);
    /// without a target, only the edge lists, for [`GpuScene::complexity_report`] to size the
    /// list.
    pub(crate) fn record_complexity(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &FrameInputs,
        gbuffer: &GBuffer,
        target: Option<&wgpu::TextureView>,
        timer: &Timer,
    ) -> Result<(), GpuError> {
        debug_assert_eq!(inputs.technique, Technique::DepthComplexity);
        let size = inputs.camera.size;
        if self.complexity.is_none() {
            let (data, bytes) = ComplexityScene::build(self);
            self.uploads.shadows += bytes;
            self.complexity = Some(data);
        }
        let (tx, ty) = tiles(size);
        if self.list_capacity == 0 {
            self.list_capacity = (tx * ty).saturating_mul(FIRST_ENTRIES_PER_TILE);
        }
        let device = &self.ctx.device;
        // V and the list are storage buffers: each must fit one binding.
        let limit = device.limits().max_storage_buffer_binding_size;
        let largest = (4 * size.0 as u64 * size.1 as u64).max(4 * self.list_capacity as u64);
        if largest > limit {
            return Err(GpuError::TooLarge(format!(
                "depth-complexity at {} x {} pixels needs a storage buffer of {largest} bytes \
                 (V, or an edge list of {} entries), more than the device binds ({limit})",
                size.0, size.1, self.list_capacity
            )));
        }
        if self
            .complexity_frame
            .as_ref()
            .is_none_or(|f| f.size != size || f.capacity != self.list_capacity)
        {
            self.complexity_frame = Some(ComplexityFrame::new(device, size, self.list_capacity));
        }
        let data = self.complexity.as_ref().expect("built above");
        let frame = self.complexity_frame.as_mut().expect("made above");
        let p = &self.pipelines;
        let mut params = ComplexityParams {
            edges: data.edge_count,
            crossings: data.crossing_count,
            capacity: frame.capacity,
            per_axis: self.samples_per_axis,
            tiles_x: tx,
            triangles: data.triangle_count,
            budget: self.loop_budget,
            ..Default::default()
        };
        params.set_camera(&inputs.camera, &self.light);
        self.ctx
            .queue
            .write_buffer(&frame.params, 0, bytemuck::bytes_of(&params));
        self.uploads.frame += std::mem::size_of::<ComplexityParams>() as u64;
        let position = p.resolve.receivers(device, gbuffer);
        let bindings = FrameBindings {
            frame: &self.frame,
            depth: &gbuffer.depth_view,
            position: &position,
        };
        if target.is_some() {
            p.stencil.record(
                encoder,
                bindings,
                &data.volume,
                &data.volume_ranges,
                timer.render(Pass::Stencil),
            );
        }
        let group = bind_group(
            device,
            "depth-complexity inputs",
            &p.complexity_layout,
            &[
                wgpu::BindingResource::TextureView(&gbuffer.position_view),
                wgpu::BindingResource::TextureView(&gbuffer.stencil_view),
                data.edges.as_entire_binding(),
                data.faces.as_entire_binding(),
                data.crossings.as_entire_binding(),
                frame.tile_ranges.as_entire_binding(),
                frame.list.as_entire_binding(),
                frame.demand.as_entire_binding(),
                frame.params.as_entire_binding(),
                frame.visibility.as_entire_binding(),
                data.triangles.as_entire_binding(),
            ],
        );
        encoder.clear_buffer(&frame.demand, 0, None);
        p.edge_lists.record(
            encoder,
            (&self.frame, &group),
            (tx, ty),
            timer.compute(Pass::EdgeLists),
        );
        frame.pending = true;
        let Some(target) = target else {
            encoder.copy_buffer_to_buffer(&frame.demand, 0, &frame.demand_readback, 0, 8);
            return Ok(());
        };
        p.count.record(
            encoder,
            (&self.frame, &group),
            (size.0.div_ceil(COUNT_GROUP), size.1.div_ceil(COUNT_GROUP)),
            timer.compute(Pass::Count),
        );
        encoder.copy_buffer_to_buffer(&frame.demand, 0, &frame.demand_readback, 0, 8);
        let v = bind_group(
            device,
            "visibility buffer",
            &p.resolve.final_layout,
            &[frame.visibility.as_entire_binding()],
        );
        p.resolve.record(
            encoder,
            bindings,
            ResolveInput::Visibility(&v),
            target,
            timer.render(Pass::Resolve),
        );
        Ok(())
    }
}
