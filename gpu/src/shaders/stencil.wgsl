// z-fail stencil pass of the shadow volumes (Carmack 2000; Everitt & Kilgard 2002), Forest et al.'s
// first per-silhouette pass. Vertices are homogeneous: w = 1 for the casters' vertices (as the
// depth pre-pass reads them: mesh `mesh`'s stored vertices, placed by `eye_relative`), w = 0 for
// their projections to infinity away from the light's centre (world directions), so the side
// quads and dark caps reach infinity and the reversed, infinite projection puts them at depth 0.
// No colour output: the stencil operations do the counting.

// `frame` (group 0) is declared in common.wgsl, prepended by `passes::shader`.

@vertex
fn vs(
    @location(0) h: vec4<f32>,
    @builtin(instance_index) mesh: u32,
) -> @builtin(position) @invariant vec4<f32> {
    if (h.w == 0.0) {
        return frame.view_proj * h;
    }
    return frame.view_proj * eye_relative(mesh, h.xyz);
}
