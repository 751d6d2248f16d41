//! The volume techniques on the GPU. `hard`: depth pre-pass, z-fail stencil pass, resolve.
//! `wedges` (additive): the same, plus the wedge pass of every silhouette edge before the resolve.
//! `wedges-blend`: the depth pre-pass, then Forest et al.'s "per-silhouette 3 passes algorithm" for
//! each occluder (stencil pass of its volume, wedge pass of its edges into a silhouette buffer,
//! blend of that buffer into the final one), then the resolve. Occluders whose screen tiles
//! are disjoint share those three passes (`passes::blend::disjoint_groups`): their silhouette
//! buffers cannot meet.

use penumbra_geom::image::VisibilityImage;
use penumbra_geom::{Scene, Technique};
use penumbra_volumes::Volumes;

use crate::context::{GpuContext, GpuError};
use crate::frame::{FrameUniforms, frame_group, scene_radius, view_proj_f64};
use crate::passes::blend::{
    BlendPass, FINAL_WORDS, SILHOUETTE_ADDED, SILHOUETTE_FORMATS, TileRange, disjoint_groups,
};
use crate::passes::wedge::OCCLUSION_FORMAT;
use crate::passes::wedge::{WedgeOutput, WedgePass, unit_cube};
use crate::passes::{
    bind_group, buffer,
    depth::{DepthPass, ScreenTargets},
    frame_layout,
    resolve::ResolvePass,
    stencil::StencilPass,
    texture, view,
};
pub use crate::scene_data::{
    CLUSTER_TRIANGLES, ReceiverClusters, VertexData, merged_solid, occluder_tiles, screen_tiles,
    vertex_data, wedge_instances,
};
pub use crate::timing::PassTimes;
use crate::timing::{Pass, Timer, read_frame};

/// Pipelines of the GPU techniques, built once per device.
pub struct GpuRenderer {
    ctx: GpuContext,
    frame_layout: wgpu::BindGroupLayout,
    depth: DepthPass,
    stencil: StencilPass,
    wedge: WedgePass,
    blend: BlendPass,
    resolve: ResolvePass,
}

impl GpuRenderer {
    /// Builds the pipelines on `ctx`'s device.
    pub fn new(ctx: &GpuContext) -> Self {
        let device = &ctx.device;
        let frame_layout = frame_layout(device);
        let resolve = ResolvePass::new(device, &frame_layout);
        let wedge = WedgePass::new(device, &frame_layout, &resolve.texture_layout);
        GpuRenderer {
            depth: DepthPass::new(device, &frame_layout),
            stencil: StencilPass::new(device, &frame_layout, ctx.unclipped_depth),
            blend: BlendPass::new(device, &frame_layout),
            wedge,
            resolve,
            frame_layout,
            ctx: ctx.clone(),
        }
    }

    /// Renders V of `scene` by `technique` with the volumes and wedges of `volumes`.
    pub fn render(
        &self,
        scene: &Scene,
        volumes: &Volumes,
        technique: Technique,
    ) -> Result<VisibilityImage, GpuError> {
        Ok(self.render_timed(scene, volumes, technique)?.0)
    }

    /// [`GpuRenderer::render`], with the GPU time of each pass when the device has timestamp
    /// queries.
    ///
    /// # Panics
    ///
    /// If `technique` is not a volume technique (`hard`, `wedges`, `wedges-blend`).
    pub fn render_timed(
        &self,
        scene: &Scene,
        volumes: &Volumes,
        technique: Technique,
    ) -> Result<(VisibilityImage, Option<PassTimes>), GpuError> {
        assert!(
            technique.is_volume(),
            "{technique} is not a volume technique"
        );
        let device = &self.ctx.device;
        let (w, h) = (scene.camera.width, scene.camera.height);
        let world = scene.triangles();
        let (tris, vol, vol_ranges) = vertex_data(scene, &world, volumes);
        let radius = scene_radius(&tris);
        let camera = view_proj_f64(scene, radius);
        let frame = frame_group(
            device,
            &self.frame_layout,
            &FrameUniforms::new(scene, radius),
        );
        let vertex = wgpu::BufferUsages::VERTEX;
        let tri_buf = buffer(device, "scene triangles", &tris, vertex);
        let vol_buf = buffer(device, "volume triangles", &vol, vertex);
        let att = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let sampled = att | wgpu::TextureUsages::TEXTURE_BINDING;
        let screen = ScreenTargets::new(device, w, h);
        let (depth, depth_view) = (&screen.depth, &screen.depth_view);
        let (position_view, visibility_view) = (&screen.position, &screen.visibility_view);
        let single = |view: &wgpu::TextureView| {
            bind_group(
                device,
                "texture",
                &self.resolve.texture_layout,
                &[wgpu::BindingResource::TextureView(view)],
            )
        };
        let position_group = single(position_view);

        // Timestamp queries (for `wedges-blend` at most three passes per occluder: its group's).
        let blending = technique == Technique::WedgesBlend;
        let timer = Timer::new(
            &self.ctx,
            if blending {
                2 + 3 * volumes.occluders.len()
            } else {
                4
            },
        );
        let stamp = |kind| timer.render(kind);

        let mut enc = device.create_command_encoder(&Default::default());
        self.depth.record(
            &mut enc,
            &frame,
            &tri_buf,
            tris.len() as u32,
            position_view,
            &screen.normal,
            depth_view,
            stamp(Pass::Depth),
        );
        let cube = buffer(device, "unit cube", &unit_cube(), vertex);
        let (instances, inst_ranges) = match technique {
            Technique::Hard => (Vec::new(), Vec::new()),
            _ => wedge_instances(&scene.light, &world, volumes),
        };
        let inst = buffer(device, "wedges", &instances, vertex);
        let occlusion_view;
        let mut final_group = None;
        match technique {
            Technique::Hard | Technique::Wedges => {
                self.stencil.record(
                    &mut enc,
                    &frame,
                    &vol_buf,
                    std::slice::from_ref(&(0..vol.len() as u32)),
                    false,
                    depth_view,
                    stamp(Pass::Stencil),
                );
                occlusion_view = (technique == Technique::Wedges).then(|| {
                    let v = view(&texture(
                        device,
                        "occlusion",
                        (w, h),
                        OCCLUSION_FORMAT,
                        sampled,
                    ));
                    self.wedge.record(
                        &mut enc,
                        &frame,
                        &position_group,
                        &cube,
                        &inst,
                        std::slice::from_ref(&(0..instances.len() as u32)),
                        WedgeOutput::Additive,
                        &[(&v, wgpu::Color::TRANSPARENT)],
                        None,
                        depth_view,
                        stamp(Pass::Wedge),
                    );
                    v
                });
            }
            Technique::WedgesBlend => {
                occlusion_view = None;
                // One silhouette buffer, and the final buffer (zeroed at creation: no occlusion),
                // updated in place by each blend.
                let sil: Vec<wgpu::TextureView> = SILHOUETTE_FORMATS
                    .iter()
                    .map(|&f| view(&texture(device, "silhouette", (w, h), f, sampled)))
                    .collect();
                let final_buffer = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("final buffer"),
                    size: 4 * FINAL_WORDS * (w as u64) * (h as u64),
                    usage: wgpu::BufferUsages::STORAGE,
                    mapped_at_creation: false,
                });
                let stencil_view = depth.create_view(&wgpu::TextureViewDescriptor {
                    label: Some("stencil counts"),
                    format: Some(wgpu::TextureFormat::Stencil8),
                    aspect: wgpu::TextureAspect::StencilOnly,
                    ..Default::default()
                });
                let stencil_group = bind_group(
                    device,
                    "stencil counts",
                    &self.wedge.stencil_layout,
                    &[wgpu::BindingResource::TextureView(&stencil_view)],
                );
                let mut inputs: Vec<wgpu::BindingResource> =
                    sil.iter().map(wgpu::BindingResource::TextureView).collect();
                inputs.push(wgpu::BindingResource::TextureView(&stencil_view));
                inputs.push(final_buffer.as_entire_binding());
                let blend_inputs =
                    bind_group(device, "blend inputs", &self.blend.inputs_layout, &inputs);
                let masks =
                    occluder_tiles(scene, &camera, &world, volumes, &instances, &inst_ranges);
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
                    &self.blend.tiles_layout,
                    &[
                        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                            buffer: &range_buf,
                            offset: 0,
                            size: wgpu::BufferSize::new(std::mem::size_of::<TileRange>() as u64),
                        }),
                        tile_buf.as_entire_binding(),
                    ],
                );
                let zero = wgpu::Color::TRANSPARENT;
                let clears: Vec<(&wgpu::TextureView, wgpu::Color)> = sil
                    .iter()
                    .enumerate()
                    // Areas and cover start at 0, encoded rectangles at 1 (empty).
                    .map(|(i, v)| {
                        (
                            v,
                            if i < SILHOUETTE_ADDED {
                                zero
                            } else {
                                wgpu::Color::WHITE
                            },
                        )
                    })
                    .collect();
                for (i, ((group, _), &count)) in groups.iter().zip(&counts).enumerate() {
                    let ranges = |r: &[std::ops::Range<u32>]| -> Vec<std::ops::Range<u32>> {
                        group.iter().map(|&o| r[o].clone()).collect()
                    };
                    // Forest et al.'s three passes for these silhouettes.
                    self.stencil.record(
                        &mut enc,
                        &frame,
                        &vol_buf,
                        &ranges(&vol_ranges),
                        true,
                        depth_view,
                        stamp(Pass::Stencil),
                    );
                    self.wedge.record(
                        &mut enc,
                        &frame,
                        &position_group,
                        &cube,
                        &inst,
                        &ranges(&inst_ranges),
                        WedgeOutput::Silhouette,
                        &clears,
                        Some(&stencil_group),
                        depth_view,
                        stamp(Pass::Wedge),
                    );
                    let t = timer.compute(Pass::Blend);
                    let offset = (i as u64 * stride) as u32;
                    self.blend.record(
                        &mut enc,
                        &frame,
                        &blend_inputs,
                        &tile_group,
                        offset,
                        count,
                        t,
                    );
                }
                final_group = Some(bind_group(
                    device,
                    "final buffer",
                    &self.resolve.final_layout,
                    &[final_buffer.as_entire_binding()],
                ));
            }
            _ => unreachable!("a volume technique, checked above"),
        }
        let occlusion_group = occlusion_view.as_ref().map(&single);
        self.resolve.record(
            &mut enc,
            &frame,
            &position_group,
            occlusion_group.as_ref().or(final_group.as_ref()),
            blending,
            visibility_view,
            depth_view,
            stamp(Pass::Resolve),
        );
        read_frame(&self.ctx, enc, &timer, &screen.visibility)
    }
}
