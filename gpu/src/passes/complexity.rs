//! The compute passes of depth-complexity sampling, `shaders/edge_lists.wgsl` ([`ComplexityPass`])
//! and `shaders/count.wgsl` (`passes::count`, which builds its pipelines with it), and what they share
//! (`shaders/complexity.wgsl`): the potential silhouette edges as the GPU reads them, the
//! uniforms and the bind group of both ([`inputs_layout`]).

use crate::timing::PassQueries;
use bytemuck::{Pod, Zeroable};
use glam::{DVec3, DVec4};
use penumbra_geom::HalfEdgeMesh;
use penumbra_geom::RectLight;
use penumbra_volumes::PotentialEdges;

/// WGSL declarations shared by the edge-list and the counting pass.
pub const COMPLEXITY_WGSL: &str = include_str!("../shaders/complexity.wgsl");

/// A potential silhouette edge (`struct Edge`): light-space ends, its faces' range and the
/// plane through it and the light's centre.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuEdge {
    /// Light-space start.
    pub a: [f32; 3],
    /// First of its faces in the face buffer.
    pub first_face: u32,
    /// Light-space end.
    pub b: [f32; 3],
    /// Number of faces.
    pub face_count: u32,
    /// `(b - a) x (c - a)` for the light's centre `c`.
    pub toward_centre: [f32; 3],
    /// Padding.
    pub pad: u32,
    /// What `a` rounded off ([`split`]).
    pub a_low: [f32; 3],
    /// Padding.
    pub pad1: u32,
    /// What `toward_centre` rounded off.
    pub toward_centre_low: [f32; 3],
    /// Padding.
    pub pad2: u32,
}

/// One face on an edge (`struct Face`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuFace {
    /// `(b - a) x (w - a)` for its third vertex `w`.
    pub normal: [f32; 3],
    /// Its triangle's index in the scene.
    pub triangle: u32,
    /// What `normal` rounded off.
    pub normal_low: [f32; 3],
    /// Padding.
    pub pad: u32,
}

/// A triangle through the light's plane (`struct Crossing`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuCrossing {
    /// Start of the segment where it crosses the light's plane.
    pub a: [f32; 2],
    /// End of that segment.
    pub b: [f32; 2],
    /// A point of the triangle just in front of the segment.
    pub inside: [f32; 3],
    /// Its triangle's index in the scene.
    pub triangle: u32,
}

/// The passes' uniforms (`struct Params`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct ComplexityParams {
    /// Potential silhouette edges.
    pub edges: u32,
    /// Triangles through the light's plane.
    pub crossings: u32,
    /// Entries the edge list holds.
    pub capacity: u32,
    /// Samples per axis, `N`.
    pub per_axis: u32,
    /// Tiles per image row.
    pub tiles_x: u32,
    /// Scene triangles (in the triangle buffer).
    pub triangles: u32,
    /// Loop iterations an invocation of the counting pass may take before it counts its pixel
    /// as cut short.
    pub budget: u32,
    /// 0, which the shader compiler cannot see: the counting pass passes the steps of its
    /// error-free transformations through an integer operation with it (`count.wgsl`,
    /// `opaque`), so that no algebraic rewrite (`(a + b) - a` to `b`) loses the rounding error
    /// they measure.
    pub zero: u32,
    /// Entries of a pixel's work (its tile's edges, then the crossings) that one dispatch of
    /// the counting pass takes (`passes::count::edges_per_dispatch`).
    pub chunk: u32,
    /// Dispatches of the counting pass recorded for them.
    pub chunks: u32,
    /// Image rows whose state and counts the counting pass keeps at once (`passes::count`).
    pub band_rows: u32,
    /// `1 + y * width + x` of a pixel whose stencil count the counting pass reads two above
    /// the rasteriser's, as a crack between the shadow volumes' faces makes it (tests,
    /// [`crate::GpuScene::set_stencil_error`]); 0 for none.
    pub stencil_error: u32,
    /// 1 where every pixel's `D(P, c)` is counted again over every triangle, its stencil
    /// count set aside: a closed mesh around the light (a room) takes every triangle as a
    /// caster in these volumes, its walls over their own receivers, where the rasterised count
    /// is not to be trusted; 0 elsewhere.
    pub recount_all: u32,
    /// Padding to the next vector.
    pub pad: [u32; 3],
    /// The eye in light space (`w` unused).
    pub eye: [f32; 4],
    /// The light-space direction of the ray through normalised device coordinates `(x, y)`:
    /// `x ray_x + y ray_y + ray_1` (`w` unused).
    pub ray_x: [f32; 4],
    /// See `ray_x`.
    pub ray_y: [f32; 4],
    /// See `ray_x`.
    pub ray_1: [f32; 4],
}

impl ComplexityParams {
    /// The camera's part: the eye and the rays through the pixels, in `light`'s space, from
    /// the inverse of `camera`'s view-projection composed in `f64` (a direction is the inverse
    /// image of a point at depth 0, at infinity).
    pub fn set_camera(&mut self, camera: &crate::frame_uniforms::FrameCamera, light: &RectLight) {
        let inv = camera.view_proj.inverse();
        let h = light.half_size();
        let dir = |v: DVec4| {
            let v = v.truncate();
            let l = DVec3::new(
                v.dot(light.tangent) / h.x,
                v.dot(light.bitangent) / h.y,
                v.dot(light.normal),
            );
            l.as_vec3().extend(0.0).to_array()
        };
        self.eye = light
            .to_light_space(camera.eye)
            .as_vec3()
            .extend(0.0)
            .to_array();
        self.ray_x = dir(inv.x_axis);
        self.ray_y = dir(inv.y_axis);
        self.ray_1 = dir(inv.w_axis);
    }
}

/// A scene triangle as the counting pass reads it, in light space (`struct Triangle`): its plane
/// `(n, w)` with `n` a unit normal and `n . x = w` (zero for a degenerate triangle), and its
/// corners, each as the `f32` nearest the `f64` light-space position and what that rounded off,
/// as the potential edges' ends (a corner the receiver shares with an edge is the same pair).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuTriangle {
    /// `(n, w)`.
    pub plane: [f32; 4],
    /// The corners (`w` unused).
    pub corners: [[f32; 4]; 3],
    /// What the corners rounded off (`w` unused).
    pub corners_low: [[f32; 4]; 3],
    /// Across the side opposite each corner, a triangle sharing it ([`NO_NEIGHBOUR`] for none;
    /// one of them where three or more faces meet).
    pub neighbours: [u32; 3],
    /// Padding.
    pub pad: u32,
}

/// [`GpuTriangle::neighbours`] where a side has no other face.
pub const NO_NEIGHBOUR: u32 = u32::MAX;

/// For each triangle of `meshes` (numbered through them in order), a triangle across the side
/// opposite each corner ([`GpuTriangle::neighbours`]).
pub fn neighbours(meshes: &[HalfEdgeMesh]) -> Vec<[u32; 3]> {
    let mut out = Vec::new();
    for mesh in meshes {
        let first = out.len() as u32;
        out.extend((0..mesh.faces.len() as u32).map(|f| {
            [0u32, 1, 2].map(|corner| {
                let h = 3 * f + (corner + 1) % 3;
                let edge = &mesh.edges[mesh.half_edges[h as usize].edge as usize];
                edge.half_edges
                    .iter()
                    .find(|&&other| other != h)
                    .map_or(NO_NEIGHBOUR, |&other| first + HalfEdgeMesh::face(other))
            })
        }));
    }
    out
}

/// A light-space vector as the `f32` nearest it and what that rounds off: the pair is the `f64`
/// vector to about 1e-14 of it, and the counting pass takes differences and dot products of
/// such pairs where `f32` alone cannot tell a side (`count.wgsl`, `side_of_p`).
pub fn split(p: DVec3) -> ([f32; 3], [f32; 3]) {
    let high = p.as_vec3();
    (high.to_array(), (p - high.as_dvec3()).as_vec3().to_array())
}

/// Each of `triangles` (world space) as a [`GpuTriangle`], from its corners in `f64`, with its
/// `neighbours`.
pub fn light_triangles(
    light: &RectLight,
    triangles: &[[DVec3; 3]],
    neighbours: &[[u32; 3]],
) -> Vec<GpuTriangle> {
    triangles
        .iter()
        .zip(neighbours)
        .map(|(t, &neighbours)| {
            let [a, b, c] = t.map(|v| light.to_light_space(v));
            let n = (b - a).cross(c - a).normalize_or_zero();
            let corner = |v: DVec3| {
                let (high, low) = split(v);
                (
                    [high[0], high[1], high[2], 0.0],
                    [low[0], low[1], low[2], 0.0],
                )
            };
            let [ca, cb, cc] = [a, b, c].map(corner);
            GpuTriangle {
                plane: n.extend(n.dot(a)).as_vec4().to_array(),
                corners: [ca.0, cb.0, cc.0],
                corners_low: [ca.1, cb.1, cc.1],
                neighbours,
                pad: 0,
            }
        })
        .collect()
}

const _: () = assert!(std::mem::size_of::<GpuEdge>() == 80);
const _: () = assert!(std::mem::size_of::<GpuFace>() == 32);
const _: () = assert!(std::mem::size_of::<GpuTriangle>() == 128);
const _: () = assert!(std::mem::size_of::<GpuCrossing>() == 32);
const _: () = assert!(std::mem::size_of::<ComplexityParams>() == 128);

/// The edges, their faces and the crossings of `edges` as the GPU reads them.
pub fn gpu_edges(edges: &PotentialEdges) -> (Vec<GpuEdge>, Vec<GpuFace>, Vec<GpuCrossing>) {
    let v = |p: glam::DVec3| p.as_vec3().to_array();
    let e = edges
        .edges
        .iter()
        .map(|e| GpuEdge {
            a: v(e.a),
            first_face: e.first_face,
            b: v(e.b),
            face_count: e.face_count,
            toward_centre: v(e.toward_centre),
            pad: 0,
            a_low: split(e.a).1,
            pad1: 0,
            toward_centre_low: split(e.toward_centre).1,
            pad2: 0,
        })
        .collect();
    let f = edges
        .faces
        .iter()
        .map(|f| GpuFace {
            normal: v(f.normal),
            triangle: f.triangle,
            normal_low: split(f.normal).1,
            pad: 0,
        })
        .collect();
    let x = edges
        .crossings
        .iter()
        .map(|x| GpuCrossing {
            a: x.a.truncate().as_vec2().to_array(),
            b: x.b.truncate().as_vec2().to_array(),
            inside: v(x.inside),
            triangle: x.triangle,
        })
        .collect();
    (e, f, x)
}

/// Layout of group 1 of both passes, at bindings 0 to 10: the positions and the stencil counts
/// of the depth pre-pass, the edges, faces and crossings, the tiles' ranges, the edge list, the
/// demand counter, the [`ComplexityParams`], V and the triangles ([`GpuTriangle`]).
pub fn inputs_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let storage = |read_only| wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Storage { read_only },
        has_dynamic_offset: false,
        min_binding_size: None,
    };
    super::layout(
        device,
        "depth-complexity inputs",
        wgpu::ShaderStages::COMPUTE,
        &[
            super::float_texture(),
            wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Uint,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            storage(true),
            storage(true),
            storage(true),
            storage(false),
            storage(false),
            storage(false),
            wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            storage(false),
            storage(true),
            wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Uint,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
        ],
    )
}

/// One compute pass of depth-complexity sampling over the frame (group 0) and the inputs
/// (group 1, [`inputs_layout`]).
pub struct ComplexityPass {
    pipeline: wgpu::ComputePipeline,
    label: &'static str,
}

impl ComplexityPass {
    /// The edge-list pass (`edge_lists.wgsl`): one workgroup per tile of
    /// [`crate::constants::TILE`] x `TILE` pixels lists the potential silhouette edges its
    /// receivers' views of the light may meet.
    pub fn edge_lists(
        device: &wgpu::Device,
        frame_layout: &wgpu::BindGroupLayout,
        inputs: &wgpu::BindGroupLayout,
    ) -> Self {
        let source = include_str!("../shaders/edge_lists.wgsl");
        Self::new(
            device,
            (frame_layout, inputs),
            ("edge lists", source, "lists"),
        )
    }

    /// The pipeline of `entry` in `source`, prepended with [`COMPLEXITY_WGSL`].
    fn new(
        device: &wgpu::Device,
        (frame_layout, inputs): (&wgpu::BindGroupLayout, &wgpu::BindGroupLayout),
        (label, source, entry): (&'static str, &str, &str),
    ) -> Self {
        let module = super::shader(device, label, &format!("{COMPLEXITY_WGSL}\n{source}"));
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: &[Some(frame_layout), Some(inputs)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(label),
            layout: Some(&layout),
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        });
        ComplexityPass { pipeline, label }
    }

    /// Records one dispatch over `groups` workgroups.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        (frame, inputs): (&wgpu::BindGroup, &wgpu::BindGroup),
        groups: (u32, u32),
        queries: PassQueries<'_>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(self.label),
            timestamp_writes: queries.compute_writes(),
        });
        queries.begin_compute(&mut pass);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame, &[]);
        pass.set_bind_group(1, inputs, &[]);
        pass.dispatch_workgroups(groups.0, groups.1, 1);
        queries.end_compute(&mut pass);
    }
}
