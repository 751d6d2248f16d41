// The counting pass's tolerances and loop counter, the lines on the light's plane and the
// regions of samples they bound, and the regions an edge and a triangle through the light's
// plane change: the first part of depth-complexity sampling's counting pass, compiled ahead of
// count.wgsl, which holds the pass itself (`passes::complexity`).

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

// The regions of the samples an edge and a triangle through the light's plane change, and the
// pyramid from a point to the light that bounds them.

// The samples edge `ei` separates from the centre as seen from `pl` on triangle `receiver`
// (`penumbra_volumes::region::edge_region`); delta 0 when it changes none.
fn edge_region(ei: u32, pl: vec3<f32>, pyramid: array<vec4<f32>, 5>, receiver: u32) -> Region {
    let e = edges[ei];
    let a = e.a;
    let b = e.b;
    let side_c = side_of_p(e.toward_centre, e.toward_centre_low, a, e.a_low);
    if (side_c == 0.0) {
        return no_region();
    }
    var delta = 0i;
    for (var f = e.first_face; f < e.first_face + e.face_count; f++) {
        spent++;
        let face = faces[f];
        if (face.triangle == receiver) {
            continue;
        }
        // P on a face's plane sees it edge-on: it covers no sample.
        let s = side_of_p(face.normal, face.normal_low, a, e.a_low);
        if (s == 0.0) {
            continue;
        }
        if ((s < 0.0) != (side_c < 0.0)) {
            delta += 1;
        } else {
            delta -= 1;
        }
    }
    if (delta == 0) {
        return no_region();
    }
    for (var k = 0u; k < 5u; k++) {
        spent++;
        let q = pyramid[k];
        if (dot(q.xyz, a) + q.w < 0.0 && dot(q.xyz, b) + q.w < 0.0) {
            return no_region();
        }
    }
    let t = slab(a.z, b.z, pl.z);
    if (!(t.x < t.y)) {
        return no_region();
    }
    let l = b - a;
    // The plane of P and the edge, from the receiver's corners: for an edge of the receiver's
    // own triangle, that triangle's plane exactly.
    let m = cross(l, from_edge(a, e.a_low, b));
    let o1 = dot(m, -a);
    if (o1 == 0.0) {
        return no_region();
    }
    let flip = sign(o1);
    // Three of the four planes pass through the light's centre, the origin: their lines meet
    // the light's plane through it, with no constant term (in exact arithmetic the oracle's
    // is 0 too; computed in f32 it would be rounding noise). `o2` is the plane of the edge
    // and the centre, `f0` and `f1` those of P, the centre and each end.
    let o2 = through_centre(cross(a, b) * flip);
    let o3 = line_through(-m * flip, a);
    let f0 = through_centre(cross(pl, a));
    let f1 = through_centre(cross(pl, b));
    // `f0 f1 < 0` holds on two opposite cones at the centre; the samples lie in the one that
    // holds the edge's projection from P. The oracle tests the projection q of a point of the
    // edge between depths 0 and P's against f0: f0(q) = det(P, a, q), a positive multiple of
    // det(P, a, b) = side_c, whose sign is taken here from the precise side test (the
    // projection runs within rounding of the centre where side_c is that small).
    if (side_c > 0.0) {
        return make_region(delta, o3, f0, -f1, o2);
    }
    return make_region(delta, o3, -f0, f1, o2);
}

fn cross2(a: vec2<f32>, b: vec2<f32>) -> f32 {
    return a.x * b.y - a.y * b.x;
}

// The samples whose count a triangle through the light's plane changes
// (`penumbra_volumes::region::crossing_region`).
fn crossing_region(x: Crossing, pl: vec3<f32>, receiver: u32) -> Region {
    if (x.triangle == receiver || !(x.inside.z < pl.z)) {
        return no_region();
    }
    let a = x.a;
    let b = x.b;
    let side_c = cross2(b - a, -a);
    let q = pl + (x.inside - pl) * (pl.z / (pl.z - x.inside.z));
    let side_q = cross2(b - a, q.xy - a);
    if (side_c == 0.0 || side_q == 0.0) {
        return no_region();
    }
    let delta = select(-1, 1, (side_q < 0.0) != (side_c < 0.0));
    let beyond = vec3<f32>(-(b - a).y, (b - a).x, cross2(b - a, -a)) * -sign(side_c);
    let ga = vec3<f32>(-a.y, a.x, 0.0);
    let gb = -vec3<f32>(-b.y, b.x, 0.0);
    let mid = 0.5 * (a + b);
    if (line_at(ga, mid) > 0.0) {
        return make_region(delta, beyond, ga, gb, beyond);
    }
    return make_region(delta, beyond, -ga, -gb, beyond);
}

// The five planes (n, d) of the pyramid from p to the light (`penumbra_volumes::potential::pyramid_planes`).
fn pyramid_planes(p: vec3<f32>) -> array<vec4<f32>, 5> {
    var planes: array<vec4<f32>, 5>;
    planes[0] = vec4<f32>(0.0, 0.0, 1.0, 0.0);
    for (var k = 0u; k < 4u; k++) {
        spent++;
        let c0 = light_corner(k);
        let c1 = light_corner((k + 1u) % 4u);
        var n = cross(c0 - p, c1 - p);
        if (dot(n, -p) < 0.0) {
            n = -n;
        }
        planes[k + 1u] = vec4<f32>(n, -dot(n, p));
    }
    return planes;
}
