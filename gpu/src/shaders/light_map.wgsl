// Light map pass of the shadow-map techniques (seeds 000-003 all start from one): the scene's
// triangles seen from the light's centre, looking along its normal, through the frustum that
// `shadow_maps::LightFrustum` fits to the scene. Depth is reversed (near / z, compare Greater) in
// a Depth32Float target; the colour target (R32Float) stores the linear light depth
// z = dot(X - c, n), which is affine in X and so interpolates exactly. Cleared to BIG: no
// surface. Both faces of every triangle are drawn; the fractional-disk technique passes only
// its back faces (and open meshes) in the vertex buffer.

struct LightOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) z: f32,
}

@vertex
fn vs_light(@location(0) rel: vec3<f32>) -> LightOut {
    let l = light_coords(rel);
    // Slopes to [-1, 1]: x right, y up (texture rows go down, as map_uv's v).
    let f = (vec2<f32>(l.x, l.y) - shadow.frustum.xy * l.z) / frustum_extent() * 2.0 - l.z;
    var out: LightOut;
    out.clip = vec4<f32>(f, shadow.depth.x, l.z);
    out.z = l.z;
    return out;
}

@fragment
fn fs_light(in: LightOut) -> @location(0) vec4<f32> {
    return vec4<f32>(in.z, 0.0, 0.0, 0.0);
}
