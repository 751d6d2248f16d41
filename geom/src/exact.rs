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
//!    every polygon edge, split where edges cross. No constraint crosses a face, so every face
//!    lies inside or outside each polygon as a whole: a face is covered when its centroid lies
//!    in at least one polygon, and the union area is the sum of the covered faces' areas.
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
//! The crossings of step 3 are not left to spade's splitting insertion
//! ([`spade::ConstrainedDelaunayTriangulation::add_constraint_and_split`]): on the nearly
//! collinear and nearly concurrent edges that projected meshes produce (boxes seen from points
//! aligned with their edges, lattice-like input) it panicked (`!previous_region.is_empty() ||
//! from == final_vertex`, `is_ordered_ccw` in `legalize_edge`) on about 0.4% of the receiver
//! points of an aligned-box test scene and on about one lattice input in five, and one input
//! made it loop with memory growing without bound. The edges are instead snap rounded (Hobby
//! 1999) to a grid of spacing `2^-40` with exact integer predicates, which yields fragments that
//! meet only at grid points: spade receives exactly representable vertices and non-crossing
//! constraints (`try_add_constraint`; the splitting insertion remains only as a fallback that
//! the tests check is never taken), and the face classification is exact as well. The union
//! computed is that of the snapped polygons, whose vertices move by at most `2^-41` per
//! coordinate: the occluded area is off by about the union's perimeter times `2^-41`, around
//! `1e-12` of 4.
//!
//! Degenerate input is skipped rather than propagated: triangles with a non-finite vertex,
//! triangles whose supporting plane passes through `P` (they project to a segment: zero area,
//! which also covers the receiver's coplanar neighbours) and projected polygons of area below
//! `1e-14` (of 4) never reach the triangulation, so the result is never NaN.

use std::cmp::Ordering;
use std::collections::{HashMap, HashSet};
use std::hash::{BuildHasherDefault, Hasher};

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
/// `V = 1 - |union of projected occluders| / 4`, clamped to `[0, 1]`; see the module
/// documentation for the method. A point that is not strictly on the emitting side
/// ([`RectLight::is_lit_side`]) or not finite gets `V = 0`. Never panics and never returns NaN:
/// non-finite and degenerate triangles are skipped.
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
/// `1e-14`) are dropped. The union is measured on a constrained Delaunay triangulation whose
/// constraints are the square's boundary and all polygon edges, split where they cross by snap
/// rounding to a grid of spacing `2^-40` (see the module documentation): each face counts when
/// its centroid lies in some polygon (even-odd rule). The result is exact for the snapped
/// polygons, which differ from the given ones by at most `2^-41` per coordinate.
pub fn union_area(polys: &[Vec<DVec2>]) -> f64 {
    let clean: Vec<Vec<DVec2>> = polys
        .iter()
        .filter_map(|p| finish_polygon(clip_polygon_to_rect(p)))
        .collect();
    union_area_of_clean(&clean).area
}

/// A union area and how often the triangulation had to split a constraint after all.
#[derive(Clone, Copy, Debug)]
struct UnionArea {
    area: f64,
    /// Snap-rounded fragments that still crossed an existing constraint and went through
    /// spade's splitting insertion. Zero unless snap rounding broke its guarantee.
    #[cfg_attr(
        not(test),
        allow(dead_code, reason = "read by the tests, which check it stays zero")
    )]
    split_fallbacks: usize,
}

/// [`union_area`] of polygons already clipped and cleaned by [`finish_polygon`].
fn union_area_of_clean(polys: &[Vec<DVec2>]) -> UnionArea {
    let done = |area| UnionArea {
        area,
        split_fallbacks: 0,
    };
    // A polygon that fills the square (up to rounding) leaves nothing to triangulate.
    if polys
        .iter()
        .any(|p| polygon_area(p).abs() >= LIGHT_SQUARE_AREA * (1.0 - 1e-12))
    {
        return done(LIGHT_SQUARE_AREA);
    }
    match polys.len() {
        0 => return done(0.0),
        1 => return done(polygon_area(&polys[0]).abs()),
        _ => {}
    }

    // Polygons on the grid, and their unique undirected edges plus the square's boundary.
    let square = [
        [-GRID_ONE, -GRID_ONE],
        [GRID_ONE, -GRID_ONE],
        [GRID_ONE, GRID_ONE],
        [-GRID_ONE, GRID_ONE],
    ];
    let mut grid_polys: Vec<Vec<GridPoint>> = Vec::with_capacity(polys.len() + 1);
    grid_polys.push(square.to_vec());
    for poly in polys {
        let mut g: Vec<GridPoint> = poly.iter().map(|&v| to_grid(v)).collect();
        g.dedup();
        while g.len() > 1 && g.first() == g.last() {
            g.pop();
        }
        if g.len() >= 3 {
            grid_polys.push(g);
        }
    }
    let mut segment_of: FastMap<[GridPoint; 2], usize> = FastMap::default();
    let mut segments: Vec<[GridPoint; 2]> = Vec::new();
    for poly in &grid_polys {
        for (i, &a) in poly.iter().enumerate() {
            let b = poly[(i + 1) % poly.len()];
            segment_of.entry(ordered(a, b)).or_insert_with(|| {
                segments.push(ordered(a, b));
                segments.len() - 1
            });
        }
    }

    let arrangement = snap_round(&segments);

    // Every hot pixel is a vertex, every fragment between consecutive hot pixels of a route a
    // constraint. Grid points are exact in f64 and fragments do not cross, so the splitting
    // insertion is only a fallback.
    let vertices: Vec<Point2<f64>> = arrangement.hot.iter().map(|&h| from_grid(h)).collect();
    let mut cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::bulk_load_cdt(vertices, vec![])
        .expect("grid points in [-1, 1] are valid spade input");
    let mut fragments: HashSet<[u32; 2], FastHash> = HashSet::default();
    let mut split_fallbacks = 0;
    for route in &arrangement.routes {
        for w in route.windows(2) {
            let (a, b) = (w[0], w[1]);
            if a == b || !fragments.insert([a.min(b), a.max(b)]) {
                continue;
            }
            let (a, b) = (
                FixedVertexHandle::from_index(a as usize),
                FixedVertexHandle::from_index(b as usize),
            );
            if cdt.try_add_constraint(a, b).is_empty() {
                split_fallbacks += 1;
                cdt.add_constraint_and_split(a, b, |v| v);
            }
        }
    }

    // The snapped polygons: each edge replaced by its route through the hot pixels.
    let snapped: Vec<Vec<GridPoint>> = grid_polys[1..]
        .iter()
        .map(|poly| {
            let mut out: Vec<GridPoint> = Vec::new();
            for (i, &a) in poly.iter().enumerate() {
                let b = poly[(i + 1) % poly.len()];
                let route = &arrangement.routes[segment_of[&ordered(a, b)]];
                let forward = ordered(a, b)[0] == a;
                let mut push = |h: u32| {
                    let p = arrangement.hot[h as usize];
                    if out.last() != Some(&p) {
                        out.push(p);
                    }
                };
                if forward {
                    route.iter().for_each(|&h| push(h));
                } else {
                    route.iter().rev().for_each(|&h| push(h));
                }
            }
            while out.len() > 1 && out.first() == out.last() {
                out.pop();
            }
            out
        })
        .collect();

    let buckets = Buckets::new(&snapped);
    let mut area = 0.0;
    for face in cdt.inner_faces() {
        let [a, b, c] = face.positions().map(|q| DVec2::new(q.x, q.y));
        let face_area = 0.5 * (b - a).perp_dot(c - a);
        if face_area <= 0.0 {
            continue;
        }
        // Three times the centroid, exactly, on the grid.
        let [ga, gb, gc] = [a, b, c].map(to_grid);
        let q3 = [ga[0] + gb[0] + gc[0], ga[1] + gb[1] + gc[1]];
        if buckets
            .candidates(q3)
            .iter()
            .any(|&i| contains_thrice(&snapped[i as usize], q3))
        {
            area += face_area;
        }
    }
    UnionArea {
        area: area.min(LIGHT_SQUARE_AREA),
        split_fallbacks,
    }
}

/// The multiply-rotate hash of rustc's `FxHasher`: the keys here are small integer arrays from
/// one evaluation, not adversarial input, and SipHash cost a tenth of the running time.
#[derive(Clone, Copy, Default)]
struct FxHasher(u64);

impl Hasher for FxHasher {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(word));
        }
    }

    fn write_u64(&mut self, i: u64) {
        self.0 = (self.0.rotate_left(5) ^ i).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }

    fn write_u32(&mut self, i: u32) {
        self.write_u64(i as u64);
    }

    fn write_usize(&mut self, i: usize) {
        self.write_u64(i as u64);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

type FastHash = BuildHasherDefault<FxHasher>;
type FastMap<K, V> = HashMap<K, V, FastHash>;

/// A point of the snapping grid: light-space coordinates times `2^GRID_BITS`.
type GridPoint = [i64; 2];

/// Bits of the fixed-point grid. With `|x| <= 2^40`, every orientation and every rounded
/// intersection below is exact in `i128` (the largest product is at most `2^125`).
const GRID_BITS: u32 = 40;

/// The square's half side on the grid.
const GRID_ONE: i64 = 1 << GRID_BITS;

fn to_grid(v: DVec2) -> GridPoint {
    let s = GRID_ONE as f64;
    [(v.x * s).round() as i64, (v.y * s).round() as i64]
}

fn from_grid(p: GridPoint) -> Point2<f64> {
    let s = 1.0 / GRID_ONE as f64;
    Point2::new(p[0] as f64 * s, p[1] as f64 * s)
}

fn ordered(a: GridPoint, b: GridPoint) -> [GridPoint; 2] {
    if a <= b { [a, b] } else { [b, a] }
}

/// `cross(b - a, c - a)`, exactly: positive when `a, b, c` turn counter-clockwise.
fn orient(a: GridPoint, b: GridPoint, c: GridPoint) -> i128 {
    let d = |p: GridPoint, q: GridPoint| [(q[0] - p[0]) as i128, (q[1] - p[1]) as i128];
    let (u, v) = (d(a, b), d(a, c));
    u[0] * v[1] - u[1] * v[0]
}

/// Segments snap-rounded to the grid: the hot pixels and, per segment, the hot pixels it passes
/// through in order from its first end to its second.
struct Arrangement {
    hot: Vec<GridPoint>,
    routes: Vec<Vec<u32>>,
}

/// Snap rounding (Hobby 1999, "Practical segment intersection with finite precision output",
/// CGTA 13(4); Guibas & Marimont 1998): a pixel (the half-open unit square `[c - 1/2,
/// c + 1/2)^2` around a grid point `c`) is hot when it holds an endpoint or a crossing of two
/// segments, and every segment is replaced by the polyline through the centres of the hot
/// pixels it meets, in the order it meets them. The resulting fragments meet only at hot pixel
/// centres, so they can be inserted as constraints without any splitting, and every coordinate
/// the triangulation sees is exact.
///
/// Segments (with distinct ends, on the grid) are bucketed in a uniform grid of cells; crossings
/// are only sought between segments sharing a cell, and hot pixels only in the cells a segment
/// runs through.
fn snap_round(segments: &[[GridPoint; 2]]) -> Arrangement {
    let mut hot_index: FastMap<GridPoint, u32> = FastMap::default();
    let mut hot: Vec<GridPoint> = Vec::new();
    let mut add_hot = |p: GridPoint, hot: &mut Vec<GridPoint>| {
        *hot_index.entry(p).or_insert_with(|| {
            hot.push(p);
            hot.len() as u32 - 1
        })
    };
    for s in segments {
        add_hot(s[0], &mut hot);
        add_hot(s[1], &mut hot);
    }

    let cells = CellGrid::for_count(segments.len());
    let mut seg_cells: Vec<Vec<u32>> = vec![Vec::new(); cells.n * cells.n];
    let mut scratch = Vec::new();
    for (i, s) in segments.iter().enumerate() {
        cells.along_segment(s[0], s[1], &mut scratch);
        for &c in &scratch {
            seg_cells[c].push(i as u32);
        }
    }
    for list in &seg_cells {
        for (k, &i) in list.iter().enumerate() {
            for &j in &list[k + 1..] {
                if let Some(p) = crossing(segments[i as usize], segments[j as usize]) {
                    add_hot(p, &mut hot);
                }
            }
        }
    }

    let mut hot_cells: Vec<Vec<u32>> = vec![Vec::new(); cells.n * cells.n];
    for (h, &p) in hot.iter().enumerate() {
        hot_cells[cells.cell_of(p)].push(h as u32);
    }
    let routes = segments
        .iter()
        .map(|&[a, b]| {
            cells.along_segment(a, b, &mut scratch);
            let mut on: Vec<(Bound, u32)> = scratch
                .iter()
                .flat_map(|&c| hot_cells[c].iter())
                .filter_map(|&h| pixel_entry(a, b, hot[h as usize]).map(|t| (t, h)))
                .collect();
            // A closed bound comes before an open one of equal value.
            on.sort_unstable_by(|x, y| x.0.value_cmp(&y.0).then(x.0.open.cmp(&y.0.open)));
            on.into_iter().map(|(_, h)| h).collect()
        })
        .collect();
    Arrangement { hot, routes }
}

/// The grid point nearest to the proper crossing of segments `s` and `t` (rounding halves up),
/// or `None` when they do not cross properly. Touching and overlapping segments meet at
/// endpoints, which are hot already.
fn crossing(s: [GridPoint; 2], t: [GridPoint; 2]) -> Option<GridPoint> {
    let (a, b, c, d) = (s[0], s[1], t[0], t[1]);
    let (o1, o2) = (orient(a, b, c), orient(a, b, d));
    let (o3, o4) = (orient(c, d, a), orient(c, d, b));
    if !((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) || !((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)) {
        return None;
    }
    // a + (b - a) * num / den with num / den = o3 / (o3 - o4) in (0, 1).
    let (mut num, mut den) = (o3, o3 - o4);
    if den < 0 {
        (num, den) = (-num, -den);
    }
    let round = |from: i64, delta: i64| -> i64 {
        // floor((2 * delta * num + den) / (2 * den)), with |2 * delta * num| <= 2^125.
        let q = (2 * delta as i128 * num + den).div_euclid(2 * den);
        from + q as i64
    };
    Some([round(a[0], b[0] - a[0]), round(a[1], b[1] - a[1])])
}

/// A bound `num / den` (`den > 0`) of an interval of the segment parameter `t`, and whether
/// the bound itself is excluded.
#[derive(Clone, Copy, Debug)]
struct Bound {
    num: i128,
    den: i128,
    open: bool,
}

impl Bound {
    /// Compares the values, exactly (numerators and denominators stay below `2^44`).
    fn value_cmp(&self, other: &Bound) -> Ordering {
        (self.num * other.den).cmp(&(other.num * self.den))
    }
}

/// Where the segment `a + t (b - a)`, `t` in `[0, 1]`, enters the half-open pixel
/// `[c - 1/2, c + 1/2)^2`, or `None` when it misses it. Exact, in doubled coordinates. Half-open
/// pixels partition the plane, so the pixels a segment meets occupy disjoint intervals of `t`
/// and their entry parameters order them along the segment.
fn pixel_entry(a: GridPoint, b: GridPoint, c: GridPoint) -> Option<Bound> {
    let mut lower = Bound {
        num: 0,
        den: 1,
        open: false,
    };
    let mut upper = Bound {
        num: 1,
        den: 1,
        open: false,
    };
    for k in 0..2 {
        let (a2, d2) = (2 * a[k] as i128, 2 * (b[k] - a[k]) as i128);
        let lo = 2 * c[k] as i128 - 1;
        let hi = lo + 2;
        let (l, u) = match d2.cmp(&0) {
            Ordering::Equal if lo <= a2 && a2 < hi => continue,
            Ordering::Equal => return None,
            // lo <= a2 + t d2 < hi.
            Ordering::Greater => (
                Bound {
                    num: lo - a2,
                    den: d2,
                    open: false,
                },
                Bound {
                    num: hi - a2,
                    den: d2,
                    open: true,
                },
            ),
            Ordering::Less => (
                Bound {
                    num: a2 - hi,
                    den: -d2,
                    open: true,
                },
                Bound {
                    num: a2 - lo,
                    den: -d2,
                    open: false,
                },
            ),
        };
        match l.value_cmp(&lower) {
            Ordering::Greater => lower = l,
            Ordering::Equal => lower.open |= l.open,
            Ordering::Less => {}
        }
        match u.value_cmp(&upper) {
            Ordering::Less => upper = u,
            Ordering::Equal => upper.open |= u.open,
            Ordering::Greater => {}
        }
    }
    match lower.value_cmp(&upper) {
        Ordering::Less => Some(lower),
        Ordering::Equal if !lower.open && !upper.open => Some(lower),
        _ => None,
    }
}

/// Even-odd test of the point `q3 / 3` against the closed polyline `poly`, exact: all
/// coordinates are scaled by 3 so the face centroid stays on an integer grid.
fn contains_thrice(poly: &[GridPoint], q3: GridPoint) -> bool {
    let mut inside = false;
    let n = poly.len();
    for i in 0..n {
        let (u, v) = (poly[i], poly[(i + 1) % n]);
        let (u, v) = ([3 * u[0], 3 * u[1]], [3 * v[0], 3 * v[1]]);
        if (u[1] > q3[1]) != (v[1] > q3[1]) && (orient(u, v, q3) > 0) == (v[1] > u[1]) {
            inside = !inside;
        }
    }
    inside
}

/// A uniform grid of `n x n` cells over the square `[-2^40, 2^40]^2` of grid points, `n` a
/// power of two.
struct CellGrid {
    n: usize,
    /// log2 of a cell's side in grid units.
    shift: u32,
}

impl CellGrid {
    /// About one item per cell, at most 256 x 256 cells.
    fn for_count(count: usize) -> Self {
        let n = ((count as f64).sqrt().ceil() as usize)
            .next_power_of_two()
            .clamp(1, 256);
        CellGrid {
            n,
            shift: GRID_BITS + 1 - n.trailing_zeros(),
        }
    }

    fn index(&self, s: i64) -> usize {
        (((s + GRID_ONE).max(0) >> self.shift) as usize).min(self.n - 1)
    }

    fn cell_of(&self, p: GridPoint) -> usize {
        self.index(p[1]) * self.n + self.index(p[0])
    }

    /// Every cell that comes within two grid units of the segment `a-b`, row by row: a superset
    /// of the cells holding the centre of a pixel the segment meets.
    fn along_segment(&self, a: GridPoint, b: GridPoint, out: &mut Vec<usize>) {
        out.clear();
        const MARGIN: i64 = 2;
        let (y_lo, y_hi) = (a[1].min(b[1]) - MARGIN, a[1].max(b[1]) + MARGIN);
        let (x_min, x_max) = (a[0].min(b[0]) - MARGIN, a[0].max(b[0]) + MARGIN);
        // The x-extent of the part of the segment within [y0, y1], up to f64 rounding.
        let x_span = |y0: i64, y1: i64| -> (f64, f64) {
            if a[1] == b[1] {
                return (a[0].min(b[0]) as f64, a[0].max(b[0]) as f64);
            }
            let x_at = |y: i64| {
                let t = ((y - a[1]) as f64 / (b[1] - a[1]) as f64).clamp(0.0, 1.0);
                a[0] as f64 + (b[0] - a[0]) as f64 * t
            };
            let (xa, xb) = (x_at(y0), x_at(y1));
            (xa.min(xb), xa.max(xb))
        };
        for row in self.index(y_lo)..=self.index(y_hi) {
            let row_lo = ((row as i64) << self.shift) - GRID_ONE;
            let row_hi = row_lo + (1 << self.shift);
            // A pixel centred in this row reaches half a unit into its neighbours.
            let (y0, y1) = (y_lo.max(row_lo - MARGIN), y_hi.min(row_hi + MARGIN));
            let (xa, xb) = x_span(y0, y1);
            // The f64 error is far below one grid unit; the margin covers it.
            let lo = ((xa.floor() as i64) - MARGIN).max(x_min);
            let hi = ((xb.ceil() as i64) + MARGIN).min(x_max);
            for col in self.index(lo)..=self.index(hi) {
                out.push(row * self.n + col);
            }
        }
    }
}

/// The snapped polygons whose bounding box meets each cell of a [`CellGrid`].
struct Buckets {
    cells: CellGrid,
    lists: Vec<Vec<u32>>,
}

impl Buckets {
    fn new(polys: &[Vec<GridPoint>]) -> Self {
        let cells = CellGrid::for_count(polys.len());
        let mut lists = vec![Vec::new(); cells.n * cells.n];
        for (i, poly) in polys.iter().enumerate() {
            if poly.is_empty() {
                continue;
            }
            let (mut lo, mut hi) = ([i64::MAX; 2], [i64::MIN; 2]);
            for p in poly {
                for k in 0..2 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            for row in cells.index(lo[1])..=cells.index(hi[1]) {
                for col in cells.index(lo[0])..=cells.index(hi[0]) {
                    lists[row * cells.n + col].push(i as u32);
                }
            }
        }
        Buckets { cells, lists }
    }

    /// Polygons that may contain the point `q3 / 3`.
    fn candidates(&self, q3: GridPoint) -> &[u32] {
        // floor division keeps the cell consistent with the bounding boxes.
        let q = [q3[0].div_euclid(3), q3[1].div_euclid(3)];
        &self.lists[self.cells.cell_of(q)]
    }
}
