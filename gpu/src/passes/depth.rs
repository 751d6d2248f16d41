//! Depth pre-pass: drives `shaders/depth.wgsl`.

use super::{DEPTH_FORMAT, NORMAL_FORMAT, POSITION_FORMAT, VISIBILITY_FORMAT};

/// The depth pre-pass pipeline.
pub struct DepthPass {
    pipeline: wgpu::RenderPipeline,
}

impl DepthPass {
    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device, frame_layout: &wgpu::BindGroupLayout) -> Self {
        let module = super::shader(device, "depth", include_str!("../shaders/depth.wgsl"));
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("depth"),
            bind_group_layouts: &[Some(frame_layout)],
            immediate_size: 0,
        });
        let pipeline = super::triangle_pipeline(
            device,
            "depth",
            &layout,
            &module,
            ("vs", "fs"),
            DEPTH_FORMAT,
            &[POSITION_FORMAT, NORMAL_FORMAT],
        );
        DepthPass { pipeline }
    }

    /// Clears depth to 0 (infinitely far), the stencil to 0 and positions and normals to "no
    /// hit", then draws `vertex_count` vertices of `vertices` (eye-relative triangles).
    #[allow(clippy::too_many_arguments)] // One argument per resource the pass touches.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::BindGroup,
        vertices: &wgpu::Buffer,
        vertex_count: u32,
        position: &wgpu::TextureView,
        normal: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("depth"),
            color_attachments: &[
                super::cleared(position, wgpu::Color::TRANSPARENT),
                super::cleared(normal, wgpu::Color::TRANSPARENT),
            ],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0),
                    store: wgpu::StoreOp::Store,
                }),
            }),
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame, &[]);
        pass.set_vertex_buffer(0, vertices.slice(..));
        pass.draw(0..vertex_count, 0..1);
    }
}

/// The camera-resolution targets every technique shares: the depth pre-pass's depth-stencil,
/// positions and normals (all sampled by later passes) and the `R32Float` visibility that is read
/// back.
pub struct ScreenTargets {
    /// Depth and stencil (`DEPTH_FORMAT`).
    pub depth: wgpu::Texture,
    /// View of all of `depth`.
    pub depth_view: wgpu::TextureView,
    /// Eye-relative positions (`POSITION_FORMAT`).
    pub position: wgpu::TextureView,
    /// Normals (`NORMAL_FORMAT`).
    pub normal: wgpu::TextureView,
    /// V (`VISIBILITY_FORMAT`), copyable.
    pub visibility: wgpu::Texture,
    /// View of `visibility`.
    pub visibility_view: wgpu::TextureView,
}

impl ScreenTargets {
    /// Targets of `width x height` pixels.
    pub fn new(device: &wgpu::Device, width: u32, height: u32) -> Self {
        let att = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let sampled = att | wgpu::TextureUsages::TEXTURE_BINDING;
        let make =
            |label, format, usage| super::texture(device, label, (width, height), format, usage);
        let view = super::view;
        let depth = make("depth", DEPTH_FORMAT, sampled);
        let visibility = make(
            "visibility",
            VISIBILITY_FORMAT,
            att | wgpu::TextureUsages::COPY_SRC,
        );
        ScreenTargets {
            depth_view: view(&depth),
            position: view(&make("position", POSITION_FORMAT, sampled)),
            normal: view(&make("normal", NORMAL_FORMAT, sampled)),
            visibility_view: view(&visibility),
            depth,
            visibility,
        }
    }
}
