// Forest, Barthe & Paulin's blending of one silhouette's radial part into the final buffer's
// (2006, section 3.2), as the CPU oracle's `blend_part` does it, shared by the blend pass of
// each group of silhouettes (`blend.wgsl`) and the tiled pass (`blend_tiles.wgsl`):
//     eps = |core_f ∩ core_s|,   A = A_f + A_s - eps,   B = B_f ∪ B_s,
// a region's core being its rectangle B scaled about its centre to the area A.

// The inner half-wedges must cover this much of a part's border (length 2) for the hard region's
// rectangle to end at them (CPU: 2 (1 - 1e-9); the cover is summed in f16, 11 bits).
const FULL_COVER: f32 = 1.996;

// The core of a region of area a in the encoded rectangle e of part k: the decoded rectangle
// scaled about its centre to area a (the CPU's `blend::core`).
fn core(e: vec4<f32>, k: u32, a: f32) -> vec4<f32> {
    let t = part_rect(k);
    let ext = t.zw - t.xy;
    let lo = t.xy + e.xy * ext;
    let hi = t.zw - e.zw * ext;
    let size = hi - lo;
    let half = size * (0.5 * sqrt(clamp(a / (size.x * size.y), 0.0, 1.0)));
    let c = (lo + hi) * 0.5;
    return vec4<f32>(c - half, c + half);
}

// A part's occluded area and its rectangle, encoded (`encode_rect`).
struct Part {
    area: f32,
    rect: vec4<f32>,
}

// Part k of a silhouette of stencil count n (its casters between P and the light's centre),
// occluded area s_area > 0 (its hard shadow plus its edges), inner half-wedges' cover and
// encoded rectangle e, blended into the final buffer's part of area fa and encoded rectangle
// f_rect.
fn blend_part(k: u32, n: f32, s_area: f32, cover: f32, e: vec4<f32>, fa: f32, f_rect: vec4<f32>) -> Part {
    // In hard shadow the region reaches the part's border unless the inner half-wedges cover all
    // of it (CPU: `Accum::buffer`): then the rectangle is the whole part, (0, 0, 0, 0) encoded.
    var s_rect = e;
    if (n > 0.0 && cover < FULL_COVER) {
        s_rect = vec4<f32>(0.0);
    }
    if (fa <= 0.0) {
        return Part(s_area, s_rect);
    }
    var eps = 0.0;
    if (encoded_area(f_rect) > 0.0 && encoded_area(s_rect) > 0.0) {
        let cf = core(f_rect, k, fa);
        let cs = core(s_rect, k, s_area);
        let size = max(min(cf.zw, cs.zw) - max(cf.xy, cs.xy), vec2<f32>(0.0));
        eps = min(size.x * size.y, min(fa, s_area));
    }
    return Part(clamp(fa + s_area - eps, 0.0, 1.0), min(f_rect, s_rect));
}
