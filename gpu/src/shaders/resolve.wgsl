// Resolve of the hard shadow: V = 0 where the stencil count is not zero or where P is not
// strictly on the light's emitting side, V = 1 elsewhere and where the camera ray hit nothing.
// Drawn twice as a full-screen triangle, once per stencil outcome.

struct Frame {
    view_proj: mat4x4<f32>,
    light_center: vec4<f32>,
    light_normal: vec4<f32>,
    size: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(1) @binding(0) var position: texture_2d<f32>;

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.5, 1.0);
}

fn lit(pixel: vec4<f32>) -> vec2<f32> {
    let p = textureLoad(position, vec2<i32>(pixel.xy), 0);
    let side = dot(p.xyz - frame.light_center.xyz, frame.light_normal.xyz);
    // x: hit something, y: strictly on the emitting side.
    return vec2<f32>(p.w, select(0.0, 1.0, side > 0.0));
}

// Stencil count zero: lit unless behind the light's plane.
@fragment
fn fs_unshadowed(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let l = lit(pixel);
    return vec4<f32>(select(l.y, 1.0, l.x == 0.0), 0.0, 0.0, 0.0);
}

// Stencil count non-zero: in the hard shadow, unless the ray hit nothing.
@fragment
fn fs_shadowed(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let l = lit(pixel);
    return vec4<f32>(select(0.0, 1.0, l.x == 0.0), 0.0, 0.0, 0.0);
}
