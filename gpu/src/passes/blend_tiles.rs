//! The tiled pass of `wedges-blend` (`shaders/blend_tiles.wgsl`): one compute workgroup per
//! screen tile culls the blending units' items (their counts at the eye, their volumes' side
//! quads, their wedges) against the tile, and each of its invocations counts, integrates and
//! blends the units of its pixel in order into the final buffer the resolve reads. It replaces
//! a stencil, a wedge and a blend pass per group of silhouettes.

use super::blend::BLEND_PARTS_WGSL;
use super::build::WORKGROUP_SCAN_WGSL;
use super::wedge::WEDGE_INTEGRAL_WGSL;
use super::wedge_tiles::TILE_WEDGES_WGSL;
use crate::timing::PassQueries;

/// The pass's pipeline and the layout of its group 1.
pub struct BlendTilesPass {
    pipeline: wgpu::ComputePipeline,
    /// Group 0: the frame's uniforms and model matrices, these visible to the compute stage
    /// ([`super::frame_layout_for`]): the pass places the quads' corners as the depth pre-pass
    /// places the meshes' vertices.
    pub frame_layout: wgpu::BindGroupLayout,
    /// Group 1: the receivers, the wedges in two parts, the items, the counts at the eye, the
    /// side quads, the final buffer, the receivers' normals and each triangle's unit.
    pub layout: wgpu::BindGroupLayout,
}

/// What a frame's tiled blend reads and writes.
pub struct BlendTilesInputs<'a> {
    /// The receivers: the G-buffer's positions.
    pub position: &'a wgpu::TextureView,
    /// The wedge instances, in two parts ([`super::wedge_tiles::two_parts`]).
    pub wedges: [wgpu::BufferBinding<'a>; 2],
    /// The items ([`crate::blend_units::BlendUnits::items`]).
    pub items: &'a wgpu::Buffer,
    /// Each unit's count at the eye.
    pub eye_counts: &'a wgpu::Buffer,
    /// The side quads.
    pub quads: &'a wgpu::Buffer,
    /// The final buffer, written whole.
    pub final_buffer: &'a wgpu::Buffer,
    /// The receivers' normals: the G-buffer's.
    pub normal: &'a wgpu::TextureView,
    /// The unit each scene triangle casts for.
    pub triangle_units: &'a wgpu::Buffer,
}

impl BlendTilesPass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> Self {
        let frame_layout = super::frame_layout_for(device, wgpu::ShaderStages::COMPUTE);
        let source = format!(
            "{WEDGE_INTEGRAL_WGSL}\n{WORKGROUP_SCAN_WGSL}\n{TILE_WEDGES_WGSL}\n{BLEND_PARTS_WGSL}\n{}",
            include_str!("../shaders/blend_tiles.wgsl")
        );
        let module = super::shader(device, "blend tiles", &source);
        let storage = |read_only| wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        };
        let layout = super::layout(
            device,
            "blend tiles",
            wgpu::ShaderStages::COMPUTE,
            &[
                super::float_texture(),
                storage(true),
                storage(true),
                storage(true),
                storage(true),
                storage(true),
                storage(false),
                super::float_texture(),
                storage(true),
            ],
        );
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("blend tiles"),
            bind_group_layouts: &[Some(&frame_layout), Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("blend tiles"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("tile"),
            compilation_options: Default::default(),
            cache: None,
        });
        BlendTilesPass {
            pipeline,
            frame_layout,
            layout,
        }
    }

    /// Records the pass over an image of `size` pixels; `frame` is bound in
    /// [`BlendTilesPass::frame_layout`].
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        device: &wgpu::Device,
        frame: &wgpu::BindGroup,
        inputs: BlendTilesInputs<'_>,
        size: (u32, u32),
        queries: PassQueries<'_>,
    ) {
        let [first, more] = inputs.wedges;
        let group = super::bind_group(
            device,
            "blend tiles",
            &self.layout,
            &[
                wgpu::BindingResource::TextureView(inputs.position),
                wgpu::BindingResource::Buffer(first),
                wgpu::BindingResource::Buffer(more),
                inputs.items.as_entire_binding(),
                inputs.eye_counts.as_entire_binding(),
                inputs.quads.as_entire_binding(),
                inputs.final_buffer.as_entire_binding(),
                wgpu::BindingResource::TextureView(inputs.normal),
                inputs.triangle_units.as_entire_binding(),
            ],
        );
        super::dispatch_tiles(
            encoder,
            "blend tiles",
            &self.pipeline,
            [frame, &group],
            size,
            queries,
        );
    }
}
