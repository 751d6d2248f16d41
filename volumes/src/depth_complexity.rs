//! Exact soft shadows by depth-complexity sampling (Laine, Aila, Assarsson, Lehtinen &
//! Akenine-Möller, "Soft Shadow Volumes for Ray Tracing", 2005; Forest, Barthe & Paulin,
//! "Accurate Shadows by Depth Complexity Sampling", 2008).
//!
//! The depth complexity of a light sample `s` seen from a receiver point `P` is the number of
//! scene triangles the open segment `P s` crosses (the receiver's own triangle never counts);
//! `s` is visible where it is zero, and
//!
//! ```text
//! V(P) = (1 / N²) · #{ s : D(P, s) = 0 }
//! ```
//!
//! over `N x N` light samples. Rather than one ray per sample, one ray counts the crossings
//! towards the light's centre `c`, `D(P, c)`, and every other count follows from the edges the
//! segment crosses as its end slides from `c` to `s` on the light: the segment `P s` sweeps the
//! triangle `P c s`, and an edge `a b` that crosses that triangle moves `s` into the projections
//! of the faces on its far side and out of those on its near side, so
//!
//! ```text
//! D(P, s) = D(P, c) + Σ_{edges e crossing triangle P c s} (far_e − near_e)
//! ```
//!
//! where `far_e` and `near_e` count the edge's faces (other than the receiver's triangle) whose
//! third vertex lies on the far and on the near side of the plane through `P` and the edge,
//! relative to `c`. A face in that plane (seen edge-on from `P`) covers no sample and counts on
//! neither side. An edge whose faces straddle the plane changes nothing (`far = near = 1`): only
//! silhouettes as seen from `P` matter, and those are among the light's potential silhouette
//! edges ([`crate::potential`]). This holds for any topology: open sheets, folds, edges of three
//! or more faces, intersecting meshes.
//!
//! The edge `a b` crosses the open triangle `P c s` when `a` and `b` lie strictly on opposite
//! sides of its plane, and the lines through `a b` and through each side of the triangle turn
//! the same way (the signed-volume segment-triangle test):
//!
//! ```text
//! [a, c, s] and [b, c, s] of opposite signs,   [a b P c], [a b c s], [a b s P] of one sign
//! ```
//!
//! (`[x y z w]` the orientation of the tetrahedron, `[x, c, s]` that of `P c s x`). With `P`, `a`,
//! `b` and `c` fixed, each is an affine function of `s` on the light's plane: four lines cut
//! the light into the samples the edge changes, evaluated per sample with no trigonometry and
//! clipped beforehand to the cells they can reach.
//!
//! Numbers are `f64` in light space; the reference casts `f32` rays, so the two differ only for
//! samples within rounding of a projected edge, and where the reference's start and end offset
//! [`Tracer::epsilon`] hides a triangle crossed within that distance of `P` or of the light.

use glam::{DVec2, DVec3, Vec3A};
use penumbra_geom::image::VisibilityImage;
use penumbra_geom::reference::REFERENCE_SEED;
use penumbra_geom::{Rng, Scene, SurfacePoint, Tracer};
use rayon::prelude::*;

use crate::potential::PotentialEdges;

/// A face is seen edge-on from the receiver point `P` when `P` lies within this share of
/// `|P - a|` of the face's plane (`a` an end of the edge): within rounding of it, where the
/// reference's rays meet the face only in ties.
const EDGE_ON: f64 = 1e-10;

/// Where the `N x N` light samples lie.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SamplePattern {
    /// Samples per axis, `N`.
    pub per_axis: usize,
    /// One uniform point per cell drawn from the reference's per-pixel stream (the same points
    /// as [`Tracer::sampled_visibility`]), instead of the cells' centres.
    pub jitter: bool,
}

impl SamplePattern {
    /// The pattern's points for camera pixel `pixel` (`y * width + x`), in `[-1, 1]^2`, row by
    /// row: sample `j * N + i` lies in cell `(i, j)`.
    pub fn points(&self, pixel: u64, out: &mut Vec<DVec2>) {
        let n = self.per_axis;
        let cell = 2.0 / n as f64;
        out.clear();
        if self.jitter {
            let mut rng = Rng::stream(REFERENCE_SEED, pixel);
            for j in 0..n {
                for i in 0..n {
                    let u = -1.0 + (i as f64 + rng.next_f64()) * cell;
                    let v = -1.0 + (j as f64 + rng.next_f64()) * cell;
                    out.push(DVec2::new(u, v));
                }
            }
        } else {
            for j in 0..n {
                for i in 0..n {
                    out.push(DVec2::new(
                        -1.0 + (i as f64 + 0.5) * cell,
                        -1.0 + (j as f64 + 0.5) * cell,
                    ));
                }
            }
        }
    }
}

/// What depth-complexity sampling found at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointVisibility {
    /// Share of the samples with depth complexity zero.
    pub visibility: f64,
    /// Triangles between the point and the light's centre, `D(P, c)`.
    pub centre_count: u32,
    /// Potential silhouette edges that changed the count of at least one sample.
    pub edges: usize,
}

/// An affine function `f(u, v) = k.x u + k.y v + k.z` on the light's plane.
#[derive(Clone, Copy, Debug)]
struct Line {
    k: DVec3,
}

impl Line {
    /// `m . (s - o)` for `s = (u, v, 0)`.
    fn through(m: DVec3, o: DVec3) -> Self {
        Line {
            k: DVec3::new(m.x, m.y, -m.dot(o)),
        }
    }

    #[inline(always)]
    fn at(&self, s: DVec2) -> f64 {
        self.k.x * s.x + self.k.y * s.y + self.k.z
    }

    fn neg(self) -> Self {
        Line { k: -self.k }
    }
}

/// A convex polygon of at most eight vertices: the light square cut by four lines.
#[derive(Clone, Copy, Debug)]
struct Polygon {
    v: [DVec2; 8],
    len: usize,
}

impl Polygon {
    const LIGHT: Polygon = Polygon {
        v: [
            DVec2::new(-1.0, -1.0),
            DVec2::new(1.0, -1.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(-1.0, 1.0),
            DVec2::ZERO,
            DVec2::ZERO,
            DVec2::ZERO,
            DVec2::ZERO,
        ],
        len: 4,
    };

    /// Keeps the part where `line >= 0` (Sutherland & Hodgman); returns whether any is left.
    /// Each cut adds at most one vertex to a convex polygon.
    fn clip(&mut self, line: Line) -> bool {
        let mut out = [DVec2::ZERO; 8];
        let mut k = 0;
        for i in 0..self.len {
            let (a, b) = (self.v[i], self.v[(i + 1) % self.len]);
            let (fa, fb) = (line.at(a), line.at(b));
            if fa >= 0.0 && k < 8 {
                out[k] = a;
                k += 1;
            }
            if (fa >= 0.0) != (fb >= 0.0) && k < 8 {
                out[k] = a + (b - a) * (fa / (fa - fb));
                k += 1;
            }
        }
        self.v = out;
        self.len = k;
        k > 0
    }

    fn bounds(&self) -> (DVec2, DVec2) {
        let mut lo = self.v[0];
        let mut hi = lo;
        for &q in &self.v[1..self.len] {
            lo = lo.min(q);
            hi = hi.max(q);
        }
        (lo, hi)
    }
}

/// The samples one edge changes: up to two convex parts of the light, each the samples where
/// four lines are positive, with its bounding box.
struct Region {
    delta: i32,
    parts: [Option<([Line; 4], (DVec2, DVec2))>; 2],
}

impl Region {
    /// Adds the change to the counts of the samples inside, looking only at the cells the parts'
    /// boxes reach (sample `j * n + i` lies in cell `(i, j)`). Returns whether any was inside.
    fn apply(&self, n: usize, points: &[DVec2], counts: &mut [i32]) -> bool {
        let cell = 2.0 / n as f64;
        let index = |x: f64| (((x + 1.0) / cell).floor().max(0.0) as usize).min(n - 1);
        let mut reached = false;
        for ([l0, l1, l2, l3], (lo, hi)) in self.parts.iter().flatten() {
            for j in index(lo.y)..=index(hi.y) {
                let row = j * n;
                for i in index(lo.x)..=index(hi.x) {
                    let s = points[row + i];
                    if l0.at(s) > 0.0 && l1.at(s) > 0.0 && l2.at(s) > 0.0 && l3.at(s) > 0.0 {
                        counts[row + i] += self.delta;
                        reached = true;
                    }
                }
            }
        }
        reached
    }
}

/// Per-thread working memory of [`DepthComplexity::visibility`].
#[derive(Default)]
pub struct Scratch {
    points: Vec<DVec2>,
    counts: Vec<i32>,
    hits: Vec<u32>,
    near: Vec<u32>,
}

/// The depth-complexity renderer of one scene: its ray tracer (for the surface points and the
/// centre's count) and its potential silhouette edges.
pub struct DepthComplexity {
    /// Ray casting.
    pub tracer: Tracer,
    /// The light's potential silhouette edges.
    pub edges: PotentialEdges,
}

impl DepthComplexity {
    /// Builds the BVH and the potential silhouette edges of `scene`.
    pub fn new(scene: &Scene) -> Self {
        DepthComplexity {
            tracer: Tracer::new(scene),
            edges: PotentialEdges::build(scene),
        }
    }

    /// `D(P, c)`: the triangles other than `p`'s that the segment from `p` to the light's centre
    /// crosses, by the reference's rule ([`Tracer::sees`]): in `f32` from the start offset on,
    /// and in `f64` from `p` itself for the triangles `near` it.
    pub fn centre_count(&self, p: &SurfacePoint, near: &[u32], hits: &mut Vec<u32>) -> u32 {
        let t = &self.tracer;
        let c = t.light.center;
        hits.clear();
        hits.extend(near.iter().filter(|&&n| t.crosses(p.position, c, n)));
        let d = c - p.position;
        let dist = d.length();
        if dist > t.epsilon {
            let dir = d / dist;
            let o: Vec3A = p.position.as_vec3().into();
            t.bvh.for_each_hit(
                o,
                dir.as_vec3().into(),
                t.epsilon as f32,
                (dist - t.epsilon) as f32,
                p.triangle,
                |tri| hits.push(tri),
            );
        }
        // A triangle split over several leaves is reported once per leaf, a near one perhaps
        // twice.
        hits.sort_unstable();
        hits.dedup();
        hits.len() as u32
    }

    /// Visibility of the surface point `p` seen through camera pixel `pixel` (`y * width + x`,
    /// which seeds the jittered pattern).
    pub fn visibility(
        &self,
        p: &SurfacePoint,
        pattern: SamplePattern,
        pixel: u64,
        scratch: &mut Scratch,
    ) -> PointVisibility {
        let light = &self.tracer.light;
        let pl = light.to_light_space(p.position);
        if !light.is_lit_side(p.position) || !(pl.z > 0.0) {
            return PointVisibility {
                visibility: 0.0,
                centre_count: 0,
                edges: 0,
            };
        }
        self.tracer.near_triangles(p, &mut scratch.near);
        let centre_count = self.centre_count(p, &scratch.near, &mut scratch.hits);
        let n = pattern.per_axis;
        let mut edges = 0;
        let mut ready = false;
        self.edges.for_each_near(pl, |ei| {
            let Some(region) = self.region(pl, p.triangle, ei) else {
                return;
            };
            if !ready {
                // Only points that some edge reaches need their samples.
                pattern.points(pixel, &mut scratch.points);
                scratch.counts.clear();
                scratch.counts.resize(n * n, 0);
                ready = true;
            }
            if region.apply(n, &scratch.points, &mut scratch.counts) {
                edges += 1;
            }
        });
        if !ready {
            scratch.counts.clear();
            scratch.counts.push(0);
        }
        let counts = &scratch.counts;
        let base = centre_count as i32;
        let seen = counts.iter().filter(|&&c| base + c <= 0).count();
        PointVisibility {
            visibility: seen as f64 / counts.len() as f64,
            centre_count,
            edges,
        }
    }

    /// The samples edge `ei` separates from the centre as seen from the light-space point `pl`
    /// on triangle `receiver`, and the change of their counts; `None` when it changes none.
    fn region(&self, pl: DVec3, receiver: u32, ei: u32) -> Option<Region> {
        let e = &self.edges.edges[ei as usize];
        let (a, b) = (e.a, e.b);
        let c = DVec3::ZERO;
        // The plane through P and the edge: the sides of c and of each face, each the sign of
        // the plane through the edge and that point (or that face) at P.
        let d = pl - a;
        let side_c = e.toward_centre.dot(d);
        if side_c == 0.0 {
            return None;
        }
        let d2 = d.length_squared();
        let mut delta = 0i32;
        for f in self.edges.faces_of(e) {
            if f.triangle == receiver {
                continue;
            }
            // P within rounding of a face's plane (a neighbour coplanar with the receiver, say)
            // sees it edge-on: it covers no sample.
            let s = f.normal.dot(d);
            if s * s <= EDGE_ON * EDGE_ON * f.normal.length_squared() * d2 {
                continue;
            }
            if s * side_c < 0.0 {
                delta += 1;
            } else {
                delta -= 1;
            }
        }
        if delta == 0 {
            return None;
        }
        // The segment-triangle test's four functions of s.
        let l = b - a;
        let o1 = l.cross(pl - a).dot(c - a);
        if o1 == 0.0 {
            return None;
        }
        let flip = o1.signum();
        let o2 = Line::through(l.cross(c - a) * flip, a);
        let o3 = Line::through(-l.cross(pl - a) * flip, a);
        let f0 = Line::through(-(c - pl).cross(a - pl), pl);
        let f1 = Line::through(-(c - pl).cross(b - pl), pl);
        // The light clipped by the four lines, for both signs of the pair (f0, f1): at most one
        // of the two is not empty unless the edge's line passes behind P.
        let mut light = Polygon::LIGHT;
        if !(light.clip(o2) && light.clip(o3)) {
            return None;
        }
        let mut parts = [None; 2];
        for (k, (g0, g1)) in [(f0, f1.neg()), (f0.neg(), f1)].into_iter().enumerate() {
            let mut poly = light;
            if poly.clip(g0) && poly.clip(g1) {
                parts[k] = Some(([o2, o3, g0, g1], poly.bounds()));
            }
        }
        (parts[0].is_some() || parts[1].is_some()).then_some(Region { delta, parts })
    }

    /// Renders the whole image; `progress` gets the number of finished rows.
    pub fn render(
        &self,
        scene: &Scene,
        pattern: SamplePattern,
        progress: &(dyn Fn(u64) + Sync),
    ) -> VisibilityImage {
        let cam = &scene.camera;
        let w = cam.width as usize;
        let mut img = VisibilityImage::filled(cam.width, cam.height, 1.0);
        let done = std::sync::atomic::AtomicU64::new(0);
        img.data.par_chunks_mut(w).enumerate().for_each(|(j, row)| {
            let mut scratch = Scratch::default();
            for (i, out) in row.iter_mut().enumerate() {
                let dir = cam.ray_dir(i as u32, j as u32);
                if let Some(p) = self.tracer.surface_point(cam.eye, dir) {
                    let pixel = j as u64 * w as u64 + i as u64;
                    *out = self.visibility(&p, pattern, pixel, &mut scratch).visibility as f32;
                }
            }
            progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
        });
        img
    }
}

#[cfg(test)]
#[path = "depth_complexity_tests.rs"]
mod tests;
