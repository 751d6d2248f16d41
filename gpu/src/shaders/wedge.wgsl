// Penumbra-wedge pass (Akenine-Möller & Assarsson 2002; Forest et al. 2006, sections 3.1, 4.2 and 4.3).
// Each instance is one silhouette edge. A convex light-space solid holding its wedge (the smaller
// of a box and a frustum narrowing to the edge, `penumbra_volumes::render::wedge_frustum`; both
// the unit cube mapped by depth) is rasterised by its back faces, so that every pixel whose view
// ray meets the solid gets exactly one fragment, the camera inside it included. The fragment
// reads the receiver P written by the depth pre-pass, and adds the edge's signed occluded area
// per radial part of the light: outer half-wedges add, inner ones subtract. The same integral as
// the CPU oracle, `penumbra_volumes::wedge::Wedge::integral`, in f32.

struct WedgeIn {
    @location(0) corner: vec3<f32>,
    @location(1) lo: vec4<f32>,
    @location(2) hi: vec4<f32>,
    // Edge start in light space; w = multiplicity.
    @location(3) edge_from: vec4<f32>,
    @location(4) edge_to: vec4<f32>,
    // The rasterised solid's rectangles (min x, min y, max x, max y) at depths lo.z and hi.z.
    @location(5) near: vec4<f32>,
    @location(6) far: vec4<f32>,
    // A point of the edge's caster (w = 1) on a mesh that the light's plane cuts; w = 0 else.
    @location(7) caster: vec4<f32>,
}

struct WedgeOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) edge_from: vec4<f32>,
    @location(1) @interpolate(flat) edge_to: vec4<f32>,
    @location(2) @interpolate(flat) caster: vec4<f32>,
}

@group(1) @binding(0) var position: texture_2d<f32>;

@vertex
fn vs(in: WedgeIn) -> WedgeOut {
    var out: WedgeOut;
    let r = mix(in.near, in.far, in.corner.z);
    let l = vec3<f32>(mix(r.xy, r.zw, in.corner.xy), mix(in.lo.z, in.hi.z, in.corner.z));
    out.clip = frame.view_proj * vec4<f32>(from_light(l), 1.0);
    out.edge_from = in.edge_from;
    out.edge_to = in.edge_to;
    out.caster = in.caster;
    return out;
}

// `integral` and its helpers are in wedge_integral.wgsl, prepended by `passes::wedge`.

fn receiver(pixel: vec4<f32>) -> vec4<f32> {
    let hit = textureLoad(position, vec2<i32>(pixel.xy), 0);
    if (hit.w == 0.0) {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(to_light(hit.xyz), 1.0);
}

// Additive wedges: the signed area per part.
@fragment
fn fs(in: WedgeOut) -> @location(0) vec4<f32> {
    let p = receiver(in.clip);
    if (p.w == 0.0) {
        discard;
    }
    let i = integral(in.edge_from, in.edge_to, in.caster, p.xyz, AREAS_ONLY);
    if (!i.valid) {
        discard;
    }
    return i.area * i.sign;
}

// The silhouette buffer of Forest et al. 2006, in one pass split by the silhouette's stencil count: the
// signed areas (added, `Rgba32Float`), the inner half-wedges' cover of each part's border
// (added, `Rgba16Float`), and one rectangle per part, encoded in 8 bits per coordinate
// (`encode_rect`, `Rgba8Unorm`) and kept by `Min` blending. Where the silhouette's stencil count
// is zero the rectangle bounds the outer half-wedges' regions only; in its hard shadow it bounds
// the outer regions and the inner half-wedges' near regions together, which is all the blend
// needs (Forest et al. 2006, Figure 10). 40 bytes per pixel.
struct Silhouette {
    @location(0) area: vec4<f32>,
    @location(1) cover: vec4<f32>,
    @location(2) rect0: vec4<f32>,
    @location(3) rect1: vec4<f32>,
    @location(4) rect2: vec4<f32>,
    @location(5) rect3: vec4<f32>,
}

// The silhouette's stencil counts (the stencil aspect of the depth pre-pass's target).
@group(2) @binding(0) var stencil_count: texture_2d<u32>;

@fragment
fn fs_silhouette(in: WedgeOut) -> Silhouette {
    let hard = casters(textureLoad(stencil_count, vec2<i32>(in.clip.xy), 0).r) != 0u;
    let p = receiver(in.clip);
    if (p.w == 0.0) {
        discard;
    }
    let i = integral(in.edge_from, in.edge_to, in.caster, p.xyz, select(RECTS_OUTER, RECTS_INNER, hard));
    if (!i.valid) {
        discard;
    }
    var out: Silhouette;
    out.area = i.area * i.sign;
    out.cover = i.cover;
    // Outer half-wedges: the regions beyond their edges; inner ones (in hard shadow only): the
    // regions between the centre and their edges.
    out.rect0 = encode_rect(i.rect0, 0u);
    out.rect1 = encode_rect(i.rect1, 1u);
    out.rect2 = encode_rect(i.rect2, 2u);
    out.rect3 = encode_rect(i.rect3, 3u);
    return out;
}
