// Declarations shared by the shadow-map techniques (pcf, pcss, fractional-disk, mdsm,
// gaussian); `passes::shadow_shader` prepends this file (after common.wgsl) to each of their
// shaders. The light map is a perspective view from the light's centre along its normal, fitted
// to the scene: texel (u, v) looks along light-space direction (a, b, 1) with
// (a, b) = frustum.xy + (u, 1 - v) * (frustum.zw - frustum.xy). Texels store the linear light
// depth z = dot(X - c, n) of the nearest surface (BIG where none), read with textureLoad only.

struct Shadow {
    // The frustum in slopes (x/z, y/z) of light space: (min a, min b, max a, max b).
    frustum: vec4<f32>,
    // Map width and height in texels, texels per side of a fractional-disk preprocessing cell,
    // one unused lane.
    map: vec4<f32>,
    // Projection near depth, nearest and farthest light depth of the scene, constant depth bias
    // (fraction of the receiver's depth).
    depth: vec4<f32>,
    // Light half sides hx, hy (world), radius of the disk of equal area, slope bias (texels).
    light: vec4<f32>,
    // Technique parameters (each shader names its lanes).
    params: vec4<f32>,
    iparams: vec4<u32>,
    // The slopes whose receivers this render decides (min x/z, min y/z, max x/z, max y/z): a
    // light that lights a room is rendered as several maps (`shadow_maps::windows`), each
    // receiver by the one whose core holds its slopes.
    core: vec4<f32>,
    // Per-pass filter taps (gaussian multi): offset in pixels (xy), weight (z).
    taps: array<vec4<f32>, MAX_TAPS>,
}

@group(1) @binding(0) var<uniform> shadow: Shadow;
// Eye-relative receiver position P (w = 1 where the camera ray hit something).
@group(1) @binding(1) var position: texture_2d<f32>;
// The receiver's geometric normal (xyz): outward on closed meshes (w = 2), facing the camera
// elsewhere (w = 1); w = 0 where nothing was hit.
@group(1) @binding(2) var normal_map: texture_2d<f32>;
// The technique's inputs: light maps or intermediate images (unused ones are dummies).
@group(1) @binding(3) var map0: texture_2d<f32>;
@group(1) @binding(4) var map1: texture_2d<f32>;
@group(1) @binding(5) var map2: texture_2d<f32>;
@group(1) @binding(6) var map3: texture_2d<f32>;

const PI: f32 = 3.14159265358979;

// World-unit light coordinates of an eye-relative position: along the tangent, the bitangent
// and the normal (the light depth z).
fn light_coords(rel: vec3<f32>) -> vec3<f32> {
    let d = rel - frame.light_center.xyz;
    return vec3<f32>(
        dot(d, frame.light_tangent.xyz),
        dot(d, frame.light_bitangent.xyz),
        dot(d, frame.light_normal.xyz),
    );
}

fn light_dir(rel: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        dot(rel, frame.light_tangent.xyz),
        dot(rel, frame.light_bitangent.xyz),
        dot(rel, frame.light_normal.xyz),
    );
}

fn frustum_extent() -> vec2<f32> {
    return shadow.frustum.zw - shadow.frustum.xy;
}

// Map uv (v down) of a light-space point in front of the light.
fn map_uv(l: vec3<f32>) -> vec2<f32> {
    let f = (l.xy / l.z - shadow.frustum.xy) / frustum_extent();
    return vec2<f32>(f.x, 1.0 - f.y);
}

// Light-space direction (a, b, 1) that map uv looks along.
fn uv_dir(uv: vec2<f32>) -> vec3<f32> {
    return vec3<f32>(shadow.frustum.xy + vec2<f32>(uv.x, 1.0 - uv.y) * frustum_extent(), 1.0);
}

// uv per world length at light depth z, per axis.
fn uv_per_world(z: f32) -> vec2<f32> {
    return 1.0 / (z * frustum_extent());
}

fn map_size() -> vec2<f32> {
    return shadow.map.xy;
}

fn inside_map(uv: vec2<f32>) -> bool {
    return all(uv >= vec2<f32>(0.0)) && all(uv < vec2<f32>(1.0));
}

fn texel_of(uv: vec2<f32>) -> vec2<i32> {
    return vec2<i32>(floor(uv * map_size()));
}

fn texel_center(t: vec2<i32>) -> vec2<f32> {
    return (vec2<f32>(t) + 0.5) / map_size();
}

// Depth of map0 at a texel; BIG outside the map (no occluder).
fn depth_at(t: vec2<i32>) -> f32 {
    let size = vec2<i32>(map_size());
    if (any(t < vec2<i32>(0)) || any(t >= size)) {
        return BIG;
    }
    return textureLoad(map0, t, 0).r;
}

fn depth_uv(uv: vec2<f32>) -> f32 {
    if (!inside_map(uv)) {
        return BIG;
    }
    return depth_at(texel_of(uv));
}

// A camera pixel's receiver, in light space.
struct Receiver {
    // 0: nothing hit (V = 1); 1: in front of the light and facing it (the map decides);
    // 2: not strictly in front of the light's plane, or on a closed mesh and facing away from
    // the whole light (V = 0).
    kind: u32,
    // Light coordinates of P.
    l: vec3<f32>,
    // Light-space normal: outward on closed meshes, facing the camera elsewhere.
    n: vec3<f32>,
    // Map uv of P.
    uv: vec2<f32>,
    // On a closed mesh (`n` outward).
    closed: bool,
}

fn receiver(pixel: vec2<i32>) -> Receiver {
    var r: Receiver;
    let p = textureLoad(position, pixel, 0);
    if (p.w == 0.0) {
        r.kind = 0u;
        return r;
    }
    r.l = light_coords(p.xyz);
    r.n = light_dir(textureLoad(normal_map, pixel, 0).xyz);
    r.uv = map_uv(r.l);
    r.kind = 1u;
    // The scene format's rule: only points strictly on the emitting side are lit.
    if (!strictly_in_front(p.xyz, r.l.z)) {
        r.kind = 2u;
    }
    // A point of a closed mesh whose outward normal faces away from every point of the light
    // sees none of it: its rays to the light enter the solid. (An open surface does not shadow
    // itself: V is what the point sees, whichever way it faces, as the reference defines it.)
    let nw = textureLoad(normal_map, pixel, 0).w;
    r.closed = nw > 1.5;
    if (r.closed) {
        var front = false;
        for (var i = 0u; i < 4u; i++) {
            let c = vec3<f32>(
                select(-1.0, 1.0, (i & 1u) != 0u) * shadow.light.x,
                select(-1.0, 1.0, (i & 2u) != 0u) * shadow.light.y,
                0.0,
            );
            front = front || dot(r.n, c - r.l) > 0.0;
        }
        if (!front) {
            r.kind = 2u;
        }
    }
    return r;
}

// The share of the light's area on the outer side of the receiver's tangent plane, for a point
// of a closed mesh: rays to the rest of the light leave it into the solid, so the point sees at
// most this share (exactly, a polygon clip of the light rectangle by the plane). 1 elsewhere.
// The techniques take the smaller of their estimate and this share, so that the self-shadow at
// the terminator, which the maps' depth bias lets through, is not lost.
fn front_share(r: Receiver) -> f32 {
    if (!r.closed) {
        return 1.0;
    }
    // Light points X = (u hx, v hy, 0) with n . (X - P) > 0.
    let h = shadow.light.xy;
    return square_share_above(-dot(r.n, r.l), r.n.x * h.x, r.n.y * h.y);
}

// A technique's V at receiver `r`, capped by `front_share`, as the pass's output.
fn shaded(r: Receiver, v: f32) -> vec4<f32> {
    return vec4<f32>(min(v, front_share(r)), 0.0, 0.0, 0.0);
}

// The depth of the receiver's tangent plane along the direction of map uv ("receiver-plane
// depth"), so that a tap far from P is compared with its own plane rather than with P's depth:
// this removes acne under wide kernels on sloped receivers. 0 where the plane is seen edge-on
// from the light or recedes beyond 4 times P's depth there.
fn plane_depth_or_0(r: Receiver, uv: vec2<f32>) -> f32 {
    let den = dot(r.n, uv_dir(uv));
    let z = dot(r.n, r.l) / den;
    if (!(abs(den) > 1e-6) || !(z > 0.0) || z > r.l.z * 4.0) {
        return 0.0;
    }
    return z;
}

// `plane_depth_or_0`, P's own depth where that is 0.
fn plane_depth(r: Receiver, uv: vec2<f32>) -> f32 {
    let z = plane_depth_or_0(r, uv);
    return select(r.l.z, z, z > 0.0);
}

// Largest slope of a receiver's plane that the bias follows (depth change per unit of lateral
// distance); steeper planes, and planes seen edge-on, take this one.
const MAX_SLOPE: f32 = 10.0;

// The depth a stored value must fall below for the receiver at map uv to count as occluded
// there: the plane's depth minus the bias, the constant part a fraction of the depth and the
// slope part the plane's depth change across `texels` texels.
fn threshold_across(r: Receiver, uv: vec2<f32>, texels: f32) -> f32 {
    let step = 1.0 / map_size();
    let z = plane_depth_or_0(r, uv);
    let zx = plane_depth_or_0(r, uv + vec2<f32>(step.x, 0.0));
    let zy = plane_depth_or_0(r, uv + vec2<f32>(0.0, step.y));
    // The plane's depth change across one texel, at most MAX_SLOPE texel widths.
    let texel_world = r.l.z * max(step.x * frustum_extent().x, step.y * frustum_extent().y);
    var dz = MAX_SLOPE * texel_world;
    if (z > 0.0 && zx > 0.0 && zy > 0.0) {
        dz = min(max(abs(zx - z), abs(zy - z)), dz);
    }
    let zp = select(r.l.z, z, z > 0.0);
    return zp - shadow.depth.w * zp - texels * dz;
}

// `threshold_across` with the slope bias of the parameters.
fn occlusion_threshold(r: Receiver, uv: vec2<f32>) -> f32 {
    return threshold_across(r, uv, shadow.light.w);
}

// The first texel of a kernel x kernel footprint around continuous texel coordinate t: odd
// kernels centred on t's texel, even ones on the nearest texel corner (Pagot et al.'s PCF(k, n)).
fn footprint_origin(t: vec2<f32>, kernel: i32) -> vec2<i32> {
    if (kernel % 2 == 0) {
        return vec2<i32>(floor(t - 0.5)) - (kernel / 2 - 1);
    }
    return vec2<i32>(floor(t)) - (kernel - 1) / 2;
}

// What a render writes for a receiver in another map's core (read back as "not mine").
const NOT_MINE: f32 = 2.0;

// Whether the receiver (in front of the light) lies in this map's core of slopes.
fn in_core(r: Receiver) -> bool {
    let s = r.l.xy / r.l.z;
    return all(s >= shadow.core.xy) && all(s < shadow.core.zw);
}

// V where the map has no say: 1 where nothing was hit or outside the map, 0 behind the light's
// plane (and on closed meshes facing away from the light), NOT_MINE in another map's core; -1
// where the technique decides.
fn settled_v(r: Receiver) -> f32 {
    if (r.kind == 0u) {
        return 1.0;
    }
    if (r.kind == 2u) {
        return 0.0;
    }
    if (!in_core(r)) {
        return NOT_MINE;
    }
    return select(1.0, -1.0, inside_map(r.uv));
}

// Fullscreen vertex stage of every pass of these techniques.
@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return fullscreen(i);
}
