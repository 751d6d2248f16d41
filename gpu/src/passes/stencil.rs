//! z-fail stencil pass of the shadow volumes: drives `shaders/stencil.wgsl`.
//!
//! Two pipelines share the shader. Seen from the camera, the volume's back faces increment the
//! stencil where they fail the depth test (they lie behind the receiver) and its front faces
//! decrement it, so the count is the volumes' winding number around the receiver: the number of
//! volume boundaries the view ray still crosses beyond it, outward minus inward, the dark caps at
//! infinity included. A light cap lies exactly on the surface it caps. The receiver counts as
//! lying on the light's side of its own triangle (it is not shadowed by it), so at equal depth a
//! cap facing the camera is behind the receiver (fails a strict `Greater`) and a cap facing away
//! is in front of it (passes `GreaterEqual`).

use super::{DEPTH_FORMAT, FrameBindings};
use crate::timing::PassQueries;

/// The stencil pass pipelines: back faces and front faces of the volumes the CPU built (a
/// vertex buffer), of the caps the GPU built and of its side quads.
pub struct StencilPass {
    front: wgpu::RenderPipeline,
    back: wgpu::RenderPipeline,
    caps: [wgpu::RenderPipeline; 2],
    sides: [wgpu::RenderPipeline; 2],
    /// Layout of group 1 of the GPU-built volumes' pipelines: the build's positions, faces,
    /// casters and side quads (`build.wgsl`'s bindings 0, 1, 4 and 8).
    pub built_layout: wgpu::BindGroupLayout,
}

/// The volumes a stencil pass draws.
#[derive(Clone, Copy)]
pub enum VolumeDraws<'a> {
    /// Built on the CPU: homogeneous vertices, `w = 1` a mesh's stored vertex placed by the
    /// model matrix of the mesh whose index is its range's, `w = 0` a direction from the
    /// light's centre.
    Vertices {
        /// The vertices.
        vertices: &'a wgpu::Buffer,
        /// Each range's mesh and vertices.
        ranges: &'a [(u32, std::ops::Range<u32>)],
    },
    /// Built on the GPU (`passes::build`): the caps over every face's corners, the side quads
    /// as many as the build's draw arguments say.
    Built {
        /// A bind group of [`StencilPass::built_layout`].
        group: &'a wgpu::BindGroup,
        /// The scene's faces.
        faces: u32,
        /// The build's draw arguments (the side quads' at offset 0).
        args: &'a wgpu::Buffer,
    },
}

fn pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    entry: &str,
    unclipped_depth: bool,
    front_faces: bool,
) -> wgpu::RenderPipeline {
    let face = wgpu::StencilFaceState {
        compare: wgpu::CompareFunction::Always,
        fail_op: wgpu::StencilOperation::Keep,
        depth_fail_op: if front_faces {
            wgpu::StencilOperation::DecrementWrap
        } else {
            wgpu::StencilOperation::IncrementWrap
        },
        pass_op: wgpu::StencilOperation::Keep,
    };
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(if front_faces {
            "stencil front"
        } else {
            "stencil back"
        }),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            buffers: if entry == "vs" {
                &[Some(wgpu::VertexBufferLayout {
                    array_stride: 16,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x4],
                })]
            } else {
                &[]
            },
        },
        primitive: wgpu::PrimitiveState {
            front_face: wgpu::FrontFace::Ccw,
            cull_mode: Some(if front_faces {
                wgpu::Face::Back
            } else {
                wgpu::Face::Front
            }),
            unclipped_depth,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(false),
            depth_compare: Some(if front_faces {
                wgpu::CompareFunction::Greater
            } else {
                wgpu::CompareFunction::GreaterEqual
            }),
            stencil: wgpu::StencilState {
                front: face,
                back: face,
                read_mask: 0xff,
                write_mask: 0xff,
            },
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: None,
        multiview_mask: None,
        cache: None,
    })
}

impl StencilPass {
    /// Builds both pipelines; `unclipped_depth` when the device has `DEPTH_CLIP_CONTROL`.
    pub fn new(
        device: &wgpu::Device,
        frame_layout: &wgpu::BindGroupLayout,
        unclipped_depth: bool,
    ) -> Self {
        let module = super::shader(device, "stencil", include_str!("../shaders/stencil.wgsl"));
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("stencil"),
            bind_group_layouts: &[Some(frame_layout)],
            immediate_size: 0,
        });
        let built_layout = super::build::storage_layout(
            device,
            "built volumes",
            wgpu::ShaderStages::VERTEX,
            &[(0, true), (1, true), (4, true), (8, true)],
        );
        let built = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("stencil built"),
            bind_group_layouts: &[Some(frame_layout), Some(&built_layout)],
            immediate_size: 0,
        });
        let pair = |layout, entry| {
            [false, true]
                .map(|front| pipeline(device, layout, &module, entry, unclipped_depth, front))
        };
        let [back, front] = pair(&layout, "vs");
        StencilPass {
            front,
            back,
            caps: pair(&built, "vs_cap"),
            sides: pair(&built, "vs_side"),
            built_layout,
        }
    }

    /// Counts the volumes `draws` into the stencil of `frame.depth`, keeping the depth from the
    /// pre-pass, after zeroing the stencil.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: FrameBindings<'_>,
        draws: VolumeDraws<'_>,
        queries: PassQueries<'_>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("stencil"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: frame.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
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
        pass.set_bind_group(0, frame.frame, &[]);
        match draws {
            VolumeDraws::Vertices { vertices, ranges } => {
                pass.set_vertex_buffer(0, vertices.slice(..));
                for p in [&self.back, &self.front] {
                    pass.set_pipeline(p);
                    for (mesh, range) in ranges.iter().filter(|(_, r)| !r.is_empty()) {
                        pass.draw(range.clone(), *mesh..*mesh + 1);
                    }
                }
            }
            VolumeDraws::Built { group, faces, args } => {
                pass.set_bind_group(1, group, &[]);
                for k in 0..2 {
                    pass.set_pipeline(&self.caps[k]);
                    pass.draw(0..3 * faces, 0..2);
                    pass.set_pipeline(&self.sides[k]);
                    pass.draw_indirect(args, 0);
                }
            }
        }
        queries.end_render(&mut pass);
    }
}
