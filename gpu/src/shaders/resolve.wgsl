// Resolve into V. Hard shadow: V = 0 where the stencil count is positive or where P is not
// strictly on the light's emitting side, V = 1 elsewhere and where the camera ray hit nothing.
// Drawn as a full-screen triangle once per stencil outcome (zero, not zero, then negative:
// `casters`, whose draw writes the unshadowed value over the second's).

// `frame` (group 0) is declared in common.wgsl, prepended by `passes::shader`.
@group(1) @binding(0) var position: texture_2d<f32>;
// The depth pre-pass's normals: w = 2 where the receiver lies on a closed mesh, xyz outward.
@group(1) @binding(1) var normal_map: texture_2d<f32>;

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return fullscreen(i);
}

fn lit(pixel: vec4<f32>) -> vec2<f32> {
    let p = textureLoad(position, vec2<i32>(pixel.xy), 0);
    let side = dot(p.xyz - frame.light_center.xyz, frame.light_normal.xyz);
    // x: hit something, y: strictly on the emitting side.
    return vec2<f32>(p.w, select(0.0, 1.0, strictly_in_front(p.xyz, side)));
}

// Stencil count zero: lit unless behind the light's plane, or on a closed mesh facing away
// from the light's centre (the segment to it enters the solid at once, or leaves a room, and
// must cross the mesh again).
@fragment
fn fs_unshadowed(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let l = lit(pixel);
    let nm = textureLoad(normal_map, vec2<i32>(pixel.xy), 0);
    let p = textureLoad(position, vec2<i32>(pixel.xy), 0).xyz;
    let away = nm.w > 1.5 && dot(nm.xyz, frame.light_center.xyz - p) < 0.0;
    return vec4<f32>(select(select(l.y, 0.0, away), 1.0, l.x == 0.0), 0.0, 0.0, 0.0);
}

// Stencil count non-zero: in the hard shadow, unless the ray hit nothing.
@fragment
fn fs_shadowed(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let l = lit(pixel);
    return vec4<f32>(select(0.0, 1.0, l.x == 0.0), 0.0, 0.0, 0.0);
}

// The share of the light's area in front of the receiver's tangent plane where it lies on a
// closed mesh, else 1 (`penumbra_volumes::terminator::front_share`, the CPU oracle's): rays to
// the rest of the light enter the solid at once. The wedge techniques cap V by it, which gives
// the terminator of curved meshes its soft self-shadow.
fn front_share(pixel: vec4<f32>) -> f32 {
    let nm = textureLoad(normal_map, vec2<i32>(pixel.xy), 0);
    if (nm.w < 1.5) {
        return 1.0;
    }
    let p = textureLoad(position, vec2<i32>(pixel.xy), 0).xyz;
    let n = nm.xyz;
    // Over the light's square in half sides: n . (X - P) = c + a u + b v.
    let c = dot(n, frame.light_center.xyz - p);
    let a = dot(n, frame.light_tangent.xyz) * frame.light_tangent.w;
    let b = dot(n, frame.light_bitangent.xyz) * frame.light_bitangent.w;
    return square_share_above(c, a, b);
}

struct ResolveOut {
    @builtin(position) pixel: vec4<f32>,
    // The stencil count this draw resolves (the draw's instance).
    @location(0) @interpolate(flat) count: u32,
}

@group(2) @binding(0) var occlusion: texture_2d<f32>;

@vertex
fn vs_counted(@builtin(vertex_index) i: u32, @builtin(instance_index) k: u32) -> ResolveOut {
    var out: ResolveOut;
    out.pixel = fullscreen(i);
    out.count = k;
    return out;
}

// Additive wedges: V = 1 - clamp(4 n + Σ parts, 0, 4) / 4 with n the stencil count (the draw
// for count n runs with stencil reference n; the last draw takes every larger count too, and a
// draw for count 0 where the count is negative, `casters`, follows).
@fragment
fn fs_wedges(in: ResolveOut) -> @location(0) vec4<f32> {
    let l = lit(in.pixel);
    if (l.x == 0.0) {
        return vec4<f32>(1.0, 0.0, 0.0, 0.0);
    }
    if (l.y == 0.0) {
        return vec4<f32>(0.0);
    }
    let o = textureLoad(occlusion, vec2<i32>(in.pixel.xy), 0);
    let total = 4.0 * f32(in.count) + o.x + o.y + o.z + o.w;
    let v = 1.0 - clamp(total, 0.0, 4.0) / 4.0;
    return vec4<f32>(min(v, front_share(in.pixel)), 0.0, 0.0, 0.0);
}

// The final buffer of `wedges-blend` (`FINAL_WORDS` words per pixel), hard shadows included.
@group(2) @binding(0) var<storage, read> final_buffer: array<u32>;

// Blended wedges: V = 1 - clamp(Σ parts, 0, 4) / 4 from the final buffer.
@fragment
fn fs_blended(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let l = lit(pixel);
    if (l.x == 0.0) {
        return vec4<f32>(1.0, 0.0, 0.0, 0.0);
    }
    if (l.y == 0.0) {
        return vec4<f32>(0.0);
    }
    let i = final_index(vec2<u32>(pixel.xy));
    let o = unpack_final_area(final_buffer[i], final_buffer[i + 1u]);
    let total = o.x + o.y + o.z + o.w;
    let v = 1.0 - clamp(total, 0.0, 4.0) / 4.0;
    return vec4<f32>(min(v, front_share(pixel)), 0.0, 0.0, 0.0);
}

// V computed by depth-complexity sampling's counting pass, row by row, in the same buffer binding
// as the final buffer (a buffer of f32 read as words).
@fragment
fn fs_copied(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<u32>(pixel.xy);
    return vec4<f32>(bitcast<f32>(final_buffer[p.y * u32(frame.size.x) + p.x]), 0.0, 0.0, 0.0);
}
