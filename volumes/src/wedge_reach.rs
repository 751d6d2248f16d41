//! How far a penumbra wedge reaches, in light space: a box and a frustum bounding it within
//! the receivers' box, which the wedge grid bins (`wedge_grid.rs`) and the GPU rasterises, and
//! the receivers' box itself.

use glam::{DVec2, DVec3};
use penumbra_geom::RectLight;

use crate::clip::RADIAL_PARTS;
use crate::wedge::Wedge;

/// A light-space box holding every point of `w`'s wedge at light-space depth `z <= zmax`: the
/// wedge is `{ s + t (s - l) : s on the edge, l on the light, t >= 0 }` (light space is an affine
/// image of world space), whose depth is `z_s (1 + t)`, so `t <= zmax / z_s - 1`. That bound is
/// convex along the edge, hence at most its value `T` at an end, and the points `s + T (s - l)`
/// for the edge's ends and the light's corners bound the rest (the map is bilinear in `s`, `l`).
pub fn wedge_bounds(w: &Wedge, zmax: f64) -> (DVec3, DVec3) {
    let zmin = w.from.z.min(w.to.z);
    if !(zmin > 0.0) {
        return (DVec3::splat(f64::NEG_INFINITY), DVec3::splat(f64::INFINITY));
    }
    let t = (zmax / zmin - 1.0).max(0.0);
    let mut lo = w.from.min(w.to);
    let mut hi = w.from.max(w.to);
    for s in [w.from, w.to] {
        for l in RADIAL_PARTS.iter().map(|p| p[1]) {
            let q = s + (s - l.extend(0.0)) * t;
            lo = lo.min(q);
            hi = hi.max(q);
        }
    }
    (lo, hi)
}

/// The light-space box holding every receiver: the bounds of `triangles`, padded by a thousandth
/// of their extent (the unit box when there are none).
pub fn receiver_box(light: &RectLight, triangles: &[[DVec3; 3]]) -> (DVec3, DVec3) {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for v in triangles.iter().flatten() {
        let l = light.to_light_space(*v);
        lo = lo.min(l);
        hi = hi.max(l);
    }
    if !(lo.x <= hi.x) {
        lo = DVec3::ZERO;
        hi = DVec3::ONE;
    }
    padded(lo, hi)
}

/// The box `[lo, hi]` grown by a thousandth of its extent (of `1e-6` on a flat axis), so that
/// points on its faces lie inside despite rounding.
pub(crate) fn padded(lo: DVec3, hi: DVec3) -> (DVec3, DVec3) {
    let pad = (hi - lo).max(DVec3::splat(1e-6)) * 1e-3;
    (lo - pad, hi + pad)
}

/// [`wedge_bounds`] clipped to the receivers' box `[lo, hi]`, or `None` when the wedge misses it.
pub fn wedge_box(w: &Wedge, lo: DVec3, hi: DVec3) -> Option<(DVec3, DVec3)> {
    let (blo, bhi) = wedge_bounds(w, hi.z);
    let (blo, bhi) = (blo.max(lo), bhi.min(hi));
    (blo.x <= bhi.x && blo.y <= bhi.y && blo.z <= bhi.z).then_some((blo, bhi))
}

/// A light-space solid bounding a wedge within the receivers' box: at depth `z` between `z.0` and
/// `z.1`, the rectangle interpolated linearly from `near` (at `z.0`) to `far` (at `z.1`), each
/// `(min, max)` in x and y. Convex, with the unit cube's topology (its side faces are planar), so
/// the GPU rasterises it as it would a box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WedgeFrustum {
    /// Depth range.
    pub z: (f64, f64),
    /// Rectangle at `z.0`.
    pub near: (DVec2, DVec2),
    /// Rectangle at `z.1`.
    pub far: (DVec2, DVec2),
}

impl WedgeFrustum {
    /// The rectangle at depth `z` (not clamped to the depth range).
    pub fn section(&self, z: f64) -> (DVec2, DVec2) {
        let t = if self.z.1 > self.z.0 {
            (z - self.z.0) / (self.z.1 - self.z.0)
        } else {
            0.0
        };
        (
            self.near.0.lerp(self.far.0, t),
            self.near.1.lerp(self.far.1, t),
        )
    }

    /// Its bounding box: both rectangles over its depths.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        (
            self.near.0.min(self.far.0).extend(self.z.0),
            self.near.1.max(self.far.1).extend(self.z.1),
        )
    }

    /// Light-space volume.
    pub fn volume(&self) -> f64 {
        let area = |r: (DVec2, DVec2)| {
            let d = (r.1 - r.0).max(DVec2::ZERO);
            d.x * d.y
        };
        let (a0, a1) = (area(self.near), area(self.far));
        (self.z.1 - self.z.0) * (a0 + a1 + (a0 * a1).sqrt()) / 3.0
    }

    /// Whether `p` lies inside (with a relative tolerance `eps` of the rectangles' size).
    pub fn holds(&self, p: DVec3, eps: f64) -> bool {
        let (lo, hi) = self.section(p.z);
        let pad = (hi - lo).max(DVec2::ONE) * eps;
        let dz = (self.z.1 - self.z.0).abs().max(1.0) * eps;
        p.z >= self.z.0 - dz
            && p.z <= self.z.1 + dz
            && p.truncate().cmpge(lo - pad).all()
            && p.truncate().cmple(hi + pad).all()
    }
}

/// The smaller of two solids holding `w`'s wedge within the receivers' box `[lo, hi]`: its
/// [`wedge_box`], or a frustum narrowing from the light's end square at the receivers' far depth
/// down to the edge. `None` when the wedge misses the box.
///
/// The frustum: keep the part of the edge at depth `zmax = hi.z` or less (nothing beyond it
/// reaches a receiver). Seen from a point `s` of the edge, the wedge at `zmax` is the light's
/// square mirrored through `s`: centre `s_xy zmax / z_s`, half-side `zmax / z_s - 1`. Along the
/// edge both are affine in the edge's central projection from the light's centre, so the wedge
/// at `zmax` lies in the two ends' squares' bounding rectangle; `far` is that rectangle grown to
/// hold `near`, the edge's own rectangle at its nearest depth. Every section then holds `near`,
/// so the frustum holds the edge, and as it is convex it holds each segment from an edge point to
/// the wedge's points at `zmax`, which is the wedge. Its depth starts at the edge's nearest end,
/// or at `lo.z` (cut there by interpolation). Its x and y are not clipped to the box: cutting its
/// far rectangle would shrink the sections between below the box's cut.
pub fn wedge_frustum(w: &Wedge, lo: DVec3, hi: DVec3) -> Option<WedgeFrustum> {
    let (blo, bhi) = wedge_box(w, lo, hi)?;
    let boxed = WedgeFrustum {
        z: (blo.z, bhi.z),
        near: (blo.truncate(), bhi.truncate()),
        far: (blo.truncate(), bhi.truncate()),
    };
    let zmax = hi.z;
    let (a, mut b) = if w.from.z <= w.to.z {
        (w.from, w.to)
    } else {
        (w.to, w.from)
    };
    if !(a.z > 0.0 && a.z < zmax) {
        return Some(boxed);
    }
    if b.z > zmax {
        b = a + (b - a) * ((zmax - a.z) / (b.z - a.z));
    }
    let near = (
        a.truncate().min(b.truncate()),
        a.truncate().max(b.truncate()),
    );
    let mut far = near;
    for s in [a, b] {
        let tau = zmax / s.z;
        let c = s.truncate() * tau;
        let h = DVec2::splat(tau - 1.0);
        far = (far.0.min(c - h), far.1.max(c + h));
    }
    let mut f = WedgeFrustum {
        z: (a.z, zmax),
        near,
        far,
    };
    if lo.z > a.z {
        f.near = f.section(lo.z);
        f.z.0 = lo.z;
    }
    // The GPU spans the box's depths with the two rectangles: they must be the frustum's.
    let finite = f.near.0.is_finite() && f.far.0.is_finite() && f.far.1.is_finite();
    if !(finite && f.z == boxed.z) {
        return Some(boxed);
    }
    Some(if f.volume() < boxed.volume() {
        f
    } else {
        boxed
    })
}
