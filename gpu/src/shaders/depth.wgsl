// Depth pre-pass (seed 004, section 4: the visibility buffer needs the receivers' depth).
// Every scene triangle, both sides, into a Depth32FloatStencil8 target with reversed z, and the
// eye-relative surface position P into an Rgba32Float target (w = 1 where something was hit).

// `frame` (group 0) is declared in frame.wgsl, prepended by `passes::shader`.

struct VertexOut {
    // Invariant: the stencil pass draws the light caps from the same positions and must land on
    // exactly the same depths.
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) rel: vec3<f32>,
}

@vertex
fn vs(@location(0) rel: vec3<f32>) -> VertexOut {
    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(rel, 1.0);
    out.rel = rel;
    return out;
}

@fragment
fn fs(in: VertexOut) -> @location(0) vec4<f32> {
    return vec4<f32>(in.rel, 1.0);
}
