//! One module per pass, each driving the WGSL file of the same name in `src/shaders/`.

pub mod blend;
pub mod blend_tiles;
pub mod build;
pub mod candidates;
pub mod complexity;
pub mod count;
pub mod depth;
pub mod fullscreen;
pub mod resolve;
pub mod stencil;
pub mod wedge;
pub mod wedge_tiles;

#[cfg(test)]
mod shaders_tests;

/// The declarations every pass shares, `shaders/common.wgsl`: the frame's uniforms, the
/// light-space transforms, the radial parts' rectangles and the final buffer's layout.
pub const COMMON_WGSL: &str = include_str!("../shaders/common.wgsl");

/// A pass's whole WGSL: the [`crate::constants::shared_constants`], the shared declarations
/// ([`COMMON_WGSL`]) and `source`.
pub fn wgsl_source(source: &str) -> String {
    format!(
        "{}\n{COMMON_WGSL}\n{source}",
        crate::constants::shared_constants()
    )
}

/// Compiles a pass's WGSL ([`wgsl_source`]).
pub fn shader(device: &wgpu::Device, label: &str, source: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(wgsl_source(source).into()),
    })
}

/// Format of the depth pre-pass target: 32-bit float depth (readable) with the stencil counts.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32FloatStencil8;

/// Format of the eye-relative position target written by the depth pre-pass.
pub const POSITION_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// Format of the camera-facing geometric normal written by the depth pre-pass.
pub const NORMAL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Format of the visibility target.
pub const VISIBILITY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// Bind group layout of the frame: the uniforms (binding 0, every stage) and the meshes'
/// model matrices (binding 1, vertex stage; `frame_uniforms::ModelMatrix`, one per mesh, indexed by
/// the instance index of the depth and stencil passes' draws).
pub fn frame_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    frame_layout_for(device, wgpu::ShaderStages::VERTEX)
}

/// [`frame_layout`] with the model matrices visible to `models` (the shadows' build reads them
/// in its compute stage, where the counting pass of depth-complexity has no binding to spare).
pub fn frame_layout_for(
    device: &wgpu::Device,
    models: wgpu::ShaderStages,
) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("frame"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::all(),
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: models,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: true },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
        ],
    })
}

/// What the passes after the depth pre-pass bind of one frame.
#[derive(Clone, Copy)]
pub struct FrameBindings<'a> {
    /// The frame's group 0 ([`frame_layout`]).
    pub frame: &'a wgpu::BindGroup,
    /// The depth pre-pass's depth-stencil target ([`DEPTH_FORMAT`]), attached.
    pub depth: &'a wgpu::TextureView,
    /// Its positions ([`POSITION_FORMAT`]) and normals ([`NORMAL_FORMAT`]) as a group of
    /// `resolve::ResolvePass::receiver_layout`.
    pub position: &'a wgpu::BindGroup,
}

/// Depth-stencil state of a full-screen pass that only tests the stencil's bits `read_mask`
/// against its reference's with `compare` (reference on the left: `Less` passes where
/// `reference < stencil`), writing neither depth nor stencil.
pub fn stencil_test(compare: wgpu::CompareFunction, read_mask: u32) -> wgpu::DepthStencilState {
    let face = wgpu::StencilFaceState {
        compare,
        fail_op: wgpu::StencilOperation::Keep,
        depth_fail_op: wgpu::StencilOperation::Keep,
        pass_op: wgpu::StencilOperation::Keep,
    };
    wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(false),
        depth_compare: Some(wgpu::CompareFunction::Always),
        stencil: wgpu::StencilState {
            front: face,
            back: face,
            read_mask,
            write_mask: 0,
        },
        bias: Default::default(),
    }
}

/// A layout of `n` non-filterable float textures at bindings `0..n`, fragment stage.
pub fn textures_layout(device: &wgpu::Device, label: &str, n: u32) -> wgpu::BindGroupLayout {
    let entries: Vec<wgpu::BindingType> = (0..n).map(|_| float_texture()).collect();
    layout(device, label, wgpu::ShaderStages::FRAGMENT, &entries)
}

/// A non-filterable 2D float texture binding (read with `textureLoad`).
pub fn float_texture() -> wgpu::BindingType {
    wgpu::BindingType::Texture {
        sample_type: wgpu::TextureSampleType::Float { filterable: false },
        view_dimension: wgpu::TextureViewDimension::D2,
        multisampled: false,
    }
}

/// A layout of `entries` at bindings `0..`, visible to `stages`.
pub fn layout(
    device: &wgpu::Device,
    label: &str,
    stages: wgpu::ShaderStages,
    entries: &[wgpu::BindingType],
) -> wgpu::BindGroupLayout {
    let entries: Vec<wgpu::BindGroupLayoutEntry> = entries
        .iter()
        .enumerate()
        .map(|(binding, ty)| wgpu::BindGroupLayoutEntry {
            binding: binding as u32,
            visibility: stages,
            ty: *ty,
            count: None,
        })
        .collect();
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &entries,
    })
}

/// A bind group of `resources` at bindings `0..`.
pub fn bind_group(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    resources: &[wgpu::BindingResource<'_>],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = resources
        .iter()
        .enumerate()
        .map(|(binding, resource)| wgpu::BindGroupEntry {
            binding: binding as u32,
            resource: resource.clone(),
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// A pipeline that draws triangles of eye-relative `Float32x3` positions (vertex buffer 0),
/// both faces, keeping the nearest with reversed depth (`Greater`, written) in a `depth` target,
/// and writing colour `targets` from fragment entry `entry.1` (vertex entry `entry.0`): the depth
/// pre-pass and the light map.
pub fn triangle_pipeline(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    entry: (&str, &str),
    depth: wgpu::TextureFormat,
    targets: &[wgpu::TextureFormat],
) -> wgpu::RenderPipeline {
    let targets: Vec<Option<wgpu::ColorTargetState>> =
        targets.iter().map(|&f| Some(f.into())).collect();
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(entry.0),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: 12,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3],
            })],
        },
        primitive: wgpu::PrimitiveState {
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: depth,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Greater),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(entry.1),
            compilation_options: Default::default(),
            targets: &targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// The descriptor of a 2D texture of `w x h` texels, one mip level, one sample.
pub fn texture_descriptor<'a>(
    label: &'a str,
    (w, h): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::TextureDescriptor<'a> {
    wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    }
}

/// A buffer holding `data` for `usage`; zero-length buffers are invalid, so empty `data` gets
/// one zeroed, unused element.
pub fn buffer<T: bytemuck::Pod>(
    device: &wgpu::Device,
    label: &str,
    data: &[T],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    let zero = [T::zeroed()];
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(if data.is_empty() { &zero } else { data }),
        usage,
    })
}

/// A 2D texture of `size` texels ([`texture_descriptor`]).
pub fn texture(
    device: &wgpu::Device,
    label: &str,
    size: (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&texture_descriptor(label, size, format, usage))
}

/// The view of all of `texture`.
pub fn view(texture: &wgpu::Texture) -> wgpu::TextureView {
    texture.create_view(&Default::default())
}

/// A colour attachment cleared to `clear` at the start of its pass and stored at the end.
pub fn cleared(
    view: &wgpu::TextureView,
    clear: wgpu::Color,
) -> Option<wgpu::RenderPassColorAttachment<'_>> {
    Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: wgpu::LoadOp::Clear(clear),
            store: wgpu::StoreOp::Store,
        },
    })
}

/// Records a compute pass of `pipeline` over the screen tiles of an image of `size` pixels, one
/// workgroup of [`crate::constants::WEDGE_TILE`]² invocations per tile, with the frame's group
/// 0 and the pass's group 1: the tiled wedges' and the tiled blend's dispatch.
pub(crate) fn dispatch_tiles(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    pipeline: &wgpu::ComputePipeline,
    [frame, group]: [&wgpu::BindGroup; 2],
    size: (u32, u32),
    queries: crate::timing::PassQueries<'_>,
) {
    use crate::constants::WEDGE_TILE;
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some(label),
        timestamp_writes: queries.compute_writes(),
    });
    queries.begin_compute(&mut pass);
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, frame, &[]);
    pass.set_bind_group(1, group, &[]);
    pass.dispatch_workgroups(size.0.div_ceil(WEDGE_TILE), size.1.div_ceil(WEDGE_TILE), 1);
    queries.end_compute(&mut pass);
}
