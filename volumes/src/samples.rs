//! The light samples of depth-complexity sampling: `N x N` points of the light square
//! `[-1, 1]^2`, one in each cell of an `N x N` grid (sample `j * N + i` in cell `(i, j)`), placed
//! per camera pixel in one of two ways:
//!
//! - **correlated multi-jittered** (the default; Kensler, "Correlated Multi-Jittered
//!   Sampling", Pixar technical memo 13-01, 2013): besides one point per cell, one point in each
//!   of the `N²` columns and `N²` rows of the fine grid, so that an edge parallel to a side of
//!   the light sweeps the samples one at a time rather than a row at once. The pattern is a
//!   function of the pixel index through 32-bit integer hashes: reproducible, and cheap on a
//!   GPU. Cell centres, the plain grid, alias against such edges: on the fixtures whose
//!   occluders' edges run along the light's sides, their penumbra error was 1.9 to 2.9 times
//!   the reference's at the same sample count (`docs/accuracy.md`).
//! - **jittered** (`--jitter`): one uniform point per cell from the reference's per-pixel
//!   stream, the very points of [`penumbra_geom::Tracer::sampled_visibility`], so that the
//!   two images can be compared sample for sample.

use glam::DVec2;
use penumbra_geom::REFERENCE_SEED;
use penumbra_geom::{RectLight, Rng};

/// Where the `N x N` light samples lie.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SamplePattern {
    /// Samples per axis, `N`.
    pub per_axis: usize,
    /// The reference's jittered points instead of the correlated multi-jittered ones.
    pub jitter: bool,
}

impl SamplePattern {
    /// The pattern's points for camera pixel `pixel` (`y * width + x`), in `[-1, 1]^2`, row by
    /// row: sample `j * N + i` lies in cell `(i, j)`.
    pub fn points(&self, pixel: u64, out: &mut Vec<DVec2>) {
        out.clear();
        if self.jitter {
            let mut rng = Rng::stream(REFERENCE_SEED, pixel);
            out.extend(RectLight::stratified_samples(self.per_axis, &mut rng));
        } else {
            out.resize(self.per_axis * self.per_axis, DVec2::ZERO);
            self.each_multi_jittered(pixel, |k, x, y| out[k] = DVec2::new(x, y));
        }
    }

    /// [`SamplePattern::points`] rounded to `f32`, their `x` in `xs` and `y` in `ys`.
    pub(crate) fn points_f32(&self, pixel: u64, xs: &mut Vec<f32>, ys: &mut Vec<f32>) {
        xs.clear();
        ys.clear();
        if self.jitter {
            let mut rng = Rng::stream(REFERENCE_SEED, pixel);
            for q in RectLight::stratified_samples(self.per_axis, &mut rng) {
                xs.push(q.x as f32);
                ys.push(q.y as f32);
            }
        } else {
            let n = self.per_axis * self.per_axis;
            xs.resize(n, 0.0);
            ys.resize(n, 0.0);
            let (xs, ys) = (&mut xs[..n], &mut ys[..n]);
            self.each_multi_jittered(pixel, |k, x, y| {
                xs[k] = x as f32;
                ys[k] = y as f32;
            });
        }
    }

    /// Calls `f(k, x, y)` for the `k`-th correlated multi-jittered point `(x, y)` of `pixel`,
    /// `k` from 0 to `N² - 1` in the order of [`SamplePattern::points`].
    #[inline(always)]
    fn each_multi_jittered(&self, pixel: u64, mut f: impl FnMut(usize, f64, f64)) {
        let n = self.per_axis;
        let cell = 2.0 / n as f64;
        let seed = (pixel ^ (pixel >> 32)) as u32;
        let m = n as u32;
        let fine = 1.0 / n as f64;
        // The fine column within cell (i, j) is a permutation of the row index j, the fine
        // row one of the column index i: one point per fine row and column.
        // The row permutation, on the stack for up to 256 per axis (65,536 samples).
        let mut rows_stack = [0u32; 256];
        let mut rows_heap = Vec::new();
        let rows: &mut [u32] = if n <= 256 {
            &mut rows_stack[..n]
        } else {
            rows_heap.resize(n, 0);
            &mut rows_heap
        };
        for (i, r) in rows.iter_mut().enumerate() {
            *r = permute(i as u32, m, seed.wrapping_mul(0xa511_e9b3));
        }
        for j in 0..m {
            let sx = permute(j, m, seed.wrapping_mul(0x63d8_3595));
            for (i, &sy) in rows.iter().enumerate() {
                let s = j * m + i as u32;
                // Both jitters from one hash, 16 bits each: a 65,536th of a fine cell.
                let h = hash(s, seed.wrapping_mul(0xa399_d265));
                let jx = (h & 0xffff) as f64 / 65_536.0;
                let jy = (h >> 16) as f64 / 65_536.0;
                let x = (i as f64 + (sx as f64 + jx) * fine) * cell;
                let y = (j as f64 + (sy as f64 + jy) * fine) * cell;
                f(s as usize, -1.0 + x, -1.0 + y);
            }
        }
    }
}

/// A permutation of `0..l` chosen by `p`, applied to `i` (Kensler 2013, listing 3: a
/// hash that is a bijection on the next power of two, cycle-walked into `0..l`).
fn permute(mut i: u32, l: u32, p: u32) -> u32 {
    let mut w = l - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    loop {
        i ^= p;
        i = i.wrapping_mul(0xe170_893d);
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i = i.wrapping_mul(0x0929_eb3f);
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i = i.wrapping_mul(1 | p >> 27);
        i = i.wrapping_mul(0x6935_fa69);
        i ^= (i & w) >> 11;
        i = i.wrapping_mul(0x74dc_b303);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0x9e50_1cc3);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0xc860_a3df);
        i &= w;
        i ^= i >> 5;
        if i < l {
            return (i + p) % l;
        }
    }
}

/// 32 bits hashed from `i` and `p` (Kensler 2013, listing 4, which divides them by 2^32 for
/// one jitter; here they serve both).
fn hash(mut i: u32, p: u32) -> u32 {
    i ^= p;
    i ^= i >> 17;
    i ^= i >> 10;
    i = i.wrapping_mul(0xb365_34e5);
    i ^= i >> 12;
    i ^= i >> 21;
    i = i.wrapping_mul(0x93fc_4795);
    i ^= 0xdf6e_307f;
    i ^= i >> 17;
    i.wrapping_mul(1 | p >> 18)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jittered_points_are_the_references() {
        let pattern = SamplePattern {
            per_axis: 4,
            jitter: true,
        };
        let mut got = Vec::new();
        pattern.points(77, &mut got);
        let mut rng = Rng::stream(REFERENCE_SEED, 77);
        let want = RectLight::stratified_samples(4, &mut rng);
        assert_eq!(got, want);
    }

    #[test]
    fn multi_jittered_points_fill_every_cell_and_every_fine_row_and_column_once() {
        for (n, pixel) in [
            (4usize, 0u64),
            (16, 77),
            (16, 76_799),
            (7, 1 << 40),
            (32, 5),
        ] {
            let pattern = SamplePattern {
                per_axis: n,
                jitter: false,
            };
            let mut pts = Vec::new();
            pattern.points(pixel, &mut pts);
            assert_eq!(pts.len(), n * n);
            let fine = |x: f64| ((x + 1.0) / 2.0 * (n * n) as f64) as usize;
            let (mut cols, mut rows) = (vec![0; n * n], vec![0; n * n]);
            for (k, p) in pts.iter().enumerate() {
                assert!(p.x > -1.0 && p.x < 1.0 && p.y > -1.0 && p.y < 1.0, "{p}");
                // Sample j * n + i in cell (i, j).
                assert_eq!((fine(p.x) / n, fine(p.y) / n), (k % n, k / n), "n {n}: {p}");
                cols[fine(p.x)] += 1;
                rows[fine(p.y)] += 1;
            }
            assert!(cols.iter().chain(&rows).all(|&c| c == 1), "n {n}");
        }
        // Another pixel, another pattern.
        let pattern = SamplePattern {
            per_axis: 16,
            jitter: false,
        };
        let (mut a, mut b) = (Vec::new(), Vec::new());
        pattern.points(1, &mut a);
        pattern.points(2, &mut b);
        assert_ne!(a, b);
    }
}
