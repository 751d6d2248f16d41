// Receiver candidates of depth-complexity sampling (`passes::candidates`), compiled after
// complexity.wgsl: for every pixel, the nearest triangle that the ray through its centre meets,
// by a test of the ray against each triangle rather than by the rasteriser. The rasteriser snaps
// corners to a fraction of a pixel, so it draws a sliver seen edge-on on no pixel and can give
// a pixel centre within that fraction of an edge to the triangle behind; the counting pass
// (`ray_receiver`) takes this candidate where it holds the ray nearer than the rasterised one.
//
// Each triangle is drawn as its box on screen grown by a pixel (the whole screen where a corner
// lies behind the eye), so that every pixel whose ray may meet it gets a fragment, and the
// fragment keeps it where the ray meets it: the depth test keeps the nearest.

struct BoxOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) triangle: u32,
}

@vertex
fn vs_box(@builtin(vertex_index) vi: u32) -> BoxOut {
    let t = vi / 6u;
    let k = vi % 6u;
    let corner = array<vec2<f32>, 6>(
        vec2<f32>(0.0, 0.0),
        vec2<f32>(1.0, 0.0),
        vec2<f32>(1.0, 1.0),
        vec2<f32>(0.0, 0.0),
        vec2<f32>(1.0, 1.0),
        vec2<f32>(0.0, 1.0),
    );
    let tri = triangles[t];
    var lo = vec2<f32>(BIG);
    var hi = vec2<f32>(-BIG);
    var behind = 0u;
    for (var i = 0u; i < 3u; i++) {
        let c = frame.view_proj * vec4<f32>(from_light(tri.corners[i].xyz), 1.0);
        if (!(c.w > 0.0)) {
            behind++;
        } else {
            lo = min(lo, c.xy / c.w);
            hi = max(hi, c.xy / c.w);
        }
    }
    // A pixel in normalised device coordinates.
    let pixel = vec2<f32>(2.0) / frame.size.xy;
    lo = max(lo - pixel, vec2<f32>(-1.0));
    hi = min(hi + pixel, vec2<f32>(1.0));
    if (behind > 0u) {
        lo = vec2<f32>(-1.0);
        hi = vec2<f32>(1.0);
    }
    var out: BoxOut;
    out.triangle = t;
    // Wholly behind the eye, or off the screen: a point, no fragment.
    if (behind == 3u || any(lo > hi)) {
        out.clip = vec4<f32>(2.0, 2.0, 0.5, 1.0);
        return out;
    }
    out.clip = vec4<f32>(mix(lo, hi, corner[k]), 0.5, 1.0);
    return out;
}

struct Nearest {
    @builtin(frag_depth) depth: f32,
    // The triangle plus one (0: none).
    @location(0) triangle: u32,
}

@fragment
fn fs_hit(in: BoxOut) -> Nearest {
    let px = vec2<u32>(floor(in.clip.xy));
    let t = triangles[in.triangle];
    let at = on_plane(px, t.plane);
    let eye = params.eye.xyz;
    // In front of the eye, and inside the triangle.
    let clip_w = (frame.view_proj * vec4<f32>(from_light(at), 1.0)).w;
    if (!(clip_w > 0.0) || !all(barycentric(t, at) >= vec3<f32>(0.0))) {
        discard;
    }
    let d = length(at - eye);
    let scale = max(length(eye), 1e-6);
    var out: Nearest;
    out.depth = d / (d + scale);
    out.triangle = in.triangle + 1u;
    return out;
}
