//! Resolve of the hard shadow into V: drives `shaders/resolve.wgsl`.

use super::{DEPTH_FORMAT, VISIBILITY_FORMAT};

/// The resolve pipelines (one per stencil outcome).
pub struct ResolvePass {
    unshadowed: wgpu::RenderPipeline,
    shadowed: wgpu::RenderPipeline,
    /// Layout of the position texture (group 1).
    pub texture_layout: wgpu::BindGroupLayout,
}

impl ResolvePass {
    /// Builds the pipelines.
    pub fn new(device: &wgpu::Device, frame_layout: &wgpu::BindGroupLayout) -> Self {
        let module = device.create_shader_module(wgpu::include_wgsl!("../shaders/resolve.wgsl"));
        let texture_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("resolve position"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("resolve"),
            bind_group_layouts: &[Some(frame_layout), Some(&texture_layout)],
            immediate_size: 0,
        });
        let make = |entry: &str, compare: wgpu::CompareFunction| {
            let face = wgpu::StencilFaceState {
                compare,
                fail_op: wgpu::StencilOperation::Keep,
                depth_fail_op: wgpu::StencilOperation::Keep,
                pass_op: wgpu::StencilOperation::Keep,
            };
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(entry),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: Default::default(),
                depth_stencil: Some(wgpu::DepthStencilState {
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
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    targets: &[Some(VISIBILITY_FORMAT.into())],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        ResolvePass {
            unshadowed: make("fs_unshadowed", wgpu::CompareFunction::Equal),
            shadowed: make("fs_shadowed", wgpu::CompareFunction::NotEqual),
            texture_layout,
        }
    }

    /// Writes V into `visibility`, testing the stencil of `depth` against 0.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::BindGroup,
        position: &wgpu::BindGroup,
        visibility: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("resolve"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: visibility,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::WHITE),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: None,
                stencil_ops: None,
            }),
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, frame, &[]);
        pass.set_bind_group(1, position, &[]);
        for (p, reference) in [(&self.unshadowed, 0), (&self.shadowed, 0)] {
            pass.set_pipeline(p);
            pass.set_stencil_reference(reference);
            pass.draw(0..3, 0..1);
        }
    }
}
