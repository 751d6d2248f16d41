//! One shadow-map render's shared resources: the frame's group, the receivers' G-buffer, the
//! light map from the light's centre, the base uniforms, V's target and the timer; and the
//! passes every technique starts with (the depth pre-pass and the light map).

use penumbra_geom::LitScene;
use penumbra_params::TechniqueParams;

use super::inputs::{ShadowUniforms, back_faces};
use super::pipelines::ShadowPipelines;
use crate::context::GpuContext;
use crate::counters::{Pass, Traffic};
use crate::frame_uniforms::{FrameCamera, FrameUniforms, eye_relative, single_frame_group};
use crate::passes::depth::{GBuffer, MeshDraws, visibility_target};
use crate::passes::fullscreen::{INPUT_IMAGES, LIGHT_DEPTH_FORMAT, LIGHT_MAP_FORMAT};
use crate::passes::{bind_group, buffer, texture, view};
use crate::timing::Timer;

/// Usage of a target that a later pass reads.
pub(super) const SAMPLED: wgpu::TextureUsages =
    wgpu::TextureUsages::RENDER_ATTACHMENT.union(wgpu::TextureUsages::TEXTURE_BINDING);

/// Format of the intermediate images of the techniques' passes.
pub(super) const RGBA: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// What one render's passes share.
pub(super) struct ShadowFrame<'a> {
    pub(super) ctx: &'a GpuContext,
    pipelines: &'a ShadowPipelines,
    /// The scene's parameters.
    pub(super) params: &'a TechniqueParams,
    /// Group 0.
    frame: wgpu::BindGroup,
    /// The technique's uniforms and their buffer.
    pub(super) base: ShadowUniforms,
    pub(super) base_buf: wgpu::Buffer,
    /// The receivers' positions and normals.
    gbuffer: GBuffer,
    /// Bound where a pass reads fewer than [`INPUT_IMAGES`] images.
    dummy: wgpu::TextureView,
    /// The light map and its depth test target, of `map_size` texels.
    pub(super) map: wgpu::TextureView,
    pub(super) light_depth: wgpu::TextureView,
    pub(super) map_size: (u32, u32),
    /// The image's size in pixels, and V's target.
    pub(super) screen: (u32, u32),
    pub(super) visibility: wgpu::Texture,
    pub(super) visibility_view: wgpu::TextureView,
    /// The scene's triangles (eye-relative, closed meshes first) and their vertex buffer.
    pub(super) triangles: Vec<[f32; 3]>,
    pub(super) triangle_buffer: wgpu::Buffer,
    pub(super) timer: Timer,
}

impl<'a> ShadowFrame<'a> {
    /// The resources of a render of `scene` (whose triangles, closed meshes first, are
    /// `world`, `closed` of them closed) with uniforms `base`.
    pub(super) fn new(
        ctx: &'a GpuContext,
        pipelines: &'a ShadowPipelines,
        scene: &'a LitScene,
        (world, closed): (&[[glam::DVec3; 3]], usize),
        base: ShadowUniforms,
        counters: bool,
    ) -> Self {
        let device = &ctx.device;
        let params = &scene.params;
        let (w, h) = (scene.camera.width, scene.camera.height);
        let triangles = eye_relative(scene.camera.eye, world);
        let frame = single_frame_group(
            device,
            &pipelines.frame_layout,
            &FrameUniforms {
                size: [w as f32, h as f32, 3.0 * closed as f32, 0.0],
                ..FrameUniforms::new(
                    &FrameCamera::for_scene(&scene.camera, &triangles),
                    &scene.light,
                )
            },
        );
        let base_buf = uniform_buffer(device, &base);
        let res = params.shadow_map.resolution;
        let map_size = (res, res);
        let screen = (w, h);
        let att = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let visibility = visibility_target(device, screen);
        ShadowFrame {
            ctx,
            pipelines,
            params,
            frame,
            base,
            base_buf,
            gbuffer: GBuffer::new(device, screen),
            dummy: view(&texture(
                device,
                "unused",
                (1, 1),
                LIGHT_MAP_FORMAT,
                SAMPLED,
            )),
            light_depth: view(&texture(
                device,
                "light depth",
                map_size,
                LIGHT_DEPTH_FORMAT,
                att,
            )),
            map: view(&texture(
                device,
                "light map",
                map_size,
                LIGHT_MAP_FORMAT,
                SAMPLED,
            )),
            map_size,
            screen,
            visibility_view: view(&visibility),
            visibility,
            triangle_buffer: buffer(
                device,
                "scene triangles",
                &triangles,
                wgpu::BufferUsages::VERTEX,
            ),
            triangles,
            timer: Timer::new(
                ctx,
                8 + params.fractional_disk.passes as usize + params.gaussian.passes as usize,
                counters,
            ),
        }
    }

    /// Group 1 with uniforms `buffer` and up to four input images.
    pub(super) fn inputs(
        &self,
        buffer: &wgpu::Buffer,
        images: &[&wgpu::TextureView],
    ) -> wgpu::BindGroup {
        let mut r = vec![
            buffer.as_entire_binding(),
            wgpu::BindingResource::TextureView(&self.gbuffer.position_view),
            wgpu::BindingResource::TextureView(&self.gbuffer.normal_view),
        ];
        for i in 0..INPUT_IMAGES {
            r.push(wgpu::BindingResource::TextureView(
                images.get(i).copied().unwrap_or(&self.dummy),
            ));
        }
        bind_group(
            &self.ctx.device,
            "shadow inputs",
            &self.pipelines.shadow_layout,
            &r,
        )
    }

    /// Records full-screen pass `entry` reading uniforms `buffer` and `images`, writing
    /// `target`, timed as a pass of kind `kind`.
    pub(super) fn run(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        entry: &str,
        (buffer, images): (&wgpu::Buffer, &[&wgpu::TextureView]),
        target: &wgpu::TextureView,
        kind: Pass,
    ) {
        self.pipelines.pass(entry).record(
            encoder,
            &self.frame,
            &self.inputs(buffer, images),
            target,
            self.timer
                .pass(kind, self.traffic(buffer, images).writes(target)),
        );
    }

    /// What a full-screen pass reading uniforms `buffer`, the receivers and `images` reads.
    fn traffic(&self, buffer: &wgpu::Buffer, images: &[&wgpu::TextureView]) -> Traffic {
        let t = Traffic::new()
            .reads(buffer)
            .reads(&self.gbuffer.position)
            .reads(&self.gbuffer.normal);
        images.iter().fold(t, |t, i| t.reads(*i))
    }

    /// A `size` texture of `format` that passes write and later passes read.
    pub(super) fn image(
        &self,
        label: &str,
        size: (u32, u32),
        format: wgpu::TextureFormat,
    ) -> wgpu::TextureView {
        view(&texture(&self.ctx.device, label, size, format, SAMPLED))
    }

    /// Records the depth pre-pass of the scene's triangles into the G-buffer.
    pub(super) fn record_depth(&self, encoder: &mut wgpu::CommandEncoder) {
        self.pipelines.depth.record(
            encoder,
            &self.frame,
            MeshDraws {
                vertices: &self.triangle_buffer,
                ranges: std::slice::from_ref(&(0..self.triangles.len() as u32)),
            },
            &self.gbuffer,
            self.timer.pass(
                Pass::Depth,
                self.gbuffer.drawn().reads(&self.triangle_buffer),
            ),
        );
    }

    /// Records the light map of `casters` (eye-relative triangles) into `map`.
    pub(super) fn record_light_map(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        (casters, count): (&wgpu::Buffer, u32),
        map: &wgpu::TextureView,
    ) {
        let base_group = self.inputs(&self.base_buf, &[]);
        self.pipelines.light.record(
            encoder,
            (&self.frame, &base_group),
            (casters, count),
            (map, &self.light_depth),
            self.timer.pass(
                Pass::LightMap,
                Traffic::new()
                    .reads(casters)
                    .reads(&self.base_buf)
                    .updates(&self.light_depth)
                    .writes(map),
            ),
        );
    }

    /// The vertex buffer of `triangles` (eye-relative).
    pub(super) fn vertex_buffer(&self, label: &str, triangles: &[[f32; 3]]) -> wgpu::Buffer {
        buffer(
            &self.ctx.device,
            label,
            triangles,
            wgpu::BufferUsages::VERTEX,
        )
    }
}

/// The light map's casters of the scene, for `fractional-disk` its back faces
/// ([`back_faces`]) of `world` (`closed` of which closed), eye-relative.
pub(super) fn back_face_casters(
    scene: &LitScene,
    (world, closed): (&[[glam::DVec3; 3]], usize),
) -> Vec<[f32; 3]> {
    eye_relative(
        scene.camera.eye,
        &back_faces(scene.light.center, world, closed),
    )
}

/// A uniform buffer holding `u`.
pub(super) fn uniform_buffer(device: &wgpu::Device, u: &ShadowUniforms) -> wgpu::Buffer {
    buffer(
        device,
        "shadow uniforms",
        std::slice::from_ref(u),
        wgpu::BufferUsages::UNIFORM,
    )
}
