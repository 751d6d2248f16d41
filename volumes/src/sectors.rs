//! One receiver point's light samples sorted by their angle around the light's centre, so that
//! an edge's region, which lies in the cone from the centre over the edge's projection (two of
//! its four lines pass through the centre, `region.rs`), reads only the samples of the
//! sectors that cone spans instead of every sample of its bounding box.
//!
//! The angle is the "diamond angle" `p(x, y)` in `[0, 4)`, a monotone function of the polar
//! angle with no trigonometry: `y / (x + y)` in the first quadrant, continued quadrant by
//! quadrant. `B = 2 N` sectors of equal `p`-width for `N` samples are filled by a counting
//! sort. A cone's sectors are those its two bounding rays span, widened by a margin of `1e-4`
//! in `p` (at least `1e-4` radians), far beyond the `f32` rounding of the lines' coefficients
//! and of the samples (about `1e-7` radians), so that the sectors hold every sample the exact
//! test can find inside. Samples within [`NEAR_CENTRE`] of the centre, whose angle that
//! rounding could turn, are read by every cone.

use glam::{DVec2, DVec3};

/// Samples closer than this to the light's centre (light-space units, the light's half side
/// being 1) belong to no sector and are read by every region.
pub const NEAR_CENTRE: f64 = 1e-3;

/// Widening of a cone's `p` range on each side.
const MARGIN: f64 = 1e-4;

/// The diamond angle of `(x, y) != 0`, in `[0, 4)`, increasing counter-clockwise from the `+x`
/// axis.
#[inline]
pub fn diamond_angle(x: f64, y: f64) -> f64 {
    if y >= 0.0 {
        if x >= 0.0 {
            y / (x + y)
        } else {
            1.0 - x / (y - x)
        }
    } else if x < 0.0 {
        2.0 - y / (-x - y)
    } else {
        3.0 + x / (x - y)
    }
}

/// The samples of one point, sorted by sector; `xs[k], ys[k]` is sample `k` in that order.
#[derive(Default)]
pub struct Sectors {
    /// Sample `x` coordinates in `f32`, in sector order, the near-centre ones last.
    pub xs: Vec<f32>,
    /// Sample `y` coordinates in `f32`, in the same order.
    pub ys: Vec<f32>,
    /// `start[b]..start[b + 1]` are the samples of sector `b`; `start[B]` is where the
    /// near-centre samples begin.
    start: Vec<u32>,
    bucket: Vec<u32>,
}

impl Sectors {
    /// Sorts the samples `(xs[k], ys[k])` (in `[-1, 1]^2`) into two sectors per sample: the thin cone of a short
    /// edge then reads one sample or two.
    pub fn fill(&mut self, xs: &[f32], ys: &[f32]) {
        let sectors = (xs.len() * 2).max(1);
        let scale = sectors as f64 / 4.0;
        self.start.clear();
        self.start.resize(sectors + 2, 0);
        self.bucket.clear();
        // The samples' angles in `f32`: their
        // rounding, about 1e-7, is far inside the cones' margin.
        let (scale32, near2) = (scale as f32, (NEAR_CENTRE * NEAR_CENTRE) as f32);
        let last = (sectors - 1) as f32;
        self.bucket.extend(xs.iter().zip(ys).map(|(&x, &y)| {
            let r = y / (x.abs() + y.abs());
            let p = if x < 0.0 {
                2.0 - r
            } else if y < 0.0 {
                4.0 + r
            } else {
                r
            };
            if x * x + y * y < near2 {
                sectors as u32
            } else {
                (p * scale32).min(last) as u32
            }
        }));
        for &b in &self.bucket {
            self.start[b as usize + 1] += 1;
        }
        // The running sum in a register: adding each entry to the one before it in memory waited
        // for that store every step (two thirds of this function's time at 4096 samples).
        let mut total = 0;
        for s in &mut self.start {
            total += *s;
            *s = total;
        }
        self.xs.clear();
        self.xs.resize(xs.len(), 0.0);
        self.ys.clear();
        self.ys.resize(xs.len(), 0.0);
        // `next` runs through `start` shifted by one: after the scatter, `start[b]` again
        // begins sector `b`.
        let mut next = std::mem::take(&mut self.start);
        for ((&x, &y), &b) in xs.iter().zip(ys).zip(&self.bucket) {
            let at = next[b as usize] as usize;
            self.xs[at] = x;
            self.ys[at] = y;
            next[b as usize] += 1;
        }
        next.rotate_right(1);
        next[0] = 0;
        self.start = next;
    }

    /// Number of sectors, `B`.
    fn sectors(&self) -> usize {
        self.start.len() - 2
    }

    /// The near-centre samples, which every non-empty cone reads besides its runs.
    pub fn near(&self) -> std::ops::Range<usize> {
        self.start[self.sectors()] as usize..self.xs.len()
    }

    /// The ranges of sample indices that may lie in the open cone `k0 . s > 0, k1 . s > 0`
    /// (`k0`, `k1` the `x`, `y` coefficients of two lines through the centre): one or two runs
    /// of sectors (the second empty when there is one), to be read with the near-centre
    /// samples ([`Sectors::near`]). `None` for an empty cone, which reads no sample.
    pub fn cone_runs(&self, k0: DVec3, k1: DVec3) -> Option<[std::ops::Range<u32>; 2]> {
        let (k0, k1) = (k0.truncate(), k1.truncate());
        // The half-plane `k . s > 0` spans the directions from `k` turned by -90 degrees to `k`
        // turned by +90; the cone runs from the later start to the earlier end.
        let (c, d) = (k0.perp_dot(k1), k0.dot(k1));
        let minus = |k: DVec2| DVec2::new(k.y, -k.x);
        let plus = |k: DVec2| DVec2::new(-k.y, k.x);
        let (from, to) = if k0 == DVec2::ZERO || k1 == DVec2::ZERO || (c == 0.0 && d <= 0.0) {
            // A line with no slope holds no sample (`0 > 0`), as do opposite half-planes.
            return None;
        } else if c == 0.0 {
            (minus(k0), plus(k0))
        } else if c > 0.0 {
            (minus(k1), plus(k0))
        } else {
            (minus(k0), plus(k1))
        };
        let b = self.sectors();
        let scale = b as f64 / 4.0;
        let mut p0 = diamond_angle(from.x, from.y) - MARGIN;
        let mut p1 = diamond_angle(to.x, to.y) + MARGIN;
        if p0 < 0.0 {
            p0 += 4.0;
        }
        if p1 >= 4.0 {
            p1 -= 4.0;
        }
        let sector = |p: f64| ((p * scale) as usize).min(b - 1);
        let (s0, s1) = (sector(p0), sector(p1));
        let run = |a: usize, z: usize| self.start[a]..self.start[z + 1];
        Some(if p0 <= p1 {
            [run(s0, s1), 0..0]
        } else {
            [run(s0, b - 1), run(0, s1)]
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_diamond_angle_grows_with_the_polar_angle() {
        let mut last = -1.0;
        for k in 0..3600 {
            let t = (k as f64 + 0.5) * std::f64::consts::TAU / 3600.0;
            let p = diamond_angle(t.cos(), t.sin());
            assert!(p > last && (0.0..4.0).contains(&p), "{t}: {p}");
            last = p;
        }
    }

    #[test]
    fn a_cone_s_sectors_hold_every_sample_inside_it() {
        // Random cones and random samples: every sample inside a cone (by the f32 test the
        // regions make) is in one of the ranges.
        let mut rng = penumbra_geom::Rng::stream(7, 0);
        let mut u = || 2.0 * rng.next_f64() - 1.0;
        let points: Vec<DVec2> = (0..256)
            .map(|_| DVec2::new(u(), u()))
            .chain([DVec2::ZERO, DVec2::new(1e-4, -2e-4), DVec2::new(0.0, 0.5)])
            .collect();
        let mut s = Sectors::default();
        let xs: Vec<f32> = points.iter().map(|q| q.x as f32).collect();
        let ys: Vec<f32> = points.iter().map(|q| q.y as f32).collect();
        s.fill(&xs, &ys);
        assert_eq!(s.xs.len(), points.len());
        let mut checked = 0;
        for _ in 0..2000 {
            let k0 = DVec3::new(u(), u(), 0.0);
            let k1 = if u() > 0.9 {
                -k0
            } else {
                DVec3::new(u(), u(), 0.0)
            };
            let mut listed = vec![false; points.len()];
            if let Some(runs) = s.cone_runs(k0, k1) {
                for r in runs.iter().map(|r| r.start as usize..r.end as usize) {
                    r.for_each(|i| listed[i] = true);
                }
                s.near().for_each(|i| listed[i] = true);
            }
            for ((&x, &y), &listed) in s.xs.iter().zip(&s.ys).zip(&listed) {
                let at = |k: DVec3| k.x as f32 * x + k.y as f32 * y;
                if at(k0) > 0.0 && at(k1) > 0.0 {
                    assert!(listed, "sample ({x}, {y}) in the cone {k0} {k1} not listed");
                    checked += 1;
                }
            }
        }
        assert!(checked > 10_000, "{checked}");
    }
}
