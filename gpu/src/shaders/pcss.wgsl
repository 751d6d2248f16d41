// `pcss`: percentage-closer soft shadows, Fernando 2005, as Shinde 2022 analyses it:
// blocker search, penumbra estimate, variable PCF (its section 2.1.4: "Blocker search, Penumbra
// estimation and filtering").
// 1. Blocker search (4.2.1): iparams.x^2 grids over the region where a blocker can hide part of
//    the light from P, the light rectangle shrunk by (d_R - z)/d_R about P's projection, at
//    nested depths z (below); the taps nearer than P's plane whose depth puts them inside that
//    pyramid are blockers, kept in depth layers (below) with one mean depth d_B each. No
//    blocker: lit.
// 2. Penumbra width (Eq. 2) per layer: w = (d_R - d_B) * w_light / d_B, per axis of the
//    rectangle light.
// 3. PCF over the light's points on an F x F grid, F = clamp(ceil(2 * widest kernel in texels),
//    1, iparams.y): a point is hidden when some layer's map tap on its ray to P, inside that
//    layer's box of half-width w / 2 on the receiver (the light's own shape, so exact for one
//    blocker parallel to the receiver), holds a blocker. iparams.z = 1: Shinde's section 4.4
//    instead, four points of a 4x4 lattice per pixel, chosen by the pixel's place in its 2x2
//    screen quad (GPU Gems 1, 11.4).

fn cell(i: u32, n: u32) -> f32 {
    return (f32(i) + 0.5) / f32(n) * 2.0 - 1.0;
}

// Half extents in uv of the section at depth z of the pyramid from a receiver at depth zr to the
// light (half sides h): the light shrunk by (zr - z) / zr, seen from the light's centre; at most
// a quarter of the map.
fn search_region(h: vec2<f32>, zr: f32, z: f32) -> vec2<f32> {
    return min(h * max(zr - z, 0.0) / zr * uv_per_world(z), vec2<f32>(0.25));
}

// Depth layers of the blocker search. Layer i holds the blockers of depth d with
// (zr - z0) / (zr - d) in [2^(i STEP), 2^((i + 1) STEP)), z0 the search's first (nearest)
// section and zr the receiver's depth: a quarter of an octave of the distance to the receiver,
// which the penumbra width (zr - d) / d follows near the receiver, and a quarter of the nested
// sections' halving step. The search's 12 rounds span 12 octaves, 48 layers.
const LAYERS: u32 = 48u;
const STEP: f32 = 0.25;
// Adjacent filled layers merge into one blocker, at most this many layers (half an octave)
// wide: finer blockers make a slanted plate (`fence`, `woody`, the pages of `nonmanifold`) a
// stack of blockers whose errors at their edges add up, too dark.
const MERGE: u32 = 2u;

// The layer of a blocker at depth d, for a receiver at depth zr and a first section at z0.
fn layer_of(zr: f32, z0: f32, d: f32) -> u32 {
    let q = max(zr - z0, 1e-30) / max(zr - d, 1e-30);
    return u32(clamp(floor(log2(max(q, 1.0)) / STEP), 0.0, f32(LAYERS - 1u)));
}

// Whether light point `cell` (in [-1, 1]^2 of the light's half sides) is hidden from the
// receiver by some blocker: blocker i (stored at its nearest layer, `cuts[i] > 0`) looks at the
// tap where the ray from that point to P crosses its mean depth, r.uv + cell * k_i, and counts
// it when the map holds a surface there in front of the receiver's plane and no deeper than the
// next deeper blocker's layers begin (`cuts[i]`): a solid's near side hides the rays that pass
// below it, further in, and the deeper blocker tests those depths itself.
fn cell_hidden(
    r: Receiver,
    cell: vec2<f32>,
    kernels: ptr<function, array<vec2<f32>, LAYERS>>,
    cuts: ptr<function, array<f32, LAYERS>>,
    first: u32,
    last: u32,
) -> bool {
    for (var i = first; i <= last; i++) {
        let cut = (*cuts)[i];
        if (cut <= 0.0) {
            continue;
        }
        let uv = r.uv + cell * (*kernels)[i];
        let d = depth_uv(uv);
        if (d < cut && d < occlusion_threshold(r, uv)) {
            return true;
        }
    }
    return false;
}

@fragment
fn fs_pcss(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let r = receiver(vec2<i32>(pixel.xy));
    // (A receiver outside the map still searches: its pyramid may reach into the map.)
    if (r.kind != 1u) {
        return vec4<f32>(select(0.0, 1.0, r.kind == 0u), 0.0, 0.0, 0.0);
    }
    if (!in_core(r)) {
        return vec4<f32>(NOT_MINE, 0.0, 0.0, 0.0);
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
    // with that share.
    //
    //
    // The blockers are kept in depth layers (`layer_of`), each with its share-weighted mean
    // depth, rather than averaged into one d_B. Fernando 2005 assumes one planar blocker
    // parallel to the receiver; under a group of objects as wide as the light, P's pyramid
    // takes in both the object right above P and the tops of taller neighbours, which hide
    // other parts of the same light. Their mean depth puts "the" blocker far nearer the light
    // than the object that hides P: the penumbra estimate (Eq. 2) widens, and the filter
    // reaches past that object's shadow into light, in the middle of its umbra (12% of the
    // umbra lit on the `scale` scene). Layered, each blocker filters at its own width and a
    // light point counts as hidden when any of them hides it, so the nearest object keeps
    // its umbra whatever lies above it. Within one object, too, the layers near the receiver
    // (a sphere's lower half, a body over its feet) get their own, narrower widths: the
    // penumbra no longer widens with the object's height.
    let ns = shadow.iparams.x;
    var sums: array<f32, LAYERS>;
    var weights: array<f32, LAYERS>;
    for (var i = 0u; i < LAYERS; i++) {
        sums[i] = 0.0;
        weights[i] = 0.0;
    }
    let z0 = min(shadow.depth.y, zr);
    var z = z0;
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
                    let l = layer_of(zr, z0, d);
                    sums[l] += share * d;
                    weights[l] += share;
                }
            }
        }
        if (last) {
            break;
        }
        z = z_next;
    }
    // 2. Blockers: runs of adjacent filled layers, at most MERGE layers each, from the
    // receiver up, each with its mean depth zb and its penumbra width on the receiver per axis
    // (Eq. 2 with w_light = 2h), as the half-width k = w / 2 in uv of its filter box (the light
    // seen from P, at depth zb). Blocker i is stored at its nearest layer; `cuts[i]`, the depth
    // where the next deeper blocker's layers begin (BIG for the deepest), bounds what it tests.
    var kernels: array<vec2<f32>, LAYERS>;
    var cuts: array<f32, LAYERS>;
    for (var i = 0u; i < LAYERS; i++) {
        cuts[i] = 0.0;
        kernels[i] = vec2<f32>(0.0);
    }
    var first = LAYERS;
    var deepest = 0u;
    var k_max = 0.0;
    var cut = BIG;
    var csum = 0.0;
    var cw = 0.0;
    var top = LAYERS;
    var gap = false;
    var start = 0u;
    for (var n = 0u; n <= LAYERS; n++) {
        let i = LAYERS - 1u - min(n, LAYERS - 1u);
        let filled = n < LAYERS && weights[i] > 0.0;
        let close = cw > 0.0 && (n == LAYERS || (filled && (gap || start - i >= MERGE)));
        if (close) {
            let zb = csum / cw;
            let w = (zr - zb) * 2.0 * h / zb;
            kernels[top] = 0.5 * w * uv_per_world(zr);
            k_max = max(k_max, max(kernels[top].x * map_size().x, kernels[top].y * map_size().y));
            cuts[top] = cut;
            cut = zr - (zr - z0) * exp2(-STEP * f32(top));
            first = top;
            deepest = max(deepest, top);
            csum = 0.0;
            cw = 0.0;
        }
        if (filled) {
            if (cw == 0.0) {
                start = i;
            }
            csum += sums[i];
            cw += weights[i];
            top = i;
            gap = false;
        } else {
            gap = true;
        }
    }
    if (first == LAYERS) {
        return shaded(r, 1.0);
    }
    // 3. PCF: the light's points on a grid, each hidden when some blocker hides it.
    var lit = 0.0;
    var taps = 0u;
    if (shadow.iparams.z != 0u) {
        let p = vec2<u32>(pixel.xy);
        let o = vec2<u32>(p.x & 1u, (p.x ^ p.y) & 1u);
        for (var b = 0u; b < 2u; b++) {
            for (var a = 0u; a < 2u; a++) {
                let ij = vec2<f32>(o + 2u * vec2<u32>(a, b));
                // Cell centres of a 4x4 grid over the kernel, as `cell(i, 4)`.
                let c = (ij - 1.5) * 0.5;
                lit += select(1.0, 0.0, cell_hidden(r, c, &kernels, &cuts, first, deepest));
                taps += 1u;
            }
        }
    } else {
        let f = clamp(u32(ceil(2.0 * k_max)), 1u, shadow.iparams.y);
        for (var j = 0u; j < f; j++) {
            for (var i = 0u; i < f; i++) {
                let c = vec2<f32>(cell(i, f), cell(j, f));
                lit += select(1.0, 0.0, cell_hidden(r, c, &kernels, &cuts, first, deepest));
                taps += 1u;
            }
        }
    }
    return shaded(r, lit / f32(taps));
}
