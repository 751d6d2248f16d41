// `gaussian`: multi-pass Gaussian contact-hardening soft shadows (Cherry & Kooima 2015). Screen-space: a
// distance map per camera pixel (r = S, the hard-shadow bit from the light's centre; g = D, the
// occluder distance ^ Dp * Dm), an optional Gaussian dilation of D, then one of three filters of
// S whose size follows D ("pcf", "single" separable Gaussian, "multi": several Poisson-tap
// Gaussian passes, D decremented by one per pass), and the read-out V = 1 - S.
// The image being filtered is map1 (ping-pong). params: x = Dp, y = Dm, z = the scene's light
// depth range (the occluder distance is a fraction of it). iparams: x = largest kernel (odd),
// y = taps of a multi pass, z = dilation kernel (odd).

// The hard-shadow bit and D of each pixel (the "distance map").
@fragment
fn fs_distance(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let r = receiver(vec2<i32>(pixel.xy));
    if (r.kind == 0u) {
        return vec4<f32>(0.0);
    }
    if (r.kind == 2u) {
        // Hard and never blurred.
        return vec4<f32>(1.0, 0.0, 0.0, 0.0);
    }
    if (!inside_map(r.uv)) {
        return vec4<f32>(0.0);
    }
    let t = texel_of(r.uv);
    let zb = depth_at(t);
    if (zb >= occlusion_threshold(r, texel_center(t))) {
        // Lit pixels are untouched (section 5).
        return vec4<f32>(0.0);
    }
    let delta = (r.l.z - zb) / shadow.params.z;
    return vec4<f32>(1.0, pow(max(delta, 0.0), shadow.params.x) * shadow.params.y, 0.0, 0.0);
}

fn image_load(x: vec2<i32>) -> vec4<f32> {
    let size = vec2<i32>(textureDimensions(map1));
    return textureLoad(map1, clamp(x, vec2<i32>(0), size - 1), 0);
}

// Kernel side from D: the odd number at most D + 1, between 1 and the largest kernel.
fn kernel_of(d: f32) -> i32 {
    return clamp(2 * i32(floor(d * 0.5)) + 1, 1, i32(shadow.iparams.x));
}

// A separable Gaussian (sigma = size / 3, "sigma be equal to size divided by three") of
// channel `c` along `dir`, `ks` wide.
fn gauss_1d(x: vec2<i32>, dir: vec2<i32>, ks: i32, c: u32) -> f32 {
    let h = (ks - 1) / 2;
    let sigma = f32(ks) / 3.0;
    var acc = 0.0;
    var wsum = 0.0;
    for (var t = -h; t <= h; t++) {
        let w = exp(-f32(t * t) / (2.0 * sigma * sigma));
        acc += w * image_load(x + dir * t)[c];
        wsum += w;
    }
    return acc / wsum;
}

// The optional dilation pass (section 3.1, "apply a Gaussian filter over the channel [D] to
// expand the penumbra region"), horizontal then vertical.
@fragment
fn fs_dilate_h(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let x = vec2<i32>(pixel.xy);
    let c = image_load(x);
    return vec4<f32>(c.r, gauss_1d(x, vec2<i32>(1, 0), i32(shadow.iparams.z), 1u), 0.0, 0.0);
}

@fragment
fn fs_dilate_v(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let x = vec2<i32>(pixel.xy);
    let c = image_load(x);
    return vec4<f32>(c.r, gauss_1d(x, vec2<i32>(0, 1), i32(shadow.iparams.z), 1u), 0.0, 0.0);
}

// Variant `pcf`: "Apply PCF to S value using D to control kernel size".
@fragment
fn fs_pcf(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let x = vec2<i32>(pixel.xy);
    let c = image_load(x);
    let ks = kernel_of(c.g);
    let h = (ks - 1) / 2;
    var acc = 0.0;
    for (var b = -h; b <= h; b++) {
        for (var a = -h; a <= h; a++) {
            acc += image_load(x + vec2<i32>(a, b)).r;
        }
    }
    return vec4<f32>(acc / f32(ks * ks), c.g, 0.0, 0.0);
}

// Variant `single`: one separable Gaussian of S sized by the centre pixel's D, horizontal then
// vertical (D is carried to the second pass).
@fragment
fn fs_single_h(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let x = vec2<i32>(pixel.xy);
    let c = image_load(x);
    return vec4<f32>(gauss_1d(x, vec2<i32>(1, 0), kernel_of(c.g), 0u), c.g, 0.0, 0.0);
}

@fragment
fn fs_single_v(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let x = vec2<i32>(pixel.xy);
    let c = image_load(x);
    return vec4<f32>(gauss_1d(x, vec2<i32>(0, 1), kernel_of(c.g), 0u), c.g, 0.0, 0.0);
}

// Variant `multi`, one pass (section 3.1 and its pseudo-code): pixels with D > 0 take the
// Gaussian-weighted sum of S at this pass's Poisson taps (the first at the origin; offsets and
// normalised weights from the CPU) and D decreases by one; the others are copied.
@fragment
fn fs_multi(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let x = vec2<i32>(pixel.xy);
    let c = image_load(x);
    if (c.g <= 0.0) {
        return vec4<f32>(c.r, 0.0, 0.0, 0.0);
    }
    var s = 0.0;
    var wsum = 0.0;
    for (var i = 0u; i < shadow.iparams.y; i++) {
        let tap = shadow.taps[i];
        s += tap.z * image_load(x + vec2<i32>(tap.xy)).r;
        wsum += tap.z;
    }
    // Divided by the f32 sum of the weights, so that a neighbourhood all in shadow stays
    // exactly 1.
    return vec4<f32>(s / wsum, max(c.g - 1.0, 0.0), 0.0, 0.0);
}

// Read-out: "If S = 0 Fragment is lit. Else if S = 1 Fragment is in shadow. Else fragment is in
// penumbra with intensity S."
@fragment
fn fs_readout(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let r = receiver(vec2<i32>(pixel.xy));
    if (r.kind == 1u && !in_core(r)) {
        return vec4<f32>(NOT_MINE, 0.0, 0.0, 0.0);
    }
    return vec4<f32>(1.0 - clamp(image_load(vec2<i32>(pixel.xy)).r, 0.0, 1.0), 0.0, 0.0, 0.0);
}
