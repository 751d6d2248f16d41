//! The shadows' build pass (`shaders/build.wgsl`): silhouettes, shadow volumes and wedges from
//! the meshes' vertices as they are on the GPU, for the frame's light, in four compute
//! dispatches (faces, edges, the prefix sum over blocks of edges, the edges' output), and the
//! meshes' corners rewritten after their vertices moved.

use crate::timing::PassQueries;

/// Invocations per workgroup of every dispatch (`BUILD_GROUP` in the shader).
pub const BUILD_GROUP: u32 = 256;

/// A prefix sum over a workgroup of 256 invocations (`shaders/workgroup_scan.wgsl`), prepended
/// to the passes that compact their output in order: the build and the tiled wedges.
pub const WORKGROUP_SCAN_WGSL: &str = include_str!("../shaders/workgroup_scan.wgsl");

// The scan's workgroup is the build's and the tiled wedges' (`SCAN_GROUP` in the shader).
const _: () = assert!(BUILD_GROUP == 256 && crate::constants::WEDGE_TILE.pow(2) == BUILD_GROUP);

/// Workgroups per row of a dispatch: larger ones take more rows.
const ROW: u32 = 32_768;

/// One side quad as the build writes it and the stencil pass reads it (`Side` in the
/// shaders): the edge's stored ends, and the mesh in `from[3]`.
pub const SIDE_BYTES: u64 = 32;

/// The build's storage buffers, by their bindings in `build.wgsl` (group 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    /// The meshes' stored vertices.
    Positions = 0,
    /// Faces with their mesh.
    Faces = 1,
    /// Undirected edges.
    Edges = 2,
    /// The faces on each edge.
    Incidences = 3,
    /// Per face, how it casts.
    CasterSign = 4,
    /// The receivers' light-space box.
    Bounds = 5,
    /// Per edge, its multiplicity and wedge.
    EdgeCounts = 6,
    /// Per block of edges, its output's first place.
    Blocks = 7,
    /// Side quads.
    Sides = 8,
    /// Wedge instances.
    Wedges = 9,
    /// The draws' arguments.
    Args = 10,
    /// The meshes' triangles' corners.
    Corners = 11,
    /// The wedge instances beyond those [`Slot::Wedges`] binds.
    MoreWedges = 12,
}

/// A dispatch: its entry point and the slots it binds, read only or not.
struct Entry {
    name: &'static str,
    slots: &'static [(Slot, bool)],
}

/// The dispatches' indices in [`ENTRIES`].
const CAST_FACES: usize = 0;
const COUNT_EDGES: usize = 1;
const SCAN_BLOCKS: usize = 2;
const WRITE_EDGES: usize = 3;
const EXPAND_CORNERS: usize = 4;

const ENTRIES: [Entry; 5] = [
    Entry {
        name: "cast_faces",
        slots: &[
            (Slot::Positions, true),
            (Slot::Faces, true),
            (Slot::CasterSign, false),
            (Slot::Bounds, false),
        ],
    },
    Entry {
        name: "count_edges",
        slots: &[
            (Slot::Positions, true),
            (Slot::Edges, true),
            (Slot::Incidences, true),
            (Slot::CasterSign, false),
            (Slot::Bounds, false),
            (Slot::EdgeCounts, false),
            (Slot::Blocks, false),
        ],
    },
    Entry {
        name: "scan_blocks",
        slots: &[(Slot::Blocks, false), (Slot::Args, false)],
    },
    Entry {
        name: "write_edges",
        slots: &[
            (Slot::Positions, true),
            (Slot::Edges, true),
            (Slot::Bounds, false),
            (Slot::EdgeCounts, false),
            (Slot::Blocks, false),
            (Slot::Sides, false),
            (Slot::Wedges, false),
            (Slot::MoreWedges, false),
        ],
    },
    Entry {
        name: "expand_corners",
        slots: &[
            (Slot::Positions, true),
            (Slot::Faces, true),
            (Slot::Corners, false),
        ],
    },
];

/// The build's pipelines, one per dispatch, with the layout of each one's group 1.
pub struct BuildPass {
    pipelines: Vec<(wgpu::ComputePipeline, wgpu::BindGroupLayout)>,
    /// Layout of group 0: the frame's uniforms and model matrices, these visible to the compute
    /// stage ([`super::frame_layout_for`]).
    pub frame_layout: wgpu::BindGroupLayout,
}

/// A layout of storage buffers at the bindings `slots` names, visible to `stages`.
pub fn storage_layout(
    device: &wgpu::Device,
    label: &str,
    stages: wgpu::ShaderStages,
    slots: &[(u32, bool)],
) -> wgpu::BindGroupLayout {
    let entries: Vec<wgpu::BindGroupLayoutEntry> = slots
        .iter()
        .map(|&(binding, read_only)| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: stages,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        })
        .collect();
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &entries,
    })
}

/// The workgroups of a dispatch over `n` items: rows of at most [`ROW`]. The edges' dispatch
/// has one block of `blocks` per workgroup.
pub fn workgroups(n: u32) -> (u32, u32) {
    let groups = n.div_ceil(BUILD_GROUP).max(1);
    if groups <= ROW {
        (groups, 1)
    } else {
        (ROW, groups.div_ceil(ROW))
    }
}

/// The buffers of one scene's build, by slot, and how many faces, edges and corners it has.
pub struct BuildBuffers<'a> {
    /// The buffer (or a range of one) of each [`Slot`], in slot order.
    pub slots: [wgpu::BufferBinding<'a>; 13],
    /// Faces.
    pub faces: u32,
    /// Edges.
    pub edges: u32,
}

/// The bind groups of [`BuildPass::record`], made once per scene.
pub struct BuildGroups {
    groups: Vec<wgpu::BindGroup>,
    faces: u32,
    edges: u32,
}

impl BuildPass {
    /// Builds the pipelines.
    pub fn new(device: &wgpu::Device) -> Self {
        let frame_layout = &super::frame_layout_for(device, wgpu::ShaderStages::COMPUTE);
        let source = format!(
            "{WORKGROUP_SCAN_WGSL}\n{}",
            include_str!("../shaders/build.wgsl")
        );
        let module = super::shader(device, "build", &source);
        let pipelines = ENTRIES
            .iter()
            .map(|e| {
                let slots: Vec<(u32, bool)> =
                    e.slots.iter().map(|&(s, ro)| (s as u32, ro)).collect();
                let group = storage_layout(device, e.name, wgpu::ShaderStages::COMPUTE, &slots);
                let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some(e.name),
                    bind_group_layouts: &[Some(frame_layout), Some(&group)],
                    immediate_size: 0,
                });
                let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(e.name),
                    layout: Some(&layout),
                    module: &module,
                    entry_point: Some(e.name),
                    compilation_options: Default::default(),
                    cache: None,
                });
                (pipeline, group)
            })
            .collect();
        BuildPass {
            pipelines,
            frame_layout: frame_layout.clone(),
        }
    }

    /// The bind groups of `buffers`.
    pub fn groups(&self, device: &wgpu::Device, buffers: &BuildBuffers<'_>) -> BuildGroups {
        let groups = ENTRIES
            .iter()
            .zip(&self.pipelines)
            .map(|(e, (_, layout))| {
                let entries: Vec<wgpu::BindGroupEntry> = e
                    .slots
                    .iter()
                    .map(|&(s, _)| wgpu::BindGroupEntry {
                        binding: s as u32,
                        resource: wgpu::BindingResource::Buffer(buffers.slots[s as usize].clone()),
                    })
                    .collect();
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(e.name),
                    layout,
                    entries: &entries,
                })
            })
            .collect();
        BuildGroups {
            groups,
            faces: buffers.faces,
            edges: buffers.edges,
        }
    }

    /// Records the build, the receivers' box (`bounds`) zeroed first.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::BindGroup,
        groups: &BuildGroups,
        bounds: &wgpu::Buffer,
        queries: PassQueries<'_>,
    ) {
        encoder.clear_buffer(bounds, 0, None);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("build"),
            timestamp_writes: queries.compute_writes(),
        });
        queries.begin_compute(&mut pass);
        pass.set_bind_group(0, frame, &[]);
        self.dispatch(&mut pass, groups, CAST_FACES, workgroups(groups.faces));
        self.dispatch(&mut pass, groups, COUNT_EDGES, workgroups(groups.edges));
        // One workgroup scans every block.
        self.dispatch(&mut pass, groups, SCAN_BLOCKS, (1, 1));
        self.dispatch(&mut pass, groups, WRITE_EDGES, workgroups(groups.edges));
        queries.end_compute(&mut pass);
    }

    /// Records the rewriting of the meshes' corners from their stored vertices (after the
    /// application moved some).
    pub fn record_expand(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::BindGroup,
        groups: &BuildGroups,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("corners"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, frame, &[]);
        self.dispatch(
            &mut pass,
            groups,
            EXPAND_CORNERS,
            workgroups(3 * groups.faces),
        );
    }

    fn dispatch(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        groups: &BuildGroups,
        entry: usize,
        (x, y): (u32, u32),
    ) {
        pass.set_pipeline(&self.pipelines[entry].0);
        pass.set_bind_group(1, &groups.groups[entry], &[]);
        pass.dispatch_workgroups(x, y, 1);
    }
}
