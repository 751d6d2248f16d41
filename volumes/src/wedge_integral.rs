//! The wedge integral: what one penumbra wedge hides or reveals of each radial part of the light
//! at a receiver point, in light space (the light is `[-1, 1]^2` at `z = 0`, its centre the
//! origin).
//!
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

use crate::clip::{Poly, RADIAL_PARTS, Rect, area, clip_segment, clip_segment_by, cross};
use crate::silhouette::orient3d;
use crate::wedge::Wedge;

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
