// Blend pass of penumbra-wedges blending (Forest, Barthe & Paulin 2006, section 3.2), once per
// silhouette (occluder): builds the silhouette's buffer per radial part from its stencil count n
// and its wedge pass's targets, exactly as the CPU oracle's `Accum::buffer`, and blends it into
// the final buffer as the oracle's `blend_part` does,
//     eps = |core_f ∩ core_s|,   A = A_f + A_s - eps,   B = B_f ∪ B_s,
// a region's core being its rectangle B scaled about its centre to the area A; skipped where
// either occlusion is zero. A compute pass over the screen tiles the silhouettes
// of one group can shadow (a workgroup per tile, an invocation per pixel), updating the final
// buffer in place.

// Silhouette buffer, as the wedge pass's `fs_silhouette` wrote it.
@group(1) @binding(0) var sil_area: texture_2d<f32>;
@group(1) @binding(1) var sil_cover: texture_2d<f32>;
@group(1) @binding(2) var sil_rect0: texture_2d<f32>;
@group(1) @binding(3) var sil_rect1: texture_2d<f32>;
@group(1) @binding(4) var sil_rect2: texture_2d<f32>;
@group(1) @binding(5) var sil_rect3: texture_2d<f32>;
// The silhouette's stencil counts (the stencil aspect of the depth pre-pass's target).
@group(1) @binding(6) var stencil_count: texture_2d<u32>;
// The final buffer: `FINAL_WORDS` words per pixel, row-major (`final_index`).
@group(1) @binding(7) var<storage, read_write> final_buffer: array<u32>;

// The tiles to blend: `count` tiles of `tiles` from `first`, each `x | y << 16` in tiles of
// `TILE` pixels (`passes::blend::TileMask::packed_tiles`).
struct TileRange {
    first: u32,
    count: u32,
}
@group(2) @binding(0) var<uniform> range: TileRange;
@group(2) @binding(1) var<storage, read> tiles: array<u32>;

// TILE (tile side in pixels) and MAX_WORKGROUPS (workgroups along x of a dispatch: the tile
// index is x + MAX_WORKGROUPS y) come from Rust (`constants::shared_constants`).

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

@compute @workgroup_size(TILE, TILE)
fn blend(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_id) local: vec3<u32>,
) {
    let t = group.x + MAX_WORKGROUPS * group.y;
    if (t >= range.count) {
        return;
    }
    let packed = tiles[range.first + t];
    let pixel = vec2<u32>(packed & 0xffffu, packed >> 16u) * TILE + local.xy;
    if (any(pixel >= vec2<u32>(frame.size.xy))) {
        return;
    }
    let px = vec2<i32>(pixel);
    let n = f32(casters(textureLoad(stencil_count, px, 0).r));
    let sa = textureLoad(sil_area, px, 0);
    let s_areas = clamp(vec4<f32>(n) + sa, vec4<f32>(0.0), vec4<f32>(1.0));
    if (all(s_areas <= vec4<f32>(0.0))) {
        return;
    }
    let i = final_index(pixel);
    let f_areas = unpack_final_area(final_buffer[i], final_buffer[i + 1u]);
    var out_areas = f_areas;
    let cover = textureLoad(sil_cover, px, 0);
    // Outer regions where the count is zero; outer and inner (near) regions in hard shadow.
    // Rectangles stay encoded (`encoded_area`); chosen per part by `select`, not an array.
    let e0 = textureLoad(sil_rect0, px, 0);
    let e1 = textureLoad(sil_rect1, px, 0);
    let e2 = textureLoad(sil_rect2, px, 0);
    let e3 = textureLoad(sil_rect3, px, 0);
    for (var k = 0u; k < 4u; k++) {
        // The silhouette's part: its hard shadow plus its edges, as a rectangle-bounded area.
        let s_area = s_areas[k];
        if (s_area <= 0.0) {
            continue;
        }
        // In hard shadow the region reaches the part's border unless the inner half-wedges
        // cover all of it (CPU: `Accum::buffer`): then the rectangle is the whole part, (0, 0,
        // 0, 0) encoded.
        var s_rect = select(select(select(e3, e2, k == 2u), e1, k == 1u), e0, k == 0u);
        if (n > 0.0 && cover[k] < FULL_COVER) {
            s_rect = vec4<f32>(0.0);
        }
        let w = i + 2u + k;
        let fa = f_areas[k];
        if (fa <= 0.0) {
            out_areas[k] = s_area;
            final_buffer[w] = pack4x8unorm(s_rect);
            continue;
        }
        let f_rect = unpack4x8unorm(final_buffer[w]);
        var eps = 0.0;
        if (encoded_area(f_rect) > 0.0 && encoded_area(s_rect) > 0.0) {
            let cf = core(f_rect, k, fa);
            let cs = core(s_rect, k, s_area);
            let size = max(min(cf.zw, cs.zw) - max(cf.xy, cs.xy), vec2<f32>(0.0));
            eps = min(size.x * size.y, min(fa, s_area));
        }
        out_areas[k] = clamp(fa + s_area - eps, 0.0, 1.0);
        final_buffer[w] = pack4x8unorm(min(f_rect, s_rect));
    }
    final_buffer[i] = pack2x16unorm(out_areas.xy);
    final_buffer[i + 1u] = pack2x16unorm(out_areas.zw);
}
