//! Penumbra wedges (Akenine-Möller & Assarsson 2002, "Approximate soft shadows on arbitrary
//! surfaces using penumbra wedges"; Assarsson & Akenine-Möller 2003) in light space (the light
//! is `[-1, 1]^2` at `z = 0`, its centre the origin): a silhouette edge's projection from a
//! receiver point onto the light, whether the point lies in its wedge, the edges a mesh that the
//! light's plane cuts adds, and the wedge's bounding planes. What a wedge hides of each radial
//! part of the light is in `wedge_integral.rs`.

use glam::{DVec2, DVec3};
use penumbra_geom::Plane;

use crate::clip::RADIAL_PARTS;

/// Fraction of `z_P` kept between the clipped edge and the local near plane, so that no
/// projected coordinate grows beyond about `1e9`.
pub const NEAR_PLANE_MARGIN: f64 = 1e-9;

/// One penumbra wedge: a silhouette edge in light space with its multiplicity and occluder.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wedge {
    /// Edge start in light space (casters run `from -> to`).
    pub from: DVec3,
    /// Edge end in light space.
    pub to: DVec3,
    /// Multiplicity `m >= 1`.
    pub multiplicity: u32,
    /// Index of the occluder (scene mesh) the edge belongs to: the unit that is blended.
    pub occluder: u32,
    /// Index of the silhouette loop within the occluder.
    pub silhouette_loop: u32,
    /// The blending unit (Forest et al.'s "silhouette"): the caster patch whose boundary the
    /// edge is, numbered across the scene, occluder by occluder.
    pub unit: u32,
    /// For an edge of a mesh that the light's plane cuts (its silhouette edges, clipped to the
    /// emitting side, and its cut edges, [`Wedge::cut`]), a point of its caster next to it;
    /// `None` for the others. It tells the wedge's halves apart (see [`Wedge::integral`]).
    pub caster: Option<DVec3>,
}

impl Wedge {
    /// The edge clipped to the local near plane of `p` and projected from `p` onto the light
    /// plane, or `None` when nothing of it lies in front of `p` or `p` is not on the emitting
    /// side.
    #[inline]
    pub fn project(&self, p: DVec3) -> Option<(DVec2, DVec2)> {
        let (a, b) = self.clip(p)?;
        project_from(p, a, b)
    }

    /// The edge clipped to `p`'s near plane ([`Wedge::project`]), or `None`.
    #[inline(always)]
    fn clip(&self, p: DVec3) -> Option<(DVec3, DVec3)> {
        if !(p.z > 0.0) || !p.is_finite() {
            return None;
        }
        let limit = p.z * (1.0 - NEAR_PLANE_MARGIN);
        let (mut a, mut b) = (self.from, self.to);
        match (a.z <= limit, b.z <= limit) {
            (false, false) => return None,
            (true, false) => b = a + (b - a) * ((limit - a.z) / (b.z - a.z)),
            (false, true) => a = b + (a - b) * ((limit - b.z) / (a.z - b.z)),
            (true, true) => {}
        }
        Some((a, b))
    }

    /// [`Wedge::project`] when the projected edge meets the light square, else `None`: whether
    /// `p` lies in the wedge.
    ///
    /// Decided before the divisions of the projection, which half of a pixel's candidates
    /// never need: in homogeneous coordinates the end `a` projects to `(A, w_a)` with
    /// `A = p.z a.xy - a.z p.xy` and `w_a = p.z - a.z > 0`, tested by `meets_square`.
    #[inline(always)]
    pub fn project_onto_light(&self, p: DVec3) -> Option<(DVec2, DVec2)> {
        let (a, b) = self.clip(p)?;
        if !meets_square(homogeneous(p, a), homogeneous(p, b)) {
            return None;
        }
        project_from(p, a, b)
    }

    /// Whether `p` lies in the wedge: the projected, clipped edge meets the light square, so the
    /// edge hides or reveals some of the light from `p`.
    pub fn contains(&self, p: DVec3) -> bool {
        self.project_onto_light(p).is_some()
    }
}

impl Wedge {
    /// The silhouette edge `from -> to` (light space) clipped to the emitting side of the light's
    /// plane, `z >= 0`: only that part can hide any light. `None` when nothing of it is left.
    pub fn clipped_to_light(from: DVec3, to: DVec3) -> Option<(DVec3, DVec3)> {
        match (from.z >= 0.0, to.z >= 0.0) {
            (true, true) => Some((from, to)),
            (false, false) => None,
            (true, false) => Some((from, cut_point(from, to))),
            (false, true) => Some((cut_point(to, from), to)),
        }
        .filter(|(a, b)| a != b)
    }

    /// The cut edge of a caster triangle (light space) that crosses the light's plane: the
    /// segment along `z = 0` where the plane cuts the part of it that can occlude (`z >= 0`)
    /// off the rest. With the clipped silhouette edges it closes the occluder's outline as seen
    /// from any receiver. Returns the edge and the triangle's vertex farthest in front of the
    /// light (its [`Wedge::caster`]), or `None` when the triangle does not reach both sides
    /// of the plane.
    pub fn cut(tri: [DVec3; 3]) -> Option<(DVec3, DVec3, DVec3)> {
        let top = tri.into_iter().max_by(|a, b| a.z.total_cmp(&b.z))?;
        if !(top.z > 0.0) || !tri.iter().any(|v| v.z < 0.0) {
            return None;
        }
        // Where the boundary leaves the emitting side, and where it comes back.
        let (mut exit, mut entry) = (None, None);
        for i in 0..3 {
            let (a, b) = (tri[i], tri[(i + 1) % 3]);
            if a.z >= 0.0 && b.z < 0.0 {
                exit = Some(cut_point(a, b));
            } else if a.z < 0.0 && b.z >= 0.0 {
                entry = Some(cut_point(b, a));
            }
        }
        let (x, y) = (exit?, entry?);
        (x != y).then_some((x, y, top))
    }
}

/// The point of segment `a b` (`a.z >= 0 > b.z`) on the light's plane, `a` itself when it lies
/// on it.
fn cut_point(a: DVec3, b: DVec3) -> DVec3 {
    if a.z == 0.0 {
        return a;
    }
    let p = a + (b - a) * (a.z / (a.z - b.z));
    DVec3::new(p.x, p.y, 0.0)
}

impl Wedge {
    /// The plane through the edge and the light's centre that splits the wedge of an edge in
    /// front of the light ([`Wedge::caster`] `None`) into its outer half (positive side, away
    /// from the casters) and its inner half (negative side).
    pub fn split_plane(&self) -> Plane {
        let n = (self.to - self.from).cross(-self.from);
        Plane {
            n,
            d: -n.dot(self.from),
        }
    }

    /// Bounding planes of the wedge for the fast outside test of Lengyel (GDC 2005): every
    /// point of the wedge is inside all of them, so a point outside any one is outside the wedge;
    /// the GPU rejects fragments with this test before the integral.
    ///
    /// The wedge `{ s + t (s - l) }` (s on the edge, l on the light, t >= 0) lies in the convex
    /// polyhedron `from + { a (to - from) + Σ_k b_k (s_k - l_k) : 0 <= a <= 1, b >= 0 }`, the
    /// edge swept along the eight directions from the light's corners through its ends (expand
    /// `(1 + t) s - t l` with `s`, `l` convex combinations). Its faces are the planes spanned by
    /// two of the generators that leave all directions on one side: the front and back planes
    /// (through the edge and a corner, supporting the light) and the side planes at the ends.
    /// When the edge's line pierces the light rectangle there are no front and back planes and
    /// the side planes alone bound the wedge, so an edge pointing at the light stays conservative
    /// and never yields a NaN plane. The light's plane is always included.
    pub fn bounding_planes(&self) -> Vec<Plane> {
        if !(self.from.z > 0.0 && self.to.z > 0.0) {
            // An edge on the light's plane (a cut edge, or a clipped end): its wedge may reach
            // every receiver.
            return vec![Plane {
                n: DVec3::Z,
                d: 0.0,
            }];
        }
        let e = self.to - self.from;
        let mut dirs = Vec::with_capacity(8);
        for s in [self.from, self.to] {
            for l in RADIAL_PARTS.map(|p| p[1].extend(0.0)) {
                dirs.push(s - l);
            }
        }
        let mut gens = dirs.clone();
        gens.push(e);
        let mut planes = vec![Plane {
            n: DVec3::Z,
            d: 0.0,
        }];
        for i in 0..gens.len() {
            for j in i + 1..gens.len() {
                let n = gens[i].cross(gens[j]);
                let len = n.length();
                if !(len > 1e-12 * gens[i].length() * gens[j].length()) || !len.is_finite() {
                    continue;
                }
                let n = n / len;
                for n in [n, -n] {
                    // All sweep directions must point into the inside (n · d >= 0).
                    let tol = 1e-12 * (1.0 + self.from.length());
                    if dirs.iter().any(|d| n.dot(*d) < -tol * d.length()) {
                        continue;
                    }
                    let p = Plane {
                        n,
                        d: -(n.dot(self.from).min(n.dot(self.to))),
                    };
                    if !planes.iter().any(|q| q.n.dot(n) > 1.0 - 1e-9) {
                        planes.push(p);
                    }
                }
            }
        }
        planes
    }
}

/// The ends `a` and `b` (in front of `p`'s near plane) projected from `p` onto the light's plane,
/// or `None` where that overflows.
#[inline(always)]
fn project_from(p: DVec3, a: DVec3, b: DVec3) -> Option<(DVec2, DVec2)> {
    let proj = |x: DVec3| {
        let k = p.z / (p.z - x.z);
        DVec2::new(p.x + (x.x - p.x) * k, p.y + (x.y - p.y) * k)
    };
    let (a, b) = (proj(a), proj(b));
    (a.is_finite() && b.is_finite()).then_some((a, b))
}

/// `x` (in front of `p`'s near plane) projected from `p` onto the light's plane, in homogeneous
/// coordinates `(X, Y, W)`, `W > 0`: the point `(X / W, Y / W)`.
#[inline(always)]
fn homogeneous(p: DVec3, x: DVec3) -> DVec3 {
    DVec3::new(p.z * x.x - x.z * p.x, p.z * x.y - x.z * p.y, p.z - x.z)
}

/// Whether the segment `a b` meets the closed square `[-1, 1]^2` ([`meets_square`] of its ends
/// with weight 1).
#[inline]
pub fn segment_meets_square(a: DVec2, b: DVec2) -> bool {
    meets_square(a.extend(1.0), b.extend(1.0))
}

/// Whether the segment between the points `(A.x / A.z, A.y / A.z)` and `(B.x / B.z, B.y / B.z)`
/// (homogeneous, `A.z`, `B.z > 0`) meets the closed square `[-1, 1]^2`, without dividing.
///
/// Two disjoint convex polygons have a separating line parallel to a side of one of them: here
/// a side of the square (both ends beyond it: `A.x > A.z` and `B.x > B.z` for the side
/// `x = 1`) or the segment's own line `L = A x B`, whose value `L . (c, 1)` at a corner `c` is
/// `A.z B.z` times the corner's side of the line through the projected points; the square's
/// four corners lie strictly on one side of it where `L.z ± (|L.x| + |L.y|)`, its extremes over
/// them, have one sign. Rounding decides only ties, a segment through a corner or along a side
/// to within rounding of its coordinates, where Liang and Barsky's clipping (1984) may answer
/// the other way (`volumes/src/wedge_tests.rs`).
#[inline(always)]
fn meets_square(a: DVec3, b: DVec3) -> bool {
    let beyond = |k: usize| (a[k] > a.z && b[k] > b.z) || (a[k] < -a.z && b[k] < -b.z);
    if beyond(0) || beyond(1) {
        return false;
    }
    let l = a.cross(b);
    let r = l.x.abs() + l.y.abs();
    !(l.z - r > 0.0 || l.z + r < 0.0)
}
