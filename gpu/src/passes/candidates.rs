//! The receiver candidates of depth-complexity sampling (`shaders/candidates.wgsl`): for every
//! pixel, the nearest triangle that the ray through its centre meets, found by testing the ray
//! against every triangle whose box on screen, grown by a pixel, holds the pixel, rather than by
//! the rasteriser, which snaps corners to a fraction of a pixel and so draws a sliver seen
//! edge-on on no pixel. The counting pass takes it as its receiver where it holds the ray nearer
//! than the rasterised triangle (`count_receiver.wgsl`, `ray_receiver`).

use super::complexity::COMPLEXITY_WGSL;
use crate::timing::PassQueries;

/// Format of the candidates' depth: the nearest hit's distance, mapped into `[0, 1)`.
pub const CANDIDATE_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Format of the candidates: the triangle plus one, 0 where none.
pub const CANDIDATE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;

/// The candidates' pipeline and the layout of its group 1: depth-complexity sampling's
/// parameters (binding 8) and triangles (binding 10), as `complexity.wgsl` declares them.
pub struct CandidatePass {
    pipeline: wgpu::RenderPipeline,
    /// Group 1.
    pub layout: wgpu::BindGroupLayout,
}

impl CandidatePass {
    /// The pipeline over the frame (group 0) and its group 1.
    pub fn new(device: &wgpu::Device, frame_layout: &wgpu::BindGroupLayout) -> Self {
        let stages = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: stages,
            ty,
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("receiver candidates"),
            entries: &[
                entry(
                    8,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                ),
                entry(
                    10,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: true },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                ),
            ],
        });
        let module = super::shader(
            device,
            "receiver candidates",
            &format!(
                "{COMPLEXITY_WGSL}\n{}",
                include_str!("../shaders/candidates.wgsl")
            ),
        );
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("receiver candidates"),
            bind_group_layouts: &[Some(frame_layout), Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("receiver candidates"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_box"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState {
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: CANDIDATE_DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_hit"),
                compilation_options: Default::default(),
                targets: &[Some(CANDIDATE_FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        CandidatePass { pipeline, layout }
    }

    /// Its group 1: depth-complexity sampling's `params` and `triangles`.
    pub fn inputs(
        &self,
        device: &wgpu::Device,
        params: &wgpu::Buffer,
        triangles: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("receiver candidates"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 8,
                    resource: params.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 10,
                    resource: triangles.as_entire_binding(),
                },
            ],
        })
    }

    /// Draws the boxes of `triangles` triangles into `target` ([`CANDIDATE_FORMAT`]) and
    /// `depth` ([`CANDIDATE_DEPTH_FORMAT`]), both cleared first.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        (frame, inputs): (&wgpu::BindGroup, &wgpu::BindGroup),
        (target, depth): (&wgpu::TextureView, &wgpu::TextureView),
        triangles: u32,
        queries: PassQueries<'_>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("receiver candidates"),
            color_attachments: &[super::cleared(target, wgpu::Color::TRANSPARENT)],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: queries.render_writes(),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        queries.begin_render(&mut pass);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame, &[]);
        pass.set_bind_group(1, inputs, &[]);
        pass.draw(0..6 * triangles, 0..1);
        queries.end_render(&mut pass);
    }
}
