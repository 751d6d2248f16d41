//! Visibility buffers and Forest et al.'s blending of a silhouette's buffer into the final one.
//!
//! A buffer holds, per radial part of the light (see [`crate::clip::RADIAL_PARTS`]), the occluded
//! area `A` (light-space units; each part has area 1) and a rectangle `B` bounding the occluded
//! region. Blending a silhouette buffer `s` into the final buffer `f` (Forest, Barthe & Paulin
//! 2006, section 3.2) estimates how much of the two occluded regions overlap by assuming each is
//! spread evenly over its rectangle:
//!
//! ```text
//! eps = (A_f / |B_f|) · (A_s / |B_s|) · beta,     beta = |B_f ∩ B_s|
//! A   = A_f + A_s - eps,                            B = bounding rectangle of B_f ∪ B_s
//! ```
//!
//! and is skipped where either occlusion is zero.

use crate::clip::{PART_AREA, Rect};

/// One radial part's occlusion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Part {
    /// Occluded area, in `[0, 1]`.
    pub area: f64,
    /// Bounding rectangle of the occluded region.
    pub rect: Rect,
}

impl Part {
    /// No occlusion.
    pub const EMPTY: Part = Part {
        area: 0.0,
        rect: Rect::EMPTY,
    };
}

/// A visibility buffer: four radial parts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VBuffer {
    /// The parts, counter-clockwise from +x.
    pub parts: [Part; 4],
}

impl Default for VBuffer {
    fn default() -> Self {
        VBuffer {
            parts: [Part::EMPTY; 4],
        }
    }
}

impl VBuffer {
    /// Occluded fraction of the whole light, `Σ A_k / 4`, clamped to `[0, 1]`.
    pub fn occlusion(&self) -> f64 {
        (self.parts.iter().map(|p| p.area).sum::<f64>() / (4.0 * PART_AREA)).clamp(0.0, 1.0)
    }

    /// Blends the silhouette buffer `s` into `self` (Forest et al. 2006, section 3.2).
    pub fn blend(&mut self, s: &VBuffer) {
        for (f, s) in self.parts.iter_mut().zip(&s.parts) {
            *f = blend_part(f, s);
        }
    }
}

/// Forest et al.'s blending function for one radial part.
pub fn blend_part(f: &Part, s: &Part) -> Part {
    if s.area <= 0.0 {
        return *f;
    }
    if f.area <= 0.0 {
        return *s;
    }
    let (bf, bs) = (f.rect.area(), s.rect.area());
    let beta = f.rect.intersection(&s.rect).area();
    let eps = if bf > 0.0 && bs > 0.0 {
        (f.area / bf) * (s.area / bs) * beta
    } else {
        0.0
    };
    Part {
        area: (f.area + s.area - eps).clamp(0.0, PART_AREA),
        rect: f.rect.union(&s.rect),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    fn part(area: f64, min: [f64; 2], max: [f64; 2]) -> Part {
        Part {
            area,
            rect: Rect {
                min: DVec2::from(min),
                max: DVec2::from(max),
            },
        }
    }

    #[test]
    fn disjoint_rectangles_add() {
        let b = blend_part(
            &part(0.2, [0., 0.], [0.5, 0.5]),
            &part(0.1, [0.6, 0.], [1., 0.5]),
        );
        assert!((b.area - 0.3).abs() < 1e-15);
        assert_eq!(b.rect.min, DVec2::new(0., 0.));
        assert_eq!(b.rect.max, DVec2::new(1., 0.5));
    }

    #[test]
    fn identical_full_rectangles_count_once() {
        // Both fill the same rectangle completely: eps = 1 · 1 · |B| removes the double count.
        let p = part(0.25, [0., 0.], [0.5, 0.5]);
        assert!((blend_part(&p, &p).area - 0.25).abs() < 1e-15);
    }

    #[test]
    fn partial_fill_follows_the_formula() {
        let f = part(0.1, [0., 0.], [0.5, 0.5]); // fill 0.4
        let s = part(0.05, [0.25, 0.], [0.75, 0.5]); // fill 0.2, beta = 0.125
        let want = 0.1 + 0.05 - 0.4 * 0.2 * 0.125;
        assert!((blend_part(&f, &s).area - want).abs() < 1e-15);
    }

    #[test]
    fn zero_occlusion_is_skipped() {
        let f = part(0.1, [0., 0.], [0.5, 0.5]);
        assert_eq!(blend_part(&f, &Part::EMPTY), f);
        assert_eq!(blend_part(&Part::EMPTY, &f), f);
    }
}
