// `pcf`: percentage-closer filtering, Reeves, Salesin & Cook, "Rendering antialiased shadows
// with depth maps" (SIGGRAPH 1987), as seed 001 (section 3.6) and seed 002 (section 2.1) recall
// it: the fraction of a fixed kernel x kernel block of light-map texels around the receiver's
// projection whose stored depth does not occlude it. Odd kernels are centred on the receiver's
// texel, even ones on the nearest texel corner. Each texel is tested at its centre against the
// receiver's plane (`occlusion_threshold`). iparams.x: the kernel side (3, 4 or 5).

// The first texel of a kernel x kernel footprint around continuous texel coordinate t.
fn footprint_origin(t: vec2<f32>, kernel: i32) -> vec2<i32> {
    if (kernel % 2 == 0) {
        return vec2<i32>(floor(t - 0.5)) - (kernel / 2 - 1);
    }
    return vec2<i32>(floor(t)) - (kernel - 1) / 2;
}

@fragment
fn fs_pcf(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let r = receiver(vec2<i32>(pixel.xy));
    if (r.kind != 1u) {
        return vec4<f32>(select(0.0, 1.0, r.kind == 0u), 0.0, 0.0, 0.0);
    }
    if (!inside_map(r.uv)) {
        return vec4<f32>(1.0, 0.0, 0.0, 0.0);
    }
    let k = i32(shadow.iparams.x);
    let o = footprint_origin(r.uv * map_size(), k);
    var lit = 0;
    for (var b = 0; b < k; b++) {
        for (var a = 0; a < k; a++) {
            let t = o + vec2<i32>(a, b);
            lit += select(0, 1, depth_at(t) >= occlusion_threshold(r, texel_center(t)));
        }
    }
    return vec4<f32>(f32(lit) / f32(k * k), 0.0, 0.0, 0.0);
}
