//! The shadow-map techniques (Fernando's PCSS, fractional-disk, multiple-depth and Gaussian
//! contact-hardening shadow maps) and Reeves et al.'s PCF, on the same scenes and
//! with the same `V` output as the volume techniques: the depth pre-pass (receivers' positions
//! and normals), a light map from the light's centre fitted to the scene, the technique's own
//! passes, and a full-screen pass writing V.

use bytemuck::Zeroable;
use glam::DVec2;
use penumbra_geom::VisibilityImage;
use penumbra_geom::{Scene, Technique};
use penumbra_params::GaussianVariant;
use wgpu::util::DeviceExt;

pub use crate::constants::{MAX_TAPS, NOISE_SIZE};
use crate::context::{GpuContext, GpuError};
use crate::frame::{FrameCamera, FrameUniforms, eye_relative, scene_radius, single_frame_group};
use crate::passes::fullscreen::{
    FullscreenPass, INPUT_IMAGES, LIGHT_DEPTH_FORMAT, LIGHT_MAP_FORMAT, LightMapPass,
    shadow_layout, shadow_shader,
};
use crate::passes::{
    VISIBILITY_FORMAT, bind_group, buffer,
    depth::{DepthPass, GBuffer, MeshDraws, visibility_target},
    frame_layout, texture, texture_descriptor, view,
};
use crate::readback::read_r32f;
pub use crate::shadow_inputs::{
    FD_GRID, LightFrustum, MAX_SLOPE, ShadowUniforms, back_faces, closed_first, fd_block,
    multi_pass_kernel, multi_pass_taps, noise_map, poisson_taps, uniforms,
};
use crate::timing::read_frame;
use crate::timing::{Pass as Kind, PassTimes, Timer};

/// The pipelines of one shadow-map technique, built once per device.
pub struct ShadowMapRenderer {
    ctx: GpuContext,
    technique: Technique,
    frame_layout: wgpu::BindGroupLayout,
    shadow_layout: wgpu::BindGroupLayout,
    depth: DepthPass,
    light: LightMapPass,
    passes: Vec<(&'static str, FullscreenPass)>,
}

/// The passes of each technique: (entry point, target format).
fn technique_passes(t: Technique) -> (&'static str, Vec<(&'static str, wgpu::TextureFormat)>) {
    let r = VISIBILITY_FORMAT;
    let rgba = wgpu::TextureFormat::Rgba32Float;
    match t {
        Technique::Pcf => (include_str!("shaders/pcf.wgsl"), vec![("fs_pcf", r)]),
        Technique::Pcss => (include_str!("shaders/pcss.wgsl"), vec![("fs_pcss", r)]),
        Technique::Mdsm => (
            include_str!("shaders/mdsm.wgsl"),
            vec![("fs_build", rgba), ("fs_mdsm", r), ("fs_probe", r)],
        ),
        Technique::FractionalDisk => (
            include_str!("shaders/fractional_disk.wgsl"),
            vec![
                ("fs_edges", rgba),
                ("fs_propagate", rgba),
                ("fs_fractional_disk", r),
                ("fs_probe_count", r),
            ],
        ),
        Technique::Gaussian => (
            include_str!("shaders/gaussian.wgsl"),
            vec![
                ("fs_distance", rgba),
                ("fs_dilate_h", rgba),
                ("fs_dilate_v", rgba),
                ("fs_pcf", rgba),
                ("fs_single_h", rgba),
                ("fs_single_v", rgba),
                ("fs_multi", rgba),
                ("fs_readout", r),
            ],
        ),
        _ => unreachable!("a shadow-map technique, checked in new"),
    }
}

/// A 2D texture of `size` texels filled with `data` (rows of texels, no padding), to be sampled.
fn upload(
    ctx: &GpuContext,
    label: &str,
    size: (u32, u32),
    format: wgpu::TextureFormat,
    data: &[u8],
) -> wgpu::Texture {
    ctx.device.create_texture_with_data(
        &ctx.queue,
        &texture_descriptor(label, size, format, wgpu::TextureUsages::TEXTURE_BINDING),
        Default::default(),
        data,
    )
}

impl ShadowMapRenderer {
    /// Builds the pipelines of `technique` on `ctx`'s device.
    ///
    /// # Panics
    ///
    /// If `technique` is not a shadow-map technique ([`Technique::is_shadow_map`]).
    pub fn new(ctx: &GpuContext, technique: Technique) -> Self {
        assert!(
            technique.is_shadow_map(),
            "{technique} is not a shadow-map technique"
        );
        let device = &ctx.device;
        let frame_layout = frame_layout(device);
        let shadow_layout = shadow_layout(device);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("shadow map"),
            bind_group_layouts: &[Some(&frame_layout), Some(&shadow_layout)],
            immediate_size: 0,
        });
        let (source, entries) = technique_passes(technique);
        let module = shadow_shader(device, "shadow technique", source);
        let passes = entries
            .into_iter()
            .map(|(e, f)| (e, FullscreenPass::new(device, &layout, &module, e, f)))
            .collect();
        ShadowMapRenderer {
            depth: DepthPass::new(device, &frame_layout),
            light: LightMapPass::new(device, &layout),
            ctx: ctx.clone(),
            technique,
            frame_layout,
            shadow_layout,
            passes,
        }
    }

    /// The technique these pipelines render.
    pub fn technique(&self) -> Technique {
        self.technique
    }

    fn pass(&self, entry: &str) -> &FullscreenPass {
        &self
            .passes
            .iter()
            .find(|(e, _)| *e == entry)
            .unwrap_or_else(|| panic!("{entry} is a pass of {:?}", self.technique))
            .1
    }

    /// Renders V of `scene` with the parameters of `scene.params`.
    pub fn render(&self, scene: &Scene) -> Result<VisibilityImage, GpuError> {
        Ok(self.render_timed(scene)?.0)
    }

    /// [`ShadowMapRenderer::render`], with the GPU time of each kind of pass when the device
    /// has timestamp queries (the light maps, the preprocessing passes, the filter passes, the
    /// read-out).
    pub fn render_timed(
        &self,
        scene: &Scene,
    ) -> Result<(VisibilityImage, Option<PassTimes>), GpuError> {
        let device = &self.ctx.device;
        let params = &scene.params;
        let (w, h) = (scene.camera.width, scene.camera.height);
        let (world, closed) = closed_first(scene);
        let eye = scene.camera.eye;
        let tris = eye_relative(eye, &world);
        let radius = scene_radius(&tris);
        let frame = single_frame_group(
            device,
            &self.frame_layout,
            &FrameUniforms {
                size: [w as f32, h as f32, 3.0 * closed as f32, 0.0],
                ..FrameUniforms::new(&FrameCamera::for_scene(&scene.camera, radius), &scene.light)
            },
        );
        // Nothing in front of the light: a frustum that no receiver falls in (every receiver is
        // then behind the light's plane, V = 0, or lit).
        let frustum =
            LightFrustum::fit_view(&scene.light, &world, &scene.camera).unwrap_or(LightFrustum {
                lo: DVec2::splat(-1.0),
                hi: DVec2::splat(1.0),
                near: 1.0,
                z_min: 1.0,
                z_max: 2.0,
            });
        let base = uniforms(scene, &frustum, self.technique, params);
        let uniform = |u: &ShadowUniforms| {
            buffer(
                device,
                "shadow uniforms",
                std::slice::from_ref(u),
                wgpu::BufferUsages::UNIFORM,
            )
        };
        let base_buf = uniform(&base);
        let vbuf =
            |label, data: &[[f32; 3]]| buffer(device, label, data, wgpu::BufferUsages::VERTEX);

        let att = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let sampled = att | wgpu::TextureUsages::TEXTURE_BINDING;
        let screen = (w, h);
        let res = params.shadow_map.resolution;
        let map_size = (res, res);
        let targets = GBuffer::new(device, screen);
        let visibility = visibility_target(device, screen);
        let (position_view, normal_view) = (&targets.position_view, &targets.normal_view);
        let dummy_view = view(&texture(
            device,
            "unused",
            (1, 1),
            LIGHT_MAP_FORMAT,
            sampled,
        ));
        let light_depth = texture(device, "light depth", map_size, LIGHT_DEPTH_FORMAT, att);
        let light_depth_view = view(&light_depth);
        let map = texture(device, "light map", map_size, LIGHT_MAP_FORMAT, sampled);
        let map_view = view(&map);
        // Group 1 with `buffer` and up to four input images.
        let inputs = |buffer: &wgpu::Buffer, images: &[&wgpu::TextureView]| {
            let mut r = vec![
                buffer.as_entire_binding(),
                wgpu::BindingResource::TextureView(position_view),
                wgpu::BindingResource::TextureView(normal_view),
            ];
            for i in 0..INPUT_IMAGES {
                r.push(wgpu::BindingResource::TextureView(
                    images.get(i).copied().unwrap_or(&dummy_view),
                ));
            }
            bind_group(device, "shadow inputs", &self.shadow_layout, &r)
        };

        // Timestamp queries.
        let timer = Timer::new(
            &self.ctx,
            8 + params.fractional_disk.passes as usize + params.gaussian.passes as usize,
        );
        let stamp = |kind| timer.render(kind);

        let mut enc = device.create_command_encoder(&Default::default());
        let tri_buf = vbuf("scene triangles", &tris);
        self.depth.record(
            &mut enc,
            &frame,
            MeshDraws {
                vertices: &tri_buf,
                ranges: std::slice::from_ref(&(0..tris.len() as u32)),
            },
            &targets,
            stamp(Kind::Depth),
        );
        let base_group = inputs(&base_buf, &[]);
        // The light map: every triangle, or the back faces for fractional-disk.
        let casters = if self.technique == Technique::FractionalDisk {
            eye_relative(eye, &back_faces(scene.light.center, &world, closed))
        } else {
            tris.clone()
        };
        let caster_buf = vbuf("light map triangles", &casters);
        self.light.record(
            &mut enc,
            (&frame, &base_group),
            (&caster_buf, casters.len() as u32),
            (&map_view, &light_depth_view),
            stamp(Kind::LightMap),
        );
        // Fractional-disk's hard test reads a map of every surface too.
        let full_view = if self.technique == Technique::FractionalDisk {
            let full = view(&texture(
                device,
                "full light map",
                map_size,
                LIGHT_MAP_FORMAT,
                sampled,
            ));
            self.light.record(
                &mut enc,
                (&frame, &base_group),
                (&tri_buf, tris.len() as u32),
                (&full, &light_depth_view),
                stamp(Kind::LightMap),
            );
            Some(full)
        } else {
            None
        };
        let vis_view = &view(&visibility);
        let rgba = wgpu::TextureFormat::Rgba32Float;
        let mut keep: Vec<wgpu::Buffer> = Vec::new();
        match self.technique {
            Technique::Pcf | Technique::Pcss => {
                let entry = if self.technique == Technique::Pcf {
                    "fs_pcf"
                } else {
                    "fs_pcss"
                };
                self.pass(entry).record(
                    &mut enc,
                    &frame,
                    &inputs(&base_buf, &[&map_view]),
                    vis_view,
                    stamp(Kind::Filter),
                );
            }
            Technique::Mdsm => {
                let multi = view(&texture(device, "mdsm", map_size, rgba, sampled));
                self.pass("fs_build").record(
                    &mut enc,
                    &frame,
                    &inputs(&base_buf, &[&map_view]),
                    &multi,
                    stamp(Kind::Preprocess),
                );
                self.pass("fs_mdsm").record(
                    &mut enc,
                    &frame,
                    &inputs(&base_buf, &[&map_view, &multi]),
                    vis_view,
                    stamp(Kind::Filter),
                );
            }
            Technique::FractionalDisk => {
                let cells = res.div_ceil(fd_block(res));
                let grid = (cells, cells);
                let ping = [
                    view(&texture(device, "fd ping", grid, rgba, sampled)),
                    view(&texture(device, "fd pong", grid, rgba, sampled)),
                ];
                self.pass("fs_edges").record(
                    &mut enc,
                    &frame,
                    &inputs(&base_buf, &[&map_view]),
                    &ping[0],
                    stamp(Kind::Preprocess),
                );
                let n = params.fractional_disk.passes as usize;
                for p in 0..n {
                    self.pass("fs_propagate").record(
                        &mut enc,
                        &frame,
                        &inputs(&base_buf, &[&map_view, &ping[p % 2]]),
                        &ping[(p + 1) % 2],
                        stamp(Kind::Preprocess),
                    );
                }
                let noise = upload(
                    &self.ctx,
                    "noise",
                    (NOISE_SIZE as u32, NOISE_SIZE as u32),
                    rgba,
                    bytemuck::cast_slice(&noise_map()),
                );
                self.pass("fs_fractional_disk").record(
                    &mut enc,
                    &frame,
                    &inputs(
                        &base_buf,
                        &[
                            &map_view,
                            &ping[n % 2],
                            &view(&noise),
                            full_view.as_ref().expect("made above"),
                        ],
                    ),
                    vis_view,
                    stamp(Kind::Filter),
                );
            }
            Technique::Gaussian => {
                let ping = [
                    view(&texture(device, "gaussian ping", screen, rgba, sampled)),
                    view(&texture(device, "gaussian pong", screen, rgba, sampled)),
                ];
                self.pass("fs_distance").record(
                    &mut enc,
                    &frame,
                    &inputs(&base_buf, &[&map_view]),
                    &ping[0],
                    stamp(Kind::Preprocess),
                );
                let g = &params.gaussian;
                let mut cur = 0;
                let run = |enc: &mut wgpu::CommandEncoder,
                           entry: &str,
                           buf: &wgpu::Buffer,
                           kind: Kind,
                           cur: &mut usize| {
                    self.pass(entry).record(
                        enc,
                        &frame,
                        &inputs(buf, &[&map_view, &ping[*cur]]),
                        &ping[1 - *cur],
                        stamp(kind),
                    );
                    *cur = 1 - *cur;
                };
                if g.dilation > 0 {
                    run(
                        &mut enc,
                        "fs_dilate_h",
                        &base_buf,
                        Kind::Preprocess,
                        &mut cur,
                    );
                    run(
                        &mut enc,
                        "fs_dilate_v",
                        &base_buf,
                        Kind::Preprocess,
                        &mut cur,
                    );
                }
                match g.variant {
                    GaussianVariant::Pcf => {
                        run(&mut enc, "fs_pcf", &base_buf, Kind::Filter, &mut cur)
                    }
                    GaussianVariant::Single => {
                        run(&mut enc, "fs_single_h", &base_buf, Kind::Filter, &mut cur);
                        run(&mut enc, "fs_single_v", &base_buf, Kind::Filter, &mut cur);
                    }
                    GaussianVariant::Multi => {
                        for p in 0..g.passes {
                            let mut u = base;
                            for (slot, t) in u.taps.iter_mut().zip(multi_pass_taps(
                                p,
                                g.max_kernel,
                                g.taps as usize,
                            )) {
                                *slot = t;
                            }
                            let buf = uniform(&u);
                            run(&mut enc, "fs_multi", &buf, Kind::Filter, &mut cur);
                            keep.push(buf);
                        }
                    }
                }
                self.pass("fs_readout").record(
                    &mut enc,
                    &frame,
                    &inputs(&base_buf, &[&map_view, &ping[cur]]),
                    vis_view,
                    stamp(Kind::Resolve),
                );
            }
            _ => unreachable!("a shadow-map technique, checked in new"),
        }

        let frame = read_frame(&self.ctx, enc, &timer, &visibility);
        drop(keep);
        frame
    }

    /// Runs probe pass `entry` (`fs_probe` of `mdsm`, `fs_probe_count` of `fractional-disk`)
    /// over a `size` image with `base` uniforms and `map` (`R32Float` texels, row-major, the
    /// map's size from `base.map`) as the base light map; `mdsm`'s build pass runs first. Returns
    /// the probe image, row-major. For the property tests of the techniques' shaders.
    pub fn probe(
        &self,
        entry: &str,
        base: &ShadowUniforms,
        map: &[f32],
        size: (u32, u32),
    ) -> Result<Vec<f32>, GpuError> {
        let device = &self.ctx.device;
        let sampled = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let map_size = (base.map[0] as u32, base.map[1] as u32);
        let base_map = upload(
            &self.ctx,
            "probe map",
            map_size,
            LIGHT_MAP_FORMAT,
            bytemuck::cast_slice(map),
        );
        let base_view = view(&base_map);
        let dummy = view(&texture(
            device,
            "unused",
            (1, 1),
            LIGHT_MAP_FORMAT,
            sampled,
        ));
        let buf = buffer(
            device,
            "probe uniforms",
            std::slice::from_ref(base),
            wgpu::BufferUsages::UNIFORM,
        );
        // The frame is unused by the probes but part of the layout.
        let frame = single_frame_group(device, &self.frame_layout, &FrameUniforms::zeroed());
        let group = |images: [&wgpu::TextureView; 3]| {
            let mut r = vec![
                buf.as_entire_binding(),
                wgpu::BindingResource::TextureView(&dummy),
                wgpu::BindingResource::TextureView(&dummy),
            ];
            r.extend(images.map(wgpu::BindingResource::TextureView));
            r.resize(3 + INPUT_IMAGES, wgpu::BindingResource::TextureView(&dummy));
            bind_group(device, "probe inputs", &self.shadow_layout, &r)
        };
        let mut enc = device.create_command_encoder(&Default::default());
        let built = (self.technique == Technique::Mdsm).then(|| {
            let v = view(&texture(
                device,
                "mdsm",
                map_size,
                wgpu::TextureFormat::Rgba32Float,
                sampled,
            ));
            self.pass("fs_build").record(
                &mut enc,
                &frame,
                &group([&base_view, &dummy, &dummy]),
                &v,
                None,
            );
            v
        });
        let out = texture(
            device,
            "probe",
            size,
            VISIBILITY_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let images = [&base_view, built.as_ref().unwrap_or(&dummy), &dummy];
        self.pass(entry)
            .record(&mut enc, &frame, &group(images), &view(&out), None);
        read_r32f(&self.ctx, &mut enc, &out, size.0, size.1)
    }
}
