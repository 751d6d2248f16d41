// The integral of a penumbra wedge at a receiver, per radial part of the light (Forest et al. 2006,
// sections 3.1 and 4.3): the same integral as the CPU oracle,
// `penumbra_volumes::wedge::Wedge::integral`, in f32. Declarations only, prepended to the passes
// that evaluate wedges: the rasterised wedge pass (`wedge.wgsl`) and the tiled one
// (`wedge_tiles.wgsl`).

fn cross2(a: vec2<f32>, b: vec2<f32>) -> f32 {
    return a.x * b.y - a.y * b.x;
}

// The four radial parts are the triangles (0, corner(k), corner(k + 1)) from the centre to each
// side, counter-clockwise from +x. Chosen by `select`, not an array indexed at run time, which
// CPU drivers keep in memory.
fn corner(k: u32) -> vec2<f32> {
    let i = k % 4u;
    return vec2<f32>(select(-1.0, 1.0, i == 0u || i == 1u), select(-1.0, 1.0, i == 1u || i == 2u));
}

// The radial part holding direction d (on a diagonal: the part whose side is vertical).
fn part_of(d: vec2<f32>) -> u32 {
    return select(select(3u, 1u, d.y > 0.0), select(2u, 0u, d.x > 0.0), abs(d.x) >= abs(d.y));
}

// Outward normal of part k's side of the square.
fn side_normal(k: u32) -> vec2<f32> {
    return select(
        select(vec2<f32>(0.0, -1.0), vec2<f32>(-1.0, 0.0), k == 2u),
        select(vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 0.0), k == 0u),
        k < 2u,
    );
}

// Whether direction x lies in the sector from u counter-clockwise to v (less than a half turn).
fn in_sector(x: vec2<f32>, u: vec2<f32>, v: vec2<f32>) -> bool {
    return cross2(u, x) >= 0.0 && cross2(x, v) >= 0.0;
}

// The cone over the projected edge (the sector from u counter-clockwise to v, apex at the
// light's centre) within part k: both are sectors with that apex, so their intersection is one
// sector, and with the part's side a triangle (0, p1, p2), p1 and p2 on the side. `ok` is false
// when it has no area.
struct ConePart {
    ok: bool,
    p1: vec2<f32>,
    p2: vec2<f32>,
}

fn cone_part(k: u32, u: vec2<f32>, v: vec2<f32>) -> ConePart {
    var c: ConePart;
    c.ok = false;
    let u2 = corner(k);
    let v2 = corner(k + 1u);
    // The intersection starts at whichever start lies in the other sector, and ends likewise.
    let u_in = in_sector(u, u2, v2);
    let v_in = in_sector(v, u2, v2);
    if (!(u_in || in_sector(u2, u, v)) || !(v_in || in_sector(v2, u, v))) {
        return c;
    }
    let s = select(u2, u, u_in);
    let e = select(v2, v, v_in);
    let n = side_normal(k);
    let ds = dot(s, n);
    let de = dot(e, n);
    if (!(ds > 0.0 && de > 0.0)) {
        return c;
    }
    c.p1 = s / ds;
    c.p2 = e / de;
    c.ok = cross2(c.p1, c.p2) > 0.0;
    return c;
}

// Triangle (0, p1, p2) split by the line dot(h.xy, x) + h.z = 0, in closed form: nothing is
// clipped or stored. The area beyond the line (>= 0), and the bounding rectangle of one side:
// beyond, or near (<= 0) when `near` is asked for. `n` says whether that side holds a vertex
// (3) or nothing (0), as a Sutherland-Hodgman walk would count.
//
// Each side is the vertices on it plus the line's crossings of the edges whose ends lie on
// opposite sides; a crossing at a vertex on the line is that vertex, already on both sides. A
// side holding one vertex alone is the triangle (vertex, its two edges' crossings); one holding
// two is the whole triangle less the other vertex's.
struct Split {
    area: f32,
    rect: vec4<f32>,
    n: u32,
}

// The crossing of segment a-b (values fa, fb) with the line.
fn crossing(a: vec2<f32>, b: vec2<f32>, fa: f32, fb: f32) -> vec2<f32> {
    return a + (b - a) * (fa / (fa - fb));
}

fn with_point(r: vec4<f32>, x: vec2<f32>, keep: bool) -> vec4<f32> {
    return select(r, vec4<f32>(min(r.xy, x), max(r.zw, x)), keep);
}

fn split_triangle(p1: vec2<f32>, p2: vec2<f32>, h: vec3<f32>, near: bool) -> Split {
    var m: Split;
    let o = vec2<f32>(0.0);
    let f = vec3<f32>(h.z, dot(h.xy, p1) + h.z, dot(h.xy, p2) + h.z);
    let beyond = f >= vec3<f32>(0.0);
    let on_near = f <= vec3<f32>(0.0);
    // Edges 0-1, 1-2, 2-0, crossed where their ends lie strictly on opposite sides.
    let crossed = vec3<bool>(
        (f.x > 0.0 && f.y < 0.0) || (f.x < 0.0 && f.y > 0.0),
        (f.y > 0.0 && f.z < 0.0) || (f.y < 0.0 && f.z > 0.0),
        (f.z > 0.0 && f.x < 0.0) || (f.z < 0.0 && f.x > 0.0),
    );
    let c01 = crossing(o, p1, f.x, f.y);
    let c12 = crossing(p1, p2, f.y, f.z);
    let c20 = crossing(p2, o, f.z, f.x);
    var cross_rect = with_point(EMPTY_RECT, c01, crossed.x);
    cross_rect = with_point(cross_rect, c12, crossed.y);
    cross_rect = with_point(cross_rect, c20, crossed.z);

    // One side's rectangle: its vertices and the crossings.
    let side = select(beyond, on_near, near);
    var r = with_point(cross_rect, o, side.x);
    r = with_point(r, p1, side.y);
    m.rect = with_point(r, p2, side.z);
    m.n = select(0u, 3u, any(side));

    // Area: the whole triangle, nothing, or the triangle at the vertex alone on its side
    // (subtracted when that vertex is the near one).
    let whole = 0.5 * abs(cross2(p1, p2));
    let count = u32(beyond.x) + u32(beyond.y) + u32(beyond.z);
    // The lone vertex: the one beyond when one is, the one not beyond when two are.
    let lone_is = select(!beyond, beyond, count == 1u);
    let small = select(
        select(
            0.5 * abs(cross2(c12 - p2, c20 - p2)),
            0.5 * abs(cross2(c01 - p1, c12 - p1)),
            lone_is.y,
        ),
        0.5 * abs(cross2(c01, c20)),
        lone_is.x,
    );
    m.area = select(
        select(select(0.0, small, count == 1u), whole - small, count == 2u),
        whole,
        count == 3u,
    );
    return m;
}

// Whether the segment a-b meets the square [-1, 1]^2 (Liang & Barsky 1984).
fn meets_square(a: vec2<f32>, b: vec2<f32>) -> bool {
    let d = b - a;
    // The four sides as p t <= q, one after the other.
    let p = vec4<f32>(-d.x, d.x, -d.y, d.y);
    let q = vec4<f32>(a.x + 1.0, 1.0 - a.x, a.y + 1.0, 1.0 - a.y);
    let r = q / p;
    var t0 = 0.0;
    var t1 = 1.0;
    for (var i = 0u; i < 4u; i++) {
        if (p[i] == 0.0) {
            if (q[i] < 0.0) {
                return false;
            }
        } else if (p[i] < 0.0) {
            t0 = max(t0, r[i]);
        } else {
            t1 = min(t1, r[i]);
        }
    }
    return t0 <= t1;
}

// `meets_square` of the projected edge from a to b, where `far` (1: a, 2: b) says which end, if
// any, is a direction from P's projection rather than a point: then the ray from the finite end
// along it, taken far enough to leave the square.
fn meets_square_towards(a: vec2<f32>, b: vec2<f32>, far: u32) -> bool {
    if (far == 0u) {
        return meets_square(a, b);
    }
    let start = select(a, b, far == 1u);
    let d = select(b, a, far == 1u);
    let reach = 4.0 + 2.0 * length(start);
    return meets_square(start, start + d * (reach / max(length(d), 1e-30)));
}

// Fraction of z_P kept between the clipped edge and the local near plane (f32: coarser than the
// CPU's 1e-9; projected coordinates stay below about 1e6).
const NEAR_MARGIN: f32 = 1e-6;

// What one edge contributes at one receiver, per radial part: the CPU's `EdgeIntegral`.
struct Integral {
    // False when the edge does not touch the light as seen from P.
    valid: bool,
    // +1 outer half-wedge, -1 inner.
    sign: f32,
    // m · |R_e ∩ T_k|.
    area: vec4<f32>,
    // Per part, the bounding rectangle of R_e ∩ T_k (beyond the edge) for an outer half-wedge,
    // or of the cone's part between the centre and the edge (near) for an inner one. Four
    // fields, not an array: an array indexed by the loop's k lives in memory on CPU drivers.
    rect0: vec4<f32>,
    rect1: vec4<f32>,
    rect2: vec4<f32>,
    rect3: vec4<f32>,
    // Length of the part's outer side inside the cone over the edge.
    cover: vec4<f32>,
}

// What the caller needs besides the areas: `RECTS_OUTER` the outer half-wedges' rectangles,
// `RECTS_INNER` also the inner ones' near rectangles and cover (in the silhouette's hard shadow).
const AREAS_ONLY: u32 = 0u;
const RECTS_OUTER: u32 = 1u;
const RECTS_INNER: u32 = 2u;

fn integral(edge_from: vec4<f32>, edge_to: vec4<f32>, caster: vec4<f32>, p: vec3<f32>, want: u32) -> Integral {
    var out: Integral;
    out.valid = false;
    if (!(p.z > 0.0)) {
        return out;
    }
    // Clip the edge to the local near plane and project it from P onto the light plane.
    var a3 = edge_from.xyz;
    var b3 = edge_to.xyz;
    let limit = p.z * (1.0 - NEAR_MARGIN);
    if (a3.z > limit && b3.z > limit) {
        return out;
    }
    // An end beyond the near plane projects to infinity, in the direction from P to where the
    // edge crosses P's depth: kept as that direction (`far`), not as a point a million units
    // out, whose f32 rounding would move the line and the cone that the closed forms take.
    var far = 0u;
    if (b3.z > limit) {
        b3 = a3 + (b3 - a3) * ((limit - a3.z) / (b3.z - a3.z));
        far = 2u;
    } else if (a3.z > limit) {
        a3 = b3 + (a3 - b3) * ((limit - b3.z) / (a3.z - b3.z));
        far = 1u;
    }
    let a = select(p.xy + (a3.xy - p.xy) * (p.z / (p.z - a3.z)), a3.xy - p.xy, far == 1u);
    let b = select(p.xy + (b3.xy - p.xy) * (p.z / (p.z - b3.z)), b3.xy - p.xy, far == 2u);
    // Outside the wedge: the projected edge misses the light (most fragments of the box).
    if (!meets_square_towards(a, b, far)) {
        return out;
    }
    // The cone's sides from the centre (a far end's direction is its own), and the edge's
    // line: through its finite end, along the edge or its far end's direction.
    let s0 = sign(cross2(a, b));
    if (s0 == 0.0) {
        return out;
    }
    // Outer half-wedge (the caster beyond the edge from the centre) adds, inner subtracts: by
    // p's side of the plane (from, to, c), or on a mesh that the light's plane cuts by the
    // caster's and the centre's sides of the plane (from, to, p) (CPU: `Wedge::integral`).
    let e3 = edge_to.xyz - edge_from.xyz;
    var side = dot(cross(e3, -edge_from.xyz), p - edge_from.xyz);
    if (caster.w != 0.0) {
        let n = cross(e3, p - edge_from.xyz);
        let a = dot(n, caster.xyz - edge_from.xyz);
        let b = dot(n, -edge_from.xyz);
        side = select(-sign(a * b), 0.0, a == 0.0 || b == 0.0);
    }
    if (side == 0.0) {
        return out;
    }
    out.sign = sign(side);
    var e = b - a;
    var on_line = a;
    if (far == 2u) {
        e = b;
    } else if (far == 1u) {
        e = -a;
        on_line = b;
    }
    let beyond = -s0 * vec3<f32>(-e.y, e.x, -cross2(e, on_line));
    out.area = vec4<f32>(0.0);
    out.cover = vec4<f32>(0.0);
    let outer = out.sign > 0.0;
    let beyond_rects = want != AREAS_ONLY && outer;
    let near_rects = want == RECTS_INNER && !outer;
    out.rect0 = EMPTY_RECT;
    out.rect1 = EMPTY_RECT;
    out.rect2 = EMPTY_RECT;
    out.rect3 = EMPTY_RECT;
    // The cone over the edge as the sector from u counter-clockwise to v.
    let u = select(b, a, s0 > 0.0);
    let v = select(a, b, s0 > 0.0);
    // Only the parts the cone meets: from u's part counter-clockwise to v's, at most three (the
    // cone is less than a half turn). A CPU driver runs a loop as often as its busiest lane
    // needs, so fragments outside the wedge cost one pass through it, not four.
    let first = part_of(u);
    let count = (part_of(v) + 4u - first) % 4u + 1u;
    for (var j = 0u; j < count; j++) {
        let k = (first + j) % 4u;
        var rect = EMPTY_RECT;
        let cone = cone_part(k, u, v);
        if (!cone.ok) {
            continue;
        }
        let r = split_triangle(cone.p1, cone.p2, beyond, near_rects);
        if (r.area > 0.0) {
            out.area[k] = edge_from.w * r.area;
            out.valid = true;
            if (beyond_rects) {
                rect = r.rect;
            }
        }
        if (near_rects) {
            // The part's side inside the cone is the triangle's far side.
            out.cover[k] = length(cone.p2 - cone.p1);
            if (r.n >= 3u) {
                rect = r.rect;
                out.valid = true;
            }
        }
        if (beyond_rects || near_rects) {
            out.rect0 = select(out.rect0, rect, k == 0u);
            out.rect1 = select(out.rect1, rect, k == 1u);
            out.rect2 = select(out.rect2, rect, k == 2u);
            out.rect3 = select(out.rect3, rect, k == 3u);
        }
    }
    return out;
}
