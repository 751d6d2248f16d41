// The counting pass's receiver: the triangle and the point of it that a pixel's ray meets, as
// the CPU oracle's ray caster finds them, and the sides of planes taken from its corners,
// compiled ahead of count.wgsl (`passes::count::COUNT_WGSL`).

// The receiver's triangle, for the side tests: its corners and P's barycentric weights on it.
// The side of P of a plane through an edge's end `a` is the weighted sum of its corners' sides
// (`side_of_p`), each zero where the corner lies on the plane within rounding. A corner the
// receiver shares with the edge or a face lies on that plane, so a face next to the receiver, or
// the plane of an edge of its own and the light's centre, takes its side from the receiver's
// other corners: P's f32 rounding, which can move P across a plane that passes within a fraction
// of a pixel of it, does not enter. Each corner and each edge's end carries what its f32 rounded
// off, so that corner - end is as precise as in the oracle's f64. Where the triangle is unknown
// or degenerate, P stands for all three corners.
var<private> corners: array<vec3<f32>, 3>;
var<private> corners_low: array<vec3<f32>, 3>;
var<private> weights: vec3<f32>;

fn set_receiver(pl: vec3<f32>, receiver: u32) {
    corners = array<vec3<f32>, 3>(pl, pl, pl);
    corners_low = array<vec3<f32>, 3>(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
    weights = vec3<f32>(1.0, 0.0, 0.0);
    if (receiver >= params.triangles) {
        return;
    }
    let t = triangles[receiver];
    let w = barycentric(t, pl);
    let sum = w.x + w.y + w.z;
    if (!(sum > 0.0) || !(sum < BIG)) {
        return;
    }
    corners = array<vec3<f32>, 3>(t.corners[0].xyz, t.corners[1].xyz, t.corners[2].xyz);
    corners_low = array<vec3<f32>, 3>(t.corners_low[0].xyz, t.corners_low[1].xyz, t.corners_low[2].xyz);
    weights = w / sum;
}

// The receiver through pixel `px` as the oracle's first hit finds it. The rasteriser snaps the
// triangles' corners to a fraction of a pixel, so a pixel centre that close to an edge can land
// on the wrong triangle, or on the wrong surface at an outline: where the rasteriser's,
// `receiver` (P at `pl`), does not hold the pixel's ray, or (`holds`) where another triangle
// nearer the eye does, of the triangles across the receiver's sides, those of the
// neighbouring pixels and the pixel's candidate (`candidates.wgsl`), the nearest to the eye
// that holds the ray: (P on it, its index); `receiver` and `pl` where none does.
fn ray_receiver(px: vec2<u32>, receiver: u32, pl: vec3<f32>, holds: bool) -> vec4<f32> {
    best_hit = vec4<f32>(pl, bitcast<f32>(receiver));
    best_depth = select(BIG, length(pl - params.eye.xyz) * (1.0 - 1e-5), holds);
    let size = vec2<i32>(frame.size.xy);
    let across = triangles[receiver].neighbours;
    for (var k = 0u; k < 3u; k++) {
        spent++;
        consider(px, across[k], receiver, pl);
    }
    // A neighbouring pixel's triangle, and those across its sides: a triangle smaller than a
    // pixel may be no pixel's.
    for (var k = 0u; k < 9u; k++) {
        spent++;
        let q = vec2<i32>(px) + vec2<i32>(i32(k % 3u) - 1, i32(k / 3u) - 1);
        if (k == 4u || any(q < vec2<i32>(0)) || any(q >= size)) {
            continue;
        }
        let w = textureLoad(position, q, 0).w;
        let c = receiver_triangle(w);
        if (w == 0.0 || c == receiver || c >= params.triangles) {
            continue;
        }
        if (!consider(px, c, receiver, pl)) {
            let next = triangles[c].neighbours;
            consider(px, next[0], receiver, pl);
            consider(px, next[1], receiver, pl);
            consider(px, next[2], receiver, pl);
        }
    }
    // The nearest triangle that holds the ray, found by testing the ray against every
    // triangle near the pixel (`candidates.wgsl`): a sliver the rasteriser drew on no pixel.
    let nearest = textureLoad(candidate, vec2<i32>(px), 0).r;
    if (nearest != 0u) {
        consider(px, nearest - 1u, receiver, pl);
    }
    return best_hit;
}

// `ray_receiver`'s best candidate so far and its distance from the eye.
var<private> best_hit: vec4<f32>;
var<private> best_depth: f32;

// Takes triangle c as `ray_receiver`'s best candidate where it holds the pixel's ray nearer the
// eye than the best so far; whether it holds the ray at all.
fn consider(px: vec2<u32>, c: u32, receiver: u32, pl: vec3<f32>) -> bool {
    if (c == receiver || c >= params.triangles) {
        return false;
    }
    let t = triangles[c];
    let at = on_plane(px, t.plane);
    let eye = params.eye.xyz;
    if (!(dot(at - eye, pl - eye) > 0.0) || !all(barycentric(t, at) >= vec3<f32>(0.0))) {
        return false;
    }
    let depth = length(at - eye);
    if (depth < best_depth) {
        best_hit = vec4<f32>(at, bitcast<f32>(c));
        best_depth = depth;
    }
    return true;
}

// The side of P of a plane, and whether the segment from P to a light point crosses a triangle,
// from the receiver's corners (`set_receiver`).

// Σ w_k f(corner k) for f(x) = k . (x - o), the receiver's corners on the plane
// (`set_receiver`) dropping out exactly: the side of P of the plane through o with normal k,
// up to a positive factor.
fn side_from(k: vec3<f32>, o: vec3<f32>, a: vec3<f32>, b: vec3<f32>) -> f32 {
    // Written out rather than looped: this runs once per triangle of the scene.
    return corner_term(0u, k, o, a, b) + corner_term(1u, k, o, a, b) + corner_term(2u, k, o, a, b);
}

// w_i k . (corner i - o), zero where the corner is a or b.
fn corner_term(i: u32, k: vec3<f32>, o: vec3<f32>, a: vec3<f32>, b: vec3<f32>) -> f32 {
    let c = corners[i];
    return select(weights[i] * dot(k, c - o), 0.0, all(c == a) || all(c == b));
}

// w_i n . (corner i - v0), zero where the corner is one of v0, v1, v2.
fn plane_term(i: u32, n: vec3<f32>, v0: vec3<f32>, v1: vec3<f32>, v2: vec3<f32>) -> f32 {
    let c = corners[i];
    let on_t = all(c == v0) || all(c == v1) || all(c == v2);
    return select(weights[i] * dot(n, c - v0), 0.0, on_t);
}

// Whether the segment from P (the receiver's corners weighted, `set_receiver`) to the light
// point o crosses triangle t, edges included (the oracle's `Tracer::crosses`): P lies within
// the three planes through o and t's sides, and P and o lie strictly on opposite sides of t's
// plane. A corner of the receiver that t shares lies on those planes exactly, so a triangle
// folded against the receiver along a shared side is crossed or not by that fold's shape, not
// by P's rounding.
fn crosses_to(t: Triangle, o: vec3<f32>) -> bool {
    let v0 = t.corners[0].xyz;
    let v1 = t.corners[1].xyz;
    let v2 = t.corners[2].xyz;
    let s0 = side_of_side(v0, v1, o);
    let s1 = side_of_side(v1, v2, o);
    let s2 = side_of_side(v2, v0, o);
    let inside = (s0 >= 0.0 && s1 >= 0.0 && s2 >= 0.0) || (s0 <= 0.0 && s1 <= 0.0 && s2 <= 0.0);
    let n = cross(v1 - v0, v2 - v0);
    let at_p = plane_term(0u, n, v0, v1, v2) + plane_term(1u, n, v0, v1, v2)
        + plane_term(2u, n, v0, v1, v2);
    return inside && at_p * dot(n, o - v0) < 0.0;
}

// The side of P of the plane through the light point o and a triangle's side from a to b, up
// to a positive factor: the normal `(a - o) x (b - a)` taken as `(lo - o) x (hi - lo)`, its
// ends in one order whichever way the triangle runs along them, so that the two triangles of
// a shared side get exactly opposite values and a segment through it crosses one of them, not
// both or neither (with the products' rounding fused differently each way, `a x b` lost a
// crossing or counted one twice where P lay within 1e-6 of such a plane). The difference of
// close ends is exact, so the normal is as precise as its ends.
fn side_of_side(a: vec3<f32>, b: vec3<f32>, o: vec3<f32>) -> f32 {
    let forward = a.x < b.x || (a.x == b.x && (a.y < b.y || (a.y == b.y && a.z < b.z)));
    let lo = select(b, a, forward);
    let hi = select(a, b, forward);
    let s = side_from(cross(lo - o, hi - lo), o, a, b);
    return select(-s, s, forward);
}

// Corner i minus the point (a, a_low): the difference of the f32 parts is exact for points
// within a factor of two of each other (Sterbenz), so the result is within f32 rounding of the
// f64 difference.
fn corner_minus(i: u32, a: vec3<f32>, a_low: vec3<f32>) -> vec3<f32> {
    return (corners[i] - a) + (corners_low[i] - a_low);
}

// (k + k_low) . (corner i - (a + a_low)) in about twice f32's precision: for a corner that f32
// finds on the plane.
fn precise_side(k: vec3<f32>, k_low: vec3<f32>, i: u32, a: vec3<f32>, a_low: vec3<f32>) -> f32 {
    // Written out rather than looped: lavapipe counts a loop's iterations against its limit.
    let dx = two_sum(corners[i].x, -a.x);
    let dy = two_sum(corners[i].y, -a.y);
    let dz = two_sum(corners[i].z, -a.z);
    let d = vec3<f32>(dx.x, dy.x, dz.x);
    let d_low = vec3<f32>(dx.y, dy.y, dz.y) + (corners_low[i] - a_low);
    let px = two_product(k.x, d.x);
    let py = two_product(k.y, d.y);
    let pz = two_product(k.z, d.z);
    let t1 = two_sum(px.x, py.x);
    let t2 = two_sum(t1.x, pz.x);
    let lo = t1.y + t2.y + px.y + py.y + pz.y + dot(k, d_low) + dot(k_low, d);
    return t2.x + lo;
}

// k . (P - a) up to a positive factor, from the receiver's corners (`set_receiver`), for the
// plane through `a` with normal `k` (`k_low`, `a_low`: what they rounded off); zero when P lies
// on the plane. A corner within f32 rounding of the plane takes its side in about twice f32's
// precision, and lies on the plane within the oracle's 1e-10.
fn side_of_p(k: vec3<f32>, k_low: vec3<f32>, a: vec3<f32>, a_low: vec3<f32>) -> f32 {
    var s = 0.0;
    for (var i = 0u; i < 3u; i++) {
        spent++;
        let d = corner_minus(i, a, a_low);
        var g = dot(k, d);
        if (abs(g) <= EDGE_ON * dot(abs(k), abs(d))) {
            g = precise_side(k, k_low, i, a, a_low);
            if (abs(g) <= TIE * length(k) * length(d)) {
                g = 0.0;
            }
        }
        s += weights[i] * g;
    }
    return s;
}

// P - a up to a positive factor and to a multiple of b - a, from the receiver's corners: the
// corners it shares with the edge `a b` drop out exactly.
fn from_edge(a: vec3<f32>, a_low: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    var q = vec3<f32>(0.0);
    for (var i = 0u; i < 3u; i++) {
        spent++;
        let c = corners[i];
        if (!all(c == a) && !all(c == b)) {
            q += weights[i] * corner_minus(i, a, a_low);
        }
    }
    return q;
}
