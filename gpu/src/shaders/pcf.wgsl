// `pcf`: percentage-closer filtering, Reeves, Salesin & Cook, "Rendering antialiased shadows
// with depth maps" (SIGGRAPH 1987), as Shinde 2022 (section 3.6) and Pagot et al. 2004 (section 2.1) recall
// it: the fraction of a fixed kernel x kernel block of light-map texels around the receiver's
// projection whose stored depth does not occlude it. Odd kernels are centred on the receiver's
// texel, even ones on the nearest texel corner. Each texel is tested at its centre against the
// receiver's plane (`occlusion_threshold`). iparams.x: the kernel side (3, 4 or 5).

@fragment
fn fs_pcf(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let r = receiver(vec2<i32>(pixel.xy));
    let settled = settled_v(r);
    if (settled >= 0.0) {
        return vec4<f32>(settled, 0.0, 0.0, 0.0);
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
    return shaded(r, f32(lit) / f32(k * k));
}
