//! The buffers of depth-complexity sampling (`super::complexity_state` records the passes that
//! read them): what it builds of a scene for the current light and transforms (the open-rule
//! shadow volumes, the potential silhouette edges and their faces, the triangles through the
//! light's plane), and each frame's buffers at one image size and list capacity (the tiles'
//! ranges, the edge list, the report, the counting pass's state and counts).

use std::ops::Range;

use penumbra_geom::{HalfEdgeMesh, RectLight, Warp};
use penumbra_volumes::PotentialEdges;
use penumbra_volumes::Silhouette;
use penumbra_volumes::{ShadowVolume, VolumeVertex};

use super::complexity_receivers::ReceiverTargets;
use super::meshes::{StoredMesh, world};
use crate::constants::TILE;
use crate::counters::Traffic;
use crate::passes::complexity::{ComplexityParams, gpu_edges, light_triangles, neighbours};
use crate::passes::count::count_bytes;
use crate::passes::depth::GBuffer;
use crate::passes::{bind_group, buffer};
use crate::pipelines::Pipelines;

/// What depth-complexity sampling keeps of a scene for the current light and transforms.
pub(super) struct ComplexityScene {
    /// The open-rule shadow volumes' vertices (as `scene_data::volume_vertices`) and each mesh's
    /// range.
    pub(super) volume: wgpu::Buffer,
    pub(super) volume_ranges: Vec<(u32, Range<u32>)>,
    edges: wgpu::Buffer,
    faces: wgpu::Buffer,
    crossings: wgpu::Buffer,
    pub(super) triangles: wgpu::Buffer,
    pub(super) edge_count: u32,
    pub(super) crossing_count: u32,
    pub(super) triangle_count: u32,
    /// Whether a closed mesh winds around the lamp (a room lit from inside): its walls are
    /// casters over their own receivers in the open-rule volumes, and every pixel is counted
    /// again (`ComplexityParams::recount_all`).
    pub(super) room: bool,
    /// Most faces on one potential edge (the counting pass's work per edge grows with it).
    pub(super) max_faces: u32,
    /// Potential silhouette edges, and all edges, for reports.
    pub(super) potential: usize,
    pub(super) all_edges: usize,
}

/// The per-frame buffers of depth-complexity sampling at one image size and list capacity.
pub(super) struct ComplexityFrame {
    pub(super) size: (u32, u32),
    pub(super) capacity: u32,
    /// Samples per axis and dispatches of the counting pass the buffers are made for.
    pub(super) per_axis: u32,
    pub(super) chunks: u32,
    /// Rows whose state and counts the counting pass keeps at once.
    pub(super) band_rows: u32,
    tile_ranges: wgpu::Buffer,
    list: wgpu::Buffer,
    pub(super) demand: wgpu::Buffer,
    pub(super) demand_readback: wgpu::Buffer,
    pub(super) params: wgpu::Buffer,
    /// V, then each pixel's state and counts between the counting pass's dispatches.
    pub(super) visibility: wgpu::Buffer,
    /// The indirect arguments of the counting pass's chunk dispatches.
    pub(super) args: wgpu::Buffer,
    /// What the receivers' checks draw (`super::complexity_receivers`).
    pub(super) receivers: ReceiverTargets,
    /// Whether the last recorded frame's report awaits [`ComplexityState::report`](super::complexity_state::ComplexityState::report).
    pub(super) pending: bool,
}

/// Tiles per row and rows of tiles of an image of `size` pixels.
pub(super) fn tiles((w, h): (u32, u32)) -> (u32, u32) {
    (w.div_ceil(TILE), h.div_ceil(TILE))
}

impl ComplexityScene {
    /// Builds and uploads what the passes read of `meshes` lit by `light`; and the bytes
    /// uploaded.
    pub(super) fn build(
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
        let lamp = penumbra_volumes::in_front_of(light);
        let room = warp.is_none()
            && half_edge.iter().any(|m| {
                m.is_closed()
                    && penumbra_volumes::winds_around(
                        m.faces.iter().map(|f| f.map(|v| m.positions[v as usize])),
                        lamp,
                    )
            });
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
            room,
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
    pub(super) fn edge_list_traffic(&self, data: &ComplexityScene, gbuffer: &GBuffer) -> Traffic {
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
    pub(super) fn count_traffic(&self, data: &ComplexityScene, gbuffer: &GBuffer) -> Traffic {
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

    /// The buffers of a frame of `size` pixels whose edge list holds `capacity` entries, for
    /// `per_axis` samples per axis, `chunks` dispatches of the counting pass and bands of
    /// `band_rows` rows.
    pub(super) fn new(
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

    /// Group 1 of both compute passes (`passes::complexity::inputs_layout`).
    pub(super) fn inputs(
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
