// `fractional-disk`: Valient & de Boer, "Fractional-Disk Soft Shadows" (2004). The light is
// the disk of the rectangle's area, radius r = shadow.light.z. Inputs: map0, the back-face
// ("second-depth") light map; map1, its preprocessed form (R depth, G nearest occluder depth,
// B inverse distance to the hard-shadow edge); map2, the NOISE_SIZE² noise map (RG a Poisson disk set
// per row in [0, 1]^2, BA uniform start coordinates).
// params: x = a (Eq. 2), y = largest radius in texels, z = edge threshold, w = 1 for the disk
// re-test.
// iparams: x = most samples, y = propagation passes N.

// Eq. 2: f(q) = ceil(pi q^2 / a) samples for a disk of q texels, capped.
fn sample_count(q: f32) -> u32 {
    let f = ceil(PI * q * q / shadow.params.x);
    return u32(clamp(f, 0.0, f32(shadow.iparams.x)));
}

fn load_clamped(m: u32, t: vec2<i32>) -> vec4<f32> {
    let c = clamp(t, vec2<i32>(0), vec2<i32>(map_size()) - 1);
    if (m == 0u) {
        return textureLoad(map0, c, 0);
    }
    return textureLoad(map1, c, 0);
}

// "Shadow map preprocessing", listing 1: texels at a depth discontinuity (a relative jump of
// params.z, or a surface next to no surface) keep the nearest depth of their 3x3 block in G and
// one distance unit (a texel) in B; the others BIG and 0.
@fragment
fn fs_edges(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let x = vec2<i32>(pixel.xy);
    let z = load_clamped(0u, x).r;
    var edge = false;
    var nearest = z;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let m = load_clamped(0u, x + vec2<i32>(dx, dy)).r;
            let empty = (m >= BIG) != (z >= BIG);
            let jump = abs(m - z) > shadow.params.z * min(m, z);
            edge = edge || empty || jump;
            nearest = min(nearest, m);
        }
    }
    if (edge) {
        return vec4<f32>(z, nearest, 1.0, 0.0);
    }
    return vec4<f32>(z, BIG, 0.0, 0.0);
}

// Listing 2, one of N passes: G becomes the 3x3 minimum (the nearest occluder near an edge),
// and B grows by one unit on every texel that an edge has reached, so after N passes
// B = N + 1 - k at Chebyshev distance k <= N from the nearest edge texel, 0 beyond.
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
    let c = textureLoad(map1, texel_of(r.uv), 0);
    // The hard test: the back faces alone (map1's R) put a closed occluder's far side within
    // the bias of a receiver in contact with it. A receiver on an open surface (a ground) is
    // tested against the nearest surface (map3, both faces); one on a closed mesh against the
    // midpoint of the nearest surface and the nearest back face (Woo 1992), which lies beyond
    // the receiver's own lit side but in front of it where another part of a solid is near.
    let nearest = textureLoad(map3, texel_of(r.uv), 0).r;
    let midpoint = select(nearest, 0.5 * (nearest + c.r), c.r < BIG);
    let first = select(nearest, midpoint, r.closed);
    let hard = select(1.0, 0.0, first < occlusion_threshold(r, r.uv));
    var zo = c.r;
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
    // Eq. 1: q = r d2 / d1 on the receiver's plane, in uv and in texels, clamped.
    let light_r = shadow.light.z;
    var q_uv = light_r * (zp - zo) / zo * uv_per_world(zp);
    var q = 0.5 * dot(q_uv, map_size());
    if (q > shadow.params.y) {
        q_uv *= shadow.params.y / q;
        q = shadow.params.y;
    }
    let passes = f32(shadow.iparams.y);
    let edge = select(BIG, passes + 1.0 - c.b, c.b > 0.0);
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
