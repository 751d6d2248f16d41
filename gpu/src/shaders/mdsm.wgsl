// `mdsm`: multiple-depth shadow maps, Pagot, Comba & Oliveira (2004), a point-light filter
// at the light's centre (the paper has no light size).
// Build pass (section 4.3, section 5: "The second and third depth values were chosen as the
// maximum and minimum values on a neighborhood in the first shadow map"): per texel the base
// depth Z_b and the min and max over the (2R + 1)^2 neighbourhood, stored in descending order
// (3-SM: max, Z_b, min; 2-SM: max, Z_b or Z_b, min), unused lanes repeating the last.
// Shade pass: the n-shadow test of each tap, s = #{j <= n : Z_j < d} with outcome s / n, averaged
// over a k = kernel^2 box: PCF(k, n), with at most n k + 1 distinct values (Table 1).
// iparams: x = n, y = kernel side, z = R, w = 1 for a 2-SM keeping the max (0: the min).

@fragment
fn fs_build(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let x = vec2<i32>(pixel.xy);
    let size = vec2<i32>(map_size());
    let zb = textureLoad(map0, x, 0).r;
    let rad = i32(shadow.iparams.z);
    var mn = zb;
    var mx = zb;
    for (var dy = -rad; dy <= rad; dy++) {
        for (var dx = -rad; dx <= rad; dx++) {
            let y = clamp(x + vec2<i32>(dx, dy), vec2<i32>(0), size - 1);
            let z = textureLoad(map0, y, 0).r;
            mn = min(mn, z);
            mx = max(mx, z);
        }
    }
    switch shadow.iparams.x {
        case 3u: {
            return vec4<f32>(mx, zb, mn, mn);
        }
        case 2u: {
            return select(vec4<f32>(zb, mn, mn, mn), vec4<f32>(mx, zb, zb, zb), shadow.iparams.w == 1u);
        }
        default: {
            return vec4<f32>(zb);
        }
    }
}

// The n-shadow test of one texel's depths z against receiver depth d: how many of the first n
// lie in front of the receiver (ties count lit).
fn count_front(z: vec4<f32>, d: f32) -> i32 {
    var s = 0;
    for (var j = 0u; j < shadow.iparams.x; j++) {
        s += select(0, 1, z[j] < d);
    }
    return s;
}

fn mdsm_load(t: vec2<i32>) -> vec4<f32> {
    let size = vec2<i32>(map_size());
    return textureLoad(map1, clamp(t, vec2<i32>(0), size - 1), 0);
}

@fragment
fn fs_mdsm(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let r = receiver(vec2<i32>(pixel.xy));
    let settled = settled_v(r);
    if (settled >= 0.0) {
        return vec4<f32>(settled, 0.0, 0.0, 0.0);
    }
    let ks = i32(shadow.iparams.y);
    let o = footprint_origin(r.uv * map_size(), ks);
    // The extra depths come from up to R sqrt(2) texels away: the slope bias covers them too.
    let texels = shadow.light.w + f32(shadow.iparams.z) * 1.4142135;
    var s = 0;
    for (var b = 0; b < ks; b++) {
        for (var a = 0; a < ks; a++) {
            let t = o + vec2<i32>(a, b);
            s += count_front(mdsm_load(t), threshold_across(r, texel_center(t), texels));
        }
    }
    let n = i32(shadow.iparams.x);
    return shaded(r, 1.0 - f32(s) / f32(n * ks * ks));
}

// Probe of PCF(k, n) for the distinct-values property: pixel (i, j) takes footprint origin
// number i (row-major over the origins whose taps and neighbourhoods lie inside the map) and
// receiver depth (j + 0.5) / params.y, with no bias; returns the shadowed fraction.
@fragment
fn fs_probe(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let ks = i32(shadow.iparams.y);
    let rad = i32(shadow.iparams.z);
    let w = i32(map_size().x) - ks - 2 * rad + 1;
    let i = i32(pixel.x);
    let o = vec2<i32>(rad + i % w, rad + i / w);
    let d = pixel.y / shadow.params.y;
    var s = 0;
    for (var b = 0; b < ks; b++) {
        for (var a = 0; a < ks; a++) {
            s += count_front(mdsm_load(o + vec2<i32>(a, b)), d);
        }
    }
    let n = i32(shadow.iparams.x);
    return vec4<f32>(f32(s) / f32(n * ks * ks), 0.0, 0.0, 0.0);
}
