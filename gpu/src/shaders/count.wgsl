// Counting pass of depth-complexity sampling (Forest, Barthe & Paulin 2008): one invocation per
// pixel starts from the light centre's depth complexity D(P, c) (the stencil count of the
// volumes built by the open-mesh rule, one per triangle facing either way), adds the change of
// every edge of its tile's list to the N x N samples it separates from the centre, and writes
// V = #{ s : D(P, s) = 0 } / N². A port of `penumbra_volumes::region` (the four lines of the
// segment-triangle test per edge, the light clipped by three of them to find the cells they
// reach) and of the correlated multi-jittered pattern of `penumbra_volumes::samples`, so that the
// GPU and the CPU oracle agree sample for sample up to f32 rounding.

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

// The counting pass runs in dispatches so that no invocation runs more than a fixed number of
// loop iterations whatever the scene (`passes::count`): `count_setup` finds each pixel's
// receiver and its work (its tile's listed edges, or every edge where the tile's range did not
// fit the list, then the crossings), each `count_chunk` dispatch takes the next `params.chunk`
// entries of it, and `count_finish` turns the counts into V. Between dispatches a pixel keeps
// its state in `visibility` (after V): P (3 words), the receiver, the centre's count (or, where
// it is counted again, the counts towards it and two samples, a byte each), the entries done, the entries in all and its flags (`STATE_WORDS`, from Rust); then its counts, one byte per sample.
// Flags of a pixel's state: its V is still to be counted; a region changed its counts; an
// invocation of it ran past `params.budget`; it counts D(P, c) again over the triangles.
const ACTIVE: u32 = 1u;
const CHANGED: u32 = 2u;
const CUT: u32 = 4u;
const RECOUNT: u32 = 8u;

// The pattern's fine column per cell row and fine row per cell column.
var<private> columns: array<u32, MAX_AXIS>;
var<private> rows: array<u32, MAX_AXIS>;
var<private> jitter_seed: u32;

fn pixel_count() -> u32 {
    return u32(frame.size.x) * u32(frame.size.y);
}

// The first word of the state of the band's pixel i (`band_pixel`).
fn state_at(i: u32) -> u32 {
    return pixel_count() + STATE_WORDS * i;
}

// The first word of the counts of the band's pixel i.
fn counts_at(i: u32) -> u32 {
    let n = params.per_axis;
    let band = params.band_rows * u32(frame.size.x);
    return pixel_count() + STATE_WORDS * band + i * ((n * n + 3u) / 4u);
}

// The image keeps the state and counts of `params.band_rows` rows at a time: the pass runs
// band by band from the top, `count_band` moving to the next (`demand[4]`, its first row).
// The pixel of invocation `id` of the current band, and its index in the band; (0, 0, 1) where
// it lies outside the band or the image.
fn band_pixel(id: vec3<u32>) -> vec3<u32> {
    let row = id.y + atomicLoad(&demand[4]);
    if (id.y >= params.band_rows || id.x >= u32(frame.size.x) || row >= u32(frame.size.y)) {
        return vec3<u32>(0u, 0u, 1u);
    }
    return vec3<u32>(id.x, row, 0u);
}

@compute @workgroup_size(1)
fn count_band() {
    atomicAdd(&demand[4], params.band_rows);
}

// Adds the region's change to the samples inside it, visiting only the cells its box reaches.
fn apply(r: Region, n: u32, own: u32) {
    let cell = 2.0 / f32(n);
    let i0 = u32(clamp(floor((r.lo.x + 1.0) / cell), 0.0, f32(n - 1u)));
    let i1 = u32(clamp(floor((r.hi.x + 1.0) / cell), 0.0, f32(n - 1u)));
    let j0 = u32(clamp(floor((r.lo.y + 1.0) / cell), 0.0, f32(n - 1u)));
    let j1 = u32(clamp(floor((r.hi.y + 1.0) / cell), 0.0, f32(n - 1u)));
    for (var j = j0; j <= j1; j++) {
        spent++;
        for (var i = i0; i <= i1; i++) {
            spent++;
            let s = j * n + i;
            let at = pattern_point(i, j, columns[j], rows[i], jitter_seed);
            if (line_at(r.l0, at) > 0.0 && line_at(r.l1, at) > 0.0 && line_at(r.l2, at) > 0.0
                && line_at(r.l3, at) > 0.0) {
                let w = own + s / 4u;
                let shift = (s % 4u) * 8u;
                let b = ((visibility[w] >> shift) + bitcast<u32>(r.delta)) & 0xffu;
                visibility[w] = (visibility[w] & ~(0xffu << shift)) | (b << shift);
            }
        }
    }
}

// A pixel's flags with CUT where this invocation ran past its budget.
fn with_cut(flags: u32) -> u32 {
    return select(flags, flags | CUT, spent > params.budget);
}

// The count byte of sample s among the counts at `own`.
fn count_of(own: u32, s: u32) -> u32 {
    return (visibility[own + s / 4u] >> ((s % 4u) * 8u)) & 0xffu;
}

// Whether the stencil count `base` of pixel `px` differs from that of one of its four
// neighbours that sees a surface: a hard shadow's outline or a surface's passes between them,
// or the rasteriser got one of the two wrong. 1% to 17% of the pixels on the fixtures and the
// scale scene.
fn on_a_count_boundary(px: vec2<u32>, base: u32) -> bool {
    let size = vec2<i32>(frame.size.xy);
    for (var k = 0u; k < 4u; k++) {
        spent++;
        let sign = 1 - 2 * i32(k & 1u);
        let q = vec2<i32>(px) + select(vec2<i32>(0, sign), vec2<i32>(sign, 0), k < 2u);
        if (any(q < vec2<i32>(0)) || any(q >= size) || textureLoad(position, q, 0).w == 0.0) {
            continue;
        }
        if (textureLoad(stencil_count, q, 0).r != base) {
            return true;
        }
    }
    return false;
}

@compute @workgroup_size(COUNT_GROUP, COUNT_GROUP)
fn count_setup(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(frame.size.xy);
    let gid = band_pixel(id);
    if (gid.z != 0u) {
        return;
    }
    let pixel = gid.y * size.x + gid.x;
    let local = id.y * size.x + id.x;
    let st = state_at(local);
    visibility[st + 7u] = 0u;
    let p = textureLoad(position, vec2<i32>(gid.xy), 0);
    if (p.w == 0.0) {
        visibility[pixel] = bitcast<u32>(1.0);
        return;
    }
    var pl = receiver_point(gid.xy, p);
    var receiver = receiver_triangle(p.w);
    set_receiver(pl, receiver);
    var base = textureLoad(stencil_count, vec2<i32>(gid.xy), 0).r;
    if (pixel + 1u == params.stencil_error) {
        base = (base + 2u) & 0xffu;
    }
    let better = ray_receiver(gid.xy, receiver, pl, all(weights >= vec3<f32>(0.0)));
    // A new receiver: the stencil counted the other point, so D(P, c) is counted again over
    // every triangle, DISPATCH_ITERATIONS triangles per dispatch after its edges.
    var recount = 0u;
    if (bitcast<u32>(better.w) != receiver) {
        pl = better.xyz;
        receiver = bitcast<u32>(better.w);
        set_receiver(pl, receiver);
        base = 0u;
        recount = RECOUNT;
    }
    // A negative count (read as a signed byte) is never the exact D(P, c): the rasteriser
    // decided a near tie of a volume's face with the receiver against it. Nor, perhaps, is a
    // count that differs from a neighbour's: where two volumes' faces meet on the pixel's
    // centre after clipping, their rasterisation can leave a crack or cover it twice (seen
    // as a count two too high on one pixel amid thousands of its own, and next to a hard
    // shadow's outline it may equal the other side's count). Both are counted again.
    if ((base & 0x80u) != 0u || on_a_count_boundary(gid.xy, base)) {
        base = 0u;
        recount = RECOUNT;
    }
    if (!(pl.z > 0.0)) {
        visibility[pixel] = bitcast<u32>(0.0);
        return;
    }
    // This pixel's counts, zeroed.
    let own = counts_at(local);
    let n = params.per_axis;
    for (var w = 0u; w < (n * n + 3u) / 4u; w++) {
        spent++;
        visibility[own + w] = 0u;
    }
    let range = tile_ranges[(gid.y / TILE) * params.tiles_x + gid.x / TILE];
    let complete = range.x + range.y <= params.capacity;
    let total = select(params.edges, range.y, complete) + params.crossings;
    // The dispatches this pixel needs: its edges and crossings `params.chunk` at a time, then
    // the triangles towards the centre and two samples where it counts D(P, c) again.
    let chunk = max(params.chunk, 1u);
    var needed = (total + chunk - 1u) / chunk;
    if (recount != 0u) {
        needed += (params.triangles + DISPATCH_ITERATIONS - 1u) / DISPATCH_ITERATIONS;
    }
    visibility[st] = bitcast<u32>(pl.x);
    visibility[st + 1u] = bitcast<u32>(pl.y);
    visibility[st + 2u] = bitcast<u32>(pl.z);
    visibility[st + 3u] = receiver;
    visibility[st + 4u] = base;
    visibility[st + 5u] = 0u;
    visibility[st + 6u] = total;
    visibility[st + 7u] = with_cut(ACTIVE | recount);
    atomicMax(&demand[2], needed);
}

// The indirect arguments of the `params.chunks` dispatches of `count_chunk`: the whole image for
// the first as many as any pixel needs (`demand[2]`), nothing for the others.
@group(2) @binding(0) var<storage, read_write> chunk_args: array<u32>;

@compute @workgroup_size(64)
fn count_args(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = gid.x;
    if (c >= params.chunks) {
        return;
    }
    let run = c < atomicLoad(&demand[2]);
    let groups = (vec2<u32>(frame.size.xy) + vec2<u32>(COUNT_GROUP - 1u)) / COUNT_GROUP;
    chunk_args[3u * c] = select(0u, groups.x, run);
    chunk_args[3u * c + 1u] = groups.y;
    chunk_args[3u * c + 2u] = 1u;
}

// The pattern's sample in cell (i, j) of pixel `seed` (`SamplePattern::points`), on the
// light's plane.
fn sample_in_cell(i: u32, j: u32, seed: u32) -> vec3<f32> {
    let n = params.per_axis;
    let column = permute(j, n, column_seed(seed));
    let row = permute(i, n, row_seed(seed));
    return vec3<f32>(pattern_point(i, j, column, row, jitter_seed_of(seed)), 0.0);
}

// The cells of the two samples towards which D(P, c) is counted again besides the centre:
// halfway from the centre to opposite corners of the light, where the line of an edge through
// the centre passes near at most one of them.
fn vote_cells() -> vec4<u32> {
    let n = params.per_axis;
    return vec4<u32>(n / 4u, n / 4u, (3u * n) / 4u, (3u * n) / 4u);
}

// Adds to the counts of the pixel `seed` whose state is at `st` the triangles from `first` on,
// DISPATCH_ITERATIONS of them, that the segment from P on `receiver` crosses towards the
// light's centre, and towards the two samples of `vote_cells`, one byte each: `count_finish`
// takes D(P, c) from the centre's count or from a sample's less the edges' change to it,
// whichever two of the three agree on. A hard shadow's outline through P (where the stencil
// may be wrong, and so is counted again) can leave the centre's count and the edge whose
// outline it is deciding the same near tie apart; a sample's count turns any error of the
// edges' changes to that sample into an error of every sample. Two of three are right.
fn count_towards(st: u32, first: u32, receiver: u32, flags: u32, seed: u32) {
    let pl = vec3<f32>(
        bitcast<f32>(visibility[st]),
        bitcast<f32>(visibility[st + 1u]),
        bitcast<f32>(visibility[st + 2u]),
    );
    set_receiver(pl, receiver);
    let cells = vote_cells();
    let sa = sample_in_cell(cells.x, cells.y, seed);
    let sb = sample_in_cell(cells.z, cells.w, seed);
    let end = min(params.triangles, first + DISPATCH_ITERATIONS);
    var n = vec3<u32>(0u);
    for (var t = first; t < end; t++) {
        spent++;
        if (t != receiver) {
            let tri = triangles[t];
            n += vec3<u32>(vec3<bool>(
                crosses_to(tri, vec3<f32>(0.0)),
                crosses_to(tri, sa),
                crosses_to(tri, sb),
            ));
        }
    }
    let w = visibility[st + 4u];
    visibility[st + 4u] = ((w + n.x) & 0xffu) | ((((w >> 8u) + n.y) & 0xffu) << 8u)
        | ((((w >> 16u) + n.z) & 0xffu) << 16u);
    visibility[st + 5u] = visibility[st + 6u] + end;
    visibility[st + 7u] = with_cut(flags);
}

@compute @workgroup_size(COUNT_GROUP, COUNT_GROUP)
fn count_chunk(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(frame.size.xy);
    let gid = band_pixel(id);
    if (gid.z != 0u) {
        return;
    }
    let pixel = gid.y * size.x + gid.x;
    let local = id.y * size.x + id.x;
    let st = state_at(local);
    let flags = visibility[st + 7u];
    let done = visibility[st + 5u];
    let total = visibility[st + 6u];
    if ((flags & ACTIVE) == 0u) {
        return;
    }
    let receiver = visibility[st + 3u];
    if (done >= total) {
        if ((flags & RECOUNT) != 0u && done - total < params.triangles) {
            count_towards(st, done - total, receiver, flags, pixel);
        }
        return;
    }
    let pl = vec3<f32>(
        bitcast<f32>(visibility[st]),
        bitcast<f32>(visibility[st + 1u]),
        bitcast<f32>(visibility[st + 2u]),
    );
    set_receiver(pl, receiver);
    let n = params.per_axis;
    // The pattern of this pixel (`SamplePattern::points`).
    let seed = pixel;
    for (var k = 0u; k < n; k++) {
        spent++;
        columns[k] = permute(k, n, column_seed(seed));
        rows[k] = permute(k, n, row_seed(seed));
    }
    jitter_seed = jitter_seed_of(seed);
    let pyramid = pyramid_planes(pl);
    let own = counts_at(local);
    var changed = 0u;
    let range = tile_ranges[(gid.y / TILE) * params.tiles_x + gid.x / TILE];
    let complete = range.x + range.y <= params.capacity;
    let entries = select(params.edges, range.y, complete);
    let end = min(total, done + params.chunk);
    for (var k = done; k < end; k++) {
        spent++;
        var r = no_region();
        if (k < entries) {
            var ei = k;
            if (complete) {
                ei = list[range.x + k];
            } else if (!listed(edges[ei], side_keys(pl), pl, pl)) {
                continue;
            }
            r = edge_region(ei, pl, pyramid, receiver);
        } else {
            r = crossing_region(crossings[k - entries], pl, receiver);
        }
        if (r.delta != 0 && r.lo.x <= r.hi.x) {
            apply(r, n, own);
            changed = CHANGED;
        }
    }
    visibility[st + 5u] = end;
    visibility[st + 7u] = with_cut(flags | changed);
}

@compute @workgroup_size(COUNT_GROUP, COUNT_GROUP)
fn count_finish(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(frame.size.xy);
    let gid = band_pixel(id);
    if (gid.z != 0u) {
        return;
    }
    let pixel = gid.y * size.x + gid.x;
    let local = id.y * size.x + id.x;
    let st = state_at(local);
    let flags = visibility[st + 7u];
    if ((flags & ACTIVE) == 0u) {
        return;
    }
    // A pixel whose work the dispatches did not finish: reported (`demand[3]`), never left
    // silently wrong.
    let recounted = select(0u, params.triangles, (flags & RECOUNT) != 0u);
    if (visibility[st + 5u] < visibility[st + 6u] + recounted) {
        atomicAdd(&demand[3], 1u);
    }
    let n = params.per_axis;
    let own = counts_at(local);
    // D(P, c): the stencil's, or where counted again the count towards the centre or a
    // sample's less the edges' change to it, whichever two agree on (`count_towards`).
    var base = visibility[st + 4u];
    if ((flags & RECOUNT) != 0u) {
        let cells = vote_cells();
        let w = base;
        let bc = w & 0xffu;
        let ba = ((w >> 8u) - count_of(own, cells.y * n + cells.x)) & 0xffu;
        let bb = ((w >> 16u) - count_of(own, cells.w * n + cells.z)) & 0xffu;
        base = select(bc, ba, ba == bb);
    }
    // D(P, s) modulo 256, read as a signed byte: zero (or, where rounding made the counts
    // disagree, negative) is visible, as the oracle's `D <= 0`.
    var seen = 0u;
    if ((flags & CHANGED) != 0u) {
        for (var s = 0u; s < n * n; s++) {
            spent++;
            let c = count_of(own, s) + base;
            seen += select(0u, 1u, (c & 0xffu) == 0u || (c & 0x80u) != 0u);
        }
    } else {
        seen = select(0u, n * n, base == 0u || (base & 0x80u) != 0u);
    }
    if ((with_cut(flags) & CUT) != 0u) {
        atomicAdd(&demand[1], 1u);
    }
    visibility[pixel] = bitcast<u32>(f32(seen) / f32(n * n));
}
