//! The volume techniques on the GPU. `hard`: depth pre-pass, z-fail stencil pass, resolve.
//! `wedges` (additive): the same, plus the wedge pass of every silhouette edge before the resolve.

use bytemuck::Zeroable;
use glam::Vec4;
use penumbra_geom::Scene;
use penumbra_geom::image::VisibilityImage;
use penumbra_volumes::Volumes;
use penumbra_volumes::shadow_volume::VolumeVertex;
use wgpu::util::DeviceExt;

use crate::context::{GpuContext, GpuError};
use crate::frame::FrameUniforms;
use crate::passes::wedge::{OCCLUSION_FORMAT, WedgeInstance, WedgePass, unit_cube};
use crate::passes::{
    DEPTH_FORMAT, POSITION_FORMAT, VISIBILITY_FORMAT, depth::DepthPass, frame_layout,
    resolve::ResolvePass, stencil::StencilPass,
};

/// A technique the GPU renders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GpuTechnique {
    /// Hard shadow of the light's centre.
    Hard,
    /// Additive penumbra wedges.
    Wedges,
}

/// GPU time of each pass of one frame, from timestamp queries, in milliseconds.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct PassTimes {
    /// Depth pre-pass.
    pub depth: f64,
    /// z-fail stencil pass.
    pub stencil: f64,
    /// Penumbra-wedge pass (0 for `hard`).
    pub wedge: f64,
    /// Resolve into V.
    pub resolve: f64,
}

impl PassTimes {
    /// Sum of the passes.
    pub fn total(&self) -> f64 {
        self.depth + self.stencil + self.wedge + self.resolve
    }
}

/// Pipelines of the GPU techniques, built once per device.
pub struct GpuRenderer<'a> {
    ctx: &'a GpuContext,
    frame_layout: wgpu::BindGroupLayout,
    depth: DepthPass,
    stencil: StencilPass,
    wedge: WedgePass,
    resolve: ResolvePass,
}

/// The wedges of `volumes` with their light-space bounding boxes clamped to the scene's
/// light-space box (receivers lie in it); wedges wholly outside are dropped.
pub fn wedge_instances(scene: &Scene, volumes: &Volumes) -> Vec<WedgeInstance> {
    let mut lo = glam::DVec3::splat(f64::INFINITY);
    let mut hi = glam::DVec3::splat(f64::NEG_INFINITY);
    for t in scene.triangles() {
        for v in t {
            let l = scene.light.to_light_space(v);
            lo = lo.min(l);
            hi = hi.max(l);
        }
    }
    let pad = (hi - lo).max(glam::DVec3::splat(1e-6)) * 1e-3;
    let (lo, hi) = (lo - pad, hi + pad);
    volumes
        .wedges
        .iter()
        .filter_map(|w| {
            let (blo, bhi) = penumbra_volumes::render::wedge_bounds(w, hi.z);
            let (blo, bhi) = (blo.max(lo), bhi.min(hi));
            if !(blo.x <= bhi.x && blo.y <= bhi.y && blo.z <= bhi.z) {
                return None;
            }
            let f = |v: glam::DVec3, w: f32| {
                let v = v.as_vec3();
                [v.x, v.y, v.z, w]
            };
            Some(WedgeInstance {
                lo: f(blo, 0.0),
                hi: f(bhi, 0.0),
                from: f(w.from, w.multiplicity as f32),
                to: f(w.to, 0.0),
            })
        })
        .collect()
}

fn target(
    device: &wgpu::Device,
    label: &str,
    size: wgpu::Extent3d,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// Eye-relative vertices of every scene triangle, and of every shadow-volume triangle in
/// homogeneous coordinates (`w = 0` at infinity).
pub fn vertex_data(scene: &Scene, volumes: &Volumes) -> (Vec<[f32; 3]>, Vec<[f32; 4]>) {
    let eye = scene.camera.eye;
    let c = scene.light.center;
    let tris: Vec<[f32; 3]> = scene
        .triangles()
        .iter()
        .flatten()
        .map(|&v| (v - eye).as_vec3().to_array())
        .collect();
    let mut vol = Vec::new();
    for o in &volumes.occluders {
        let p = &o.volume.positions;
        for (t, _) in &o.volume.triangles {
            for v in t {
                let h = match *v {
                    VolumeVertex::Finite(i) => (p[i as usize] - eye).as_vec3().extend(1.0),
                    VolumeVertex::Infinite(i) => (p[i as usize] - c).as_vec3().extend(0.0),
                };
                vol.push(Vec4::to_array(&h));
            }
        }
    }
    (tris, vol)
}

impl<'a> GpuRenderer<'a> {
    /// Builds the pipelines on `ctx`'s device.
    pub fn new(ctx: &'a GpuContext) -> Self {
        let device = &ctx.device;
        let frame_layout = frame_layout(device);
        let resolve = ResolvePass::new(device, &frame_layout);
        GpuRenderer {
            depth: DepthPass::new(device, &frame_layout),
            stencil: StencilPass::new(device, &frame_layout, ctx.unclipped_depth),
            wedge: WedgePass::new(device, &frame_layout, &resolve.texture_layout),
            resolve,
            frame_layout,
            ctx,
        }
    }

    /// Renders V of `scene` by `technique` with the volumes and wedges of `volumes`.
    pub fn render(
        &self,
        scene: &Scene,
        volumes: &Volumes,
        technique: GpuTechnique,
    ) -> Result<VisibilityImage, GpuError> {
        Ok(self.render_timed(scene, volumes, technique)?.0)
    }

    /// [`GpuRenderer::render`], with the GPU time of each pass when the device has timestamp
    /// queries.
    pub fn render_timed(
        &self,
        scene: &Scene,
        volumes: &Volumes,
        technique: GpuTechnique,
    ) -> Result<(VisibilityImage, Option<PassTimes>), GpuError> {
        let device = &self.ctx.device;
        let (w, h) = (scene.camera.width, scene.camera.height);
        let size = wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        };
        let (tris, vol) = vertex_data(scene, volumes);
        let radius = tris
            .iter()
            .map(|v| glam::Vec3::from(*v).length() as f64)
            .fold(1e-3, f64::max);
        let uniforms = FrameUniforms::new(scene, radius);
        let frame_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("frame"),
            contents: bytemuck::bytes_of(&uniforms),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let frame = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame"),
            layout: &self.frame_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: frame_buf.as_entire_binding(),
            }],
        });
        let vbuf = |label, data: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: data,
                usage: wgpu::BufferUsages::VERTEX,
            })
        };
        // Zero-length buffers are invalid: pad empty scenes with one degenerate vertex.
        let tri_buf = vbuf(
            "scene triangles",
            bytemuck::cast_slice(if tris.is_empty() {
                &[[0f32; 3]]
            } else {
                &tris[..]
            }),
        );
        let vol_buf = vbuf(
            "volume triangles",
            bytemuck::cast_slice(if vol.is_empty() {
                &[[0f32; 4]]
            } else {
                &vol[..]
            }),
        );
        let att = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let depth = target(device, "depth", size, DEPTH_FORMAT, att);
        let position = target(
            device,
            "position",
            size,
            POSITION_FORMAT,
            att | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let visibility = target(
            device,
            "visibility",
            size,
            VISIBILITY_FORMAT,
            att | wgpu::TextureUsages::COPY_SRC,
        );
        let depth_view = depth.create_view(&Default::default());
        let position_view = position.create_view(&Default::default());
        let visibility_view = visibility.create_view(&Default::default());
        let position_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("position"),
            layout: &self.resolve.texture_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&position_view),
            }],
        });
        let queries = self.ctx.timestamps.then(|| {
            device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass times"),
                ty: wgpu::QueryType::Timestamp,
                count: 8,
            })
        });
        let stamp = |pass: u32| {
            queries.as_ref().map(|q| wgpu::RenderPassTimestampWrites {
                query_set: q,
                beginning_of_pass_write_index: Some(2 * pass),
                end_of_pass_write_index: Some(2 * pass + 1),
            })
        };
        let mut enc = device.create_command_encoder(&Default::default());
        self.depth.record(
            &mut enc,
            &frame,
            &tri_buf,
            tris.len() as u32,
            &position_view,
            &depth_view,
            stamp(0),
        );
        self.stencil.record(
            &mut enc,
            &frame,
            &vol_buf,
            vol.len() as u32,
            &depth_view,
            stamp(1),
        );
        let occlusion_group = match technique {
            GpuTechnique::Hard => None,
            GpuTechnique::Wedges => {
                let instances = wedge_instances(scene, volumes);
                let occlusion = target(
                    device,
                    "occlusion",
                    size,
                    OCCLUSION_FORMAT,
                    att | wgpu::TextureUsages::TEXTURE_BINDING,
                );
                let occlusion_view = occlusion.create_view(&Default::default());
                let cube = vbuf("unit cube", bytemuck::cast_slice(&unit_cube()));
                let zero = [WedgeInstance::zeroed()];
                let inst = vbuf(
                    "wedges",
                    bytemuck::cast_slice(if instances.is_empty() {
                        &zero[..]
                    } else {
                        &instances[..]
                    }),
                );
                self.wedge.record(
                    &mut enc,
                    &frame,
                    &position_group,
                    &cube,
                    &inst,
                    instances.len() as u32,
                    &occlusion_view,
                    stamp(2),
                );
                Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("occlusion"),
                    layout: &self.resolve.texture_layout,
                    entries: &[wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(&occlusion_view),
                    }],
                }))
            }
        };
        self.resolve.record(
            &mut enc,
            &frame,
            &position_group,
            occlusion_group.as_ref(),
            &visibility_view,
            &depth_view,
            stamp(3),
        );
        let stamps = queries.as_ref().map(|q| {
            let resolved = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("pass times"),
                size: 64,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let read = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("pass times readback"),
                size: 64,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            });
            enc.resolve_query_set(q, 0..8, &resolved, 0);
            enc.copy_buffer_to_buffer(&resolved, 0, &read, 0, 64);
            read
        });
        let data = read_r32f(self.ctx, &mut enc, &visibility, w, h)?;
        let times = match stamps {
            None => None,
            Some(read) => {
                let t = read_u64(self.ctx, &read)?;
                let period = self.ctx.queue.get_timestamp_period() as f64 * 1e-6;
                let ms = |k: usize| t[2 * k + 1].saturating_sub(t[2 * k]) as f64 * period;
                Some(PassTimes {
                    depth: ms(0),
                    stencil: ms(1),
                    wedge: if technique == GpuTechnique::Wedges {
                        ms(2)
                    } else {
                        0.0
                    },
                    resolve: ms(3),
                })
            }
        };
        Ok((
            VisibilityImage {
                width: w,
                height: h,
                data,
            },
            times,
        ))
    }
}

/// Copies an `R32Float` texture into a buffer, submits `enc` and waits for the values.
pub fn read_r32f(
    ctx: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    texture: &wgpu::Texture,
    w: u32,
    h: u32,
) -> Result<Vec<f32>, GpuError> {
    let row =
        (w * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: row as u64 * h as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    enc.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(h),
            },
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
    let encoder = std::mem::replace(enc, ctx.device.create_command_encoder(&Default::default()));
    ctx.queue.submit([encoder.finish()]);
    let slice = buffer.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    ctx.device
        .poll(wgpu::PollType::Wait {
            submission_index: None,
            timeout: None,
        })
        .map_err(|e| GpuError::Readback(e.to_string()))?;
    rx.recv()
        .map_err(|e| GpuError::Readback(e.to_string()))?
        .map_err(|e| GpuError::Readback(e.to_string()))?;
    let bytes = slice
        .get_mapped_range()
        .map_err(|e| GpuError::Readback(e.to_string()))?;
    let mut out = Vec::with_capacity((w * h) as usize);
    for y in 0..h as usize {
        let r = &bytes[y * row as usize..y * row as usize + w as usize * 4];
        out.extend(
            r.chunks_exact(4)
                .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])),
        );
    }
    drop(bytes);
    buffer.unmap();
    Ok(out)
}

/// Maps a (submitted) buffer and reads it as `u64`s.
fn read_u64(ctx: &GpuContext, buffer: &wgpu::Buffer) -> Result<Vec<u64>, GpuError> {
    let slice = buffer.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    ctx.device
        .poll(wgpu::PollType::Wait {
            submission_index: None,
            timeout: None,
        })
        .map_err(|e| GpuError::Readback(e.to_string()))?;
    rx.recv()
        .map_err(|e| GpuError::Readback(e.to_string()))?
        .map_err(|e| GpuError::Readback(e.to_string()))?;
    let bytes = slice
        .get_mapped_range()
        .map_err(|e| GpuError::Readback(e.to_string()))?;
    let out = bytes
        .chunks_exact(8)
        .map(|c| u64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect();
    drop(bytes);
    buffer.unmap();
    Ok(out)
}
