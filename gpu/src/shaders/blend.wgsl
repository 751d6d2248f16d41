// Blend pass of penumbra-wedges blending (Forest, Barthe & Paulin 2006, section 3.2), once per
// silhouette (occluder): builds the silhouette's buffer per radial part from its stencil count n
// and its wedge pass's targets, exactly as the CPU oracle's `Accum::buffer`, and blends it into
// the final buffer with
//     eps = (A_f / |B_f|) · (A_s / |B_s|) · |B_f ∩ B_s|,   A = A_f + A_s - eps,   B = B_f ∪ B_s,
// skipped where either occlusion is zero. One full-screen draw, reading the silhouette's stencil
// counts, the old final buffer and the silhouette buffer, and writing the new final buffer.

// Final buffer (old): area per part, then each part's rectangle (min x, min y, max x, max y).
@group(1) @binding(0) var final_area: texture_2d<f32>;
@group(1) @binding(1) var final_rect0: texture_2d<f32>;
@group(1) @binding(2) var final_rect1: texture_2d<f32>;
@group(1) @binding(3) var final_rect2: texture_2d<f32>;
@group(1) @binding(4) var final_rect3: texture_2d<f32>;
// Silhouette buffer, as the wedge pass's fs_silhouette_lit and fs_silhouette_hard wrote it.
@group(1) @binding(5) var sil_area: texture_2d<f32>;
@group(1) @binding(6) var sil_cover: texture_2d<f32>;
@group(1) @binding(7) var sil_min01: texture_2d<f32>;
@group(1) @binding(8) var sil_min23: texture_2d<f32>;
@group(1) @binding(9) var sil_negmax01: texture_2d<f32>;
@group(1) @binding(10) var sil_negmax23: texture_2d<f32>;

// The silhouette's stencil counts (the stencil aspect of the depth pre-pass's target).
@group(2) @binding(0) var stencil_count: texture_2d<u32>;

const BIG: f32 = 1e30;
const EMPTY_RECT: vec4<f32> = vec4<f32>(BIG, BIG, -BIG, -BIG);
// The inner half-wedges must cover this much of a part's border (length 2) for the hard region's
// rectangle to end at them (CPU: 2 (1 - 1e-9); f32 sums need more slack).
const FULL_COVER: f32 = 1.99998;

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return fullscreen(i);
}

struct FinalOut {
    @location(0) area: vec4<f32>,
    @location(1) rect0: vec4<f32>,
    @location(2) rect1: vec4<f32>,
    @location(3) rect2: vec4<f32>,
    @location(4) rect3: vec4<f32>,
}

fn rect_area(r: vec4<f32>) -> f32 {
    if (r.x <= r.z && r.y <= r.w) {
        return (r.z - r.x) * (r.w - r.y);
    }
    return 0.0;
}

fn rect_union(a: vec4<f32>, b: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(min(a.xy, b.xy), max(a.zw, b.zw));
}

fn rect_intersection(a: vec4<f32>, b: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(max(a.xy, b.xy), min(a.zw, b.zw));
}

// Bounding rectangle of radial part k (counter-clockwise from +x).
fn full_rect(k: u32) -> vec4<f32> {
    let r = array<vec4<f32>, 4>(
        vec4<f32>(0.0, -1.0, 1.0, 1.0),
        vec4<f32>(-1.0, 0.0, 1.0, 1.0),
        vec4<f32>(-1.0, -1.0, 0.0, 1.0),
        vec4<f32>(-1.0, -1.0, 1.0, 0.0),
    );
    return r[k];
}

@fragment
fn fs(@builtin(position) pixel: vec4<f32>) -> FinalOut {
    let px = vec2<i32>(pixel.xy);
    let fa = textureLoad(final_area, px, 0);
    var fr = array<vec4<f32>, 4>(
        textureLoad(final_rect0, px, 0),
        textureLoad(final_rect1, px, 0),
        textureLoad(final_rect2, px, 0),
        textureLoad(final_rect3, px, 0),
    );
    let sa = textureLoad(sil_area, px, 0);
    let cover = textureLoad(sil_cover, px, 0);
    let m01 = textureLoad(sil_min01, px, 0);
    let m23 = textureLoad(sil_min23, px, 0);
    let x01 = -textureLoad(sil_negmax01, px, 0);
    let x23 = -textureLoad(sil_negmax23, px, 0);
    // Outer regions where the count is zero; outer and inner (near) regions in hard shadow.
    let rects = array<vec4<f32>, 4>(
        vec4<f32>(m01.xy, x01.xy), vec4<f32>(m01.zw, x01.zw),
        vec4<f32>(m23.xy, x23.xy), vec4<f32>(m23.zw, x23.zw),
    );
    let n = f32(textureLoad(stencil_count, px, 0).r);
    var area = fa;
    for (var k = 0u; k < 4u; k++) {
        // The silhouette's part: its hard shadow plus its edges, as a rectangle-bounded area.
        let s_area = clamp(n + sa[k], 0.0, 1.0);
        if (s_area <= 0.0) {
            continue;
        }
        // In hard shadow the region reaches the part's border unless the inner half-wedges
        // cover all of it (CPU: `Accum::buffer`).
        var r = rects[k];
        if (n > 0.0 && cover[k] < FULL_COVER) {
            r = full_rect(k);
        }
        let s_rect = rect_intersection(r, full_rect(k));
        if (fa[k] <= 0.0) {
            area[k] = s_area;
            fr[k] = s_rect;
            continue;
        }
        let bf = rect_area(fr[k]);
        let bs = rect_area(s_rect);
        let beta = rect_area(rect_intersection(fr[k], s_rect));
        var eps = 0.0;
        if (bf > 0.0 && bs > 0.0) {
            eps = (fa[k] / bf) * (s_area / bs) * beta;
        }
        area[k] = clamp(fa[k] + s_area - eps, 0.0, 1.0);
        fr[k] = rect_union(fr[k], s_rect);
    }
    var out: FinalOut;
    out.area = area;
    out.rect0 = fr[0];
    out.rect1 = fr[1];
    out.rect2 = fr[2];
    out.rect3 = fr[3];
    return out;
}
