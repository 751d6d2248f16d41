//! Visibility buffers and Forest et al.'s blending of a silhouette's buffer into the final one.
//!
//! A buffer holds, per radial part of the light (see [`crate::clip::RADIAL_PARTS`]), the occluded
//! area `A` (light-space units; each part has area 1) and a rectangle `B` bounding the occluded
//! region. Blending a silhouette buffer `s` into the final buffer `f` (Forest, Barthe & Paulin
//! 2006, section 3.2) estimates how much of the two occluded regions overlap. The paper assumes
//! each region spread evenly over its rectangle, `eps = (A_f / |B_f|) · (A_s / |B_s|) · |B_f ∩
//! B_s|`, which counts two coinciding regions that fill part of their rectangle (the near and
//! far sides of an open body, seen from the light) nearly twice. Here each region is instead
//! gathered into its core, the rectangle of area `A` with `B`'s centre and proportions:
//!
//! ```text
//! core = B scaled by sqrt(A / |B|) about its centre
//! eps  = |core_f ∩ core_s|,     A = A_f + A_s - eps,     B = B_f ∪ B_s
//! ```
//!
//! skipped where either occlusion is zero. Regions that fill their rectangles blend as in the
//! paper; coinciding regions count once; a small region in a corner of a large one's rectangle
//! overlaps it only where the cores meet.

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

/// The blending function for one radial part: Forest et al.'s, with the overlap of the two
/// regions' cores (module documentation).
pub fn blend_part(f: &Part, s: &Part) -> Part {
    if s.area <= 0.0 {
        return *f;
    }
    if f.area <= 0.0 {
        return *s;
    }
    let eps = if f.rect.area() > 0.0 && s.rect.area() > 0.0 {
        core(f)
            .intersection(&core(s))
            .area()
            .min(f.area)
            .min(s.area)
    } else {
        0.0
    };
    Part {
        area: (f.area + s.area - eps).clamp(0.0, PART_AREA),
        rect: f.rect.union(&s.rect),
    }
}

/// The part's core: its rectangle scaled about its centre to the part's occluded area.
fn core(p: &Part) -> Rect {
    let k = (p.area / p.rect.area()).clamp(0.0, 1.0).sqrt();
    let half = (p.rect.max - p.rect.min) * (0.5 * k);
    let c = p.rect.centre();
    Rect {
        min: c - half,
        max: c + half,
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
    fn partial_fill_overlaps_by_the_cores() {
        // f fills 0.4 of its rectangle: its core is the centred square of half side
        // 0.25 √0.4; s fills 0.2 of its own: a square of half side 0.25 √0.2 at (0.5, 0.25).
        let f = part(0.1, [0., 0.], [0.5, 0.5]);
        let s = part(0.05, [0.25, 0.], [0.75, 0.5]);
        let (hf, hs) = (0.25 * 0.4f64.sqrt(), 0.25 * 0.2f64.sqrt());
        let overlap = ((0.25 + hf) - (0.5 - hs)) * (2.0 * hs);
        let b = blend_part(&f, &s);
        assert!((b.area - (0.15 - overlap)).abs() < 1e-15, "{}", b.area);
    }

    #[test]
    fn coincident_partial_regions_count_once() {
        // The near and far sides of an open body: the same region twice. The even spread of
        // Forest et al. would give 0.1 + 0.1 - 0.4 · 0.4 · 0.25 = 0.16.
        let p = part(0.1, [0., 0.], [0.5, 0.5]);
        assert!((blend_part(&p, &p).area - 0.1).abs() < 1e-15);
    }

    #[test]
    fn small_regions_in_far_corners_do_not_overlap() {
        // Overlapping rectangles whose small cores lie apart.
        let f = part(0.01, [0., 0.], [0.5, 0.5]);
        let s = part(0.01, [0.3, 0.], [0.8, 0.5]);
        assert!((blend_part(&f, &s).area - 0.02).abs() < 1e-15);
    }

    #[test]
    fn zero_occlusion_is_skipped() {
        let f = part(0.1, [0., 0.], [0.5, 0.5]);
        assert_eq!(blend_part(&f, &Part::EMPTY), f);
        assert_eq!(blend_part(&Part::EMPTY, &f), f);
    }
}
