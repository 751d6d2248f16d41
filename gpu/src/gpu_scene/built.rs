//! The shadows a [`super::GpuScene`] builds on the GPU (`passes::build`): the meshes' vertices
//! and topology, uploaded once (the vertices again only when the application moves them), and
//! the buffers the build writes every frame the light or a mesh moved.

use penumbra_geom::HalfEdgeMesh;

use super::meshes::StoredMesh;
use crate::passes::buffer;
use crate::passes::build::{BuildBuffers, BuildGroups, BuildPass, SIDE_BYTES, workgroups};
use crate::passes::stencil::StencilPass;
use crate::passes::wedge::WedgeInstance;
use crate::passes::wedge_tiles::two_parts;

/// A face's mesh is closed (`CLOSED_MESH` in `build.wgsl`).
const CLOSED_MESH: u32 = 0x8000_0000;

/// The most faces an edge may have, and the most meshes, in the build's packing.
const PACKED: usize = 1 << 16;

/// The meshes' topology and the build's outputs on the GPU.
pub(super) struct Built {
    /// The meshes' stored vertices, every mesh's after the one before it, and where each
    /// mesh's begin.
    pub(super) positions: wgpu::Buffer,
    pub(super) first_vertex: Vec<u32>,
    /// The receivers' box, zeroed before each build.
    pub(super) bounds: wgpu::Buffer,
    /// The wedge instances (a vertex buffer of [`WedgeInstance`]s) and the draws' arguments
    /// (side quads at 0, wedges at 16).
    pub(super) wedges: wgpu::Buffer,
    pub(super) args: wgpu::Buffer,
    /// Room for this many wedges (the edges), and a buffer of one instance that stands for the
    /// second part of their binding where the first holds them all.
    pub(super) wedge_capacity: u64,
    pub(super) spare: wgpu::Buffer,
    /// The build's bind groups, the stencil pass's group of the built volumes and the frame's
    /// group as the build binds it.
    pub(super) groups: BuildGroups,
    pub(super) stencil_group: wgpu::BindGroup,
    pub(super) frame_group: wgpu::BindGroup,
    pub(super) faces: u32,
    /// Bytes written when it was made.
    pub(super) uploaded: u64,
    /// Bytes the stencil pass binds: the vertices, faces, casters and side quads.
    volume_bytes: u64,
    /// Bytes the build binds for reading (the vertices and topology) and for writing (the
    /// rest, whole).
    pub(super) build_bytes: (u64, u64),
}

/// Why a scene's shadows are built on the CPU.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum TooLarge {
    /// More meshes, or more faces on one edge, than the build packs.
    Packing,
    /// A buffer larger than the device binds.
    Binding,
}

impl Built {
    /// The topology of `meshes` uploaded and the build's buffers made, with `corners` (the
    /// depth pre-pass's vertices, which the build rewrites when a mesh's vertices move) and the
    /// frame's `uniforms` and `models`.
    pub(super) fn new(
        device: &wgpu::Device,
        (build, stencil): (&BuildPass, &StencilPass),
        meshes: &[StoredMesh],
        corners: &wgpu::Buffer,
        (uniforms, models): (&wgpu::Buffer, &wgpu::Buffer),
    ) -> Result<Self, TooLarge> {
        if meshes.len() >= PACKED {
            return Err(TooLarge::Packing);
        }
        let mut positions: Vec<[f32; 3]> = Vec::new();
        let mut first_vertex = Vec::with_capacity(meshes.len());
        let mut faces: Vec<[u32; 4]> = Vec::new();
        let mut edges: Vec<[u32; 4]> = Vec::new();
        let mut incidences: Vec<u32> = Vec::new();
        for (mi, m) in meshes.iter().enumerate() {
            let base = positions.len() as u32;
            let first_face = faces.len() as u32;
            first_vertex.push(base);
            positions.extend(&m.stored);
            let he = HalfEdgeMesh::build(&m.mesh);
            let closed = if he.is_closed() { CLOSED_MESH } else { 0 };
            faces.extend(
                m.mesh
                    .triangles
                    .iter()
                    .map(|t| [t[0] + base, t[1] + base, t[2] + base, mi as u32 | closed]),
            );
            for e in &he.edges {
                if e.half_edges.len() >= PACKED {
                    return Err(TooLarge::Packing);
                }
                let first = incidences.len() as u32;
                for &h in &e.half_edges {
                    let runs_forward = he.half_edges[h as usize].origin == e.vertices[0];
                    incidences
                        .push(((first_face + HalfEdgeMesh::face(h)) << 1) | runs_forward as u32);
                }
                let [u, v] = e.vertices;
                edges.push([
                    u + base,
                    v + base,
                    first,
                    e.half_edges.len() as u32 | ((mi as u32) << 16),
                ]);
            }
        }
        let limits = device.limits();
        let (face_count, edge_count) = (faces.len() as u64, edges.len() as u64);
        let instance = std::mem::size_of::<WedgeInstance>() as u64;
        let wedge_bytes = edge_count.max(1) * instance;
        let side_bytes = (incidences.len() as u64).max(1) * SIDE_BYTES;
        let binding = limits.max_storage_buffer_binding_size;
        // The wedges are bound in two parts (`wedges` and `wedges_more` in `build.wgsl`,
        // `two_parts`).
        let bound = side_bytes.max(12 * 3 * face_count);
        if bound > binding || wedge_bytes > limits.max_buffer_size {
            return Err(TooLarge::Binding);
        }
        let storage = wgpu::BufferUsages::STORAGE;
        let copy = wgpu::BufferUsages::COPY_DST;
        let nonempty = |v: &mut Vec<[u32; 4]>| {
            if v.is_empty() {
                v.push([0; 4]);
            }
        };
        let uploaded = (std::mem::size_of_val(positions.as_slice())
            + std::mem::size_of_val(faces.as_slice())
            + std::mem::size_of_val(edges.as_slice())
            + std::mem::size_of_val(incidences.as_slice())) as u64;
        if positions.is_empty() {
            positions.push([0.0; 3]);
        }
        if incidences.is_empty() {
            incidences.push(0);
        }
        let (mut faces_data, mut edges_data) = (faces, edges);
        nonempty(&mut faces_data);
        nonempty(&mut edges_data);
        let empty = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(16),
                usage,
                mapped_at_creation: false,
            })
        };
        let positions_buf = buffer(device, "built positions", &positions, storage | copy);
        let faces_buf = buffer(device, "built faces", &faces_data, storage);
        let edges_buf = buffer(device, "built edges", &edges_data, storage);
        let incidences_buf = buffer(device, "built incidences", &incidences, storage);
        let caster_sign = empty("caster signs", 4 * face_count, storage);
        let bounds = empty("receivers' box", 24, storage | copy);
        let edge_counts = empty("edge counts", 4 * edge_count, storage);
        let (x, y) = workgroups(edge_count as u32);
        let blocks = empty("edge blocks", 8 * u64::from(x * y), storage);
        let sides = empty("side quads", side_bytes, storage);
        let wedges = empty(
            "built wedges",
            wedge_bytes,
            storage | wgpu::BufferUsages::VERTEX,
        );
        let args = empty("build draws", 32, storage | wgpu::BufferUsages::INDIRECT);
        let spare = empty("no more wedges", instance, storage);
        let [first_wedges, more_wedges] =
            two_parts(&wedges, edge_count, &spare, binding).ok_or(TooLarge::Binding)?;
        fn whole(buffer: &wgpu::Buffer) -> wgpu::BufferBinding<'_> {
            wgpu::BufferBinding {
                buffer,
                offset: 0,
                size: None,
            }
        }
        let slots = [
            whole(&positions_buf),
            whole(&faces_buf),
            whole(&edges_buf),
            whole(&incidences_buf),
            whole(&caster_sign),
            whole(&bounds),
            whole(&edge_counts),
            whole(&blocks),
            whole(&sides),
            first_wedges,
            whole(&args),
            whole(corners),
            more_wedges,
        ];
        let groups = build.groups(
            device,
            &BuildBuffers {
                slots,
                faces: face_count as u32,
                edges: edge_count as u32,
            },
        );
        fn entry(binding: u32, b: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry {
                binding,
                resource: b.as_entire_binding(),
            }
        }
        let stencil_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("built volumes"),
            layout: &stencil.built_layout,
            entries: &[
                entry(0, &positions_buf),
                entry(1, &faces_buf),
                entry(4, &caster_sign),
                entry(8, &sides),
            ],
        });
        let frame_group =
            crate::frame_uniforms::frame_group(device, &build.frame_layout, uniforms, models);
        let size = |b: &[&wgpu::Buffer]| b.iter().map(|b| b.size()).sum::<u64>();
        let build_bytes = (
            size(&[&positions_buf, &faces_buf, &edges_buf, &incidences_buf]),
            size(&[
                &caster_sign,
                &bounds,
                &edge_counts,
                &blocks,
                &sides,
                &wedges,
                &args,
            ]),
        );
        let volume_bytes =
            positions_buf.size() + faces_buf.size() + caster_sign.size() + sides.size();
        Ok(Built {
            positions: positions_buf,
            first_vertex,
            bounds,
            wedges,
            args,
            wedge_capacity: edge_count,
            spare,
            groups,
            stencil_group,
            frame_group,
            faces: face_count as u32,
            uploaded,
            volume_bytes,
            build_bytes,
        })
    }

    /// Bytes the stencil pass binds.
    pub(super) fn volume_bytes(&self) -> u64 {
        self.volume_bytes
    }
}
