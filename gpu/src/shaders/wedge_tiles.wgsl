// Tiled penumbra wedges (`wedges`): one workgroup per screen tile of WEDGE_TILE x WEDGE_TILE
// pixels, one invocation per pixel, culling the wedges per tile as tiled shading culls lights
// (Olsson and Assarsson 2011, "Tiled shading"; Harada, McKee and Yang 2012, "Forward+"). The
// workgroup bounds its receivers in light space; then it takes the wedges a round at a time, each
// invocation testing a run of them against that box, keeps those that meet it in their order,
// and each pixel adds the integral (`wedge_integral.wgsl`) of those whose solid holds its
// receiver. The expensive work, the integrals, is bounded by the wedges that reach the tile; the
// cheap one, the box tests, by the wedges over the tiles. Every pixel is written, in the same
// order of wedges, so the image is the same from run to run.

// The receivers (the depth pre-pass's eye-relative positions, `w` non-zero where hit).
@group(1) @binding(0) var position: texture_2d<f32>;
// Draw arguments whose word 5 is the number of wedges (the build's, or the CPU's instances').
@group(1) @binding(3) var<storage, read> wedge_args: array<u32>;
// The signed occlusion per radial part, as the rasterised pass adds it.
@group(1) @binding(4) var occlusion: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(WEDGE_TILE, WEDGE_TILE)
fn tile(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let pixel = group.xy * WEDGE_TILE + lid.xy;
    let inside = all(vec2<f32>(pixel) < frame.size.xy);
    var p = vec3<f32>(0.0);
    var has = false;
    if (inside) {
        let hit = textureLoad(position, vec2<i32>(pixel), 0);
        if (hit.w != 0.0) {
            p = to_light(hit.xyz);
            has = true;
        }
    }
    let any = receivers_box(local, has, p);
    let lo = tile_box[0];
    let hi = tile_box[1];
    var sum = vec4<f32>(0.0);
    let n = select(0u, wedge_args[5], any);
    for (var first = 0u; first < n; first += ROUND) {
        // This invocation's run of wedges, in order, tested against the tile's box.
        let start = first + local * PER_INVOCATION;
        var keep = 0u;
        var kept_here = 0u;
        for (var j = 0u; j < PER_INVOCATION; j++) {
            if (start + j < n && meets_box(solid_of(start + j), lo, hi)) {
                keep |= 1u << j;
                kept_here++;
            }
        }
        let count = keep_in_order(local, start, keep, kept_here);
        for (var k = 0u; k < count; k++) {
            let s = solid_of(kept[k]);
            let held = holds(s, p);
            if (has && held) {
                let w = tile_wedge(kept[k]);
                let e = integral(w.edge_from, w.edge_to, w.caster, p, AREAS_ONLY);
                if (e.valid) {
                    sum += e.area * e.sign;
                }
            }
        }
        workgroupBarrier();
    }
    if (inside) {
        textureStore(occlusion, vec2<i32>(pixel), sum);
    }
}
