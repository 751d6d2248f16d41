//! The samples one edge changes, as seen from a receiver point: the part of the light square
//! where four lines are positive (see [`crate::DepthComplexity`] for the test they make up),
//! looked for among the samples of the cone from the centre that two of the lines bound, and its
//! change to their depth complexity.

use glam::{DVec2, DVec3};
use penumbra_geom::Plane;

use crate::clip::cross;
use crate::potential::{EdgeFace, LightCrossing, PotentialEdge};
use crate::sectors::Sectors;

/// A face is seen edge-on from the receiver point `P` when `P` lies within this share of
/// `|P - a|` of the face's plane (`a` an end of the edge): within rounding of it, where the
/// reference's rays meet the face only in ties.
const EDGE_ON: f64 = 1e-10;

/// An affine function `f(u, v) = k.x u + k.y v + k.z` on the light's plane.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Line {
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

/// The samples one edge changes: those of the light where four lines are positive. The
/// second and third pass through the light's centre: the region lies in the cone they bound,
/// whose samples [`Sectors::cone_runs`] finds.
pub(crate) struct Region {
    delta: i32,
    lines: [Line; 4],
}

impl Region {
    /// The samples where all four `lines` are positive, changed by `delta` (`lines[1]` and
    /// `lines[2]` through the centre).
    fn new(delta: i32, lines: [Line; 4]) -> Option<Region> {
        Some(Region { delta, lines })
    }

    /// The two lines through the centre that bound its cone, whose samples
    /// [`Sectors::cone_runs`] finds.
    pub(crate) fn cone(&self) -> (DVec3, DVec3) {
        (self.lines[1].k, self.lines[2].k)
    }

    /// Adds the change to the counts of the samples inside (`counts[k]` that of sample `k` of
    /// `samples`), looking only at the samples of the sectors the cone spans: `runs`, its
    /// [`Sectors::cone_runs`] (found for every region first, so that their divisions overlap),
    /// and the near-centre ones. Returns whether any was inside.
    ///
    /// The lines are evaluated in `f32`: their rounding (about 1e-7 of the light's half side)
    /// is that of the reference's `f32` shadow rays.
    pub(crate) fn apply(
        &self,
        samples: &Sectors,
        runs: &Option<[std::ops::Range<u32>; 2]>,
        counts: &mut [i32],
    ) -> bool {
        let Some(runs) = runs else {
            return false;
        };
        let k = self.lines.map(|l| l.k.as_vec3());
        let mut inside = 0;
        for r in runs
            .iter()
            .map(|r| r.start as usize..r.end as usize)
            .chain(std::iter::once(samples.near()))
        {
            inside += add(
                &k,
                self.delta,
                &samples.xs[r.clone()],
                &samples.ys[r.clone()],
                &mut counts[r],
            );
        }
        inside > 0
    }

    /// [`Region::apply`] testing every sample (`xs[k], ys[k]` that of `counts[k]`): cheaper for a
    /// point with few regions than sorting its samples.
    pub(crate) fn apply_to_all(&self, xs: &[f32], ys: &[f32], counts: &mut [i32]) -> bool {
        add(
            &self.lines.map(|l| l.k.as_vec3()),
            self.delta,
            xs,
            ys,
            counts,
        ) > 0
    }
}

/// Adds `delta` to the counts of the samples where the four lines `k` are positive, returning
/// how many were.
#[inline(always)]
fn add(k: &[glam::Vec3; 4], delta: i32, xs: &[f32], ys: &[f32], counts: &mut [i32]) -> u32 {
    let mut inside = 0;
    for ((c, &x), &y) in counts.iter_mut().zip(xs).zip(ys) {
        let at = |k: glam::Vec3| k.x * x + k.y * y + k.z;
        let hit = (at(k[0]) > 0.0) & (at(k[1]) > 0.0) & (at(k[2]) > 0.0) & (at(k[3]) > 0.0);
        *c += delta * hit as i32;
        inside += hit as u32;
    }
    inside
}

/// The samples whose count a triangle through the light's plane changes, as seen from `pl`
/// on triangle `receiver` (`None` too where the light's centre lies on the segment, within
/// rounding: `degenerate` is set): the triangle `P c s` meets the light's plane in the segment `c s`,
/// so it meets the triangle's crossing segment `a b` where `c s` does (in the plane), and the
/// samples beyond it from `c` enter the triangle's projection, or leave it, by the side the
/// projection of a point of the triangle next to the segment lies on.
pub(crate) fn crossing_region(
    x: &LightCrossing,
    pl: DVec3,
    receiver: u32,
    degenerate: &mut bool,
) -> Option<Region> {
    if x.triangle == receiver || !(x.inside.z < pl.z) {
        return None;
    }
    let (a, b) = (x.a.truncate(), x.b.truncate());
    let side = |s: DVec2| cross(b - a, s - a);
    let side_c = side(DVec2::ZERO);
    // The light's centre on the segment, within rounding: which samples it changes, and the
    // count at the centre, hang on that rounding. The caller casts P's samples instead.
    let l2 = (b - a).length_squared();
    let along = (-a).dot(b - a);
    let near = CENTRE_NEAR_CROSSING;
    if side_c * side_c <= near * near * l2 * a.length_squared().max(l2)
        && along >= -near * l2
        && along <= (1.0 + near) * l2
    {
        *degenerate = true;
        return None;
    }
    let q = pl + (x.inside - pl) * (pl.z / (pl.z - x.inside.z));
    let side_q = side(q.truncate());
    if side_c == 0.0 || side_q == 0.0 {
        return None;
    }
    let delta = if side_q * side_c < 0.0 { 1 } else { -1 };
    // Beyond the segment's line from c, within the cone from c over the segment.
    let beyond = Line {
        k: DVec3::new(-(b - a).y, (b - a).x, cross(b - a, -a)) * -side_c.signum(),
    };
    let ray = |e: DVec2| Line {
        k: DVec3::new(-e.y, e.x, 0.0),
    };
    let (ga, gb) = (ray(a), ray(b).neg());
    let mid = 0.5 * (a + b);
    let (g0, g1) = if ga.at(mid) > 0.0 {
        (ga, gb)
    } else {
        (ga.neg(), gb.neg())
    };
    Region::new(delta, [beyond, g0, g1, beyond])
}

/// The parameters `(t0, t1)` of the part of the segment from depth `za` to depth `zb` that lies
/// strictly between depths 0 and `zp` (empty when `t0 >= t1`).
fn slab(za: f64, zb: f64, zp: f64) -> (f64, f64) {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    // The common case, without the divisions: the whole segment lies between the two depths.
    if za > 0.0 && zb > 0.0 && za < zp && zb < zp {
        return (t0, t1);
    }
    let dz = zb - za;
    for (bound, above) in [(0.0, true), (zp, false)] {
        // Keep z > bound (above) or z < bound.
        if dz == 0.0 {
            if (za > bound) != above || za == bound {
                return (1.0, 0.0);
            }
            continue;
        }
        let t = (bound - za) / dz;
        if (dz > 0.0) == above {
            t0 = t0.max(t);
        } else {
            t1 = t1.min(t);
        }
    }
    (t0, t1)
}

/// How near the light's centre, relative to a crossing's length, lies to the crossing for
/// [`crossing_region`] to leave it to rays: the samples' lines are evaluated in `f32`, whose
/// rounding (6e-8) puts the centre on either side of a line nearer than this.
const CENTRE_NEAR_CROSSING: f64 = 1e-6;

/// The relative size of the triple product of an edge, the light's centre and P below which
/// [`edge_region`] calls the three coplanar (an angle of about 1e-9 radians).
const DEGENERATE: f64 = 1e-9;

/// The samples the potential silhouette edge `e` (its faces `faces`) separates from the centre
/// as seen from the light-space point `pl` on triangle `receiver`, and the change of their
/// counts; `None` when it changes none, or when it lies in one plane with P and the light's
/// centre, within rounding (then `degenerate` is set, and P's samples are to be cast).
#[inline(always)]
pub(crate) fn edge_region(
    e: &PotentialEdge,
    faces: &[EdgeFace],
    pl: DVec3,
    pyramid: &[Plane; 5],
    receiver: u32,
    degenerate: &mut bool,
) -> Option<Region> {
    let (a, b) = (e.a, e.b);
    let c = DVec3::ZERO;
    // An edge wholly outside one plane of P's pyramid meets no triangle P c s.
    if pyramid
        .iter()
        .any(|q| q.n.dot(a) + q.d < 0.0 && q.n.dot(b) + q.d < 0.0)
    {
        return None;
    }
    // The plane through P and the edge: the sides of c and of each face, each the sign of
    // the plane through the edge and that point (or that face) at P.
    let d = pl - a;
    let d2 = d.length_squared();
    // The faces' sides of the plane through P and the edge, summed: zero where the edge is no
    // silhouette from P.
    let mut sides = 0i32;
    for f in faces {
        if f.triangle == receiver {
            continue;
        }
        // P within rounding of a face's plane (a neighbour coplanar with the receiver, say)
        // sees it edge-on: it covers no sample.
        let s = f.normal.dot(d);
        if s * s <= EDGE_ON * EDGE_ON * f.normal_length2 * d2 {
            continue;
        }
        sides += if s > 0.0 { 1 } else { -1 };
    }
    if sides == 0 {
        return None;
    }
    // Only the part of the edge between the light's plane and P's depth can cross a
    // triangle P c s (its points lie at depths between 0 and P's); none, no change.
    let (t0, t1) = slab(a.z, b.z, pl.z);
    if !(t0 < t1) {
        return None;
    }
    // A silhouette whose plane with P holds the light's centre, within rounding (the centre on
    // the edge's line, or P, the edge and the centre in one plane): which samples it changes
    // hangs on that rounding, and the count at the centre with it. The caller casts P's
    // samples instead.
    let side_c = e.toward_centre.dot(d);
    let scale = DEGENERATE * DEGENERATE * (b - a).length_squared() * a.length_squared() * d2;
    if side_c * side_c <= scale {
        *degenerate = true;
        return None;
    }
    let delta = if side_c > 0.0 { -sides } else { sides };
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
    // `f0 f1 < 0` holds on two opposite cones at c; the samples the edge changes lie in the
    // one that holds the edge's own projection from P, seen through its middle.
    let mid = a + l * (0.5 * (t0 + t1));
    let q = pl + (mid - pl) * (pl.z / (pl.z - mid.z));
    let q = DVec2::new(q.x, q.y);
    let (g0, g1) = if f0.at(q) > 0.0 {
        (f0, f1.neg())
    } else {
        (f0.neg(), f1)
    };
    // `o2` only tells the two cones apart, already chosen: the light is clipped by the others.
    Region::new(delta, [o3, g0, g1, o2])
}
