// Silhouettes, shadow volumes and penumbra wedges built on the GPU from the meshes' current
// vertices, for the light of the frame: what `penumbra_volumes::Volumes` builds on the CPU (the
// oracle), for scenes whose meshes lie wholly in front of the light's plane. Brabec and Seidel
// (2003) find silhouettes on the GPU; here one invocation per face decides whether it casts
// (Bergeron 1986's rule as `silhouette.rs` states it), one per edge sums its faces into the
// edge's multiplicity, and the edges' side quads and wedges are written in edge order through a
// prefix sum over blocks of `BUILD_GROUP` edges, so that the output is the same from run to run.
// The light caps and dark caps are not written: the stencil pass draws them from the meshes'
// corners, reading each face's `caster_sign` (`stencil.wgsl`, `vs_cap`).

// `frame` and `models` (group 0) are declared in common.wgsl, `workgroup_scan` (over
// BUILD_GROUP = SCAN_GROUP invocations) in workgroup_scan.wgsl.

const BUILD_GROUP: u32 = 256u;

// The meshes' stored vertices (as the depth pre-pass places them with `eye_relative`), three
// floats each, every mesh's after the one before it.
@group(1) @binding(0) var<storage, read> positions: array<f32>;
// Faces: their three vertices (indices into `positions`) and their mesh, with `CLOSED_MESH`
// set for a closed one.
@group(1) @binding(1) var<storage, read> faces: array<vec4<u32>>;
// Undirected edges: vertices u < v, the first of their incidences and their count, with the
// mesh in the count's upper 16 bits.
@group(1) @binding(2) var<storage, read> edges: array<vec4<u32>>;
// One per face on an edge: the face, shifted left by one, with bit 0 set where the face runs
// the edge u -> v.
@group(1) @binding(3) var<storage, read> incidences: array<u32>;
// Per face: 0 where it casts nothing, else the sign of its own winding as seen from the light's
// centre (+1: it faces the centre as stored).
@group(1) @binding(4) var<storage, read_write> caster_sign: array<i32>;
// The receivers' light-space box: `ordered` keys of min x, y, z (inverted, so that a maximum
// keeps the minimum) and of max x, y, z; zeroed before the build.
@group(1) @binding(5) var<storage, read_write> bounds: array<atomic<u32>, 6>;
// Per edge: its multiplicity (signed 16 bits) and, in bit 16, whether it has a wedge.
@group(1) @binding(6) var<storage, read_write> edge_counts: array<u32>;
// Per block of edges: its side quads and wedges, then (after `scan`) the first of each.
@group(1) @binding(7) var<storage, read_write> blocks: array<vec2<u32>>;
// Side quads, one per unit of multiplicity: the edge from -> to as the casters run it (stored
// vertices) and the mesh.
struct Side {
    start: vec4<f32>,
    to: vec4<f32>,
}
@group(1) @binding(8) var<storage, read_write> sides: array<Side>;
// Wedges, as `passes::wedge::WedgeInstance` lays them out.
struct Instance {
    lo: vec4<f32>,
    hi: vec4<f32>,
    start: vec4<f32>,
    to: vec4<f32>,
    near: vec4<f32>,
    far: vec4<f32>,
    caster: vec4<f32>,
}
@group(1) @binding(9) var<storage, read_write> wedges: array<Instance>;
// The wedges beyond `wedges`, in the rest of the same buffer: one binding holds at most the
// device's `max_storage_buffer_binding_size` (128 MiB on lavapipe, 1.2 million wedges).
@group(1) @binding(12) var<storage, read_write> wedges_more: array<Instance>;
// The draws of the side quads and of the wedges (`wgpu::util::DrawIndirectArgs` each).
@group(1) @binding(10) var<storage, read_write> args: array<u32, 8>;
// The meshes' triangles' corners, as the depth pre-pass draws them (`expand` rewrites them
// after the application moved a mesh's vertices).
@group(1) @binding(11) var<storage, read_write> corners: array<f32>;

const CLOSED_MESH: u32 = 0x80000000u;

// A face seen within this share of its size from the light's centre casts nothing: the f32
// rounding of its corners, placed relative to the eye, decides its side no better.
const EDGE_ON: f32 = 1e-5;

fn stored(i: u32) -> vec3<f32> {
    return vec3<f32>(positions[3u * i], positions[3u * i + 1u], positions[3u * i + 2u]);
}

fn placed(mesh: u32, i: u32) -> vec3<f32> {
    return eye_relative(mesh, stored(i)).xyz;
}

fn index(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return (id.y * groups.x) * BUILD_GROUP + id.x;
}

// Per face: whether and how it casts, and its corners into the receivers' box.
@compute @workgroup_size(256)
fn cast_faces(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) n: vec3<u32>) {
    let f = index(id, n);
    if (f >= arrayLength(&faces)) {
        return;
    }
    let face = faces[f];
    let mesh = face.w & ~CLOSED_MESH;
    let a = placed(mesh, face.x);
    let b = placed(mesh, face.y);
    let d = placed(mesh, face.z);
    for (var k = 0u; k < 3u; k++) {
        let l = to_light(select(select(d, b, k == 1u), a, k == 0u));
        for (var axis = 0u; axis < 3u; axis++) {
            let key = ordered(l[axis]);
            atomicMax(&bounds[axis], ~key);
            atomicMax(&bounds[3u + axis], key);
        }
    }
    let c = frame.light_center.xyz;
    let normal = cross(b - a, d - a);
    let o = dot(normal, c - a);
    let far = max(length(c - a), max(length(c - b), length(c - d)));
    var s = 0;
    if (abs(o) > EDGE_ON * length(normal) * far) {
        s = select(-1, 1, o > 0.0);
    }
    if ((face.w & CLOSED_MESH) != 0u) {
        // Closed: only the faces whose outer side faces the centre (the model matrix carries
        // the mesh's winding in the world: -1 wound inwards, or mirrored; not turned for a room
        // seen from inside, as the depth pre-pass's sign is).
        let outward = select(1.0, models[mesh][1].w, models[mesh][1].w != 0.0);
        if (f32(s) * outward <= 0.0) {
            s = 0;
        }
    }
    caster_sign[f] = s;
}

// The receivers' box, padded as `penumbra_volumes::receiver_box` pads it.
fn receiver_box() -> array<vec3<f32>, 2> {
    var lo = vec3<f32>(0.0);
    var hi = vec3<f32>(1.0);
    let k0 = atomicLoad(&bounds[0]);
    if (k0 != 0u) {
        for (var axis = 0u; axis < 3u; axis++) {
            lo[axis] = unordered(~atomicLoad(&bounds[axis]));
            hi[axis] = unordered(atomicLoad(&bounds[3u + axis]));
        }
    }
    let pad = max(hi - lo, vec3<f32>(1e-6)) * 1e-3;
    return array<vec3<f32>, 2>(lo - pad, hi + pad);
}

// An edge's multiplicity: its casters' windings along u -> v, summed.
fn multiplicity(e: vec4<u32>) -> i32 {
    var m = 0;
    for (var i = 0u; i < (e.w & 0xffffu); i++) {
        let inc = incidences[e.z + i];
        let s = caster_sign[inc >> 1u];
        m += select(-s, s, (inc & 1u) != 0u);
    }
    return m;
}

// A wedge's solid within the receivers' box (`penumbra_volumes::wedge_frustum`): the smaller of
// the wedge's bounding box clipped to the receivers' box and the frustum from the edge's
// rectangle to the light's mirrored squares at the box's far depth. `ok` false when the wedge
// misses the box.
struct Solid {
    ok: bool,
    z: vec2<f32>,
    near: vec4<f32>,
    far: vec4<f32>,
}

fn solid_volume(s: Solid) -> f32 {
    let dn = max(s.near.zw - s.near.xy, vec2<f32>(0.0));
    let df = max(s.far.zw - s.far.xy, vec2<f32>(0.0));
    let a0 = dn.x * dn.y;
    let a1 = df.x * df.y;
    return (s.z.y - s.z.x) * (a0 + a1 + sqrt(a0 * a1)) / 3.0;
}

fn wedge_solid(start: vec3<f32>, to: vec3<f32>, lo: vec3<f32>, hi: vec3<f32>) -> Solid {
    var out: Solid;
    // `wedge_bounds`: the edge swept from the light's corners to the box's far depth.
    let zmax = hi.z;
    let zmin = min(start.z, to.z);
    var blo = lo;
    var bhi = hi;
    // An edge on the light's plane (a lamp flush with a ceiling): its wedge may reach every
    // receiver, and the receivers' box bounds it.
    if (zmin > 0.0) {
        let t = max(zmax / zmin - 1.0, 0.0);
        blo = min(start, to);
        bhi = max(start, to);
        for (var k = 0u; k < 4u; k++) {
            let l = vec3<f32>(select(-1.0, 1.0, (k & 1u) != 0u), select(-1.0, 1.0, (k & 2u) != 0u), 0.0);
            let q0 = start + (start - l) * t;
            let q1 = to + (to - l) * t;
            blo = min(blo, min(q0, q1));
            bhi = max(bhi, max(q0, q1));
        }
        blo = max(blo, lo);
        bhi = min(bhi, hi);
    }
    out.ok = blo.x <= bhi.x && blo.y <= bhi.y && blo.z <= bhi.z;
    out.z = vec2<f32>(blo.z, bhi.z);
    out.near = vec4<f32>(blo.xy, bhi.xy);
    out.far = out.near;
    if (!out.ok) {
        return out;
    }
    var a = start;
    var b = to;
    if (start.z > to.z) {
        a = to;
        b = start;
    }
    if (!(a.z > 0.0 && a.z < zmax)) {
        return out;
    }
    if (b.z > zmax) {
        b = a + (b - a) * ((zmax - a.z) / (b.z - a.z));
    }
    var f: Solid;
    f.ok = true;
    f.z = vec2<f32>(a.z, zmax);
    f.near = vec4<f32>(min(a.xy, b.xy), max(a.xy, b.xy));
    f.far = f.near;
    for (var k = 0u; k < 2u; k++) {
        let s = select(b, a, k == 0u);
        let tau = zmax / s.z;
        let c = s.xy * tau;
        let h = vec2<f32>(tau - 1.0);
        f.far = vec4<f32>(min(f.far.xy, c - h), max(f.far.zw, c + h));
    }
    if (lo.z > a.z) {
        let u = (lo.z - f.z.x) / (f.z.y - f.z.x);
        f.near = mix(f.near, f.far, u);
        f.z.x = lo.z;
    }
    let finite = all(abs(f.near) < vec4<f32>(BIG)) && all(abs(f.far) < vec4<f32>(BIG));
    if (!(finite && f.z.x == out.z.x && f.z.y == out.z.y)) {
        return out;
    }
    if (solid_volume(f) < solid_volume(out)) {
        return f;
    }
    return out;
}

// Edge `e`'s ends in light space, from -> to as its casters run it (`m > 0`: u -> v).
fn edge_ends(e: vec4<u32>, m: i32) -> array<u32, 2> {
    if (m > 0) {
        return array<u32, 2>(e.x, e.y);
    }
    return array<u32, 2>(e.y, e.x);
}

// Edge i's multiplicity, as `count_edges` packed it (signed, in the low 16 bits).
fn counted_multiplicity(i: u32) -> i32 {
    return bitcast<i32>(edge_counts[i] << 16u) >> 16u;
}

// What edge `i` writes: its side quads and whether it has a wedge (0 past the last edge).
fn edge_output(i: u32) -> vec2<u32> {
    if (i >= arrayLength(&edges)) {
        return vec2<u32>(0u);
    }
    return vec2<u32>(u32(abs(counted_multiplicity(i))), (edge_counts[i] >> 16u) & 1u);
}

// Per edge: its multiplicity and whether its wedge reaches the receivers' box; per block, how
// much its edges write.
@compute @workgroup_size(256)
fn count_edges(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(num_workgroups) n: vec3<u32>,
) {
    let i = index(id, n);
    if (i < arrayLength(&edges)) {
        let e = edges[i];
        let m = multiplicity(e);
        var wedge = 0u;
        if (m != 0) {
            let mesh = e.w >> 16u;
            let ends = edge_ends(e, m);
            let bx = receiver_box();
            let s = wedge_solid(
                to_light(placed(mesh, ends[0])),
                to_light(placed(mesh, ends[1])),
                bx[0],
                bx[1],
            );
            wedge = select(0u, 1u, s.ok);
        }
        edge_counts[i] = (bitcast<u32>(m) & 0xffffu) | (wedge << 16u);
    }
    let total = workgroup_scan(local, edge_output(i));
    if (local == BUILD_GROUP - 1u) {
        blocks[group.y * n.x + group.x] = total;
    }
}

// One workgroup: the blocks' totals become their first outputs, and the draws' counts.
@compute @workgroup_size(256)
fn scan_blocks(@builtin(local_invocation_index) local: u32) {
    var carry = vec2<u32>(0u);
    let total = arrayLength(&blocks);
    for (var first = 0u; first < total; first += BUILD_GROUP) {
        let i = first + local;
        var mine = vec2<u32>(0u);
        if (i < total) {
            mine = blocks[i];
        }
        let inclusive = workgroup_scan(local, mine);
        if (i < total) {
            blocks[i] = carry + inclusive - mine;
        }
        carry += scan_sums[SCAN_GROUP - 1u];
        workgroupBarrier();
    }
    if (local == 0u) {
        args[0] = 6u;
        args[1] = carry.x;
        args[2] = 0u;
        args[3] = 0u;
        args[4] = 36u;
        args[5] = carry.y;
        args[6] = 0u;
        args[7] = 0u;
    }
}

// Per edge: its side quads and its wedge, at its place in edge order.
@compute @workgroup_size(256)
fn write_edges(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(num_workgroups) n: vec3<u32>,
) {
    let i = index(id, n);
    let mine = edge_output(i);
    let at = blocks[group.y * n.x + group.x] + workgroup_scan(local, mine) - mine;
    if (i >= arrayLength(&edges) || (mine.x == 0u)) {
        return;
    }
    let e = edges[i];
    let m = counted_multiplicity(i);
    let mesh = e.w >> 16u;
    let ends = edge_ends(e, m);
    let start = stored(ends[0]);
    let to = stored(ends[1]);
    for (var k = 0u; k < mine.x; k++) {
        sides[at.x + k] = Side(vec4<f32>(start, f32(mesh)), vec4<f32>(to, 0.0));
    }
    if (mine.y == 0u) {
        return;
    }
    let a = to_light(placed(mesh, ends[0]));
    let b = to_light(placed(mesh, ends[1]));
    let bx = receiver_box();
    let s = wedge_solid(a, b, bx[0], bx[1]);
    var w: Instance;
    w.lo = vec4<f32>(min(s.near.xy, s.far.xy), s.z.x, 0.0);
    w.hi = vec4<f32>(max(s.near.zw, s.far.zw), s.z.y, 0.0);
    w.start = vec4<f32>(a, f32(mine.x));
    w.to = vec4<f32>(b, 0.0);
    w.near = s.near;
    w.far = s.far;
    w.caster = vec4<f32>(0.0);
    let first = arrayLength(&wedges);
    if (at.y < first) {
        wedges[at.y] = w;
    } else {
        wedges_more[at.y - first] = w;
    }
}

// Per corner of the meshes' triangles: the stored vertex it stands for.
@compute @workgroup_size(256)
fn expand_corners(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) n: vec3<u32>) {
    let i = index(id, n);
    if (i >= 3u * arrayLength(&faces)) {
        return;
    }
    let v = faces[i / 3u][i % 3u];
    for (var k = 0u; k < 3u; k++) {
        corners[3u * i + k] = positions[3u * v + k];
    }
}
