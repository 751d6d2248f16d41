// Declarations shared by the two passes of depth-complexity sampling (Forest, Barthe & Paulin
// 2008): the edge-list pass (`edge_lists.wgsl`) and the counting pass (`count.wgsl`), each
// prepended with this file. Group 1 is `passes::complexity::inputs_layout`.
//
// Everything geometric is in light space (`to_light` in common.wgsl: the light is [-1, 1]^2 at
// z = 0, its centre the origin), as the CPU oracle (`penumbra_volumes::depth_complexity`) keeps
// it, in f32 here.

// A potential silhouette edge (`penumbra_volumes::potential::PotentialEdge`).
struct Edge {
    a: vec3<f32>,
    // First of its faces in `faces`.
    first_face: u32,
    b: vec3<f32>,
    face_count: u32,
    // (b - a) x (c - a) for the light's centre c.
    toward_centre: vec3<f32>,
    pad: u32,
    // What `a` and `toward_centre` rounded off (`passes::complexity::split`).
    a_low: vec3<f32>,
    pad1: u32,
    toward_centre_low: vec3<f32>,
    pad2: u32,
}

// One face on an edge `a b`: (b - a) x (w - a) for its third vertex w, and its triangle's index
// in the scene (`penumbra_volumes::potential::EdgeFace`).
struct Face {
    normal: vec3<f32>,
    triangle: u32,
    // What `normal` rounded off.
    normal_low: vec3<f32>,
    pad: u32,
}

// A triangle through the light's plane (`penumbra_volumes::potential::LightCrossing`).
struct Crossing {
    a: vec2<f32>,
    b: vec2<f32>,
    inside: vec3<f32>,
    triangle: u32,
}

struct Params {
    // Potential silhouette edges, crossings, entries the edge list holds, samples per axis N.
    edges: u32,
    crossings: u32,
    capacity: u32,
    per_axis: u32,
    // Tiles per row of the image; triangles in `triangles`; the loop iterations an invocation of
    // the counting pass may take before it counts its pixel as cut short (`demand[1]`).
    tiles_x: u32,
    triangles: u32,
    budget: u32,
    // 0, unknown to the compiler (`passes::complexity::ComplexityParams::zero`).
    zero: u32,
    // Entries of a pixel's work (its tile's edges, then the crossings) one dispatch of the
    // counting pass takes (`passes::count`), and the dispatches recorded for them.
    chunk: u32,
    chunks: u32,
    // Image rows whose state and counts the counting pass keeps at once.
    band_rows: u32,
    // 1 + y * width + x of a pixel whose stencil count reads two too many (tests); 0: none.
    stencil_error: u32,
    // 1: every pixel's D(P, c) is counted again over every triangle (a room around the
    // light, whose walls are casters over their own receivers in the volumes).
    recount_all: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
    // The eye in light space (w unused).
    eye: vec4<f32>,
    // The light-space direction of the ray through normalised device coordinates (x, y):
    // x ray_x + y ray_y + ray_1 (w unused).
    ray_x: vec4<f32>,
    ray_y: vec4<f32>,
    ray_1: vec4<f32>,
}

@group(1) @binding(0) var position: texture_2d<f32>;
@group(1) @binding(1) var stencil_count: texture_2d<u32>;
@group(1) @binding(2) var<storage, read> edges: array<Edge>;
@group(1) @binding(3) var<storage, read> faces: array<Face>;
@group(1) @binding(4) var<storage, read> crossings: array<Crossing>;
// Per tile of TILE x TILE pixels: its first entry in `list` and its number of entries. A tile
// whose entries run past `params.capacity` lost some: the counting pass reads every edge there.
@group(1) @binding(5) var<storage, read_write> tile_ranges: array<vec2<u32>>;
@group(1) @binding(6) var<storage, read_write> list: array<u32>;
// [0]: the entries the frame's tiles asked for (more than `params.capacity`: an overflow);
// [1]: the pixels whose counting went past `params.budget` loop iterations.
// [2]: the most dispatches of `count_chunk` a pixel of the bands so far needs; [3]: the pixels whose
// work they did not finish; [4]: the first row of the counting pass's current band.
@group(1) @binding(7) var<storage, read_write> demand: array<atomic<u32>>;
@group(1) @binding(8) var<uniform> params: Params;
// V, one per pixel, row by row.
// The counting pass's buffer: V (f32 bits) of every pixel, then each pixel's state between its
// dispatches (`STATE_WORDS` words), then each pixel's sample counts (`count.wgsl`).
@group(1) @binding(9) var<storage, read_write> visibility: array<u32>;
// A scene triangle in light space (`passes::complexity::GpuTriangle`): its plane, unit normal n
// and n . x = w, and its corners (w unused), the same f32 points as the edges' ends they share.
struct Triangle {
    plane: vec4<f32>,
    corners: array<vec4<f32>, 3>,
    // What the corners rounded off, as `Edge::a_low`.
    corners_low: array<vec4<f32>, 3>,
    // A triangle across the side opposite each corner (none: 0xffffffff).
    neighbours: array<u32, 3>,
    pad: u32,
}

// Each scene triangle.
@group(1) @binding(10) var<storage, read> triangles: array<Triangle>;

// Per pixel, the nearest triangle that the ray through its centre meets, plus one (0: none), by
// the receiver candidates' pass (`candidates.wgsl`).
@group(1) @binding(11) var candidate: texture_2d<u32>;

// The barycentric weights of q, a point of triangle t's plane, times twice its area squared.
fn barycentric(t: Triangle, q: vec3<f32>) -> vec3<f32> {
    let c0 = t.corners[0].xyz;
    let c1 = t.corners[1].xyz;
    let c2 = t.corners[2].xyz;
    let n = cross(c1 - c0, c2 - c0);
    return vec3<f32>(
        dot(n, cross(c1 - q, c2 - q)),
        dot(n, cross(c2 - q, c0 - q)),
        dot(n, cross(c0 - q, c1 - q)),
    );
}

// The receiver's triangle from the depth pre-pass's position w (`passes::depth::GBuffer`).
fn receiver_triangle(w: f32) -> u32 {
    return bitcast<u32>(w) - TRIANGLE_BIAS;
}

// The light's corners, counter-clockwise (`penumbra_volumes::potential::LIGHT_CORNERS`).
fn light_corner(k: u32) -> vec3<f32> {
    let c = array<vec3<f32>, 4>(
        vec3<f32>(-1.0, -1.0, 0.0),
        vec3<f32>(1.0, -1.0, 0.0),
        vec3<f32>(1.0, 1.0, 0.0),
        vec3<f32>(-1.0, 1.0, 0.0),
    );
    return c[k];
}

// The receiver seen through pixel `px` in light space, from the depth pre-pass's position `p`
// (w non-zero). The rasteriser snaps the triangles' corners to a fraction of a pixel, so the
// interpolated position lies on the triangle but off the pixel's ray, by up to a few thousandths
// of a pixel's footprint: enough to move a projected edge across a light sample. As the CPU
// oracle does, the point is taken where the ray through the pixel's centre meets the receiver's
// plane instead; the interpolated one where that is ill-conditioned (a ray grazing the plane) or
// the triangle is unknown.
fn receiver_point(px: vec2<u32>, p: vec4<f32>) -> vec3<f32> {
    let raster = to_light(p.xyz);
    let t = receiver_triangle(p.w);
    if (t >= params.triangles) {
        return raster;
    }
    let at = on_plane(px, triangles[t].plane);
    let off = length(at - raster);
    if (!(off <= 1e-3 * length(raster - params.eye.xyz))) {
        return raster;
    }
    return at;
}

// Where the ray through the centre of pixel `px` meets `plane` (unit normal n, n . x = w), in
// light space; not finite where the ray runs along the plane.
fn on_plane(px: vec2<u32>, plane: vec4<f32>) -> vec3<f32> {
    let ndc = vec2<f32>(
        2.0 * (f32(px.x) + 0.5) / frame.size.x - 1.0,
        1.0 - 2.0 * (f32(px.y) + 0.5) / frame.size.y,
    );
    let dir = ndc.x * params.ray_x.xyz + ndc.y * params.ray_y.xyz + params.ray_1.xyz;
    let eye = params.eye.xyz;
    let along = dot(plane.xyz, dir);
    return eye + dir * ((plane.w - dot(plane.xyz, eye)) / along);
}

// The edge lists' test, shared with the counting pass's reading of every edge where a tile's
// list overflowed (there the tile is the one pixel).

// Distances of p inside each side of the light, over p.z: (y + 1, 1 - x, 1 - y, x + 1) / z.
fn side_keys(p: vec3<f32>) -> vec4<f32> {
    return vec4<f32>(p.y + 1.0, 1.0 - p.x, 1.0 - p.y, p.x + 1.0) / p.z;
}

// The union pyramid's side planes at q: inward_k(q) - key_k q.z, negative outside, with a margin
// for rounding added.
fn side_values(q: vec3<f32>, keys: vec4<f32>) -> vec4<f32> {
    let inward = vec4<f32>(q.y + 1.0, 1.0 - q.x, 1.0 - q.y, q.x + 1.0);
    let v = inward - keys * q.z;
    let scale = vec4<f32>(1.0 + abs(q.x) + abs(q.y)) + abs(keys * q.z);
    return v + 1e-5 * scale;
}

// Whether the edge may change a count seen from some receiver of the tile: `keys` the union
// pyramid's, [lo, hi] the receivers' bounding box.
fn listed(e: Edge, keys: vec4<f32>, lo: vec3<f32>, hi: vec3<f32>) -> bool {
    let sa = side_values(e.a, keys);
    let sb = side_values(e.b, keys);
    if (any((sa < vec4<f32>(0.0)) & (sb < vec4<f32>(0.0)))) {
        return false;
    }
    if (e.face_count != 2u) {
        return true;
    }
    let n0 = faces[e.first_face].normal;
    let n1 = faces[e.first_face + 1u].normal;
    let centre = 0.5 * (lo + hi) - e.a;
    let half = 0.5 * (hi - lo);
    let reach = length(centre) + length(e.a) + length(half);
    let mid0 = dot(n0, centre);
    let spread0 = dot(abs(n0), half) * (1.0 + 1e-5) + 1e-5 * length(n0) * reach;
    let mid1 = dot(n1, centre);
    let spread1 = dot(abs(n1), half) * (1.0 + 1e-5) + 1e-5 * length(n1) * reach;
    let apart = (mid0 - spread0 > 0.0 && mid1 + spread1 < 0.0)
        || (mid0 + spread0 < 0.0 && mid1 - spread1 > 0.0);
    return !apart;
}
