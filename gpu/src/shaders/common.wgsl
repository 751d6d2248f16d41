// Declarations shared by every pass; `passes::shader` prepends this file to each pass's shader,
// so each is written once in WGSL: the per-frame uniforms (and once in Rust:
// `frame_uniforms::FrameUniforms`, whose size is asserted), the light-space transforms and the
// radial parts' rectangles. Positions are eye-relative.

struct Frame {
    // Eye-relative world to clip: reversed z, infinite far plane.
    view_proj: mat4x4<f32>,
    // Light centre minus eye.
    light_center: vec4<f32>,
    // Light normal.
    light_normal: vec4<f32>,
    // Image width, height in pixels; z: how many leading scene vertices belong to closed
    // meshes wound outwards (depth pre-pass; 0 but for the shadow-map techniques).
    size: vec4<f32>,
    // Light tangent (xyz) and half the first side (w).
    light_tangent: vec4<f32>,
    // Light bitangent (xyz) and half the second side (w).
    light_bitangent: vec4<f32>,
    // A distant light's warp (`frame_uniforms::FrameUniforms::with_warp`): its direction (xyz)
    // and k (w), zero without one; its origin minus the world's eye; its origin minus the warped
    // eye.
    warp_direction: vec4<f32>,
    warp_origin: vec4<f32>,
    warp_image: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;

// One matrix per mesh: its stored vertices to eye-relative world
// (`frame_uniforms::ModelMatrix`). The depth and stencil passes draw each mesh as instance `mesh`
// and place its vertices with `eye_relative`, so that both land on exactly the same positions.
@group(0) @binding(1) var<storage, read> models: array<mat4x4<f32>>;

// Under a distant light's warp, the eye-relative world point is carried to the warped scene,
// relative to the warped eye: H(x) - H(eye) = (o - H(eye)) + k (x - o) / ((x - o).D + k).
fn eye_relative(mesh: u32, p: vec3<f32>) -> vec4<f32> {
    let world = (models[mesh] * vec4<f32>(p, 1.0)).xyz;
    let k = frame.warp_direction.w;
    if (k == 0.0) {
        return vec4<f32>(world, 1.0);
    }
    let d = world - frame.warp_origin.xyz;
    let s = k / (dot(d, frame.warp_direction.xyz) + k);
    return vec4<f32>(frame.warp_image.xyz + d * s, 1.0);
}

// World (eye-relative) to light space, where the light is [-1, 1]^2 at z = 0.
fn to_light(rel: vec3<f32>) -> vec3<f32> {
    let d = rel - frame.light_center.xyz;
    return vec3<f32>(
        dot(d, frame.light_tangent.xyz) / frame.light_tangent.w,
        dot(d, frame.light_bitangent.xyz) / frame.light_bitangent.w,
        dot(d, frame.light_normal.xyz),
    );
}

// Whether eye-relative receiver `rel`, at light depth `side` (`dot(rel - c, n)`), lies strictly
// on the light's emitting side beyond the rounding of its f32 position: a surface in the light's
// plane (a ceiling flush with its lamp) reads a few ulps either side of 0, and is not lit, as
// the exact rule of the scene format has it.
fn strictly_in_front(rel: vec3<f32>, side: f32) -> bool {
    return side > PLANE_ROUNDING * (length(rel) + length(frame.light_center.xyz));
}

// Relative rounding of a receiver's light depth: 4 ulps of f32.
const PLANE_ROUNDING: f32 = 4.8e-7;

// A float as a key whose unsigned order is the float's.
fn ordered(x: f32) -> u32 {
    let b = bitcast<u32>(x);
    return select(b | 0x80000000u, ~b, (b & 0x80000000u) != 0u);
}

fn unordered(k: u32) -> f32 {
    return bitcast<f32>(select(~k, k & 0x7fffffffu, (k & 0x80000000u) != 0u));
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

// The casters a z-fail stencil count stands for: the winding number modulo 256 read as a signed
// byte, a negative one (rasterisation's, at a caster's outline: `constants::STENCIL_SIGN`) as 0.
fn casters(stencil: u32) -> u32 {
    return select(stencil, 0u, (stencil & STENCIL_SIGN) != 0u);
}

// A rectangle as (min x, min y, max x, max y); empty when min > max. BIG (larger than any
// coordinate) comes from Rust (`constants::shared_constants`).
const EMPTY_RECT: vec4<f32> = vec4<f32>(BIG, BIG, -BIG, -BIG);

// Bounding rectangle of radial part k of the light (counter-clockwise from +x).
fn part_rect(k: u32) -> vec4<f32> {
    let r = array<vec4<f32>, 4>(
        vec4<f32>(0.0, -1.0, 1.0, 1.0),
        vec4<f32>(-1.0, 0.0, 1.0, 1.0),
        vec4<f32>(-1.0, -1.0, 0.0, 1.0),
        vec4<f32>(-1.0, -1.0, 1.0, 0.0),
    );
    return r[k];
}

// Levels of a rectangle coordinate in the visibility buffers: 8 bits per coordinate, as Forest et al. 2006
// packs them (section 4.4), relative to the part's own rectangle: the levels of the `Rgba8Unorm`
// rectangle targets (`passes::blend::SILHOUETTE_FORMATS`) and of the final buffer's
// `pack4x8unorm` words.
const RECT_LEVELS: f32 = 255.0;

// A rectangle inside part k as four values in [0, 1] that grow inwards, (min, 1 - max) relative
// to the part's rectangle, rounded outwards to whole levels, so the decoded rectangle still bounds
// the region and a `Min` blend of encodings is the encoding of the union. Empty: (1, 1, 1, 1).
fn encode_rect(r: vec4<f32>, k: u32) -> vec4<f32> {
    if (!(r.x <= r.z && r.y <= r.w)) {
        return vec4<f32>(1.0);
    }
    let t = part_rect(k);
    let ext = t.zw - t.xy;
    let lo = clamp((r.xy - t.xy) / ext, vec2<f32>(0.0), vec2<f32>(1.0));
    let hi = clamp((t.zw - r.zw) / ext, vec2<f32>(0.0), vec2<f32>(1.0));
    // The slack keeps an already-encoded rectangle's levels through decoding and encoding again.
    return floor(vec4<f32>(lo, hi) * RECT_LEVELS + 1e-3) / RECT_LEVELS;
}

// The area of an encoded rectangle (`encode_rect`), 0 when empty. An encoding's width and height
// relative to its part's rectangle (whose area is 2 for every part) are 1 - (min + (1 - max)).
// In the encoded form a union is the componentwise minimum and an intersection the maximum, so
// the blend never decodes.
fn encoded_area(e: vec4<f32>) -> f32 {
    let size = max(vec2<f32>(1.0) - e.xy - e.zw, vec2<f32>(0.0));
    return 2.0 * size.x * size.y;
}

// The final visibility buffer of `wedges-blend`, a storage buffer of `FINAL_WORDS` words per
// pixel: the occluded area per part as 16-bit unorm (two words) and each part's rectangle as
// `encode_rect` in 8-bit unorm (one word per part): 24 bytes. Zeroed: no occlusion.
// FINAL_WORDS comes from Rust (`constants::FINAL_WORDS`, through `constants::shared_constants`).

fn final_index(pixel: vec2<u32>) -> u32 {
    return (pixel.y * u32(frame.size.x) + pixel.x) * FINAL_WORDS;
}

// The occluded areas of the final buffer's first two words at `final_index`.
fn unpack_final_area(w0: u32, w1: u32) -> vec4<f32> {
    return vec4<f32>(unpack2x16unorm(w0), unpack2x16unorm(w1));
}

// The share of the light's square [-1, 1]^2 (in half sides) where c + a u + b v > 0: the light
// in front of a receiver's tangent plane, for the terminator cap (Sutherland-Hodgman against the
// one line, the area summed as the vertices come).
fn square_share_above(c: f32, a: f32, b: f32) -> f32 {
    let corners = array<vec2<f32>, 4>(
        vec2<f32>(-1.0, -1.0),
        vec2<f32>(1.0, -1.0),
        vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, 1.0),
    );
    var twice = 0.0;
    var first = vec2<f32>(0.0);
    var prev = vec2<f32>(0.0);
    var count = 0u;
    for (var i = 0u; i < 4u; i++) {
        let p0 = corners[i];
        let p1 = corners[(i + 1u) % 4u];
        let f0 = c + a * p0.x + b * p0.y;
        let f1 = c + a * p1.x + b * p1.y;
        var out = array<vec2<f32>, 2>(p0, p0);
        var n_out = 0u;
        if (f0 > 0.0) {
            out[n_out] = p0;
            n_out++;
        }
        if ((f0 > 0.0) != (f1 > 0.0)) {
            out[n_out] = p0 + (p1 - p0) * (f0 / (f0 - f1));
            n_out++;
        }
        for (var k = 0u; k < n_out; k++) {
            let v = out[k];
            if (count == 0u) {
                first = v;
            } else {
                twice += prev.x * v.y - prev.y * v.x;
            }
            prev = v;
            count++;
        }
    }
    if (count < 3u) {
        return 0.0;
    }
    twice += prev.x * first.y - prev.y * first.x;
    return clamp(0.5 * twice / 4.0, 0.0, 1.0);
}
