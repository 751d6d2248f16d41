//! Recording a frame of a [`GpuScene`]: the depth pre-pass, then the passes of the technique
//! into the application's visibility target.

use crate::context::GpuError;
use crate::frame::FrameCamera;
use crate::gpu_scene::{FrameInputs, GpuScene, check_technique};
use crate::passes::blend::{SILHOUETTE_ADDED, TileRange, disjoint_groups};
use crate::passes::depth::{GBuffer, MeshDraws};
use crate::passes::resolve::ResolveInput;
use crate::passes::wedge::{WedgeDraws, WedgeOutput};
use crate::passes::{FrameBindings, VISIBILITY_FORMAT, bind_group, buffer};
use crate::scene_data::occluder_tiles;
use crate::timing::{Pass, Timer};
use penumbra_geom::Technique;

/// Checks that `size` (the camera's) is the size of `what`.
fn same_size(size: (u32, u32), what: &str, other: (u32, u32)) -> Result<(), GpuError> {
    if size == other {
        Ok(())
    } else {
        Err(GpuError::Frame(format!(
            "the camera's image is {} x {} pixels, the {what} {} x {}",
            size.0, size.1, other.0, other.1
        )))
    }
}

impl GpuScene {
    /// Records the depth pre-pass of the frame seen by `camera` into `gbuffer`: depth, stencil
    /// cleared, eye-relative positions and normals ([`GBuffer`] documents them). An application
    /// that renders these itself skips it.
    pub fn record_depth(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        camera: &FrameCamera,
        gbuffer: &GBuffer,
    ) -> Result<(), GpuError> {
        self.record_depth_timed(encoder, camera, gbuffer, &Timer::disabled())
    }

    pub(crate) fn record_depth_timed(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        camera: &FrameCamera,
        gbuffer: &GBuffer,
        timer: &Timer,
    ) -> Result<(), GpuError> {
        same_size(camera.size, "G-buffer", gbuffer.size())?;
        self.write_frame(camera);
        self.pipelines.depth.record(
            encoder,
            &self.frame,
            MeshDraws {
                vertices: &self.vertices,
                ranges: &self.vertex_ranges,
            },
            gbuffer,
            timer.render(Pass::Depth),
        );
        Ok(())
    }

    /// Records the passes of `inputs.technique` for the frame seen by `inputs.camera`, reading
    /// `gbuffer` (filled by [`GpuScene::record_depth`] or by the application) and writing V into
    /// `target`: a view of a whole `R32Float` texture of the camera's size with usage
    /// `RENDER_ATTACHMENT`. Rebuilds the silhouettes, volumes and wedges first when the light or
    /// a transform changed since they were last built.
    pub fn record(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &FrameInputs,
        gbuffer: &GBuffer,
        target: &wgpu::TextureView,
    ) -> Result<(), GpuError> {
        self.record_timed(encoder, inputs, gbuffer, target, &Timer::disabled())
    }

    pub(crate) fn record_timed(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &FrameInputs,
        gbuffer: &GBuffer,
        target: &wgpu::TextureView,
        timer: &Timer,
    ) -> Result<(), GpuError> {
        let technique = inputs.technique;
        check_technique(technique)?;
        let camera = &inputs.camera;
        same_size(camera.size, "G-buffer", gbuffer.size())?;
        let t = target.texture();
        same_size(camera.size, "target", (t.width(), t.height()))?;
        if t.format() != VISIBILITY_FORMAT
            || !t.usage().contains(wgpu::TextureUsages::RENDER_ATTACHMENT)
        {
            return Err(GpuError::Frame(format!(
                "the target is {:?} with usage {:?}: it must be R32Float with RENDER_ATTACHMENT",
                t.format(),
                t.usage()
            )));
        }
        self.write_frame(camera);
        if technique == Technique::DepthComplexity {
            return self.record_complexity(encoder, inputs, gbuffer, Some(target), timer);
        }
        self.shadows();
        self.scratch
            .prepare(&self.ctx.device, technique, camera.size);
        let shadows = self.shadows.as_ref().expect("built above");
        let p = &self.pipelines;
        let device = &self.ctx.device;
        let stamp = |kind| timer.render(kind);
        let position = p.resolve.receivers(device, gbuffer);
        let bindings = FrameBindings {
            frame: &self.frame,
            depth: &gbuffer.depth_view,
            position: &position,
        };
        let (cube, wedge_buffer) = (&self.cube, &shadows.instance_buffer);
        let all_instances = 0..shadows.instances.len() as u32;
        let all_instances = std::slice::from_ref(&all_instances);
        match technique {
            Technique::Hard | Technique::Wedges => {
                // Every volume's stencil count, then the hard shadow, or the wedges over it.
                p.stencil.record(
                    encoder,
                    bindings,
                    &shadows.volume,
                    &shadows.volume_ranges,
                    stamp(Pass::Stencil),
                );
                let group;
                let input = if technique == Technique::Hard {
                    ResolveInput::Hard
                } else {
                    let occlusion = self.scratch.occlusion.as_ref().expect("prepared above");
                    p.wedge.record(
                        encoder,
                        bindings,
                        WedgeDraws {
                            cube,
                            wedges: wedge_buffer,
                            ranges: all_instances,
                        },
                        WedgeOutput::Additive(occlusion),
                        stamp(Pass::Wedge),
                    );
                    group = bind_group(
                        device,
                        "occlusion",
                        &p.resolve.texture_layout,
                        &[wgpu::BindingResource::TextureView(occlusion)],
                    );
                    ResolveInput::Additive(&group)
                };
                p.resolve
                    .record(encoder, bindings, input, target, stamp(Pass::Resolve));
            }
            Technique::WedgesBlend => {
                // One silhouette buffer, and the final buffer, zeroed (no occlusion) and
                // updated in place by each blend.
                let (sil, final_buffer) =
                    self.scratch.silhouettes.as_ref().expect("prepared above");
                encoder.clear_buffer(final_buffer, 0, None);
                let stencil_group = bind_group(
                    device,
                    "stencil counts",
                    &p.wedge.stencil_layout,
                    &[wgpu::BindingResource::TextureView(&gbuffer.stencil_view)],
                );
                let mut blend_inputs: Vec<wgpu::BindingResource> =
                    sil.iter().map(wgpu::BindingResource::TextureView).collect();
                blend_inputs.push(wgpu::BindingResource::TextureView(&gbuffer.stencil_view));
                blend_inputs.push(final_buffer.as_entire_binding());
                let blend_inputs = bind_group(
                    device,
                    "blend inputs",
                    &p.blend.inputs_layout,
                    &blend_inputs,
                );
                let masks = occluder_tiles(
                    camera,
                    &self.light,
                    &shadows.clusters,
                    &shadows.nearest,
                    &shadows.instances,
                    &shadows.instance_ranges,
                );
                // Occluders whose tiles are disjoint share their passes: their silhouette
                // buffers cannot meet. No wedge reaching a receiver (no tile): neither does the
                // occluder's shadow.
                let groups = disjoint_groups(&masks);
                // Each group's tiles, one list, and its range of that list for the blend.
                let stride = (std::mem::size_of::<TileRange>() as u64)
                    .next_multiple_of(device.limits().min_uniform_buffer_offset_alignment as u64);
                let mut tile_list: Vec<u32> = Vec::new();
                let mut range_bytes = vec![0u8; (stride as usize) * groups.len().max(1)];
                let mut counts = Vec::with_capacity(groups.len());
                for (i, (_, union)) in groups.iter().enumerate() {
                    let tiles = union.packed_tiles();
                    let range = TileRange {
                        first: tile_list.len() as u32,
                        count: tiles.len() as u32,
                        pad: [0; 2],
                    };
                    counts.push(range.count);
                    let at = i * stride as usize;
                    range_bytes[at..at + std::mem::size_of::<TileRange>()]
                        .copy_from_slice(bytemuck::bytes_of(&range));
                    tile_list.extend(tiles);
                }
                self.uploads.frame +=
                    (range_bytes.len() + std::mem::size_of_val(tile_list.as_slice())) as u64;
                let range_buf = buffer(
                    device,
                    "blend tile ranges",
                    &range_bytes,
                    wgpu::BufferUsages::UNIFORM,
                );
                let tile_buf = buffer(
                    device,
                    "blend tiles",
                    &tile_list,
                    wgpu::BufferUsages::STORAGE,
                );
                let tile_group = bind_group(
                    device,
                    "blend tiles",
                    &p.blend.tiles_layout,
                    &[
                        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                            buffer: &range_buf,
                            offset: 0,
                            size: wgpu::BufferSize::new(std::mem::size_of::<TileRange>() as u64),
                        }),
                        tile_buf.as_entire_binding(),
                    ],
                );
                // Areas and cover start at 0, encoded rectangles at 1 (empty).
                let clears: Vec<(&wgpu::TextureView, wgpu::Color)> = sil
                    .iter()
                    .enumerate()
                    .map(|(i, v)| {
                        let clear = if i < SILHOUETTE_ADDED {
                            wgpu::Color::TRANSPARENT
                        } else {
                            wgpu::Color::WHITE
                        };
                        (v, clear)
                    })
                    .collect();
                for (i, ((group, _), &count)) in groups.iter().zip(&counts).enumerate() {
                    let volumes: Vec<(u32, std::ops::Range<u32>)> = group
                        .iter()
                        .map(|&o| shadows.volume_ranges[o].clone())
                        .collect();
                    let instances: Vec<std::ops::Range<u32>> = group
                        .iter()
                        .map(|&o| shadows.instance_ranges[o].clone())
                        .collect();
                    // Forest et al.'s three passes for these silhouettes.
                    p.stencil.record(
                        encoder,
                        bindings,
                        &shadows.volume,
                        &volumes,
                        stamp(Pass::Stencil),
                    );
                    p.wedge.record(
                        encoder,
                        bindings,
                        WedgeDraws {
                            cube,
                            wedges: wedge_buffer,
                            ranges: &instances,
                        },
                        WedgeOutput::Silhouette {
                            targets: &clears,
                            stencil: &stencil_group,
                        },
                        stamp(Pass::Wedge),
                    );
                    let offset = (i as u64 * stride) as u32;
                    p.blend.record(
                        encoder,
                        &self.frame,
                        &blend_inputs,
                        (&tile_group, offset, count),
                        timer.compute(Pass::Blend),
                    );
                }
                let final_group = bind_group(
                    device,
                    "final buffer",
                    &p.resolve.final_layout,
                    &[final_buffer.as_entire_binding()],
                );
                p.resolve.record(
                    encoder,
                    bindings,
                    ResolveInput::Blended(&final_group),
                    target,
                    stamp(Pass::Resolve),
                );
            }
            _ => unreachable!("a volume technique, checked above"),
        }
        Ok(())
    }
}
