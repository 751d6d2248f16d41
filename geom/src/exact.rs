//! The exact point evaluator of visibility: the reference that every approximate method of
//! penumbra is measured against.
//!
//! For a receiver point `P` and a one-sided rectangular light `L`,
//!
//! ```text
//! V(P) = |{ y in L : segment P-y meets no triangle }| / |L|      (no cosine weighting)
//! ```
//!
//! and `V(P) = 0` when `P` is not strictly on the emitting side. Triangles occlude from both
//! sides; the triangle `P` lies on is excluded by index.
//!
//! # Method
//!
//! Everything happens in light space ([`RectLight::to_light_space`]), where the light is the
//! square `[-1, 1]^2` of the plane `z = 0` and `P = (p_x, p_y, z_p)` with `z_p > 0`.
//!
//! 1. Each triangle is clipped to the pyramid with apex `P` over the light square, cut at the
//!    light plane: the part of the slab `0 <= z < z_p` between the local near plane (through `P`,
//!    parallel to the light) and the light plane that projects into the square. Only that part can
//!    hide light from `P`.
//! 2. The clipped polygon is projected centrally from `P` onto the light plane,
//!    `X' = P + (X - P) * z_p / (z_p - z_X)`, which is a convex polygon in `[-1, 1]^2`.
//! 3. The occluded area is the area of the union of the projected polygons. It is computed on a
//!    constrained Delaunay triangulation (spade) whose constraints are the square's boundary and
//!    every polygon edge, intersecting constraints being split
//!    ([`spade::ConstrainedDelaunayTriangulation::add_constraint_and_split`]). No constraint
//!    crosses a face, so every face lies inside or outside each polygon as a whole: a face is
//!    covered when its centroid lies in at least one polygon, and the union area is the sum of
//!    the covered faces' areas.
//! 4. Central projection onto the plane followed by the affine map to light space keeps ratios
//!    of areas, so `V = 1 - union / 4`.
//!
//! Steps 1 and 2 do the rectangle clip of the projected polygon (Sutherland & Hodgman 1974,
//! "Reentrant polygon clipping", CACM 17(1)) *before* the perspective division, in homogeneous
//! coordinates (Blinn & Newell 1978, "Clipping using homogeneous coordinates", SIGGRAPH): with
//!
//! ```text
//! w = z_p - z_X,   h = P.xy * w + (X.xy - P.xy) * z_p,   X' = h / w,
//! ```
//!
//! `-1 <= X'.x <= 1` for `w > 0` reads `w + h.x >= 0` and `w - h.x >= 0`, which are half-spaces
//! of `X` through `P`: the pyramid's four side planes. Their intersection already excludes
//! everything behind the near plane (`w <= 0`), so the near plane needs no tolerance of its own
//! and no coordinate ever grows like `1 / w`. The fifth plane is the light plane, `z >= 0`. The
//! same planes cull whole triangles cheaply before any clipping.
//!
//! Degenerate input is skipped rather than propagated: triangles with a non-finite vertex,
//! triangles whose supporting plane passes through `P` (they project to a segment: zero area,
//! which also covers the receiver's coplanar neighbours) and projected polygons of area below
//! `1e-14` (of 4) never reach the triangulation, so the result is never NaN.

use std::collections::{HashMap, HashSet};

use glam::{DVec2, DVec3};
use spade::handles::FixedVertexHandle;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use crate::light::RectLight;

#[cfg(test)]
#[path = "exact_tests.rs"]
mod exact_tests;

/// Area of the light square `[-1, 1]^2` in light-space units.
pub const LIGHT_SQUARE_AREA: f64 = 4.0;

/// Projected polygons with a smaller area (light-space units, of 4) are dropped as slivers.
const MIN_POLYGON_AREA: f64 = 1e-14;

/// A triangle whose plane passes within this fraction of its distance from `P` is taken to
/// pass through `P` (sine of the grazing angle): it projects to a segment and is skipped.
const THROUGH_APEX_TOLERANCE: f64 = 1e-9;

/// Coordinates smaller than this are flushed to zero, far above spade's smallest allowed
/// coordinate (`2^-142`) and far below any area that matters.
const FLUSH_TO_ZERO: f64 = 1e-30;

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
/// `V = 1 - |union of projected occluders| / 4`, clamped to `[0, 1]`; see the module
/// documentation for the method. A point that is not strictly on the emitting side
/// ([`RectLight::is_lit_side`], false for non-finite points) gets `V = 0`.
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
    let occluded_area = union_area_of_clean(&polys);
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
fn clip_step<T: Copy>(
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
    if !(p_light.z > 0.0) || !p_light.is_finite() || !tri_light.iter().all(|v| v.is_finite()) {
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
        if !(v.w > 0.0) {
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

/// Flushes tiny coordinates to zero, drops repeated consecutive vertices, rejects non-finite
/// polygons and slivers, and orients the rest counter-clockwise.
fn finish_polygon(mut poly: Vec<DVec2>) -> Option<Vec<DVec2>> {
    if !poly.iter().all(|v| v.is_finite()) {
        return None;
    }
    for v in &mut poly {
        // `+ 0.0` also turns -0.0 into 0.0, so equal points have equal bits.
        *v = DVec2::select(v.abs().cmplt(DVec2::splat(FLUSH_TO_ZERO)), DVec2::ZERO, *v)
            + DVec2::ZERO;
    }
    poly.dedup();
    while poly.len() > 1 && poly.first() == poly.last() {
        poly.pop();
    }
    if poly.len() < 3 {
        return None;
    }
    let area = polygon_area(&poly);
    if !(area.abs() >= MIN_POLYGON_AREA) {
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
pub fn clip_polygon_to_rect(poly: &[DVec2]) -> Vec<DVec2> {
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

/// Signed area of the closed polygon `poly` by the shoelace formula,
/// `A = 1/2 * sum_i (x_i * y_{i+1} - x_{i+1} * y_i)`: positive when counter-clockwise.
pub fn polygon_area(poly: &[DVec2]) -> f64 {
    let n = poly.len();
    if n < 3 {
        return 0.0;
    }
    let o = poly[0];
    let mut twice = 0.0;
    for i in 1..n - 1 {
        twice += (poly[i] - o).perp_dot(poly[i + 1] - o);
    }
    0.5 * twice
}

/// Area of the union of the simple polygons `polys` within the square `[-1, 1]^2`.
///
/// Each polygon is first clipped to the square; non-finite polygons and slivers (area below
/// `1e-14`) are dropped. The union is measured on a constrained Delaunay triangulation of the
/// square's boundary and all polygon edges, intersecting edges split where they cross: each
/// face counts when its centroid lies in some polygon (even-odd rule). Centroids are tested
/// only against the polygons whose bounding box meets their cell of a uniform grid.
pub fn union_area(polys: &[Vec<DVec2>]) -> f64 {
    let clean: Vec<Vec<DVec2>> = polys
        .iter()
        .filter_map(|p| finish_polygon(clip_polygon_to_rect(p)))
        .collect();
    union_area_of_clean(&clean)
}

/// [`union_area`] of polygons already clipped and cleaned by [`finish_polygon`].
fn union_area_of_clean(polys: &[Vec<DVec2>]) -> f64 {
    // A polygon that fills the square (up to rounding) leaves nothing to triangulate.
    if polys
        .iter()
        .any(|p| polygon_area(p).abs() >= LIGHT_SQUARE_AREA * (1.0 - 1e-12))
    {
        return LIGHT_SQUARE_AREA;
    }
    match polys.len() {
        0 => return 0.0,
        1 => return polygon_area(&polys[0]).abs(),
        _ => {}
    }

    // Unique vertices (bit-equal positions share one handle) and unique undirected edges: the
    // edge shared by two adjacent triangles becomes one constraint.
    let mut index: HashMap<[u64; 2], usize> = HashMap::new();
    let mut vertices: Vec<Point2<f64>> = Vec::new();
    let mut id = |v: DVec2| {
        *index
            .entry([v.x.to_bits(), v.y.to_bits()])
            .or_insert_with(|| {
                vertices.push(Point2::new(v.x, v.y));
                vertices.len() - 1
            })
    };
    let square = [
        DVec2::new(-1.0, -1.0),
        DVec2::new(1.0, -1.0),
        DVec2::new(1.0, 1.0),
        DVec2::new(-1.0, 1.0),
    ];
    let mut edges: Vec<[usize; 2]> = Vec::new();
    let mut seen: HashSet<[usize; 2]> = HashSet::new();
    for poly in std::iter::once(&square[..]).chain(polys.iter().map(|p| &p[..])) {
        let ids: Vec<usize> = poly.iter().map(|&v| id(v)).collect();
        for i in 0..ids.len() {
            let (a, b) = (ids[i], ids[(i + 1) % ids.len()]);
            if a != b && seen.insert([a.min(b), a.max(b)]) {
                edges.push([a, b]);
            }
        }
    }

    // The coordinates are finite, within [-1, 1] and flushed away from spade's lower limit, and
    // no constraints are passed to the bulk load, so it cannot fail.
    let mut cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::bulk_load_cdt(vertices, vec![])
        .expect("finite coordinates in [-1, 1] are valid spade input");
    for [a, b] in edges {
        let (a, b) = (
            FixedVertexHandle::from_index(a),
            FixedVertexHandle::from_index(b),
        );
        cdt.add_constraint_and_split(a, b, |v| v);
    }

    let grid = Grid::new(polys);
    let mut area = 0.0;
    for face in cdt.inner_faces() {
        let [a, b, c] = face.positions().map(|q| DVec2::new(q.x, q.y));
        let face_area = 0.5 * (b - a).perp_dot(c - a);
        if !(face_area > 0.0) {
            continue;
        }
        let centroid = (a + b + c) / 3.0;
        if grid
            .candidates(centroid)
            .iter()
            .any(|&i| contains(&polys[i as usize], centroid))
        {
            area += face_area;
        }
    }
    area.min(LIGHT_SQUARE_AREA)
}

/// Even-odd point-in-polygon test (crossing number).
fn contains(poly: &[DVec2], q: DVec2) -> bool {
    let mut inside = false;
    let mut j = poly.len() - 1;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[j]);
        if (a.y > q.y) != (b.y > q.y) && q.x < a.x + (b.x - a.x) * (q.y - a.y) / (b.y - a.y) {
            inside = !inside;
        }
        j = i;
    }
    inside
}

/// A uniform grid over `[-1, 1]^2` listing, per cell, the polygons whose bounding box meets it.
struct Grid {
    n: usize,
    cells: Vec<Vec<u32>>,
}

impl Grid {
    fn new(polys: &[Vec<DVec2>]) -> Self {
        // About one polygon per cell, at most 128 x 128 cells.
        let n = ((polys.len() as f64).sqrt().ceil() as usize).clamp(1, 128);
        let mut cells = vec![Vec::new(); n * n];
        for (i, poly) in polys.iter().enumerate() {
            let (lo, hi) = poly
                .iter()
                .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), &v| {
                    (lo.min(v), hi.max(v))
                });
            let (i0, j0) = Self::cell_of(n, lo);
            let (i1, j1) = Self::cell_of(n, hi);
            for j in j0..=j1 {
                for cell in &mut cells[j * n + i0..=j * n + i1] {
                    cell.push(i as u32);
                }
            }
        }
        Grid { n, cells }
    }

    fn cell_of(n: usize, q: DVec2) -> (usize, usize) {
        let f = |s: f64| (((s + 1.0) * 0.5 * n as f64).floor().max(0.0) as usize).min(n - 1);
        (f(q.x), f(q.y))
    }

    fn candidates(&self, q: DVec2) -> &[u32] {
        let (i, j) = Self::cell_of(self.n, q);
        &self.cells[j * self.n + i]
    }
}
