// Edge-list pass of depth-complexity sampling: one workgroup per tile of TILE x TILE pixels lists
// the potential silhouette edges that may change a light sample's count as seen from one of the
// tile's receivers, into `list` at `tile_ranges[tile]` (`complexity.wgsl` declares both). An edge
// is listed unless the receivers' views of the light cannot meet it, by the CPU oracle's two
// conservative tests (`penumbra_volumes::potential::PotentialEdges::for_each_near_any` and
// `may_fold_within`), with margins for f32:
//
// - it lies wholly outside one plane of the union of the receivers' pyramids to the light. For
//   each side k of the light, the planes through that side are ordered by the key
//   `inward_k(p) / p.z` (the distance of p inside the side's line over its height), and the union
//   lies inside the plane of the smallest key;
// - it is a two-face edge whose faces keep the tile's bounding box on opposite sides of each.
//
// Each tile takes one range of the list with one atomic add, so that its edges lie together.
// The list never loses an edge silently: the counting pass reads every edge for a tile whose
// range does not fit, and `demand[0]` tells the renderer how large to make the list.

var<workgroup> wkeys: array<vec4<f32>, 64>;
var<workgroup> wlo: array<vec3<f32>, 64>;
var<workgroup> whi: array<vec3<f32>, 64>;
var<workgroup> wtotal: atomic<u32>;
var<workgroup> wfirst: u32;
var<workgroup> wany: u32;

@compute @workgroup_size(64)
fn lists(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let tile = wid.y * params.tiles_x + wid.x;
    let px = vec2<u32>(wid.x * TILE + li % TILE, wid.y * TILE + li / TILE);
    let size = vec2<u32>(frame.size.xy);
    var keys = vec4<f32>(BIG);
    var lo = vec3<f32>(BIG);
    var hi = vec3<f32>(-BIG);
    if (li == 0u) {
        atomicStore(&wtotal, 0u);
        wany = 0u;
    }
    if (px.x < size.x && px.y < size.y) {
        let p = textureLoad(position, vec2<i32>(px), 0);
        if (p.w != 0.0) {
            let pl = receiver_point(px, p);
            if (pl.z > 0.0) {
                keys = side_keys(pl);
                lo = pl;
                hi = pl;
            }
        }
    }
    wkeys[li] = keys;
    wlo[li] = lo;
    whi[li] = hi;
    for (var stride = 32u; stride > 0u; stride = stride / 2u) {
        workgroupBarrier();
        if (li < stride) {
            wkeys[li] = min(wkeys[li], wkeys[li + stride]);
            wlo[li] = min(wlo[li], wlo[li + stride]);
            whi[li] = max(whi[li], whi[li + stride]);
        }
    }
    workgroupBarrier();
    keys = wkeys[0];
    lo = wlo[0];
    hi = whi[0];
    if (li == 0u && lo.x <= hi.x) {
        wany = 1u;
    }
    if (workgroupUniformLoad(&wany) == 0u) {
        if (li == 0u) {
            tile_ranges[tile] = vec2<u32>(0u, 0u);
        }
        return;
    }
    // Count this lane's edges, take the tile's range, then write them.
    var own = 0u;
    for (var e = li; e < params.edges; e += 64u) {
        if (listed(edges[e], keys, lo, hi)) {
            own++;
        }
    }
    var at = atomicAdd(&wtotal, own);
    workgroupBarrier();
    if (li == 0u) {
        let total = atomicLoad(&wtotal);
        let first = atomicAdd(&demand[0], total);
        wfirst = first;
        tile_ranges[tile] = vec2<u32>(first, total);
    }
    at += workgroupUniformLoad(&wfirst);
    for (var e = li; e < params.edges; e += 64u) {
        if (listed(edges[e], keys, lo, hi)) {
            if (at < params.capacity) {
                list[at] = e;
            }
            at++;
        }
    }
}
