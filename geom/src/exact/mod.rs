//! The exact point evaluator of visibility: the reference that every approximate method of
//! penumbra is measured against ([`exact_visibility`] gives the method).

use glam::{DVec2, DVec3};

use crate::light::RectLight;
pub use union::LIGHT_SQUARE_AREA;
use union::{polygon_area, union_area_of_clean};

mod union;

#[cfg(test)]
mod exact_scene_tests;
#[cfg(test)]
mod exact_tests;
#[cfg(test)]
mod union_tests;

/// Projected polygons with a smaller area (light-space units, of 4) are dropped as slivers.
const MIN_POLYGON_AREA: f64 = 1e-14;

/// A triangle whose plane passes within this fraction of its distance from `P` is taken to
/// pass through `P` (sine of the grazing angle): it projects to a segment and is skipped.
const THROUGH_APEX_TOLERANCE: f64 = 1e-9;

/// Coordinates smaller than this are flushed to zero, far above spade's smallest allowed
/// coordinate (`2^-142`) and far below any area that matters.
const FLUSH_TO_ZERO: f64 = 1e-30;

/// Coordinates this close to `±1` are moved onto the square's edge: rounding in clipping leaves
/// points cut by a side plane a few ulps inside.
const BOUNDARY_SNAP: f64 = 1e-12;

/// Occluded fraction and visibility at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExactVisibility {
    /// `V(P)` in `[0, 1]`: the visible fraction of the light's area.
    pub visibility: f64,
    /// Occluded area in light-space units, out of [`LIGHT_SQUARE_AREA`] (4). Points that are not
    /// on the emitting side report the whole square, so `visibility = 1 - occluded_area / 4`
    /// holds up to the clamp.
    pub occluded_area: f64,
    /// Number of projected polygons that survived culling, clipping and the sliver filter.
    pub polygons: usize,
}

/// Exact visibility of `p` with respect to `light` through `triangles` (world space, f64),
/// skipping the triangle index `exclude` (the one `p` lies on), if any.
///
/// `V = 1 - |union of projected occluders| / 4`, clamped to `[0, 1]`. A point that is not
/// strictly on the emitting side ([`RectLight::is_lit_side`]) or not finite gets `V = 0`. Never
/// panics and never returns NaN: non-finite and degenerate triangles are skipped.
///
/// For a receiver point `P` and a one-sided rectangular light `L`,
///
/// ```text
/// V(P) = |{ y in L : segment P-y meets no triangle }| / |L|      (no cosine weighting)
/// ```
///
/// and `V(P) = 0` when `P` is not strictly on the emitting side. Triangles occlude from both
/// sides; the triangle `P` lies on is excluded by index.
///
/// # Method
///
/// Everything happens in light space ([`RectLight::to_light_space`]), where the light is the
/// square `[-1, 1]^2` of the plane `z = 0` and `P = (p_x, p_y, z_p)` with `z_p > 0`.
///
/// 1. Each triangle is clipped to the pyramid with apex `P` over the light square, cut at the
///    light plane: the part of the slab `0 <= z < z_p` between the local near plane (through `P`,
///    parallel to the light) and the light plane that projects into the square. Only that part can
///    hide light from `P`.
/// 2. The clipped polygon is projected centrally from `P` onto the light plane,
///    `X' = P + (X - P) * z_p / (z_p - z_X)`, which is a convex polygon in `[-1, 1]^2`.
/// 3. The occluded area is the area of the union of the projected polygons. It is computed on a
///    constrained Delaunay triangulation (spade) whose constraints are the square's boundary and
///    every polygon edge, split where edges cross. No constraint crosses a face, so every face
///    lies inside or outside each polygon as a whole: a face is covered when its centroid lies
///    in at least one polygon, and the union area is the sum of the covered faces' areas.
/// 4. Central projection onto the plane followed by the affine map to light space keeps ratios
///    of areas, so `V = 1 - union / 4`.
///
/// Steps 1 and 2 do the rectangle clip of the projected polygon (Sutherland & Hodgman 1974,
/// "Reentrant polygon clipping", CACM 17(1)) *before* the perspective division, in homogeneous
/// coordinates (Blinn & Newell 1978, "Clipping using homogeneous coordinates", SIGGRAPH): with
///
/// ```text
/// w = z_p - z_X,   h = P.xy * w + (X.xy - P.xy) * z_p,   X' = h / w,
/// ```
///
/// `-1 <= X'.x <= 1` for `w > 0` reads `w + h.x >= 0` and `w - h.x >= 0`, which are half-spaces
/// of `X` through `P`: the pyramid's four side planes. Their intersection already excludes
/// everything behind the near plane (`w <= 0`), so the near plane needs no tolerance of its own
/// and no coordinate ever grows like `1 / w`. The fifth plane is the light plane, `z >= 0`. The
/// same planes cull whole triangles cheaply before any clipping.
///
/// The crossings of step 3 are not left to spade's splitting insertion
/// ([`spade::ConstrainedDelaunayTriangulation::add_constraint_and_split`]): on the nearly
/// collinear and nearly concurrent edges that projected meshes produce (boxes seen from points
/// aligned with their edges, lattice-like input) it panicked (`!previous_region.is_empty() ||
/// from == final_vertex`, `is_ordered_ccw` in `legalize_edge`) on about 0.4% of the receiver
/// points of an aligned-box test scene and on about one lattice input in five, and one input
/// made it loop with memory growing without bound. The edges are instead snap rounded (Hobby
/// 1999) to a grid of spacing `2^-40` with exact integer predicates, which yields fragments that
/// meet only at grid points: spade receives exactly representable vertices and non-crossing
/// constraints (`try_add_constraint`; the splitting insertion remains only as a fallback that
/// the tests check is never taken), and the face classification is exact as well. The union
/// computed is that of the snapped polygons, whose vertices move by at most `2^-41` per
/// coordinate: the occluded area is off by about the union's perimeter times `2^-41`, around
/// `1e-12` of 4.
///
/// Degenerate input is skipped rather than propagated: triangles with a non-finite vertex,
/// triangles whose supporting plane passes through `P` (they project to a segment: zero area,
/// which also covers the receiver's coplanar neighbours) and projected polygons of area below
/// `1e-14` (of 4) never reach the triangulation, so the result is never NaN.
pub fn exact_visibility(
    p: DVec3,
    light: &RectLight,
    triangles: &[[DVec3; 3]],
    exclude: Option<usize>,
) -> ExactVisibility {
    if !light.is_lit_side(p) || !p.is_finite() {
        return ExactVisibility {
            visibility: 0.0,
            occluded_area: LIGHT_SQUARE_AREA,
            polygons: 0,
        };
    }
    let p_light = light.to_light_space(p);
    let polys: Vec<Vec<DVec2>> = triangles
        .iter()
        .enumerate()
        .filter(|&(i, _)| Some(i) != exclude)
        .filter_map(|(_, tri)| project_triangle(p_light, tri.map(|v| light.to_light_space(v))))
        .collect();
    let occluded_area = union_area_of_clean(&polys).area;
    ExactVisibility {
        visibility: (1.0 - occluded_area / LIGHT_SQUARE_AREA).clamp(0.0, 1.0),
        occluded_area,
        polygons: polys.len(),
    }
}

/// A point in the homogeneous coordinates of the projection from `P`: `(x, y) / w` is its image
/// on the light plane and `z` its light-space height. Linear in the 3D point, so clipping may
/// interpolate it.
#[derive(Clone, Copy, Debug)]
struct Homogeneous {
    x: f64,
    y: f64,
    w: f64,
    z: f64,
}

impl Homogeneous {
    /// `X` seen from `p` (both in light space): `w = z_p - z_X`, `(x, y) = P.xy * w + (X.xy -
    /// P.xy) * z_p`.
    fn new(p: DVec3, x: DVec3) -> Self {
        let w = p.z - x.z;
        Homogeneous {
            x: p.x * w + (x.x - p.x) * p.z,
            y: p.y * w + (x.y - p.y) * p.z,
            w,
            z: x.z,
        }
    }

    /// Signed value of the `k`-th clip plane, non-negative inside: the light plane, then the
    /// four side planes of the pyramid.
    fn plane(self, k: usize) -> f64 {
        match k {
            0 => self.z,
            1 => self.w + self.x,
            2 => self.w - self.x,
            3 => self.w + self.y,
            _ => self.w - self.y,
        }
    }

    fn lerp(self, to: Self, t: f64) -> Self {
        Homogeneous {
            x: self.x + (to.x - self.x) * t,
            y: self.y + (to.y - self.y) * t,
            w: self.w + (to.w - self.w) * t,
            z: self.z + (to.z - self.z) * t,
        }
    }
}

/// One Sutherland–Hodgman step: keeps the part of the closed polygon `input` where `f >= 0`.
///
/// The crossing point of an edge is always interpolated from its inside end towards its outside
/// end, so an edge shared by two polygons is cut at bit-identical points whichever way each
/// polygon runs along it.
pub fn clip_step<T: Copy>(
    input: &[T],
    f: impl Fn(T) -> f64,
    lerp: impl Fn(T, T, f64) -> T,
    out: &mut Vec<T>,
) {
    out.clear();
    let n = input.len();
    for i in 0..n {
        let a = input[i];
        let b = input[(i + 1) % n];
        let (fa, fb) = (f(a), f(b));
        if fa >= 0.0 {
            out.push(a);
        }
        if (fa > 0.0 && fb < 0.0) || (fa < 0.0 && fb > 0.0) {
            let (inside, f_in, outside, f_out) = if fa > 0.0 {
                (a, fa, b, fb)
            } else {
                (b, fb, a, fa)
            };
            out.push(lerp(inside, outside, f_in / (f_in - f_out)));
        }
    }
}

/// Whether the plane of `tri` passes through `p` within [`THROUGH_APEX_TOLERANCE`], degenerate
/// (zero-area) triangles included.
fn plane_through(p: DVec3, tri: &[DVec3; 3]) -> bool {
    let [a, b, c] = *tri;
    let n = (b - a).cross(c - a);
    let reach = (p - a).length().max((p - b).length()).max((p - c).length());
    n.dot(p - a).abs() <= THROUGH_APEX_TOLERANCE * n.length() * reach
}

/// The image of a triangle on the light square as seen from `p_light`, both in light space
/// (`p_light.z > 0`): the triangle clipped to the pyramid from `p_light` over `[-1, 1]^2` and to
/// `z >= 0`, projected centrally from `p_light` onto `z = 0`. Returns the polygon's `(x, y)`
/// vertices counter-clockwise, without repeated consecutive vertices, or `None` when nothing of
/// positive area (above `1e-14`) remains, when the triangle's plane passes through `p_light`
/// (it projects to a segment), or when any input is not finite.
pub fn project_triangle(p_light: DVec3, tri_light: [DVec3; 3]) -> Option<Vec<DVec2>> {
    if !p_light.is_finite() || p_light.z <= 0.0 || !tri_light.iter().all(|v| v.is_finite()) {
        return None;
    }
    let h = tri_light.map(|v| Homogeneous::new(p_light, v));
    // Cull: a triangle wholly outside one clip plane, or wholly behind the near plane.
    if (0..5).any(|k| h.iter().all(|v| v.plane(k) <= 0.0)) || h.iter().all(|v| v.w <= 0.0) {
        return None;
    }
    if plane_through(p_light, &tri_light) {
        return None;
    }
    let mut poly = h.to_vec();
    let mut scratch = Vec::with_capacity(8);
    for k in 0..5 {
        clip_step(&poly, |v| v.plane(k), Homogeneous::lerp, &mut scratch);
        std::mem::swap(&mut poly, &mut scratch);
        if poly.len() < 3 {
            return None;
        }
    }
    // Inside the pyramid |x|, |y| <= w, so the division is bounded; the clamp only removes
    // rounding excursions and puts points cut by a side plane exactly on the square's edge.
    let mut out = Vec::with_capacity(poly.len());
    for v in &poly {
        if v.w.is_nan() || v.w <= 0.0 {
            return None;
        }
        let q = DVec2::new((v.x / v.w).clamp(-1.0, 1.0), (v.y / v.w).clamp(-1.0, 1.0));
        if !q.is_finite() {
            return None;
        }
        out.push(q);
    }
    finish_polygon(out)
}

/// Puts a coordinate within [`BOUNDARY_SNAP`] of the square's edge exactly on it, flushes tiny
/// ones to zero and turns -0.0 into 0.0, so that equal points have equal bits. A polygon edge
/// a few ulps off the square's edge would otherwise be a nearly collinear pair of constraints.
fn snap(s: f64) -> f64 {
    if s.abs() >= 1.0 - BOUNDARY_SNAP {
        s.signum()
    } else if s.abs() < FLUSH_TO_ZERO {
        0.0
    } else {
        s
    }
}

/// Flushes tiny coordinates to zero, drops repeated consecutive vertices, rejects non-finite
/// polygons and slivers, and orients the rest counter-clockwise.
fn finish_polygon(mut poly: Vec<DVec2>) -> Option<Vec<DVec2>> {
    if !poly.iter().all(|v| v.is_finite()) {
        return None;
    }
    for v in &mut poly {
        *v = DVec2::new(snap(v.x), snap(v.y));
    }
    poly.dedup();
    while poly.len() > 1 && poly.first() == poly.last() {
        poly.pop();
    }
    if poly.len() < 3 {
        return None;
    }
    let area = polygon_area(&poly);
    if area.is_nan() || area.abs() < MIN_POLYGON_AREA {
        return None;
    }
    if area < 0.0 {
        poly.reverse();
    }
    Some(poly)
}

/// The part of the closed polygon `poly` inside the square `[-1, 1]^2` (Sutherland & Hodgman
/// 1974), in the same orientation. Points on the square's boundary count as inside; points cut
/// by an edge of the square lie exactly on it. Empty when nothing is left.
#[cfg(test)]
fn clip_polygon_to_rect(poly: &[DVec2]) -> Vec<DVec2> {
    let mut cur = poly.to_vec();
    let mut next = Vec::with_capacity(poly.len() + 4);
    // (axis, sign): keeps sign * coordinate <= 1.
    for (axis, sign) in [(0, 1.0), (0, -1.0), (1, 1.0), (1, -1.0)] {
        if cur.is_empty() {
            break;
        }
        let lerp = |a: DVec2, b: DVec2, t: f64| {
            let mut q = a + (b - a) * t;
            q[axis] = sign;
            q
        };
        clip_step(&cur, |v: DVec2| 1.0 - sign * v[axis], lerp, &mut next);
        std::mem::swap(&mut cur, &mut next);
    }
    cur
}

/// Area of the union of the simple polygons `polys` within the square `[-1, 1]^2`.
///
/// Each polygon is first clipped to the square; non-finite polygons and slivers (area below
/// `1e-14`) are dropped. The union is measured on a constrained Delaunay triangulation whose
/// constraints are the square's boundary and all polygon edges, split where they cross by snap
/// rounding to a grid of spacing `2^-40` (see [`exact_visibility`]): each face counts when
/// its centroid lies in some polygon (even-odd rule). The result is exact for the snapped
/// polygons, which differ from the given ones by at most `2^-41` per coordinate. (The tests' way
/// in: [`exact_visibility`] builds its clean polygons itself.)
#[cfg(test)]
fn union_area(polys: &[Vec<DVec2>]) -> f64 {
    let clean: Vec<Vec<DVec2>> = polys
        .iter()
        .filter_map(|p| finish_polygon(clip_polygon_to_rect(p)))
        .collect();
    union_area_of_clean(&clean).area
}
