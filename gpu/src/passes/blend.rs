//! Blend pass of penumbra-wedges blending: drives `shaders/blend.wgsl`.

/// Format of every final- and silhouette-buffer target.
pub const BUFFER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// Targets of the final buffer: area per part, then one rectangle per part.
pub const FINAL_TARGETS: usize = 5;

/// Targets of a silhouette buffer: area, cover, rectangle minima (2), negated maxima (2).
pub const SILHOUETTE_TARGETS: usize = 6;

/// The blend pipeline.
pub struct BlendPass {
    pipeline: wgpu::RenderPipeline,
    /// Layout of group 1: the old final buffer, then the silhouette buffer.
    pub inputs_layout: wgpu::BindGroupLayout,
}

impl BlendPass {
    /// Builds the pipelines.
    /// `stencil_layout` is the wedge pass's layout of the stencil counts (group 2).
    pub fn new(
        device: &wgpu::Device,
        frame_layout: &wgpu::BindGroupLayout,
        stencil_layout: &wgpu::BindGroupLayout,
    ) -> Self {
        let module = super::shader(device, "blend", include_str!("../shaders/blend.wgsl"));
        let inputs_layout = super::textures_layout(
            device,
            "blend inputs",
            (FINAL_TARGETS + SILHOUETTE_TARGETS) as u32,
        );
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("blend"),
            bind_group_layouts: &[
                Some(frame_layout),
                Some(&inputs_layout),
                Some(stencil_layout),
            ],
            immediate_size: 0,
        });
        let targets: Vec<Option<wgpu::ColorTargetState>> = (0..FINAL_TARGETS)
            .map(|_| Some(BUFFER_FORMAT.into()))
            .collect();
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("blend"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        });
        BlendPass {
            pipeline,
            inputs_layout,
        }
    }

    /// Blends the silhouette buffer into the final one: reads `inputs` (old final, silhouette)
    /// and `stencil` (the silhouette's counts), writes `out` (new final).
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::BindGroup,
        inputs: &wgpu::BindGroup,
        out: &[wgpu::TextureView],
        stencil: &wgpu::BindGroup,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let attachments: Vec<Option<wgpu::RenderPassColorAttachment>> = out
            .iter()
            .map(|view| super::cleared(view, wgpu::Color::TRANSPARENT))
            .collect();
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("blend"),
            color_attachments: &attachments,
            depth_stencil_attachment: None,
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame, &[]);
        pass.set_bind_group(1, inputs, &[]);
        pass.set_bind_group(2, stencil, &[]);
        pass.draw(0..3, 0..1);
    }
}
