//! Penumbra wedges (Akenine-Möller & Assarsson 2002, "Approximate soft shadows on arbitrary
//! surfaces using penumbra wedges"; Assarsson & Akenine-Möller 2003) and the per-edge wedge
//! integral, in light space (the light is `[-1, 1]^2` at `z = 0`, its centre the origin).
//!
//! # The wedge integral
//!
//! For a receiver P, let `N(P, x)` be the number of caster triangles that the segment from P to
//! the light point `x` crosses. Moving `x` from the centre `c` along a straight line, `N` only
//! changes where the segment sweeps over a silhouette edge as seen from P. With the silhouette
//! taken from `c` (the method's one approximation), for every `x` of the light
//!
//! ```text
//! N(P, x) = N(P, c) + Σ_e s_e(P) · m_e · [segment c-x crosses the projection of e from P]
//! ```
//!
//! where `m_e` is the edge's multiplicity and `s_e(P) = +1` when P lies on the outer side of the
//! plane through the edge and `c` (the side away from the edge's caster triangles: the edge's
//! outer half-wedge), `-1` on the inner side. Integrating over one radial part `T_k` of the light
//! (Forest et al. 2006, section 3.1) gives the occluded area of the part,
//!
//! ```text
//! A_k = |T_k| · [N(P, c) > 0] + Σ_e s_e(P) · m_e · |R_e ∩ T_k|,
//! R_e = { x in L : segment c-x crosses the projected, clipped edge }
//! ```
//!
//! `R_e` is the region of the light behind the projected edge as seen from the centre: the light
//! square clipped by the two sides of the cone from `c` over the edge and by the edge's line.
//! The first term is the hard shadow (the stencil count from the centre); the sum adds the outer
//! half-wedges' areas and subtracts the inner ones', exactly as Forest et al. 2006 state. The edge is
//! first clipped to the local near plane (the plane through P parallel to the light: only the
//! part between P and the light plane can be projected, Forest et al. 2006, section 4.2, Figure 9), then
//! projected from P onto the light plane, `X' = P + (X - P) · z_P / (z_P - z_X)`.
//!
//! For a single planar occluder, whose silhouette is the same from every light point, this is
//! exact.

use glam::{DVec2, DVec3};
use penumbra_geom::Plane;

use crate::clip::{Poly, RADIAL_PARTS, Rect, area, clip_segment, clip_segment_by, cross};
use crate::silhouette::orient3d;

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

/// What one wedge contributes at one receiver point, per radial part.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeIntegral {
    /// `+1` for the outer half-wedge (added), `-1` for the inner one (subtracted).
    pub sign: f64,
    /// `m · |R_e ∩ T_k|`, unsigned.
    pub area: [f64; 4],
    /// Bounding rectangle of `R_e ∩ T_k` (the occluded side of an outer half-wedge).
    pub beyond: [Rect; 4],
    /// Bounding rectangle of the part of the cone over the edge between `c` and the edge (the
    /// occluded side of an inner half-wedge).
    pub near: [Rect; 4],
    /// Length of the part's outer side (the light's border, length 2) inside the cone over the
    /// edge: where the inner half-wedges of a loop cover the whole side, the occluded region of
    /// a part in hard shadow ends at the edges (Forest et al. 2006, Figure 10).
    pub cover: [f64; 4],
}

impl EdgeIntegral {
    /// Nothing in any part (the sign is left at 0).
    pub const NONE: EdgeIntegral = EdgeIntegral {
        sign: 0.0,
        area: [0.0; 4],
        beyond: [Rect::EMPTY; 4],
        near: [Rect::EMPTY; 4],
        cover: [0.0; 4],
    };
}

/// Which radial parts of an [`EdgeIntegral`] [`Wedge::integral_parts`] wrote; every other part
/// `k` is [`EdgeIntegral::NONE`]'s but for `near[k]`, the centre alone when `centre_near` (the
/// centre lies on the near side of the edge, whose cone misses the part).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Parts {
    /// Bit `k` for part `k`.
    pub written: u8,
    pub centre_near: bool,
}

impl Parts {
    /// No integral: the point lies outside the wedge, or in the plane of the edge and the centre.
    pub const NONE: Parts = Parts {
        written: 0,
        centre_near: false,
    };
    /// Every part written.
    pub const ALL: Parts = Parts {
        written: 0b1111,
        centre_near: false,
    };

    /// Whether there is an integral.
    pub fn any(self) -> bool {
        self.written != 0
    }

    /// Whether part `k` was written.
    #[inline(always)]
    pub fn has(self, k: usize) -> bool {
        self.written & (1 << k) != 0
    }
}

impl EdgeIntegral {
    /// Sets the parts that `parts` says were not written to what they stand for.
    fn complete(&mut self, parts: Parts) {
        for k in (0..4).filter(|&k| !parts.has(k)) {
            self.area[k] = 0.0;
            self.beyond[k] = Rect::EMPTY;
            self.near[k] = if parts.centre_near {
                Rect::of(&[DVec2::ZERO])
            } else {
                Rect::EMPTY
            };
            self.cover[k] = 0.0;
        }
    }
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

    /// The wedge integral at `p` (light space), or `None` when the edge does not touch the light
    /// as seen from `p` (`p` outside the wedge).
    pub fn integral(&self, p: DVec3) -> Option<EdgeIntegral> {
        let mut out = EdgeIntegral::NONE;
        self.integral_into(p, &mut out).then_some(out)
    }

    /// [`Wedge::integral`] written into `out`, whether there is one: the renderer keeps one
    /// integral for all its wedges rather than have each returned (a copy of some 300 bytes).
    /// `out` is unspecified when it returns `false`.
    #[inline]
    pub fn integral_into(&self, p: DVec3, out: &mut EdgeIntegral) -> bool {
        self.integral_by(p, out, true)
    }

    /// [`Wedge::integral_into`], taking the closed forms for a projected edge inside one radial
    /// part or two neighbouring ones when `closed_form`, else clipping every part (the tests
    /// compare the two).
    pub(crate) fn integral_by(&self, p: DVec3, out: &mut EdgeIntegral, closed_form: bool) -> bool {
        let parts = self.integral_parts(p, out, closed_form);
        out.complete(parts);
        parts.any()
    }

    /// The integral's parts that differ from [`EdgeIntegral::NONE`]'s, written into `out`, whose
    /// other parts are left as they were: the renderer reads only the parts written, and
    /// a short edge's projection (nearly every one) lies in one part or two.
    ///
    /// Inlined into the caller's loop up to the test of whether `p` lies in the wedge, which
    /// about half of the grid's candidates fail; the integral itself is not.
    #[inline(always)]
    pub(crate) fn integral_parts(
        &self,
        p: DVec3,
        out: &mut EdgeIntegral,
        closed_form: bool,
    ) -> Parts {
        // Only wedges containing p contribute: an edge whose projection misses the light hides
        // none of it (its near region would otherwise depend on which edges a search returns).
        let Some((a, b)) = self.project_onto_light(p) else {
            return Parts::NONE;
        };
        self.integral_of(a, b, p, out, closed_form)
    }

    /// [`Wedge::integral_parts`] of `p` whose projected edge `a b` meets the light.
    #[inline(never)]
    fn integral_of(
        &self,
        a: DVec2,
        b: DVec2,
        p: DVec3,
        out: &mut EdgeIntegral,
        closed_form: bool,
    ) -> Parts {
        let s0 = cross(a, b);
        if s0 == 0.0 {
            return Parts::NONE;
        }
        let s0 = s0.signum();
        // Outer when the caster, seen from p, lies beyond the edge from the light's centre. On a
        // mesh in front of the light, Forest et al. take that side as p's side of the plane
        // (from, to, c): the casters (facing the light) lie on its negative side. On a mesh that
        // the light's plane cuts, whose outline then runs along the light, it is taken as it
        // is: the caster and the centre on opposite sides of the plane (from, to, p), whose
        // trace on the light's plane is the projected edge.
        let side = match self.caster {
            None => orient3d(self.from, self.to, DVec3::ZERO, p),
            Some(f) => {
                let (a, b) = (
                    orient3d(self.from, self.to, p, f),
                    orient3d(self.from, self.to, p, DVec3::ZERO),
                );
                if a == 0.0 || b == 0.0 {
                    0.0
                } else {
                    -(a * b).signum()
                }
            }
        };
        if side == 0.0 {
            return Parts::NONE;
        }
        let m = self.multiplicity as f64;
        out.sign = side.signum();
        // The cone over the edge from the centre is where both `side_a` and `side_b` are
        // non-negative; `edge_line` is non-negative on the centre's side of the edge.
        let side_a = |x: DVec2| s0 * cross(a, x);
        let side_b = |x: DVec2| s0 * cross(x, b);
        let edge_line = |x: DVec2| s0 * cross(b - a, x - a);
        let centre_near = edge_line(DVec2::ZERO) >= 0.0;
        // Both projected ends inside the light, in one radial part or in two neighbours (the
        // common case of a short edge): closed forms, with no clipping. Within one part, the
        // cone meets the part's outer side at the ends' rays, `a2` and `b2`, and the edge leaves
        // the triangle `c a b` on its near side and the quadrilateral `a a2 b2 b` beyond. Across
        // two, the diagonal between them cuts the edge at `d`, and each part holds that form for
        // its half, `a d` or `d b`. The cone misses the other parts, as below. These are what
        // the clips give, up to rounding.
        if let (Some(ka), Some(kb), true) = (part_within(a), part_within(b), closed_form) {
            let mut part = |k: usize, x: DVec2, y: DVec2| {
                let to_side = |x: DVec2| x / (if k % 2 == 0 { x.x } else { x.y }).abs();
                let (x2, y2) = (to_side(x), to_side(y));
                out.cover[k] = (y2 - x2).length();
                let r = 0.5 * (cross(x2, y2).abs() - cross(x, y).abs());
                (out.area[k], out.beyond[k]) = if r > 0.0 {
                    (m * r, Rect::of(&[x, x2, y2, y]))
                } else {
                    (0.0, Rect::EMPTY)
                };
                out.near[k] = Rect::of(&[DVec2::ZERO, x, y]);
            };
            // The corner between neighbouring parts `k` and `k + 1` ends part `k`'s side.
            let shared = if (ka + 1) % 4 == kb {
                Some(RADIAL_PARTS[ka][2])
            } else if (kb + 1) % 4 == ka {
                Some(RADIAL_PARTS[kb][2])
            } else {
                None
            };
            let done = if ka == kb {
                part(ka, a, b);
                true
            } else if let Some(corner) = shared {
                let d = a + (b - a) * (cross(a, corner) / cross(a - b, corner));
                part(ka, a, d);
                part(kb, d, b);
                true
            } else {
                false
            };
            if done {
                return Parts {
                    written: (1 << ka) | (1 << kb),
                    centre_near,
                };
            }
        }
        out.area = [0.0; 4];
        out.beyond = [Rect::EMPTY; 4];
        out.near = [Rect::EMPTY; 4];
        out.cover = [0.0; 4];
        // Part k runs from corner k to corner k + 1: their values decide, before any clipping,
        // whether the cone keeps the whole part or misses it.
        let corners = RADIAL_PARTS.map(|part| part[1]);
        let (at_a, at_b) = (corners.map(side_a), corners.map(side_b));
        let (mut half, mut cone) = (Poly::EMPTY, Poly::EMPTY);
        let (mut beyond, mut near) = (Poly::EMPTY, Poly::EMPTY);
        let mut any = false;
        for (k, part) in RADIAL_PARTS.iter().enumerate() {
            let (u, v) = (k, (k + 1) % 4);
            let keeps = |f: &[f64; 4]| f[u] >= 0.0 && f[v] >= 0.0;
            let drops = |f: &[f64; 4]| f[u] < 0.0 && f[v] < 0.0;
            let misses = if drops(&at_a) {
                true
            } else if keeps(&at_a) {
                drops(&at_b)
            } else {
                // `a`'s line crosses the part's outer side at `x`: clipping by it keeps the
                // centre, one corner and `x` (the crossing computed as the clip computes it).
                // When `b`'s line leaves both behind, the cone is the centre alone: the part
                // opposite a narrow cone.
                let x = part[1] + (part[2] - part[1]) * (at_a[u] / (at_a[u] - at_a[v]));
                let corner = if at_a[u] >= 0.0 { at_b[u] } else { at_b[v] };
                corner < 0.0 && side_b(x) < 0.0
            };
            if misses {
                // The cone misses the part. Clipping the part would leave copies of the centre
                // alone (the apex every clip keeps, and the crossings of the sides through it):
                // no area, no cover, and, where the centre lies on the near side, a near
                // rectangle of that one point.
                if centre_near {
                    out.near[k] = Rect::of(&[DVec2::ZERO]);
                    any = true;
                }
                continue;
            }
            if keeps(&at_a) && keeps(&at_b) {
                // The cone holds the whole part: the clips would return it unchanged.
                cone.set(part);
            } else {
                half.set_clip(part, side_a);
                cone.set_clip(&half, side_b);
            }
            if cone.len() < 3 {
                continue;
            }
            if let Some((p0, p1)) = clip_segment_by(part[1], part[2], at_a[u], at_a[v])
                .and_then(|(p0, p1)| clip_segment(p0, p1, side_b))
            {
                out.cover[k] = (p1 - p0).length();
            }
            cone.split_into(edge_line, &mut beyond, &mut near);
            let r = area(&beyond).abs();
            if r > 0.0 {
                out.area[k] = m * r;
                out.beyond[k] = Rect::of(&beyond);
                any = true;
            }
            if near.len() >= 3 {
                out.near[k] = Rect::of(&near);
                any = true;
            }
        }
        if any { Parts::ALL } else { Parts::NONE }
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

/// The radial part (0 right, 1 top, 2 left, 3 bottom, as [`RADIAL_PARTS`]) of a point strictly
/// inside the light square, `None` outside it, at its centre or within `1e-9` of its distance
/// from a diagonal (where the clipping's rounding may put the point in either part).
pub(crate) fn part_within(x: DVec2) -> Option<usize> {
    let (ax, ay) = (x.x.abs(), x.y.abs());
    if !(ax < 1.0 && ay < 1.0) {
        return None;
    }
    let margin = 1e-9 * (ax + ay);
    if x.x - ay > margin {
        Some(0)
    } else if x.y - ax > margin {
        Some(1)
    } else if -x.x - ay > margin {
        Some(2)
    } else if -x.y - ax > margin {
        Some(3)
    } else {
        None
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
