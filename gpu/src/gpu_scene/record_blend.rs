//! Recording Forest et al.'s `wedges-blend` frame of a [`GpuScene`]: for each group of
//! occluders whose screen tiles are disjoint, the stencil pass of their volumes, the wedge pass
//! of their edges into the silhouette buffer and the blend of that buffer into the final one;
//! then the resolve.

use crate::constants::TILE;
use crate::counters::{Pass, Traffic, part};
use std::ops::Range;

use super::GpuScene;
use crate::frame_uniforms::FrameCamera;
use crate::passes::blend::{SILHOUETTE_ADDED, TileMask, TileRange, disjoint_groups};
use crate::passes::depth::GBuffer;
use crate::passes::resolve::ResolveInput;
use crate::passes::stencil::VolumeDraws;
use crate::passes::wedge::{WedgeDraws, WedgeOutput};
use crate::passes::{FrameBindings, bind_group, buffer};
use crate::pipelines::Pipelines;
use crate::scene_data::occluder_tiles;
use crate::timing::Timer;

/// The blend's tile lists of a frame, uploaded: each group's range of one list of tiles.
struct BlendTiles {
    /// The ranges (one [`TileRange`] every `stride` bytes, a dynamic offset each) and the list.
    group: wgpu::BindGroup,
    stride: u64,
    /// Each group's tile count.
    counts: Vec<u32>,
    /// Bytes uploaded.
    bytes: u64,
}

impl GpuScene {
    /// Records `wedges-blend`, with the shadows built and the scratch targets prepared.
    pub(super) fn record_blend(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        camera: &FrameCamera,
        gbuffer: &GBuffer,
        target: &wgpu::TextureView,
        timer: &Timer,
    ) {
        let shadows = self.shadows.as_ref().expect("built by record");
        let p = &self.pipelines;
        let device = &self.ctx.device;
        let position = p.resolve.receivers(device, gbuffer);
        let bindings = FrameBindings {
            frame: &self.frame,
            depth: &gbuffer.depth_view,
            position: &position,
        };
        // One silhouette buffer, and the final buffer, zeroed (no occlusion) and updated in
        // place by each blend.
        let (sil, final_buffer) = self
            .scratch
            .silhouettes
            .as_ref()
            .expect("prepared by record");
        encoder.clear_buffer(final_buffer, 0, None);
        let (stencil_group, blend_inputs) = blend_groups(device, p, gbuffer, sil, final_buffer);
        let masks = occluder_tiles(
            camera,
            self.light.rect(),
            &shadows.clusters,
            &shadows.nearest,
            &shadows.instances,
            &shadows.instance_ranges,
        );
        // Occluders whose tiles are disjoint share their passes: their silhouette buffers
        // cannot meet. No wedge reaching a receiver (no tile): neither does the occluder's
        // shadow.
        let groups = disjoint_groups(&masks);
        let tiles = blend_tiles(device, &p.blend.tiles_layout, &groups);
        self.uploads.frame += tiles.bytes;
        let clears = silhouette_clears(sil);
        // The vertex data of every volume and wedge, of which each group's passes draw theirs.
        let drawn = |ranges: &[(u32, Range<u32>)]| -> u64 {
            ranges.iter().map(|(_, r)| u64::from(r.len() as u32)).sum()
        };
        let all_volume = drawn(&shadows.volume_ranges);
        let pixels = u64::from(camera.size.0) * u64::from(camera.size.1);
        let all_instances: u64 = shadows
            .instance_ranges
            .iter()
            .map(|r| u64::from(r.len() as u32))
            .sum();
        for (i, ((group, _), &count)) in groups.iter().zip(&tiles.counts).enumerate() {
            let volumes: Vec<(u32, Range<u32>)> = group
                .iter()
                .map(|&o| shadows.volume_ranges[o].clone())
                .collect();
            let instances: Vec<Range<u32>> = group
                .iter()
                .map(|&o| shadows.instance_ranges[o].clone())
                .collect();
            // Forest et al.'s three passes for these silhouettes.
            p.stencil.record(
                encoder,
                bindings,
                VolumeDraws::Vertices {
                    vertices: &shadows.volume,
                    ranges: &volumes,
                },
                timer.pass(
                    Pass::Stencil,
                    Traffic::new()
                        .reads(&part(shadows.volume.size(), drawn(&volumes), all_volume))
                        .updates(&gbuffer.depth),
                ),
            );
            p.wedge.record(
                encoder,
                bindings,
                WedgeDraws {
                    cube: &self.cube,
                    wedges: &shadows.instance_buffer,
                    ranges: &instances,
                    indirect: None,
                },
                WedgeOutput::Silhouette {
                    targets: &clears,
                    stencil: &stencil_group,
                },
                timer.pass(
                    Pass::Wedge,
                    sil.iter().fold(
                        Traffic::new()
                            .reads(&self.cube)
                            .reads(&part(
                                shadows.instance_buffer.size(),
                                instances.iter().map(|r| u64::from(r.len() as u32)).sum(),
                                all_instances,
                            ))
                            .reads(&gbuffer.depth)
                            .reads(&gbuffer.position),
                        |t, v| t.writes(v),
                    ),
                ),
            );
            let offset = (i as u64 * tiles.stride) as u32;
            p.blend.record(
                encoder,
                &self.frame,
                &blend_inputs,
                (&tiles.group, offset, count),
                timer.pass(Pass::Blend, {
                    // It reads and updates the pixels of its tiles only.
                    let covered = (u64::from(count) * u64::from(TILE * TILE)).min(pixels);
                    let per_pixel = sil
                        .iter()
                        .fold(Traffic::new(), |t, v| t.reads(v))
                        .reads(&gbuffer.depth)
                        .updates(final_buffer);
                    per_pixel.scaled(covered, pixels).reads(&tiles.stride)
                }),
            );
        }
        self.record_blended_resolve(encoder, gbuffer, final_buffer, target, timer);
    }
}

impl GpuScene {
    /// Records the resolve of `wedges-blend`'s final buffer into `target`.
    pub(super) fn record_blended_resolve(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        gbuffer: &GBuffer,
        final_buffer: &wgpu::Buffer,
        target: &wgpu::TextureView,
        timer: &Timer,
    ) {
        let p = &self.pipelines;
        let device = &self.ctx.device;
        let position = p.resolve.receivers(device, gbuffer);
        let bindings = FrameBindings {
            frame: &self.frame,
            depth: &gbuffer.depth_view,
            position: &position,
        };
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
            timer.pass(
                Pass::Resolve,
                gbuffer.receivers_read().reads(final_buffer).writes(target),
            ),
        );
    }
}

/// The wedge pass's group of the stencil counts and the blend's inputs (the silhouette buffer
/// `sil`, the stencil counts and the final buffer).
fn blend_groups(
    device: &wgpu::Device,
    p: &Pipelines,
    gbuffer: &GBuffer,
    sil: &[wgpu::TextureView],
    final_buffer: &wgpu::Buffer,
) -> (wgpu::BindGroup, wgpu::BindGroup) {
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
    (stencil_group, blend_inputs)
}

/// Each group's tiles in one list, and its range of that list for the blend, uploaded and bound
/// in `layout` (the blend's `tiles_layout`).
fn blend_tiles(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    groups: &[(Vec<usize>, TileMask)],
) -> BlendTiles {
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
    let bytes = (range_bytes.len() + std::mem::size_of_val(tile_list.as_slice())) as u64;
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
    let group = bind_group(
        device,
        "blend tiles",
        layout,
        &[
            wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: &range_buf,
                offset: 0,
                size: wgpu::BufferSize::new(std::mem::size_of::<TileRange>() as u64),
            }),
            tile_buf.as_entire_binding(),
        ],
    );
    BlendTiles {
        group,
        stride,
        counts,
        bytes,
    }
}

/// The silhouette buffer's targets with their clear colours: areas and cover start at 0,
/// encoded rectangles at 1 (empty).
fn silhouette_clears(sil: &[wgpu::TextureView]) -> Vec<(&wgpu::TextureView, wgpu::Color)> {
    sil.iter()
        .enumerate()
        .map(|(i, v)| {
            let clear = if i < SILHOUETTE_ADDED {
                wgpu::Color::TRANSPARENT
            } else {
                wgpu::Color::WHITE
            };
            (v, clear)
        })
        .collect()
}
