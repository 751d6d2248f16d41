//! 2-D convex clipping in light space, where the light is the square `[-1, 1]^2` and its centre
//! the origin, and the light's four radial parts (Forest et al. 2006, section 3.1, Figure 6).

use glam::DVec2;

/// 2-D cross product `a.x b.y - a.y b.x`.
#[inline]
pub fn cross(a: DVec2, b: DVec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// A convex polygon of at most [`Poly::CAPACITY`] vertices, kept inline: the clips of a radial
/// part (a triangle) by a few half-planes, made for every wedge at every pixel, never touch the
/// heap. It reads as a slice of its vertices.
#[derive(Clone, Copy, Debug)]
pub struct Poly {
    points: [DVec2; Poly::CAPACITY],
    len: usize,
}

impl Poly {
    /// No vertex.
    pub const EMPTY: Poly = Poly {
        points: [DVec2::ZERO; Poly::CAPACITY],
        len: 0,
    };

    /// Most vertices. A convex polygon gains at most one vertex per clip, so a triangle clipped
    /// by three half-planes, as the wedge integrals clip their radial parts, has at most 6; the
    /// slack is for polygons that rounding left a hair short of convex.
    pub const CAPACITY: usize = 8;

    /// Appends `p`; beyond the capacity (only a polygon that rounding made non-convex, of an area
    /// at the rounding's scale, can get there) the vertex is dropped rather than panicking.
    #[inline]
    fn push(&mut self, p: DVec2) {
        if self.len < Self::CAPACITY {
            self.points[self.len] = p;
            self.len += 1;
        }
    }

    /// One step of Sutherland & Hodgman's clip by an affine `f >= 0`: the side `a b` of the
    /// polygon being clipped, with `fa = f(a)` and `fb = f(b)`, adds `a` when it is kept and
    /// the crossing when the side crosses the line.
    #[inline]
    fn clip_side(&mut self, a: DVec2, b: DVec2, fa: f64, fb: f64) {
        if fa >= 0.0 {
            self.push(a);
        }
        if (fa >= 0.0) != (fb >= 0.0) {
            let t = fa / (fa - fb);
            self.push(a + (b - a) * t);
        }
    }

    /// Makes this the polygon of `points`, as [`Poly::of`].
    #[inline]
    pub fn set(&mut self, points: &[DVec2]) {
        self.len = 0;
        for &x in points {
            self.push(x);
        }
    }

    /// Makes this [`clip_halfplane`]`(poly, f)` in place: the wedge integrals clip in buffers
    /// that stay put, where returning a polygon would copy it. Each vertex is evaluated once and
    /// its value carried to the next side.
    #[inline]
    pub fn set_clip(&mut self, poly: &[DVec2], f: impl Fn(DVec2) -> f64) {
        self.len = 0;
        let Some(&first) = poly.first() else {
            return;
        };
        let f_first = f(first);
        let (mut a, mut fa) = (first, f_first);
        for i in 1..=poly.len() {
            let (b, fb) = match poly.get(i) {
                Some(&b) => (b, f(b)),
                None => (first, f_first),
            };
            self.clip_side(a, b, fa, fb);
            (a, fa) = (b, fb);
        }
    }

    /// Makes `below` and `above` the parts of this polygon where the affine `f <= 0` and where
    /// `f >= 0`: the polygons [`clip_halfplane`] gives by `-f` and by `f`, bit for bit
    /// (negation is exact, so `below` is clipped by this `f`'s values negated), with `f`
    /// evaluated once per vertex.
    #[inline]
    pub fn split_into(&self, f: impl Fn(DVec2) -> f64, below: &mut Poly, above: &mut Poly) {
        let mut values = [0.0; Poly::CAPACITY];
        for (v, &x) in values.iter_mut().zip(self.iter()) {
            *v = f(x);
        }
        below.len = 0;
        above.len = 0;
        let n = self.len;
        for i in 0..n {
            let j = if i + 1 == n { 0 } else { i + 1 };
            let (a, b, fa, fb) = (self.points[i], self.points[j], values[i], values[j]);
            below.clip_side(a, b, -fa, -fb);
            above.clip_side(a, b, fa, fb);
        }
    }
}

impl std::ops::Deref for Poly {
    type Target = [DVec2];

    fn deref(&self) -> &[DVec2] {
        &self.points[..self.len]
    }
}

/// Keeps the part of the convex polygon `poly` where `f(x) >= 0`, `f` affine (Sutherland &
/// Hodgman 1974, one plane at a time), in at most [`Poly::CAPACITY`] vertices.
#[cfg(test)]
pub fn clip_halfplane(poly: &[DVec2], f: impl Fn(DVec2) -> f64) -> Poly {
    let mut out = Poly::EMPTY;
    out.set_clip(poly, f);
    out
}

/// Keeps the part of the segment `a b` where the affine `f >= 0`.
pub fn clip_segment(a: DVec2, b: DVec2, f: impl Fn(DVec2) -> f64) -> Option<(DVec2, DVec2)> {
    clip_segment_by(a, b, f(a), f(b))
}

/// [`clip_segment`] given `fa = f(a)` and `fb = f(b)`.
pub fn clip_segment_by(a: DVec2, b: DVec2, fa: f64, fb: f64) -> Option<(DVec2, DVec2)> {
    match (fa >= 0.0, fb >= 0.0) {
        (true, true) => Some((a, b)),
        (false, false) => None,
        (true, false) => Some((a, a + (b - a) * (fa / (fa - fb)))),
        (false, true) => Some((a + (b - a) * (fa / (fa - fb)), b)),
    }
}

/// Signed area (shoelace), positive counter-clockwise.
pub fn area(poly: &[DVec2]) -> f64 {
    let mut s = 0.0;
    for i in 0..poly.len() {
        s += cross(poly[i], poly[(i + 1) % poly.len()]);
    }
    0.5 * s
}

/// An axis-aligned rectangle in light space; empty when `min > max` on an axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// Lower-left corner.
    pub min: DVec2,
    /// Upper-right corner.
    pub max: DVec2,
}

impl Rect {
    /// The empty rectangle (identity of [`Rect::union`]).
    pub const EMPTY: Rect = Rect {
        min: DVec2::splat(f64::INFINITY),
        max: DVec2::splat(f64::NEG_INFINITY),
    };

    /// Bounding rectangle of points.
    pub fn of(points: &[DVec2]) -> Rect {
        points.iter().fold(Rect::EMPTY, |r, &p| Rect {
            min: r.min.min(p),
            max: r.max.max(p),
        })
    }

    /// Whether it holds no point.
    pub fn is_empty(&self) -> bool {
        !(self.min.x <= self.max.x && self.min.y <= self.max.y)
    }

    /// Area, 0 when empty.
    pub fn area(&self) -> f64 {
        if self.is_empty() {
            0.0
        } else {
            (self.max.x - self.min.x) * (self.max.y - self.min.y)
        }
    }

    /// Its centre (meaningless when empty).
    pub fn centre(&self) -> DVec2 {
        (self.min + self.max) * 0.5
    }

    /// Smallest rectangle holding both.
    pub fn union(&self, o: &Rect) -> Rect {
        Rect {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    /// Intersection (possibly empty).
    pub fn intersection(&self, o: &Rect) -> Rect {
        Rect {
            min: self.min.max(o.min),
            max: self.max.min(o.max),
        }
    }
}

/// The four radial parts of the light: the triangles from the centre to each side of the square,
/// counter-clockwise from the right (+x) side. Each has area 1, a quarter of the square.
pub const RADIAL_PARTS: [[DVec2; 3]; 4] = [
    [DVec2::ZERO, DVec2::new(1.0, -1.0), DVec2::new(1.0, 1.0)],
    [DVec2::ZERO, DVec2::new(1.0, 1.0), DVec2::new(-1.0, 1.0)],
    [DVec2::ZERO, DVec2::new(-1.0, 1.0), DVec2::new(-1.0, -1.0)],
    [DVec2::ZERO, DVec2::new(-1.0, -1.0), DVec2::new(1.0, -1.0)],
];

/// Area of one radial part.
pub const PART_AREA: f64 = 1.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radial_parts_tile_the_square() {
        let total: f64 = RADIAL_PARTS.iter().map(|t| area(t)).sum();
        assert!((total - 4.0).abs() < 1e-15);
        assert!(
            RADIAL_PARTS
                .iter()
                .all(|t| (area(t) - PART_AREA).abs() < 1e-15)
        );
    }

    #[test]
    fn clipping_a_square_by_a_diagonal_halves_it() {
        let sq = [
            DVec2::new(-1., -1.),
            DVec2::new(1., -1.),
            DVec2::new(1., 1.),
            DVec2::new(-1., 1.),
        ];
        let half = clip_halfplane(&sq, |p| p.x - p.y);
        assert!((area(&half) - 2.0).abs() < 1e-15);
        assert!(clip_halfplane(&sq, |p| p.x - 5.0).is_empty());
    }

    #[test]
    fn rect_algebra() {
        let a = Rect::of(&[DVec2::new(0., 0.), DVec2::new(2., 1.)]);
        let b = Rect::of(&[DVec2::new(1., 0.5), DVec2::new(3., 3.)]);
        assert_eq!(a.intersection(&b).area(), 0.5);
        assert_eq!(a.union(&b).area(), 9.0);
        assert!(Rect::EMPTY.is_empty() && Rect::EMPTY.area() == 0.0);
        assert_eq!(Rect::EMPTY.union(&a), a);
    }
}
