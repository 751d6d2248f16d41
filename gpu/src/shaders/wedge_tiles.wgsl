// Tiled penumbra wedges (`wedges`): one workgroup per screen tile of WEDGE_TILE x WEDGE_TILE
// pixels, one invocation per pixel, culling the wedges per tile as tiled shading culls lights
// (Olsson and Assarsson 2011, "Tiled shading"; Harada, McKee and Yang 2012, "Forward+"). The
// workgroup bounds its receivers in light space; then it takes the wedges a round at a time, each
// invocation testing a run of them against that box, keeps those that meet it in their order,
// and each pixel adds the integral (`wedge_integral.wgsl`) of those whose solid holds its
// receiver. The expensive work, the integrals, is bounded by the wedges that reach the tile; the
// cheap one, the box tests, by the wedges over the tiles. Every pixel is written, in the same
// order of wedges, so the image is the same from run to run.

// The receivers (the depth pre-pass's eye-relative positions, `w` non-zero where hit).
@group(1) @binding(0) var position: texture_2d<f32>;
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
// Draw arguments whose word 5 is the number of wedges (the build's, or the CPU's instances').
@group(1) @binding(3) var<storage, read> wedge_args: array<u32>;
// The signed occlusion per radial part, as the rasterised pass adds it.
@group(1) @binding(4) var occlusion: texture_storage_2d<rgba32float, write>;

const TILE_PIXELS: u32 = WEDGE_TILE * WEDGE_TILE;

// Wedges each invocation tests in one round: a round takes TILE_PIXELS x PER_INVOCATION wedges
// between the workgroup's barriers.
const PER_INVOCATION: u32 = 8u;
const ROUND: u32 = TILE_PIXELS * PER_INVOCATION;

// The tile's receivers' box: `ordered` keys of min x, y, z (inverted) and max x, y, z.
var<workgroup> box_keys: array<atomic<u32>, 6>;
// Whether the tile has a receiver, and its box.
var<workgroup> tile_box: array<vec3<f32>, 2>;
var<workgroup> tile_has: u32;
// The kept wedges in order (their prefix sums by `workgroup_scan`, over TILE_PIXELS =
// SCAN_GROUP invocations, workgroup_scan.wgsl).
var<workgroup> kept: array<u32, ROUND>;

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

@compute @workgroup_size(WEDGE_TILE, WEDGE_TILE)
fn tile(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let pixel = group.xy * WEDGE_TILE + lid.xy;
    let inside = all(vec2<f32>(pixel) < frame.size.xy);
    if (local < 6u) {
        atomicStore(&box_keys[local], 0u);
    }
    workgroupBarrier();
    var p = vec3<f32>(0.0);
    var has = false;
    if (inside) {
        let hit = textureLoad(position, vec2<i32>(pixel), 0);
        if (hit.w != 0.0) {
            p = to_light(hit.xyz);
            has = true;
            for (var axis = 0u; axis < 3u; axis++) {
                let key = ordered(p[axis]);
                atomicMax(&box_keys[axis], ~key);
                atomicMax(&box_keys[3u + axis], key);
            }
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
    let any = workgroupUniformLoad(&tile_has) != 0u;
    let lo = tile_box[0];
    let hi = tile_box[1];
    var sum = vec4<f32>(0.0);
    let n = select(0u, wedge_args[5], any);
    for (var first = 0u; first < n; first += ROUND) {
        // This invocation's run of wedges, in order, tested against the tile's box.
        let start = first + local * PER_INVOCATION;
        var keep = 0u;
        var kept_here = 0u;
        for (var j = 0u; j < PER_INVOCATION; j++) {
            if (start + j < n && meets_box(solid_of(start + j), lo, hi)) {
                keep |= 1u << j;
                kept_here++;
            }
        }
        var at = workgroup_scan(local, vec2<u32>(kept_here, 0u)).x - kept_here;
        for (var j = 0u; j < PER_INVOCATION; j++) {
            if ((keep & (1u << j)) != 0u) {
                kept[at] = start + j;
                at++;
            }
        }
        let count = workgroupUniformLoad(&scan_sums[SCAN_GROUP - 1u]).x;
        for (var k = 0u; k < count; k++) {
            let s = solid_of(kept[k]);
            // Only a receiver in the solid can be in the wedge (Lengyel's test, Forest et al.
            // 2006, section 4.2, done here on the solid itself).
            let r = section(s, p.z);
            let pad = 1e-5 * (1.0 + abs(p));
            let held = p.z >= s.z.x - pad.z && p.z <= s.z.y + pad.z
                && all(p.xy >= r.xy - pad.xy) && all(p.xy <= r.zw + pad.xy);
            if (has && held) {
                let w = tile_wedge(kept[k]);
                let e = integral(w.edge_from, w.edge_to, w.caster, p, AREAS_ONLY);
                if (e.valid) {
                    sum += e.area * e.sign;
                }
            }
        }
        workgroupBarrier();
    }
    if (inside) {
        textureStore(occlusion, vec2<i32>(pixel), sum);
    }
}
