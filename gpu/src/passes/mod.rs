//! One module per pass, each driving the WGSL file of the same name in `src/shaders/`.

pub mod blend;
pub mod depth;
pub mod fullscreen;
pub mod resolve;
pub mod stencil;
pub mod wedge;

/// The shared declarations of `shaders/frame.wgsl`.
pub const FRAME_WGSL: &str = include_str!("../shaders/frame.wgsl");

/// Compiles a pass's WGSL with the frame declarations prepended.
pub fn shader(device: &wgpu::Device, label: &str, source: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(format!("{FRAME_WGSL}\n{source}").into()),
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

/// Bind group layout of the frame uniforms (binding 0), visible to every stage.
pub fn frame_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("frame"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::all(),
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }],
    })
}

/// Depth-stencil state of a full-screen pass that only tests the stencil against its reference
/// with `compare` (reference on the left: `Less` passes where `reference < stencil`), writing
/// neither depth nor stencil.
pub fn stencil_test(compare: wgpu::CompareFunction) -> wgpu::DepthStencilState {
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
            read_mask: 0xff,
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
