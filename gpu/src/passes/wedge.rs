//! Penumbra-wedge pass: drives `shaders/wedge.wgsl`.

use bytemuck::{Pod, Zeroable};

/// Format of the per-radial-part occlusion target (one channel per part).
pub const OCCLUSION_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// One wedge as the shader reads it (per instance): its light-space bounding box and edge.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct WedgeInstance {
    /// Box minimum (light space), `w` unused.
    pub lo: [f32; 4],
    /// Box maximum, `w` unused.
    pub hi: [f32; 4],
    /// Edge start (light space), `w` = multiplicity.
    pub from: [f32; 4],
    /// Edge end, `w` unused.
    pub to: [f32; 4],
}

const _: () = assert!(std::mem::size_of::<WedgeInstance>() == 64);

/// The unit cube's 12 triangles, wound counter-clockwise seen from outside.
pub fn unit_cube() -> Vec<[f32; 3]> {
    let quads: [[[f32; 3]; 4]; 6] = [
        [[0., 0., 0.], [0., 0., 1.], [0., 1., 1.], [0., 1., 0.]],
        [[1., 0., 0.], [1., 1., 0.], [1., 1., 1.], [1., 0., 1.]],
        [[0., 0., 0.], [1., 0., 0.], [1., 0., 1.], [0., 0., 1.]],
        [[0., 1., 0.], [0., 1., 1.], [1., 1., 1.], [1., 1., 0.]],
        [[0., 0., 0.], [0., 1., 0.], [1., 1., 0.], [1., 0., 0.]],
        [[0., 0., 1.], [1., 0., 1.], [1., 1., 1.], [0., 1., 1.]],
    ];
    quads
        .iter()
        .flat_map(|q| [q[0], q[1], q[2], q[0], q[2], q[3]])
        .collect()
}

/// The wedge pass pipeline.
pub struct WedgePass {
    pipeline: wgpu::RenderPipeline,
}

impl WedgePass {
    /// Builds the pipeline; `position_layout` is the receiver texture's layout (group 1).
    pub fn new(
        device: &wgpu::Device,
        frame_layout: &wgpu::BindGroupLayout,
        position_layout: &wgpu::BindGroupLayout,
    ) -> Self {
        let module = super::shader(device, "wedge", include_str!("../shaders/wedge.wgsl"));
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("wedge"),
            bind_group_layouts: &[Some(frame_layout), Some(position_layout)],
            immediate_size: 0,
        });
        let add = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::One,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        };
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("wedge"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[
                    Some(wgpu::VertexBufferLayout {
                        array_stride: 12,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &wgpu::vertex_attr_array![0 => Float32x3],
                    }),
                    Some(wgpu::VertexBufferLayout {
                        array_stride: 64,
                        step_mode: wgpu::VertexStepMode::Instance,
                        attributes: &wgpu::vertex_attr_array![
                            1 => Float32x4, 2 => Float32x4, 3 => Float32x4, 4 => Float32x4
                        ],
                    }),
                ],
            },
            primitive: wgpu::PrimitiveState {
                front_face: wgpu::FrontFace::Ccw,
                // Back faces only: one fragment per pixel whose ray meets the box, wherever the
                // camera is.
                cull_mode: Some(wgpu::Face::Front),
                ..Default::default()
            },
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: OCCLUSION_FORMAT,
                    blend: Some(wgpu::BlendState {
                        color: add,
                        alpha: add,
                    }),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        WedgePass { pipeline }
    }

    /// Clears `occlusion` and accumulates the signed areas of `instances` wedges into it.
    #[allow(clippy::too_many_arguments)] // One argument per resource the pass touches.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::BindGroup,
        position: &wgpu::BindGroup,
        cube: &wgpu::Buffer,
        wedges: &wgpu::Buffer,
        instances: u32,
        occlusion: &wgpu::TextureView,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("wedge"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: occlusion,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame, &[]);
        pass.set_bind_group(1, position, &[]);
        pass.set_vertex_buffer(0, cube.slice(..));
        pass.set_vertex_buffer(1, wedges.slice(..));
        pass.draw(0..36, 0..instances);
    }
}
