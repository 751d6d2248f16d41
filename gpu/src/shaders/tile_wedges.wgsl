// What the tiled passes over penumbra wedges share (`wedge_tiles.wgsl` for `wedges`,
// `blend_tiles.wgsl` for `wedges-blend`): the wedges' bindings and solids, and the box of a
// screen tile's receivers in light space.

// The wedges, as `passes::wedge::WedgeInstance` lays them out, in two bindings (one binding
// holds at most the device's `max_storage_buffer_binding_size`): those past `wedges`' end are in
// `wedges_more`.
struct TileWedge {
    lo: vec4<f32>,
    hi: vec4<f32>,
    edge_from: vec4<f32>,
    edge_to: vec4<f32>,
    near: vec4<f32>,
    far: vec4<f32>,
    caster: vec4<f32>,
}
@group(1) @binding(1) var<storage, read> wedges: array<TileWedge>;
@group(1) @binding(2) var<storage, read> wedges_more: array<TileWedge>;
// The tile's receivers' box (`receivers_box`): `ordered` keys of min x, y, z (inverted) and
// max x, y, z; whether the tile has a receiver, and its box.
var<workgroup> box_keys: array<atomic<u32>, 6>;
var<workgroup> tile_box: array<vec3<f32>, 2>;
var<workgroup> tile_has: u32;

fn tile_wedge(i: u32) -> TileWedge {
    let first = arrayLength(&wedges);
    if (i < first) {
        return wedges[i];
    }
    return wedges_more[i - first];
}

// A wedge's solid: its depths, and its rectangles at them.
struct Solid {
    z: vec2<f32>,
    near: vec4<f32>,
    far: vec4<f32>,
}

// Wedge i's solid, read alone (40 of its 112 bytes).
fn solid_of(i: u32) -> Solid {
    let first = arrayLength(&wedges);
    if (i < first) {
        return Solid(vec2<f32>(wedges[i].lo.z, wedges[i].hi.z), wedges[i].near, wedges[i].far);
    }
    let j = i - first;
    return Solid(
        vec2<f32>(wedges_more[j].lo.z, wedges_more[j].hi.z),
        wedges_more[j].near,
        wedges_more[j].far,
    );
}

// The solid's rectangle at depth z.
fn section(s: Solid, z: f32) -> vec4<f32> {
    var t = 0.0;
    if (s.z.y > s.z.x) {
        t = clamp((z - s.z.x) / (s.z.y - s.z.x), 0.0, 1.0);
    }
    return mix(s.near, s.far, t);
}

// Whether the solid meets the box [lo, hi]: over the depths they share, it lies in the
// rectangle holding its sections at their ends (sections are linear in depth).
fn meets_box(s: Solid, lo: vec3<f32>, hi: vec3<f32>) -> bool {
    let z0 = max(s.z.x, lo.z);
    let z1 = min(s.z.y, hi.z);
    if (!(z0 <= z1)) {
        return false;
    }
    let a = section(s, z0);
    let b = section(s, z1);
    return all(min(a.xy, b.xy) <= hi.xy) && all(lo.xy <= max(a.zw, b.zw));
}

// Whether the light-space receiver p lies in the solid: only a receiver in the solid can be in
// the wedge (Lengyel's test, Forest et al. 2006, section 4.2, done here on the solid itself).
fn holds(s: Solid, p: vec3<f32>) -> bool {
    let r = section(s, p.z);
    let pad = 1e-5 * (1.0 + abs(p));
    return p.z >= s.z.x - pad.z && p.z <= s.z.y + pad.z
        && all(p.xy >= r.xy - pad.xy) && all(p.xy <= r.zw + pad.xy);
}

// The box of the workgroup's receivers into `tile_box`, each invocation giving its light-space
// receiver `p` where it `has` one; whether any has. Called by every invocation (it holds the
// workgroup's barriers).
fn receivers_box(local: u32, has: bool, p: vec3<f32>) -> bool {
    if (local < 6u) {
        atomicStore(&box_keys[local], 0u);
    }
    workgroupBarrier();
    if (has) {
        for (var axis = 0u; axis < 3u; axis++) {
            let key = ordered(p[axis]);
            atomicMax(&box_keys[axis], ~key);
            atomicMax(&box_keys[3u + axis], key);
        }
    }
    workgroupBarrier();
    if (local == 0u) {
        tile_has = select(0u, 1u, atomicLoad(&box_keys[3]) != 0u);
        for (var axis = 0u; axis < 3u; axis++) {
            tile_box[0][axis] = unordered(~atomicLoad(&box_keys[axis]));
            tile_box[1][axis] = unordered(atomicLoad(&box_keys[3u + axis]));
        }
    }
    return workgroupUniformLoad(&tile_has) != 0u;
}

const TILE_PIXELS: u32 = WEDGE_TILE * WEDGE_TILE;

// Items (wedges, or the tiled blend's items) each invocation tests in one round: a round takes
// TILE_PIXELS x PER_INVOCATION of them between the workgroup's barriers.
const PER_INVOCATION: u32 = 8u;
const ROUND: u32 = TILE_PIXELS * PER_INVOCATION;

// The kept items of a round, in order (their prefix sums by `workgroup_scan`, over TILE_PIXELS =
// SCAN_GROUP invocations, workgroup_scan.wgsl).
var<workgroup> kept: array<u32, ROUND>;

// Writes into `kept`, in order, the items of this invocation's run from `start` whose bits
// `keep` sets (`kept_here` of them), after those of the invocations before it; returns how many
// the whole workgroup kept. Called by every invocation (it holds the workgroup's barriers).
fn keep_in_order(local: u32, start: u32, keep: u32, kept_here: u32) -> u32 {
    var at = workgroup_scan(local, vec2<u32>(kept_here, 0u)).x - kept_here;
    for (var j = 0u; j < PER_INVOCATION; j++) {
        if ((keep & (1u << j)) != 0u) {
            kept[at] = start + j;
            at++;
        }
    }
    return workgroupUniformLoad(&scan_sums[SCAN_GROUP - 1u]).x;
}
