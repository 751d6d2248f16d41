//! Penumbra-wedge pass: drives `shaders/wedge.wgsl`.

use crate::timing::PassQueries;
use bytemuck::{Pod, Zeroable};
use penumbra_volumes::WedgeFrustum;

use super::FrameBindings;
use super::blend::{SILHOUETTE_ADDED, SILHOUETTE_FORMATS};

/// A wedge's integral at a receiver (`shaders/wedge_integral.wgsl`), prepended to the passes
/// that evaluate wedges.
pub const WEDGE_INTEGRAL_WGSL: &str = include_str!("../shaders/wedge_integral.wgsl");

/// Format of the per-radial-part occlusion target (one channel per part).
pub const OCCLUSION_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// One wedge as the shader reads it (per instance): the solid that is rasterised, holding the
/// wedge within the receivers' box ([`penumbra_volumes::WedgeFrustum`]: the rectangles
/// `near` and `far` at the depths of `lo` and `hi`), and its edge.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct WedgeInstance {
    /// Minimum of the solid's bounding box (light space), `w` unused.
    pub lo: [f32; 4],
    /// Maximum of the solid's bounding box, `w` unused.
    pub hi: [f32; 4],
    /// Edge start (light space), `w` = multiplicity.
    pub from: [f32; 4],
    /// Edge end, `w` unused.
    pub to: [f32; 4],
    /// The rasterised solid's rectangle at depth `lo.z`: min x, min y, max x, max y.
    pub near: [f32; 4],
    /// Its rectangle at depth `hi.z`.
    pub far: [f32; 4],
    /// [`penumbra_volumes::Wedge::caster`]: the point, `w` = 1 where there is one (an
    /// edge of a mesh that the light's plane cuts), all 0 where there is none.
    pub caster: [f32; 4],
}

const _: () = assert!(std::mem::size_of::<WedgeInstance>() == 112);

impl WedgeInstance {
    /// The solid it rasterises, in `f64`.
    pub fn solid(&self) -> WedgeFrustum {
        let rect = |c: [f32; 4]| {
            let v = glam::Vec4::from(c).as_dvec4();
            (glam::DVec2::new(v.x, v.y), glam::DVec2::new(v.z, v.w))
        };
        WedgeFrustum {
            z: (self.lo[2] as f64, self.hi[2] as f64),
            near: rect(self.near),
            far: rect(self.far),
        }
    }
}

/// The unit cube's 12 triangles, wound counter-clockwise seen from outside.
pub fn unit_cube() -> Vec<[f32; 3]> {
    let quads: [[[f32; 3]; 4]; 6] = [
        [[0., 0., 0.], [0., 0., 1.], [0., 1., 1.], [0., 1., 0.]],
        [[1., 0., 0.], [1., 1., 0.], [1., 1., 1.], [1., 0., 1.]],
        [[0., 0., 0.], [1., 0., 0.], [1., 0., 1.], [0., 0., 1.]],
        [[0., 1., 0.], [0., 1., 1.], [1., 1., 1.], [1., 1., 0.]],
        [[0., 0., 0.], [0., 1., 0.], [1., 1., 0.], [1., 0., 0.]],
        [[0., 0., 1.], [1., 0., 1.], [1., 1., 1.], [0., 1., 1.]],
    ];
    quads
        .iter()
        .flat_map(|q| [q[0], q[1], q[2], q[0], q[2], q[3]])
        .collect()
}

/// The wedge pass pipelines: additive (one target) and a silhouette buffer
/// ([`SILHOUETTE_FORMATS`]).
pub struct WedgePass {
    pipeline: wgpu::RenderPipeline,
    silhouette: wgpu::RenderPipeline,
    /// Layout of group 2 of the silhouette pipeline: the stencil counts as a `u32` texture.
    pub stencil_layout: wgpu::BindGroupLayout,
}

/// Which wedge pass output to write, and where.
#[derive(Clone, Copy)]
pub enum WedgeOutput<'a> {
    /// Signed area per part, added (`wedges`) into one [`OCCLUSION_FORMAT`] target, cleared
    /// first.
    Additive(&'a wgpu::TextureView),
    /// A silhouette buffer ([`SILHOUETTE_FORMATS`]), each target cleared to its colour first,
    /// reading the silhouette's stencil counts from `stencil` (group 2, a bind group of
    /// [`WedgePass::stencil_layout`]).
    Silhouette {
        /// The targets and their clear colours.
        targets: &'a [(&'a wgpu::TextureView, wgpu::Color)],
        /// The stencil counts.
        stencil: &'a wgpu::BindGroup,
    },
}

/// The wedges a wedge pass draws: the unit cube ([`unit_cube`]) instanced over ranges of a
/// buffer of [`WedgeInstance`]s.
#[derive(Clone, Copy)]
pub struct WedgeDraws<'a> {
    /// The unit cube's vertices.
    pub cube: &'a wgpu::Buffer,
    /// The instances.
    pub wedges: &'a wgpu::Buffer,
    /// The ranges of `wedges` to draw.
    pub ranges: &'a [std::ops::Range<u32>],
    /// Instead of `ranges`, the draw's arguments in this buffer at this offset (the GPU-built
    /// wedges, `passes::build`).
    pub indirect: Option<(&'a wgpu::Buffer, u64)>,
}

/// The wedge pipeline of fragment entry `entry` in `module`, writing `targets`: the unit cube's
/// back faces, one instance per wedge, behind Lengyel's depth test.
fn pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    entry: &str,
    targets: &[Option<wgpu::ColorTargetState>],
    layout: &wgpu::PipelineLayout,
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(entry),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[
                Some(wgpu::VertexBufferLayout {
                    array_stride: 12,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3],
                }),
                Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<WedgeInstance>() as u64,
                    step_mode: wgpu::VertexStepMode::Instance,
                    attributes: &wgpu::vertex_attr_array![
                        1 => Float32x4, 2 => Float32x4, 3 => Float32x4, 4 => Float32x4,
                        5 => Float32x4, 6 => Float32x4, 7 => Float32x4
                    ],
                }),
            ],
        },
        primitive: wgpu::PrimitiveState {
            front_face: wgpu::FrontFace::Ccw,
            // Back faces only: one fragment per pixel whose ray meets the box, wherever the
            // camera is.
            cull_mode: Some(wgpu::Face::Front),
            ..Default::default()
        },
        // Lengyel's depth test (Forest et al. 2006, section 4.2): a receiver behind the solid's back
        // face (reversed z: a greater depth than the face's) is outside the wedge.
        depth_stencil: Some(wgpu::DepthStencilState {
            format: super::DEPTH_FORMAT,
            depth_write_enabled: Some(false),
            depth_compare: Some(wgpu::CompareFunction::LessEqual),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

impl WedgePass {
    /// Builds the pipeline; `position_layout` is the receiver texture's layout (group 1).
    pub fn new(
        device: &wgpu::Device,
        frame_layout: &wgpu::BindGroupLayout,
        position_layout: &wgpu::BindGroupLayout,
    ) -> Self {
        let source = format!(
            "{WEDGE_INTEGRAL_WGSL}\n{}",
            include_str!("../shaders/wedge.wgsl")
        );
        let module = super::shader(device, "wedge", &source);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("wedge"),
            bind_group_layouts: &[Some(frame_layout), Some(position_layout)],
            immediate_size: 0,
        });
        let stencil_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("stencil counts"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Uint,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }],
        });
        let silhouette_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("wedge silhouette"),
            bind_group_layouts: &[
                Some(frame_layout),
                Some(position_layout),
                Some(&stencil_layout),
            ],
            immediate_size: 0,
        });
        let blend = |format, operation| {
            let c = wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::One,
                operation,
            };
            Some(wgpu::ColorTargetState {
                format,
                blend: Some(wgpu::BlendState { color: c, alpha: c }),
                write_mask: wgpu::ColorWrites::ALL,
            })
        };
        let add = blend(OCCLUSION_FORMAT, wgpu::BlendOperation::Add);
        // Areas and cover add; the encoded rectangles (which grow inwards) take the minimum.
        let silhouette: Vec<Option<wgpu::ColorTargetState>> = SILHOUETTE_FORMATS
            .iter()
            .enumerate()
            .map(|(i, &f)| {
                let op = if i < SILHOUETTE_ADDED {
                    wgpu::BlendOperation::Add
                } else {
                    wgpu::BlendOperation::Min
                };
                blend(f, op)
            })
            .collect();
        WedgePass {
            pipeline: pipeline(device, &module, "fs", std::slice::from_ref(&add), &layout),
            silhouette: pipeline(
                device,
                &module,
                "fs_silhouette",
                &silhouette,
                &silhouette_layout,
            ),
            stencil_layout,
        }
    }

    /// Accumulates the wedges `draws` into `output`. The depth-stencil target of `frame`
    /// (attached read only) rejects fragments whose receiver lies beyond the wedge's solid.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: FrameBindings<'_>,
        draws: WedgeDraws<'_>,
        output: WedgeOutput<'_>,
        queries: PassQueries<'_>,
    ) {
        let attachments: Vec<Option<wgpu::RenderPassColorAttachment>> = match output {
            WedgeOutput::Additive(view) => vec![super::cleared(view, wgpu::Color::TRANSPARENT)],
            WedgeOutput::Silhouette { targets, .. } => targets
                .iter()
                .map(|(view, clear)| super::cleared(view, *clear))
                .collect(),
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("wedge"),
            color_attachments: &attachments,
            // Read only: the receivers' depths for the depth test, and the stencil counts the
            // silhouette pipeline also reads as a texture.
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
        pass.set_vertex_buffer(0, draws.cube.slice(..));
        pass.set_vertex_buffer(1, draws.wedges.slice(..));
        match output {
            WedgeOutput::Silhouette { stencil, .. } => {
                pass.set_pipeline(&self.silhouette);
                pass.set_bind_group(2, stencil, &[]);
            }
            WedgeOutput::Additive(_) => pass.set_pipeline(&self.pipeline),
        }
        match draws.indirect {
            Some((args, offset)) => pass.draw_indirect(args, offset),
            None => {
                for r in draws.ranges.iter().filter(|r| !r.is_empty()) {
                    pass.draw(0..36, r.clone());
                }
            }
        }
        queries.end_render(&mut pass);
    }
}
