//! Depth pre-pass: drives `shaders/depth.wgsl`.

use super::{DEPTH_FORMAT, NORMAL_FORMAT, POSITION_FORMAT, VISIBILITY_FORMAT};
use crate::counters::Traffic;
use crate::timing::PassQueries;

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
    /// hit", then draws `meshes` into `targets`.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::BindGroup,
        meshes: MeshDraws<'_>,
        targets: &GBuffer,
        queries: PassQueries<'_>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("depth"),
            color_attachments: &[
                super::cleared(&targets.position_view, wgpu::Color::TRANSPARENT),
                super::cleared(&targets.normal_view, wgpu::Color::TRANSPARENT),
            ],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &targets.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0),
                    store: wgpu::StoreOp::Store,
                }),
            }),
            timestamp_writes: queries.render_writes(),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        queries.begin_render(&mut pass);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame, &[]);
        pass.set_vertex_buffer(0, meshes.vertices.slice(..));
        for (mesh, range) in meshes.ranges.iter().enumerate() {
            if !range.is_empty() {
                pass.draw(range.clone(), mesh as u32..mesh as u32 + 1);
            }
        }
        queries.end_render(&mut pass);
    }
}

/// The meshes the depth pre-pass draws: stored vertices (`Float32x3`, three per triangle, placed
/// by the frame's model matrices) and each mesh's range of them; mesh `i` is drawn as instance
/// `i`, so that its vertices take matrix `i`. The first `FrameUniforms::size[2]` vertices are
/// flagged as closed meshes' (the shadow-map techniques' receiver normals).
#[derive(Clone, Copy)]
pub struct MeshDraws<'a> {
    /// The vertices.
    pub vertices: &'a wgpu::Buffer,
    /// Each mesh's range of `vertices`.
    pub ranges: &'a [std::ops::Range<u32>],
}

/// What the passes read of the camera's view of the scene, one texel per pixel, as the depth
/// pre-pass writes it ([`crate::GpuScene::record_depth`]). An application that renders these itself must
/// match the formats, usages and conventions below.
///
/// - `depth`: [`DEPTH_FORMAT`] (`Depth32FloatStencil8`), usage `RENDER_ATTACHMENT |
///   TEXTURE_BINDING`; reversed depth from the frame's eye-relative view-projection (1 at the
///   near plane, 0 at infinity and where nothing was hit). The passes use its stencil as
///   scratch.
/// - `position`: [`POSITION_FORMAT`] (`Rgba32Float`), usage `RENDER_ATTACHMENT |
///   TEXTURE_BINDING`; the surface point minus the eye (world axes), `w` 0 where nothing was
///   hit and non-zero where a surface was. The depth pre-pass stores there the bits of the
///   triangle's index in the scene plus `0x0080_0000` (the bits of the smallest normal `f32`, so
///   that they make a positive normal number), which depth-complexity sampling reads to leave the receiver's own triangle out; any
///   other non-zero `w` (such as 1) names no triangle, and the receiver's triangle is then left
///   out as every face it lies in is, by its distance.
/// - `normal`: [`NORMAL_FORMAT`] (`Rgba16Float`), same usage; the surface's normal facing the
///   eye, read by the shadow-map techniques only.
pub struct GBuffer {
    /// Depth and stencil.
    pub depth: wgpu::Texture,
    /// View of all of `depth`.
    pub depth_view: wgpu::TextureView,
    /// View of the stencil of `depth` (read by the blend).
    pub stencil_view: wgpu::TextureView,
    /// Eye-relative positions.
    pub position: wgpu::Texture,
    /// View of `position`.
    pub position_view: wgpu::TextureView,
    /// Normals.
    pub normal: wgpu::Texture,
    /// View of `normal`.
    pub normal_view: wgpu::TextureView,
}

impl GBuffer {
    /// What the depth pre-pass writes: depth (tested and written), positions, normals.
    pub(crate) fn drawn(&self) -> Traffic {
        Traffic::new()
            .updates(&self.depth)
            .writes(&self.position)
            .writes(&self.normal)
    }

    /// What a pass over the receivers reads: depth and stencil (tested), positions, normals.
    pub(crate) fn receivers_read(&self) -> Traffic {
        Traffic::new()
            .reads(&self.depth)
            .reads(&self.position)
            .reads(&self.normal)
    }

    /// Targets of `width x height` pixels.
    pub fn new(device: &wgpu::Device, (width, height): (u32, u32)) -> Self {
        let sampled = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let make = |label, format| super::texture(device, label, (width, height), format, sampled);
        let depth = make("depth", DEPTH_FORMAT);
        let position = make("position", POSITION_FORMAT);
        let normal = make("normal", NORMAL_FORMAT);
        GBuffer {
            depth_view: super::view(&depth),
            stencil_view: depth.create_view(&wgpu::TextureViewDescriptor {
                label: Some("stencil counts"),
                format: Some(wgpu::TextureFormat::Stencil8),
                aspect: wgpu::TextureAspect::StencilOnly,
                ..Default::default()
            }),
            position_view: super::view(&position),
            normal_view: super::view(&normal),
            depth,
            position,
            normal,
        }
    }

    /// Width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.depth.width(), self.depth.height())
    }
}

/// An `R32Float` visibility target of `size` pixels that the passes can write and that can be
/// read back (`RENDER_ATTACHMENT | COPY_SRC`).
pub fn visibility_target(device: &wgpu::Device, size: (u32, u32)) -> wgpu::Texture {
    super::texture(
        device,
        "visibility",
        size,
        VISIBILITY_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    )
}
