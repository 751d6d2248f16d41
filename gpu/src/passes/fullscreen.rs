//! The passes of the shadow-map techniques: each technique's WGSL file (`pcf.wgsl`,
//! `pcss.wgsl`, `mdsm.wgsl`, `fractional_disk.wgsl`, `gaussian.wgsl`) holds its passes as
//! fragment entry points drawn over a full-screen triangle, with `shadow.wgsl` prepended. They
//! share one bind group (group 1): the technique's uniforms, the receivers' positions and
//! normals, and four input images.

use crate::constants::BIG;
use crate::timing::PassQueries;

/// The declarations shared by the shadow-map techniques' shaders.
pub const SHADOW_WGSL: &str = include_str!("../shaders/shadow.wgsl");

/// The shaders compiled with [`SHADOW_WGSL`] prepended (file stems in `src/shaders`).
#[cfg(test)]
pub(crate) const SHADOW_MAP_SHADERS: &[&str] = &[
    "light_map",
    "pcf",
    "pcss",
    "mdsm",
    "fractional_disk",
    "gaussian",
];

/// Compiles a shadow-map technique's WGSL with the frame and shadow declarations prepended.
pub fn shadow_shader(device: &wgpu::Device, label: &str, source: &str) -> wgpu::ShaderModule {
    super::shader(device, label, &format!("{SHADOW_WGSL}\n{source}"))
}

/// Number of input images of the shared group (`map0` to `map3`).
pub const INPUT_IMAGES: usize = 4;

/// Layout of group 1: the uniforms (binding 0), positions, normals and the input images.
pub fn shadow_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let mut entries = vec![wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Uniform,
        has_dynamic_offset: false,
        min_binding_size: None,
    }];
    entries.extend((0..2 + INPUT_IMAGES).map(|_| super::float_texture()));
    super::layout(
        device,
        "shadow inputs",
        wgpu::ShaderStages::VERTEX_FRAGMENT,
        &entries,
    )
}

/// One full-screen pass: a fragment entry point writing one colour target.
pub struct FullscreenPass {
    pipeline: wgpu::RenderPipeline,
    label: String,
}

impl FullscreenPass {
    /// The pass of `entry` in `module`, writing `format`.
    pub fn new(
        device: &wgpu::Device,
        layout: &wgpu::PipelineLayout,
        module: &wgpu::ShaderModule,
        entry: &str,
        format: wgpu::TextureFormat,
    ) -> Self {
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(entry),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                targets: &[Some(format.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        FullscreenPass {
            pipeline,
            label: entry.to_string(),
        }
    }

    /// Draws the pass over all of `target`.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::BindGroup,
        inputs: &wgpu::BindGroup,
        target: &wgpu::TextureView,
        queries: PassQueries<'_>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(&self.label),
            color_attachments: &[super::cleared(target, wgpu::Color::TRANSPARENT)],
            depth_stencil_attachment: None,
            timestamp_writes: queries.render_writes(),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        queries.begin_render(&mut pass);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame, &[]);
        pass.set_bind_group(1, inputs, &[]);
        pass.draw(0..3, 0..1);
        queries.end_render(&mut pass);
    }
}

/// Format of the light maps' depth test target.
pub const LIGHT_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Format of a light map: the linear light depth.
pub const LIGHT_MAP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// The light map pass (`light_map.wgsl`): the scene from the light's centre.
pub struct LightMapPass {
    pipeline: wgpu::RenderPipeline,
}

impl LightMapPass {
    /// Builds the pipeline (same layouts as the full-screen passes).
    pub fn new(device: &wgpu::Device, layout: &wgpu::PipelineLayout) -> Self {
        let module = shadow_shader(
            device,
            "light map",
            include_str!("../shaders/light_map.wgsl"),
        );
        let pipeline = super::triangle_pipeline(
            device,
            "light map",
            layout,
            &module,
            ("vs_light", "fs_light"),
            LIGHT_DEPTH_FORMAT,
            &[LIGHT_MAP_FORMAT],
        );
        LightMapPass { pipeline }
    }

    /// Clears the `map` to BIG (no surface) and its `depth` to 0, then draws the first
    /// `vertex_count` vertices of `vertices` (eye-relative triangles).
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        (frame, inputs): (&wgpu::BindGroup, &wgpu::BindGroup),
        (vertices, vertex_count): (&wgpu::Buffer, u32),
        (map, depth): (&wgpu::TextureView, &wgpu::TextureView),
        queries: PassQueries<'_>,
    ) {
        let big = wgpu::Color {
            r: BIG as f64,
            g: 0.0,
            b: 0.0,
            a: 0.0,
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("light map"),
            color_attachments: &[super::cleared(map, big)],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Store,
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
        pass.set_vertex_buffer(0, vertices.slice(..));
        if vertex_count > 0 {
            pass.draw(0..vertex_count, 0..1);
        }
        queries.end_render(&mut pass);
    }
}
