// Depth pre-pass (Forest et al. 2006, section 4: the visibility buffer needs the receivers' depth).
// Every scene triangle, both sides, into a Depth32FloatStencil8 target with reversed z, and the
// eye-relative surface position P into an Rgba32Float target (w, non-zero where something was
// hit, holds the triangle's index: `passes::depth::GBuffer`),
// and the surface's geometric normal, turned to face the camera, into an Rgba16Float target (the
// shadow-map techniques' receiver planes).

// `frame` (group 0) is declared in common.wgsl, prepended by `passes::shader`.

struct VertexOut {
    // Invariant: the stencil pass draws the light caps from the same positions and must land on
    // exactly the same depths.
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) rel: vec3<f32>,
    // For triangles of closed meshes, +1 where they are wound outwards and -1 where inwards;
    // 0 for open meshes. The first `frame.size.z` vertices are closed meshes' wound outwards (the
    // shadow-map techniques order them so); otherwise the mesh's model matrix carries its sign
    // in column 0's w (`frame_uniforms::model_matrix`).
    @location(1) @interpolate(flat) outward: f32,
    // The triangle's index in the scene (`penumbra_geom::Scene::triangles`): the meshes' vertices
    // lie three per triangle in that order, each mesh drawn from its first.
    @location(2) @interpolate(flat) triangle: u32,
}

// `p`: a vertex of mesh `mesh` as stored (`eye_relative` places it).
@vertex
fn vs(
    @location(0) p: vec3<f32>,
    @builtin(vertex_index) i: u32,
    @builtin(instance_index) mesh: u32,
) -> VertexOut {
    var out: VertexOut;
    let rel = eye_relative(mesh, p);
    out.clip = frame.view_proj * rel;
    out.rel = rel.xyz;
    out.outward = select(models[mesh][0].w, 1.0, f32(i) < frame.size.z);
    out.triangle = i / 3u;
    return out;
}

struct DepthOut {
    @location(0) position: vec4<f32>,
    @location(1) normal: vec4<f32>,
}

// The normal target: the triangle's plane from the screen derivatives of P (all of one
// triangle, helper lanes included), facing the eye (P is eye-relative), w = 1; for a closed
// mesh's triangle the outward normal instead (the eye-facing one, reversed where the eye sees the
// triangle's back), w = 2.
@fragment
fn fs(in: VertexOut, @builtin(front_facing) front: bool) -> DepthOut {
    var n = cross(dpdx(in.rel), dpdy(in.rel));
    let len = length(n);
    n = select(vec3<f32>(0.0), n / len, len > 0.0);
    if (dot(n, in.rel) > 0.0) {
        n = -n;
    }
    var out: DepthOut;
    out.position = vec4<f32>(in.rel, bitcast<f32>(in.triangle + TRIANGLE_BIAS));
    out.normal = vec4<f32>(n, 1.0);
    if (in.outward != 0.0) {
        out.normal = vec4<f32>(select(-n, n, front == (in.outward > 0.0)), 2.0);
    }
    return out;
}
