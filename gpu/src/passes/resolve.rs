//! Resolve of the hard shadow into V: drives `shaders/resolve.wgsl`.

use super::depth::GBuffer;
use super::{FrameBindings, VISIBILITY_FORMAT};
use crate::constants::STENCIL_SIGN;
use crate::timing::PassQueries;

/// Stencil counts resolved one by one by the additive-wedges resolve; larger counts share the
/// last draw (4 n already exceeds any wedge area that could be subtracted in practice).
pub const MAX_COUNT: u32 = 7;

/// Every bit of a stencil count, as a read mask.
const ALL: u32 = 0xff;

/// The stencil test that passes where a count is negative ([`STENCIL_SIGN`] set), with the
/// reference [`STENCIL_SIGN`].
const NEGATIVE: (wgpu::CompareFunction, u32) = (wgpu::CompareFunction::Equal, STENCIL_SIGN);

/// The resolve pipelines (one per stencil outcome). A count with [`STENCIL_SIGN`] set is
/// negative, no caster: the draws for counts from 1 (`hard`) or `MAX_COUNT` (`wedges`) up take it
/// too, and a last draw where the sign is set writes the count-0 value over theirs.
pub struct ResolvePass {
    unshadowed: wgpu::RenderPipeline,
    shadowed: wgpu::RenderPipeline,
    unshadowed_negative: wgpu::RenderPipeline,
    wedges_equal: wgpu::RenderPipeline,
    wedges_at_least: wgpu::RenderPipeline,
    wedges_negative: wgpu::RenderPipeline,
    blended: wgpu::RenderPipeline,
    copied: wgpu::RenderPipeline,
    /// Layout of a single non-filterable float texture (the occlusion, group 2).
    pub texture_layout: wgpu::BindGroupLayout,
    /// Layout of the receivers (group 1 of the resolve and the wedge pass): the positions and
    /// the normals of the depth pre-pass.
    pub receiver_layout: wgpu::BindGroupLayout,
    /// Layout of the final buffer of `wedges-blend` (group 2 of its resolve), a read-only storage
    /// buffer.
    pub final_layout: wgpu::BindGroupLayout,
}

/// The resolve pipeline of vertex entry `vertex` ("vs", or "vs_counted" for the draws that
/// resolve one stencil count each) and fragment entry `entry` of `module`, where the stencil test
/// `compare` of the bits `read_mask` passes.
fn pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    (vertex, entry): (&str, &str),
    (compare, read_mask): (wgpu::CompareFunction, u32),
    layout: &wgpu::PipelineLayout,
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(entry),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(vertex),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: Default::default(),
        depth_stencil: Some(super::stencil_test(compare, read_mask)),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            targets: &[Some(VISIBILITY_FORMAT.into())],
        }),
        multiview_mask: None,
        cache: None,
    })
}

impl ResolvePass {
    /// Builds the pipelines.
    pub fn new(device: &wgpu::Device, frame_layout: &wgpu::BindGroupLayout) -> Self {
        let module = super::shader(device, "resolve", include_str!("../shaders/resolve.wgsl"));
        let texture_layout = super::textures_layout(device, "one texture", 1);
        let receiver_layout = super::textures_layout(device, "receivers", 2);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("resolve"),
            bind_group_layouts: &[Some(frame_layout), Some(&receiver_layout)],
            immediate_size: 0,
        });
        let wedge_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("resolve wedges"),
            bind_group_layouts: &[
                Some(frame_layout),
                Some(&receiver_layout),
                Some(&texture_layout),
            ],
            immediate_size: 0,
        });
        let final_layout = super::layout(
            device,
            "final buffer",
            wgpu::ShaderStages::FRAGMENT,
            &[wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: true },
                has_dynamic_offset: false,
                min_binding_size: None,
            }],
        );
        let blended_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("resolve blended"),
            bind_group_layouts: &[
                Some(frame_layout),
                Some(&receiver_layout),
                Some(&final_layout),
            ],
            immediate_size: 0,
        });
        ResolvePass {
            unshadowed: pipeline(
                device,
                &module,
                ("vs", "fs_unshadowed"),
                (wgpu::CompareFunction::Equal, ALL),
                &layout,
            ),
            shadowed: pipeline(
                device,
                &module,
                ("vs", "fs_shadowed"),
                (wgpu::CompareFunction::NotEqual, ALL),
                &layout,
            ),
            unshadowed_negative: pipeline(
                device,
                &module,
                ("vs", "fs_unshadowed"),
                NEGATIVE,
                &layout,
            ),
            wedges_equal: pipeline(
                device,
                &module,
                ("vs_counted", "fs_wedges"),
                (wgpu::CompareFunction::Equal, ALL),
                &wedge_layout,
            ),
            // Passes where MAX_COUNT <= stencil.
            wedges_at_least: pipeline(
                device,
                &module,
                ("vs_counted", "fs_wedges"),
                (wgpu::CompareFunction::LessEqual, ALL),
                &wedge_layout,
            ),
            wedges_negative: pipeline(
                device,
                &module,
                ("vs_counted", "fs_wedges"),
                NEGATIVE,
                &wedge_layout,
            ),
            // The blended buffer already holds the hard shadows: count 0, every pixel.
            blended: pipeline(
                device,
                &module,
                ("vs", "fs_blended"),
                (wgpu::CompareFunction::Always, ALL),
                &blended_layout,
            ),
            // V computed already, one value per pixel.
            copied: pipeline(
                device,
                &module,
                ("vs", "fs_copied"),
                (wgpu::CompareFunction::Always, ALL),
                &blended_layout,
            ),
            texture_layout,
            receiver_layout,
            final_layout,
        }
    }

    /// The receivers of `gbuffer` (its positions and normals) as a group of
    /// [`ResolvePass::receiver_layout`].
    pub fn receivers(&self, device: &wgpu::Device, gbuffer: &GBuffer) -> wgpu::BindGroup {
        super::bind_group(
            device,
            "receivers",
            &self.receiver_layout,
            &[
                wgpu::BindingResource::TextureView(&gbuffer.position_view),
                wgpu::BindingResource::TextureView(&gbuffer.normal_view),
            ],
        )
    }

    /// Writes V into `visibility` from `input`.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: FrameBindings<'_>,
        input: ResolveInput<'_>,
        visibility: &wgpu::TextureView,
        queries: PassQueries<'_>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("resolve"),
            color_attachments: &[super::cleared(visibility, wgpu::Color::WHITE)],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: frame.depth,
                depth_ops: None,
                stencil_ops: None,
            }),
            timestamp_writes: queries.render_writes(),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        queries.begin_render(&mut pass);
        pass.set_bind_group(0, frame.frame, &[]);
        pass.set_bind_group(1, frame.position, &[]);
        match input {
            ResolveInput::Hard => {
                for p in [&self.unshadowed, &self.shadowed] {
                    pass.set_pipeline(p);
                    pass.set_stencil_reference(0);
                    pass.draw(0..3, 0..1);
                }
                pass.set_pipeline(&self.unshadowed_negative);
                pass.set_stencil_reference(STENCIL_SIGN);
                pass.draw(0..3, 0..1);
            }
            ResolveInput::Blended(o) => {
                pass.set_bind_group(2, o, &[]);
                pass.set_pipeline(&self.blended);
                pass.draw(0..3, 0..1);
            }
            ResolveInput::Visibility(o) => {
                pass.set_bind_group(2, o, &[]);
                pass.set_pipeline(&self.copied);
                pass.draw(0..3, 0..1);
            }
            ResolveInput::Additive(o) => {
                pass.set_bind_group(2, o, &[]);
                for n in 0..=MAX_COUNT {
                    pass.set_pipeline(if n < MAX_COUNT {
                        &self.wedges_equal
                    } else {
                        &self.wedges_at_least
                    });
                    pass.set_stencil_reference(n);
                    // The instance index tells the shader which count it resolves.
                    pass.draw(0..3, n..n + 1);
                }
                pass.set_pipeline(&self.wedges_negative);
                pass.set_stencil_reference(STENCIL_SIGN);
                pass.draw(0..3, 0..1);
            }
        }
        queries.end_render(&mut pass);
    }
}

/// What the resolve turns into V.
#[derive(Clone, Copy)]
pub enum ResolveInput<'a> {
    /// The hard shadow: lit where the stencil count is 0 or negative.
    Hard,
    /// Additive wedges: `1 - clamp(4 n + Σ parts, 0, 4) / 4` with `n` the stencil count and the
    /// parts' occlusion from a group of [`ResolvePass::texture_layout`].
    Additive(&'a wgpu::BindGroup),
    /// The final buffer of the blending, hard shadows included (`n = 0`): a group of
    /// [`ResolvePass::final_layout`].
    Blended(&'a wgpu::BindGroup),
    /// V itself, one `f32` per pixel row by row (depth-complexity sampling), in a buffer bound
    /// as a group of [`ResolvePass::final_layout`].
    Visibility(&'a wgpu::BindGroup),
}
