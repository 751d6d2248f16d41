// z-fail stencil pass of the shadow volumes (Carmack 2000; Everitt & Kilgard 2002), Forest et al.'s
// first per-silhouette pass. Vertices are homogeneous: w = 1 for the casters' vertices (as the
// depth pre-pass reads them: mesh `mesh`'s stored vertices, placed by `eye_relative`), w = 0 for
// their projections to infinity away from the light's centre (world directions), so the side
// quads and dark caps reach infinity and the reversed, infinite projection puts them at depth 0.
// No colour output: the stencil operations do the counting.

// `frame` (group 0) is declared in common.wgsl, prepended by `passes::shader`.

@vertex
fn vs(
    @location(0) h: vec4<f32>,
    @builtin(instance_index) mesh: u32,
) -> @builtin(position) @invariant vec4<f32> {
    if (h.w == 0.0) {
        return frame.view_proj * h;
    }
    return frame.view_proj * eye_relative(mesh, h.xyz);
}

// The volumes the GPU built (`build.wgsl`): the meshes' stored vertices, their faces with
// their meshes, how each face casts, and the side quads.
@group(1) @binding(0) var<storage, read> built_positions: array<f32>;
@group(1) @binding(1) var<storage, read> built_faces: array<vec4<u32>>;
@group(1) @binding(4) var<storage, read> built_casters: array<i32>;
struct BuiltSide {
    start: vec4<f32>,
    to: vec4<f32>,
}
@group(1) @binding(8) var<storage, read> built_sides: array<BuiltSide>;

// A stored vertex of mesh `mesh` placed as the depth pre-pass places it, or pushed to infinity
// away from the light's centre.
fn volume_vertex(mesh: u32, p: vec3<f32>, infinite: bool) -> vec4<f32> {
    let rel = eye_relative(mesh, p);
    if (infinite) {
        return frame.view_proj * vec4<f32>(rel.xyz - frame.light_center.xyz, 0.0);
    }
    return frame.view_proj * rel;
}

// The caps, drawn over every face's three corners: instance 0 the light caps, 1 the dark caps
// (`penumbra_volumes::caps`). A face that casts nothing collapses to a point.
@vertex
fn vs_cap(
    @builtin(vertex_index) i: u32,
    @builtin(instance_index) dark: u32,
) -> @builtin(position) @invariant vec4<f32> {
    let f = i / 3u;
    let s = built_casters[f];
    if (s == 0) {
        return vec4<f32>(0.0, 0.0, 0.0, 1.0);
    }
    let face = built_faces[f];
    // Light caps run the face as it faces the centre, dark caps the other way.
    var k = i % 3u;
    if ((s < 0) != (dark == 1u) && k != 0u) {
        k = 3u - k;
    }
    let v = face[k];
    let p = vec3<f32>(built_positions[3u * v], built_positions[3u * v + 1u], built_positions[3u * v + 2u]);
    return volume_vertex(face.w & 0x7fffffffu, p, dark == 1u);
}

// The side quads, one instance each (`penumbra_volumes::side`): to, from, from at infinity;
// to, from at infinity, to at infinity.
@vertex
fn vs_side(
    @builtin(vertex_index) k: u32,
    @builtin(instance_index) i: u32,
) -> @builtin(position) @invariant vec4<f32> {
    let side = built_sides[i];
    let start = k == 1u || k == 2u || k == 4u;
    let infinite = k == 2u || k == 4u || k == 5u;
    return volume_vertex(u32(side.start.w), select(side.to.xyz, side.start.xyz, start), infinite);
}
