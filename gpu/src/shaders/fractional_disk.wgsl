// `fractional-disk`: Valient & de Boer, "Fractional-Disk Soft Shadows" (2004). The light is
// the disk of the rectangle's area, radius r = shadow.light.z. Inputs: map0, the back-face
// ("second-depth") light map; map1, its preprocessed form on the preprocessing grid (G nearest
// occluder depth, B inverse distance to the hard-shadow edge); map2, the NOISE_SIZE² noise map
// (RG a Poisson disk set per row in [0, 1]^2, BA uniform start coordinates); map3, the light map
// of every surface.
// The preprocessing grid is the paper's 256² map: a cell is a block of k x k light-map texels,
// k = shadow.map.z (`shadow_inputs::fd_block`), and the texel parameters (the largest radius,
// the propagation passes, Eq. 2's q) count cells, so that they keep the paper's scale on a
// finer map. Depths are still read from the light map's own texels.
// params: x = a (Eq. 2), y = largest radius in cells, z = edge threshold, w = 1 for the disk
// re-test.
// iparams: x = most samples, y = propagation passes N.

// Texels per side of a preprocessing cell.
fn block() -> i32 {
    return i32(shadow.map.z);
}

// Eq. 2: f(q) = ceil(pi q^2 / a) samples for a disk of q cells, capped.
fn sample_count(q: f32) -> u32 {
    let f = ceil(PI * q * q / shadow.params.x);
    return u32(clamp(f, 0.0, f32(shadow.iparams.x)));
}

fn load_clamped(m: u32, t: vec2<i32>) -> vec4<f32> {
    if (m == 0u) {
        return textureLoad(map0, clamp(t, vec2<i32>(0), vec2<i32>(textureDimensions(map0)) - 1), 0);
    }
    return textureLoad(map1, clamp(t, vec2<i32>(0), vec2<i32>(textureDimensions(map1)) - 1), 0);
}

// "Shadow map preprocessing", listing 1, one cell at a time: a cell holding a texel at a depth
// discontinuity (a relative jump of params.z to one of its 8 neighbours, or a surface next to
// no surface) keeps the nearest depth of its texels and their neighbours in G and one distance
// unit (a cell) in B; the others BIG and 0. With one texel per cell, the paper's pass.
@fragment
fn fs_edges(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let k = block();
    let origin = vec2<i32>(pixel.xy) * k;
    var edge = false;
    var nearest = BIG;
    for (var j = 0; j < k * k; j++) {
        let x = origin + vec2<i32>(j % k, j / k);
        let z = load_clamped(0u, x).r;
        for (var dy = -1; dy <= 1; dy++) {
            for (var dx = -1; dx <= 1; dx++) {
                let m = load_clamped(0u, x + vec2<i32>(dx, dy)).r;
                let empty = (m >= BIG) != (z >= BIG);
                let jump = abs(m - z) > shadow.params.z * min(m, z);
                edge = edge || empty || jump;
                nearest = min(nearest, m);
            }
        }
    }
    if (edge) {
        return vec4<f32>(0.0, nearest, 1.0, 0.0);
    }
    return vec4<f32>(0.0, BIG, 0.0, 0.0);
}

// Listing 2, one of N passes over the cells: G becomes the 3x3 minimum (the nearest occluder
// near an edge), and B grows by one unit on every cell that an edge has reached, so after N
// passes B = N + 1 - d at Chebyshev distance d <= N cells from the nearest edge cell, 0 beyond.
@fragment
fn fs_propagate(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let x = vec2<i32>(pixel.xy);
    let c = load_clamped(1u, x);
    var g = c.g;
    var m = 0.0;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let n = load_clamped(1u, x + vec2<i32>(dx, dy));
            g = min(g, n.g);
            m = max(m, n.b);
        }
    }
    return vec4<f32>(c.r, g, select(0.0, c.b + 1.0, m > 0.0), 0.0);
}

fn noise(t: vec2<u32>) -> vec4<f32> {
    return textureLoad(map2, vec2<i32>(t % vec2<u32>(NOISE_SIZE)), 0);
}

// "Final rendering", listing 3, with the errata of docs/specs/fractional-disk.md fixed: the
// early-out compares the decoded edge distance with the radius, and P's own test is one of the
// N + 1 samples averaged.
@fragment
fn fs_fractional_disk(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let r = receiver(vec2<i32>(pixel.xy));
    let settled = settled_v(r);
    if (settled >= 0.0) {
        return vec4<f32>(settled, 0.0, 0.0, 0.0);
    }
    let zp = r.l.z;
    let texel = texel_of(r.uv);
    let c = textureLoad(map1, texel / block(), 0);
    let back = depth_at(texel);
    // The hard test: the back faces alone (map1's R) put a closed occluder's far side within
    // the bias of a receiver in contact with it. A receiver on an open surface (a ground) is
    // tested against the nearest surface (map3, both faces); one on a closed mesh against the
    // midpoint of the nearest surface and the nearest back face (Woo 1992), which lies beyond
    // the receiver's own lit side but in front of it where another part of a solid is near.
    let nearest = textureLoad(map3, texel, 0).r;
    let midpoint = select(nearest, 0.5 * (nearest + back), back < BIG);
    let first = select(nearest, midpoint, r.closed);
    let hard = select(1.0, 0.0, first < occlusion_threshold(r, r.uv));
    var zo = back;
    if (hard == 1.0) {
        if (c.g >= BIG) {
            // No occluder within reach: fully lit.
            return shaded(r, 1.0);
        }
        zo = c.g;
    }
    if (zp - zo <= 0.0) {
        return shaded(r, hard);
    }
    // Eq. 1: q = r d2 / d1 on the receiver's plane, in uv and in cells, clamped.
    let light_r = shadow.light.z;
    let k = f32(block());
    var q_uv = light_r * (zp - zo) / zo * uv_per_world(zp);
    var q = 0.5 * dot(q_uv, map_size()) / k;
    if (q > shadow.params.y) {
        q_uv *= shadow.params.y / q;
        q = shadow.params.y;
    }
    // The nearest edge cell is d = N - B cells away, so the nearest edge texel at least
    // max(0, (d - 1) k + 1) texels: the paper's test (distance + 1 > q) on that bound, in cells.
    let passes = f32(shadow.iparams.y);
    let d = passes - c.b;
    let edge = select(BIG, (max(0.0, (d - 1.0) * k + 1.0) + 1.0) / k, c.b > 0.0);
    if (edge > q) {
        // No hard-shadow edge within the disk: not in a penumbra.
        return shaded(r, hard);
    }
    let n = sample_count(q);
    let start = vec2<u32>(floor(noise(vec2<u32>(pixel.xy)).ba * f32(NOISE_SIZE)));
    var lit = hard;
    for (var i = 0u; i < n; i++) {
        let o = noise(vec2<u32>(start.x + i, start.y)).rg * 2.0 - 1.0;
        let uv = r.uv + o * q_uv;
        let zc = depth_uv(uv);
        let zt = occlusion_threshold(r, uv);
        var sample_lit = zc >= zt;
        if (!sample_lit && shadow.params.w != 0.0) {
            // The disk re-test (Fig. 3b): C's occluder at depth zc casts a disk of radius
            // r (z - zc) / zc about C; if P lies outside it, C's occlusion is false.
            let zpc = plane_depth(r, uv);
            let r2_uv = light_r * (zpc - zc) / zc * uv_per_world(zpc);
            sample_lit = length(o * q_uv / max(r2_uv, vec2<f32>(1e-12))) > 1.0;
        }
        lit += select(0.0, 1.0, sample_lit);
    }
    return shaded(r, lit / f32(n + 1u));
}

// Probe of Eq. 2 for the tests: pixel i gets f(i / 4).
@fragment
fn fs_probe_count(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(f32(sample_count(floor(pixel.x) * 0.25)), 0.0, 0.0, 0.0);
}
