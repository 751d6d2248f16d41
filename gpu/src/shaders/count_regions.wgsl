// The counting pass's tolerances and loop counter, the lines on the light's plane and the
// regions of samples they bound: the first part of depth-complexity sampling's counting pass,
// compiled ahead of count.wgsl, which holds the pass itself (`passes::complexity`).

// A corner of the receiver lies on a plane through an edge's end (a face's, or the edge's and
// the light's centre) when it is within this share of its distance to that end, weighted by the
// normal: within the rounding of the normal and of the f32 arithmetic (the CPU oracle's f64
// uses 1e-10).
const EDGE_ON: f32 = 2e-7;
// Within this share, the oracle's: on the plane.
const TIE: f32 = 1e-10;

// The loop iterations this invocation has run, each loop's counted (`params.budget`).
var<private> spent: u32;

// f(u, v) = k.x u + k.y v + k.z on the light's plane: m . (s - o) for s = (u, v, 0).
fn line_through(m: vec3<f32>, o: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(m.x, m.y, -dot(m, o));
}

// The line where a plane through the light's centre with normal m meets the light's plane.
fn through_centre(m: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(m.x, m.y, 0.0);
}

fn line_at(k: vec3<f32>, s: vec2<f32>) -> f32 {
    return k.x * s.x + k.y * s.y + k.z;
}

// The samples an edge changes: those where four lines are positive, in the light clipped by
// the first three (`lo`, `hi` its bounding box).
struct Region {
    delta: i32,
    l0: vec3<f32>,
    l1: vec3<f32>,
    l2: vec3<f32>,
    l3: vec3<f32>,
    lo: vec2<f32>,
    hi: vec2<f32>,
}

// The light square clipped by l0, l1 and l2 (Sutherland & Hodgman): its bounding box as
// (lo, hi), empty (lo > hi) when nothing is left.
fn clipped_bounds(l0: vec3<f32>, l1: vec3<f32>, l2: vec3<f32>) -> vec4<f32> {
    var poly = array<vec2<f32>, 8>(
        vec2<f32>(-1.0, -1.0),
        vec2<f32>(1.0, -1.0),
        vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, 1.0),
        vec2<f32>(0.0),
        vec2<f32>(0.0),
        vec2<f32>(0.0),
        vec2<f32>(0.0),
    );
    var len = 4u;
    let lines = array<vec3<f32>, 3>(l0, l1, l2);
    for (var l = 0u; l < 3u; l++) {
        spent++;
        let k = lines[l];
        var out: array<vec2<f32>, 8>;
        var n = 0u;
        for (var i = 0u; i < len; i++) {
            spent++;
            let a = poly[i];
            let b = poly[(i + 1u) % len];
            let fa = line_at(k, a);
            let fb = line_at(k, b);
            if (fa >= 0.0 && n < 8u) {
                out[n] = a;
                n++;
            }
            if ((fa >= 0.0) != (fb >= 0.0) && n < 8u) {
                out[n] = a + (b - a) * (fa / (fa - fb));
                n++;
            }
        }
        poly = out;
        len = n;
        if (len == 0u) {
            return vec4<f32>(1.0, 1.0, -1.0, -1.0);
        }
    }
    var lo = poly[0];
    var hi = poly[0];
    for (var i = 1u; i < len; i++) {
        spent++;
        lo = min(lo, poly[i]);
        hi = max(hi, poly[i]);
    }
    return vec4<f32>(lo, hi);
}

// A region of the light where the four lines are positive, changed by `delta`; none where its
// box is not finite (a degenerate edge's lines, whose indices into the cells would be
// undefined: the oracle's f64 evaluation finds no sample inside either).
fn make_region(delta: i32, l0: vec3<f32>, l1: vec3<f32>, l2: vec3<f32>, l3: vec3<f32>) -> Region {
    let b = clipped_bounds(l0, l1, l2);
    if (!all(abs(b) <= vec4<f32>(2.0))) {
        return no_region();
    }
    return Region(delta, l0, l1, l2, l3, b.xy, b.zw);
}

fn no_region() -> Region {
    let z = vec3<f32>(0.0);
    return Region(0, z, z, z, z, vec2<f32>(1.0), vec2<f32>(-1.0));
}

// The part of the segment from depth za to depth zb strictly between depths 0 and zp, as
// parameters (t0, t1), empty when t0 >= t1.
fn slab(za: f32, zb: f32, zp: f32) -> vec2<f32> {
    var t = vec2<f32>(0.0, 1.0);
    let dz = zb - za;
    let bounds = array<f32, 2>(0.0, zp);
    for (var k = 0u; k < 2u; k++) {
        spent++;
        let bound = bounds[k];
        let above = k == 0u;
        if (dz == 0.0) {
            if ((za > bound) != above || za == bound) {
                return vec2<f32>(1.0, 0.0);
            }
            continue;
        }
        let s = (bound - za) / dz;
        if ((dz > 0.0) == above) {
            t.x = max(t.x, s);
        } else {
            t.y = min(t.y, s);
        }
    }
    return t;
}

// Error-free transformations (Knuth's two-sum; Dekker's product with Veltkamp's split): a
// result and its rounding error, exactly. Shader compilers may fold `(a + b) - a` to `b`,
// reassociate sums and lower `fma` to a rounded product and sum (lavapipe does all three), so
// each step's result passes through `opaque`, which no floating-point rewrite crosses, and
// products are split instead of using `fma`.
fn opaque(x: f32) -> f32 {
    return bitcast<f32>(bitcast<u32>(x) ^ params.zero);
}

fn two_sum(a: f32, b: f32) -> vec2<f32> {
    let s = opaque(a + b);
    let bb = opaque(s - a);
    let av = opaque(s - bb);
    return vec2<f32>(s, opaque(a - av) + opaque(b - bb));
}

// a as hi + lo, each of at most 12 significant bits.
fn veltkamp(a: f32) -> vec2<f32> {
    let c = opaque(a * 4097.0);
    let t = opaque(c - a);
    let hi = opaque(c - t);
    return vec2<f32>(hi, opaque(a - hi));
}

fn two_product(a: f32, b: f32) -> vec2<f32> {
    let p = opaque(a * b);
    let x = veltkamp(a);
    let y = veltkamp(b);
    let e1 = opaque(x.x * y.x - p);
    let e2 = opaque(e1 + x.x * y.y);
    let e3 = opaque(e2 + x.y * y.x);
    return vec2<f32>(p, e3 + x.y * y.y);
}
