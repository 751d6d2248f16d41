//! The candidate edges of a receiver point or a tile of them, and the `f32` pre-test that
//! keeps, for one point, those that may change a sample's count ([`crate::DepthComplexity`]):
//! silhouettes seen from the point that may meet its pyramid to the light.

use glam::{DVec3, Vec3};

use crate::potential::{EdgeFace, PotentialEdge, PotentialEdges, pyramid_planes};

/// The candidate edges of a point or a tile, with what the silhouette pre-test reads of each
/// in `f32`, one array per number so that the test runs four edges to an instruction.
///
/// A two-face edge changes no count unless both faces lie on one side of the plane through P
/// and the edge, that is unless `F0(P)` and `F1(P)` have one sign (`F_k(x) = n_k . (x - a)`,
/// [`crate::potential::EdgeFace`]). The pre-test drops an edge only when the two values have
/// opposite signs and each is larger than a margin far above its `f32` rounding; every other
/// edge (one within the margin, a boundary or non-manifold edge, whose second normal is stored
/// as zero) goes to the exact `f64` test.
///
/// Nor does an edge change a count that lies wholly outside the pyramid from P to the light:
/// the pre-test drops one whose two ends lie outside one of the pyramid's four sides by more
/// than a margin of the same form. Under a small light (the sun) a tile's candidates are most
/// of them outside each point's thin pyramid.
#[derive(Default)]
pub(crate) struct Candidates {
    /// Their indices into the potential edges.
    pub(crate) ids: Vec<u32>,
    /// A copy of each edge and, for a two-face edge, of its faces: the exact test reads them
    /// in the list's order instead of across the whole scene's edges.
    pub(crate) edges: Vec<(PotentialEdge, [EdgeFace; 2])>,
    /// What the pre-test reads of each.
    lanes: Lanes,
    /// Whether the last pre-test kept each.
    keep: Vec<bool>,
    /// The indices (into `ids` and `edges`) of those it kept, in order.
    pub(crate) kept: Vec<u32>,
}

/// What the pre-test reads of a list of edges, in `f32`, one array per number so that the test
/// runs four edges to an instruction.
#[derive(Default)]
pub(crate) struct Lanes {
    a: [Vec<f32>; 3],
    b: [Vec<f32>; 3],
    n0: [Vec<f32>; 3],
    n1: [Vec<f32>; 3],
    /// `(MARGIN |n_k|)^2`.
    t0: Vec<f32>,
    t1: Vec<f32>,
}

/// What the pre-test reads for an edge without exactly two faces: a zero normal, never dropped.
const NO_FACE: EdgeFace = EdgeFace {
    normal: DVec3::ZERO,
    normal_length2: 0.0,
    triangle: u32::MAX,
};

/// The two faces the pre-test reads of edge `e`: its own where it has two, [`NO_FACE`] twice
/// otherwise.
fn two_faces<'a>(edges: &'a PotentialEdges, e: &PotentialEdge) -> [&'a EdgeFace; 2] {
    match edges.faces_of(e) {
        [f0, f1] => [f0, f1],
        _ => [&NO_FACE, &NO_FACE],
    }
}

/// The pre-test's margin, relative to `|n_k| sqrt(|P - a|^2 + R^2)` with `R` the largest
/// light-space coordinate: a hundred times the rounding of the `f32` products.
const MARGIN: f32 = 1e-5;

impl Candidates {
    pub(crate) fn clear(&mut self) {
        self.ids.clear();
        self.edges.clear();
        self.lanes.clear();
    }

    pub(crate) fn push(&mut self, edges: &PotentialEdges, ei: u32) {
        let e = &edges.edges[ei as usize];
        let [n0, n1] = two_faces(edges, e);
        self.ids.push(ei);
        self.edges.push((*e, [*n0, *n1]));
        self.lanes.push(e, n0, n1);
    }

    /// Lists in `kept` the edges that may change a count seen from `p`; `r2` is `R^2`. With
    /// `pyramid`, also drops those outside the point's pyramid (worth its cost where the
    /// candidates are a wider region's than the point's: under a small light).
    pub(crate) fn pretest(&mut self, p: DVec3, r2: f32, pyramid: bool) {
        let n = self.ids.len();
        self.lanes.test(0..n, p, r2, pyramid, &mut self.keep);
        // The list without a branch: every index is written, and the count moves past the kept.
        // A pass of its own: written inside the test's loop, the list's count chains its steps,
        // and the test no longer runs four edges at a time (with every tile of the scale scene
        // counting, the render took 12% longer than with no list at all).
        self.kept.clear();
        self.kept.resize(n + 1, 0);
        let mut count = 0;
        for (k, &kept) in self.keep.iter().enumerate() {
            self.kept[count] = k as u32;
            count += usize::from(kept);
        }
        self.kept.truncate(count);
    }

    /// Replaces the list with those of the edges `ids` that the pre-test (with the pyramid)
    /// keeps at `p`, `lanes[range]` holding what it reads of them; every one is kept.
    pub(crate) fn pretested_from(
        &mut self,
        edges: &PotentialEdges,
        ids: &[u32],
        lanes: &Lanes,
        range: std::ops::Range<usize>,
        p: DVec3,
        r2: f32,
    ) {
        self.clear();
        let mut keep = std::mem::take(&mut self.keep);
        lanes.test(range.clone(), p, r2, true, &mut keep);
        for (&kept, &ei) in keep.iter().zip(&ids[range]) {
            if kept {
                self.push(edges, ei);
            }
        }
        self.keep = keep;
        self.kept.clear();
        self.kept.extend(0..self.ids.len() as u32);
    }
}

impl Lanes {
    pub(crate) fn clear(&mut self) {
        for v in self
            .a
            .iter_mut()
            .chain(&mut self.b)
            .chain(&mut self.n0)
            .chain(&mut self.n1)
        {
            v.clear();
        }
        self.t0.clear();
        self.t1.clear();
    }

    /// Appends the edge `e` with its faces `n0` and `n1` ([`NO_FACE`] for an edge without two).
    fn push(&mut self, e: &PotentialEdge, n0: &EdgeFace, n1: &EdgeFace) {
        for k in 0..3 {
            self.a[k].push(e.a[k] as f32);
            self.b[k].push(e.b[k] as f32);
            self.n0[k].push(n0.normal[k] as f32);
            self.n1[k].push(n1.normal[k] as f32);
        }
        let t = |f: &EdgeFace| (MARGIN * f.normal_length2.sqrt() as f32).powi(2);
        self.t0.push(t(n0));
        self.t1.push(t(n1));
    }

    /// Appends the potential edge `ei` of `edges`.
    pub(crate) fn push_edge(&mut self, edges: &PotentialEdges, ei: u32) {
        let e = &edges.edges[ei as usize];
        let [n0, n1] = two_faces(edges, e);
        self.push(e, n0, n1);
    }

    /// Into `keep`, one flag for each edge of `range`: whether it may change a count seen from
    /// `p` ([`Candidates::pretest`]).
    fn test(
        &self,
        range: std::ops::Range<usize>,
        p: DVec3,
        r2: f32,
        pyramid: bool,
        keep: &mut Vec<bool>,
    ) {
        let n = range.len();
        keep.clear();
        keep.resize(n, false);
        // Slices of one length, so that the loop runs without bounds checks, four to a step.
        let [ax, ay, az] = self.a.each_ref().map(|v| &v[range.clone()]);
        let [n0x, n0y, n0z] = self.n0.each_ref().map(|v| &v[range.clone()]);
        let [n1x, n1y, n1z] = self.n1.each_ref().map(|v| &v[range.clone()]);
        let (t0, t1, keep) = (
            &self.t0[range.clone()],
            &self.t1[range.clone()],
            &mut keep[..n],
        );
        let (px, py, pz) = (p.x as f32, p.y as f32, p.z as f32);
        for k in 0..n {
            let (dx, dy, dz) = (px - ax[k], py - ay[k], pz - az[k]);
            let m = dx * dx + dy * dy + dz * dz + r2;
            let s0 = n0x[k] * dx + n0y[k] * dy + n0z[k] * dz;
            let s1 = n1x[k] * dx + n1y[k] * dy + n1z[k] * dz;
            let apart = (s0 * s1 < 0.0) & (s0 * s0 > t0[k] * m) & (s1 * s1 > t1[k] * m);
            keep[k] = !apart;
        }
        if pyramid {
            // The pyramid's sides, each `s . (x - p) >= 0` inside, with `(MARGIN |s|)^2`.
            let planes = pyramid_planes(p);
            let [q0, q1, q2, q3]: [(Vec3, f32); 4] = std::array::from_fn(|k| {
                let s = planes[k + 1].n.as_vec3();
                (s, (MARGIN * s.length()).powi(2))
            });
            let [bx, by, bz] = self.b.each_ref().map(|v| &v[range.clone()]);
            for k in 0..n {
                let (dx, dy, dz) = (px - ax[k], py - ay[k], pz - az[k]);
                let (ex, ey, ez) = (px - bx[k], py - by[k], pz - bz[k]);
                let ma = dx * dx + dy * dy + dz * dz + r2;
                let mb = ex * ex + ey * ey + ez * ez + r2;
                // Both ends outside one side by more than the margin (`s . (x - p)` from the
                // `p - x` computed).
                let out = |(s, t): (Vec3, f32)| {
                    let sa = -(s.x * dx + s.y * dy + s.z * dz);
                    let sb = -(s.x * ex + s.y * ey + s.z * ez);
                    (sa < 0.0) & (sb < 0.0) & (sa * sa > t * ma) & (sb * sb > t * mb)
                };
                keep[k] &= !(out(q0) | out(q1) | out(q2) | out(q3));
            }
        }
    }
}
