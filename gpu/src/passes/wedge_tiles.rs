//! The tiled wedge pass of `wedges` (`shaders/wedge_tiles.wgsl`): one compute workgroup per
//! screen tile culls the wedges against its receivers' light-space box and each of its
//! invocations adds, for its pixel, the integrals of the wedges that hold its receiver, into
//! the occlusion target the resolve reads. It replaces rasterising every wedge's solid, whose
//! fragments cover the screen many times over on large scenes.

use super::build::WORKGROUP_SCAN_WGSL;
use super::wedge::{OCCLUSION_FORMAT, WEDGE_INTEGRAL_WGSL, WedgeInstance};
use crate::timing::PassQueries;

/// What the tiled passes over wedges share: the wedges' bindings (group 1, bindings 1 and 2)
/// and solids, and the light-space box of a tile's receivers.
pub const TILE_WEDGES_WGSL: &str = include_str!("../shaders/tile_wedges.wgsl");

/// The pass's pipeline and the layout of its group 1 (the receivers, the wedges in two parts,
/// their count and the occlusion target).
pub struct WedgeTilesPass {
    pipeline: wgpu::ComputePipeline,
    /// Group 1.
    pub layout: wgpu::BindGroupLayout,
}

/// What a frame's tiled wedge pass reads and writes.
pub struct WedgeTilesInputs<'a> {
    /// The receivers: the G-buffer's positions.
    pub position: &'a wgpu::TextureView,
    /// The wedge instances ([`WedgeInstance`]), in two parts ([`two_parts`]).
    pub wedges: [wgpu::BufferBinding<'a>; 2],
    /// Draw arguments whose word 5 is the number of wedges.
    pub args: &'a wgpu::Buffer,
    /// The occlusion target (an [`OCCLUSION_FORMAT`] storage texture).
    pub occlusion: &'a wgpu::TextureView,
}

impl WedgeTilesPass {
    /// The pipeline over the frame's layout (group 0).
    pub fn new(device: &wgpu::Device, frame_layout: &wgpu::BindGroupLayout) -> Self {
        let source = format!(
            "{WEDGE_INTEGRAL_WGSL}\n{WORKGROUP_SCAN_WGSL}\n{TILE_WEDGES_WGSL}\n{}",
            include_str!("../shaders/wedge_tiles.wgsl")
        );
        let module = super::shader(device, "wedge tiles", &source);
        let compute = wgpu::ShaderStages::COMPUTE;
        let storage = wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        };
        let layout = super::layout(
            device,
            "wedge tiles",
            compute,
            &[
                super::float_texture(),
                storage,
                storage,
                storage,
                wgpu::BindingType::StorageTexture {
                    access: wgpu::StorageTextureAccess::WriteOnly,
                    format: OCCLUSION_FORMAT,
                    view_dimension: wgpu::TextureViewDimension::D2,
                },
            ],
        );
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("wedge tiles"),
            bind_group_layouts: &[Some(frame_layout), Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("wedge tiles"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("tile"),
            compilation_options: Default::default(),
            cache: None,
        });
        WedgeTilesPass { pipeline, layout }
    }

    /// Records the pass over an image of `size` pixels.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        device: &wgpu::Device,
        frame: &wgpu::BindGroup,
        inputs: WedgeTilesInputs<'_>,
        size: (u32, u32),
        queries: PassQueries<'_>,
    ) {
        let [first, more] = inputs.wedges;
        let group = super::bind_group(
            device,
            "wedge tiles",
            &self.layout,
            &[
                wgpu::BindingResource::TextureView(inputs.position),
                wgpu::BindingResource::Buffer(first),
                wgpu::BindingResource::Buffer(more),
                inputs.args.as_entire_binding(),
                wgpu::BindingResource::TextureView(inputs.occlusion),
            ],
        );
        super::dispatch_tiles(
            encoder,
            "wedge tiles",
            &self.pipeline,
            [frame, &group],
            size,
            queries,
        );
    }
}

/// `count` wedge instances of `buffer` as two bindings of at most `max_binding` bytes each, split
/// at a multiple of 16 instances (1,792 bytes, a multiple of every offset alignment); the second
/// is `spare` (a buffer of at least one instance) when the first holds them all. `None` when
/// two bindings cannot hold them.
pub fn two_parts<'a>(
    buffer: &'a wgpu::Buffer,
    count: u64,
    spare: &'a wgpu::Buffer,
    max_binding: u64,
) -> Option<[wgpu::BufferBinding<'a>; 2]> {
    let instance = std::mem::size_of::<WedgeInstance>() as u64;
    let split = (max_binding / instance) / 16 * 16;
    let count = count.max(1);
    if split == 0 || count - split.min(count) > split {
        return None;
    }
    let part = |b: &'a wgpu::Buffer, offset: u64, n: u64| wgpu::BufferBinding {
        buffer: b,
        offset,
        size: wgpu::BufferSize::new(n * instance),
    };
    let first = split.min(count);
    Some([
        part(buffer, 0, first),
        if count > split {
            part(buffer, first * instance, count - split)
        } else {
            part(spare, 0, 1)
        },
    ])
}
