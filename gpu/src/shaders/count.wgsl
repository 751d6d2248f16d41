// Counting pass of depth-complexity sampling (Forest, Barthe & Paulin 2008): one invocation per
// pixel starts from the light centre's depth complexity D(P, c) (the stencil count of the
// volumes built by the open-mesh rule, one per triangle facing either way), adds the change of
// every edge of its tile's list to the N x N samples it separates from the centre, and writes
// V = #{ s : D(P, s) = 0 } / N². A port of `penumbra_volumes::region` (the four lines of the
// segment-triangle test per edge, the light clipped by three of them to find the cells they
// reach: `count_regions.wgsl`, with the side tests from the receiver's corners in
// `count_receiver.wgsl`) and of the correlated multi-jittered pattern of
// `penumbra_volumes::samples` (`count_pattern.wgsl`), so that the GPU and the CPU oracle agree
// sample for sample up to f32 rounding. This file holds the pass itself.

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
    if ((base & 0x80u) != 0u || params.recount_all != 0u || on_a_count_boundary(gid.xy, base)) {
        base = 0u;
        recount = RECOUNT;
    }
    if (!strictly_in_front(p.xyz, pl.z)) {
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
