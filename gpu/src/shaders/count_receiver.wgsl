// The counting pass's receiver: the triangle and the point of it that a pixel's ray meets, as
// the CPU oracle's ray caster finds them, compiled ahead of count.wgsl
// (`passes::complexity::COUNT_WGSL`).

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
