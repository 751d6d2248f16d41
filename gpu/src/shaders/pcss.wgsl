// `pcss`: percentage-closer soft shadows, Fernando 2005, as Shinde 2022 analyses it:
// blocker search, penumbra estimate, variable PCF (its section 2.1.4: "Blocker search, Penumbra
// estimation and filtering").
// 1. Blocker search (4.2.1): iparams.x^2 grids over the region where a blocker can hide part of
//    the light from P, the light rectangle shrunk by (d_R - z)/d_R about P's projection, at
//    nested depths z (below); d_B = mean depth of the taps nearer than P's plane whose depth puts
//    them inside that pyramid. No blocker: lit.
// 2. Penumbra width (Eq. 2): w = (d_R - d_B) * w_light / d_B, per axis of the rectangle light.
// 3. PCF over a box of half-width w / 2 on the receiver (the light's own shape, so exact for
//    parallel planes): an F x F grid, F = clamp(ceil(2 * kernel in texels), 1, iparams.y).
//    iparams.z = 1: Shinde's section 4.4 instead, four taps of a 4x4 lattice per pixel,
//    chosen by the pixel's place in its 2x2 screen quad (GPU Gems 1, 11.4).

fn cell(i: u32, n: u32) -> f32 {
    return (f32(i) + 0.5) / f32(n) * 2.0 - 1.0;
}

// Half extents in uv of the section at depth z of the pyramid from a receiver at depth zr to the
// light (half sides h): the light shrunk by (zr - z) / zr, seen from the light's centre; at most
// a quarter of the map.
fn search_region(h: vec2<f32>, zr: f32, z: f32) -> vec2<f32> {
    return min(h * max(zr - z, 0.0) / zr * uv_per_world(z), vec2<f32>(0.25));
}

fn tap_lit(r: Receiver, uv: vec2<f32>) -> f32 {
    return select(0.0, 1.0, depth_uv(uv) >= occlusion_threshold(r, uv));
}

@fragment
fn fs_pcss(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let r = receiver(vec2<i32>(pixel.xy));
    // (A receiver outside the map still searches: its pyramid may reach into the map.)
    if (r.kind != 1u) {
        return vec4<f32>(select(0.0, 1.0, r.kind == 0u), 0.0, 0.0, 0.0);
    }
    let zr = r.l.z;
    let h = shadow.light.xy;
    // 1. Blocker search over nested regions. A blocker at depth z hides part of the light from
    // P only inside the section of the pyramid from P to the light at z, which shrinks to P as z
    // nears P's depth. One ns x ns grid over the section at the scene's nearest depth (depth.y)
    // is too sparse for blockers close to P (feet on the ground, an arm over the body): they fill
    // a small middle part of it. So the search runs over sections at depths z_i, each halfway
    // from the previous one to P, an ns x ns grid each, down to a section of about a texel; a
    // round keeps its taps outside the next round's section, so every tap stands for an equal
    // share of its round's area, and each blocker inside the pyramid at its own depth counts
    // with that share. d_B is the weighted mean of their depths.
    let ns = shadow.iparams.x;
    var sum = 0.0;
    var weight = 0.0;
    var z = min(shadow.depth.y, zr);
    let texel = 1.0 / map_size();
    for (var round = 0u; round < 12u; round++) {
        let region = search_region(h, zr, z);
        let z_next = 0.5 * (z + zr);
        let inner = search_region(h, zr, z_next);
        let last = round == 11u || all(inner < texel);
        let share = region.x * region.y;
        for (var j = 0u; j < ns; j++) {
            for (var i = 0u; i < ns; i++) {
                let o = vec2<f32>(cell(i, ns), cell(j, ns)) * region;
                if (!last && all(abs(o) <= inner)) {
                    continue;
                }
                let uv = r.uv + o;
                let d = depth_uv(uv);
                if (d < occlusion_threshold(r, uv) && all(abs(o) <= search_region(h, zr, d))) {
                    sum += share * d;
                    weight += share;
                }
            }
        }
        if (last) {
            break;
        }
        z = z_next;
    }
    if (weight == 0.0) {
        return shaded(r, 1.0);
    }
    let zb = sum / weight;
    // 2. Penumbra width on the receiver, per axis (Eq. 2 with w_light = 2h).
    let w = (zr - zb) * 2.0 * h / zb;
    // 3. PCF over the box of half-width w / 2, in uv.
    let k = 0.5 * w * uv_per_world(zr);
    var lit = 0.0;
    var taps = 0u;
    if (shadow.iparams.z != 0u) {
        let p = vec2<u32>(pixel.xy);
        let o = vec2<u32>(p.x & 1u, (p.x ^ p.y) & 1u);
        for (var b = 0u; b < 2u; b++) {
            for (var a = 0u; a < 2u; a++) {
                let ij = vec2<f32>(o + 2u * vec2<u32>(a, b));
                // Cell centres of a 4x4 grid over the kernel, as `cell(i, 4)`.
                lit += tap_lit(r, r.uv + (ij - 1.5) * 0.5 * k);
                taps += 1u;
            }
        }
    } else {
        let f = clamp(
            u32(ceil(2.0 * max(k.x * map_size().x, k.y * map_size().y))),
            1u,
            shadow.iparams.y,
        );
        for (var j = 0u; j < f; j++) {
            for (var i = 0u; i < f; i++) {
                lit += tap_lit(r, r.uv + vec2<f32>(cell(i, f), cell(j, f)) * k);
                taps += 1u;
            }
        }
    }
    return shaded(r, lit / f32(taps));
}
