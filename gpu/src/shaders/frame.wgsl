// The per-frame uniforms shared by every pass; `passes::shader` prepends this file to each
// pass's shader, so the layout is written once in WGSL (and once in Rust: `frame::FrameUniforms`,
// whose size is asserted). Positions are eye-relative.

struct Frame {
    // Eye-relative world to clip: reversed z, infinite far plane.
    view_proj: mat4x4<f32>,
    // Light centre minus eye.
    light_center: vec4<f32>,
    // Light normal.
    light_normal: vec4<f32>,
    // Image width, height in pixels.
    size: vec4<f32>,
    // Light tangent (xyz) and half the first side (w).
    light_tangent: vec4<f32>,
    // Light bitangent (xyz) and half the second side (w).
    light_bitangent: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;

// World (eye-relative) to light space, where the light is [-1, 1]^2 at z = 0.
fn to_light(rel: vec3<f32>) -> vec3<f32> {
    let d = rel - frame.light_center.xyz;
    return vec3<f32>(
        dot(d, frame.light_tangent.xyz) / frame.light_tangent.w,
        dot(d, frame.light_bitangent.xyz) / frame.light_bitangent.w,
        dot(d, frame.light_normal.xyz),
    );
}

// Light space to eye-relative world.
fn from_light(l: vec3<f32>) -> vec3<f32> {
    return frame.light_center.xyz
        + frame.light_tangent.xyz * (l.x * frame.light_tangent.w)
        + frame.light_bitangent.xyz * (l.y * frame.light_bitangent.w)
        + frame.light_normal.xyz * l.z;
}

// Clip position of vertex i (0, 1, 2) of a triangle covering the screen.
fn fullscreen(i: u32) -> vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.5, 1.0);
}
