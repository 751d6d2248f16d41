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
        if (s_areas[k] <= 0.0) {
            continue;
        }
        let w = i + 2u + k;
        let e = select(select(select(e3, e2, k == 2u), e1, k == 1u), e0, k == 0u);
        let part = blend_part(k, n, s_areas[k], cover[k], e, f_areas[k], unpack4x8unorm(final_buffer[w]));
        out_areas[k] = part.area;
        final_buffer[w] = pack4x8unorm(part.rect);
    }
    final_buffer[i] = pack2x16unorm(out_areas.xy);
    final_buffer[i + 1u] = pack2x16unorm(out_areas.zw);
}
