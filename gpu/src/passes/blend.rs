//! Blend pass of penumbra-wedges blending: drives `shaders/blend.wgsl`.

use bytemuck::{Pod, Zeroable};

/// Formats of the silhouette buffer's targets: signed area per part (added), the inner
/// half-wedges' cover of each part's border (added), one rectangle per part in 8 bits per
/// coordinate (kept by `Min` blending). 16 + 8 + 4 x 4 = 40 bytes per pixel.
pub const SILHOUETTE_FORMATS: [wgpu::TextureFormat; 6] = [
    wgpu::TextureFormat::Rgba32Float,
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::Rgba8Unorm,
    wgpu::TextureFormat::Rgba8Unorm,
    wgpu::TextureFormat::Rgba8Unorm,
    wgpu::TextureFormat::Rgba8Unorm,
];

/// The first `SILHOUETTE_ADDED` targets of [`SILHOUETTE_FORMATS`] are added (areas, cover);
/// the others hold encoded rectangles, kept by `Min`.
pub const SILHOUETTE_ADDED: usize = 2;

/// Words (`u32`) per pixel of the final buffer, a storage buffer: areas as 16-bit unorm (2),
/// rectangles as 8-bit unorm (4). `FINAL_WORDS` in `frame.wgsl`.
pub const FINAL_WORDS: u64 = 6;

/// Bytes per pixel of the visibility buffers of `wedges-blend`: one silhouette buffer and the
/// final buffer.
pub fn bytes_per_pixel() -> u64 {
    let silhouette: u64 = SILHOUETTE_FORMATS
        .iter()
        .map(|f| f.block_copy_size(None).unwrap_or(0) as u64)
        .sum();
    silhouette + 4 * FINAL_WORDS
}

/// The screen rectangle a blend dispatch covers, in pixels (`Region` in `blend.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct Region {
    /// Top-left pixel.
    pub origin: [u32; 2],
    /// Width and height.
    pub size: [u32; 2],
}

const _: () = assert!(std::mem::size_of::<Region>() == 16);

/// Workgroup side of `blend.wgsl`.
const WORKGROUP: u32 = 8;

/// The blend pipeline.
pub struct BlendPass {
    pipeline: wgpu::ComputePipeline,
    /// Layout of group 1: the silhouette buffer's six textures, its stencil counts and the final
    /// buffer.
    pub inputs_layout: wgpu::BindGroupLayout,
    /// Layout of group 2: the [`Region`], with a dynamic offset.
    pub region_layout: wgpu::BindGroupLayout,
}

impl BlendPass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device, frame_layout: &wgpu::BindGroupLayout) -> Self {
        let module = super::shader(device, "blend", include_str!("../shaders/blend.wgsl"));
        let mut entries = vec![super::float_texture(); SILHOUETTE_FORMATS.len()];
        entries.push(wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Uint,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        });
        entries.push(wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: false },
            has_dynamic_offset: false,
            min_binding_size: None,
        });
        let compute = wgpu::ShaderStages::COMPUTE;
        let inputs_layout = super::layout(device, "blend inputs", compute, &entries);
        let region_layout = super::layout(
            device,
            "blend region",
            compute,
            &[wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: true,
                min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<Region>() as u64),
            }],
        );
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("blend"),
            bind_group_layouts: &[
                Some(frame_layout),
                Some(&inputs_layout),
                Some(&region_layout),
            ],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("blend"),
            layout: Some(&layout),
            module: &module,
            entry_point: Some("blend"),
            compilation_options: Default::default(),
            cache: None,
        });
        BlendPass {
            pipeline,
            inputs_layout,
            region_layout,
        }
    }

    /// Blends the silhouette buffer into the final one over `region` (`inputs`: the silhouette
    /// buffer, its stencil counts, the final buffer; `regions` at `offset`: the [`Region`]).
    #[allow(clippy::too_many_arguments)] // One argument per resource the pass touches.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::BindGroup,
        inputs: &wgpu::BindGroup,
        regions: &wgpu::BindGroup,
        offset: u32,
        region: Region,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("blend"),
            timestamp_writes: timestamps,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame, &[]);
        pass.set_bind_group(1, inputs, &[]);
        pass.set_bind_group(2, regions, &[offset]);
        pass.dispatch_workgroups(
            region.size[0].div_ceil(WORKGROUP),
            region.size[1].div_ceil(WORKGROUP),
            1,
        );
    }
}
