//! The metrics by which a visibility image is compared against a reference: error statistics
//! over all pixels and over the reference's penumbra, and a heat map of the difference.

use crate::image::{ImageError, VisibilityImage};

/// Lower and upper bound of "penumbra" in the reference image for [`compare`]: pixels with
/// `PENUMBRA.0 < V < PENUMBRA.1`.
pub const PENUMBRA: (f32, f32) = (0.02, 0.98);

/// Error threshold counted by [`Metrics::share_over`].
pub const ERROR_THRESHOLD: f32 = 0.05;

/// Error statistics of one set of pixels.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Metrics {
    /// Number of pixels measured.
    pub pixels: usize,
    /// Mean absolute error.
    pub mae: f64,
    /// Root mean square error.
    pub rmse: f64,
    /// 99th percentile of the absolute error (nearest rank).
    pub p99: f64,
    /// Largest absolute error.
    pub max: f64,
    /// Share of pixels whose absolute error exceeds [`ERROR_THRESHOLD`].
    pub share_over: f64,
    /// Share of pixels whose values are identical (error 0).
    pub equal: f64,
}

impl Metrics {
    /// Statistics of absolute errors.
    pub fn of(mut errors: Vec<f64>) -> Self {
        if errors.is_empty() {
            return Metrics::default();
        }
        let n = errors.len();
        let mae = errors.iter().sum::<f64>() / n as f64;
        let rmse = (errors.iter().map(|e| e * e).sum::<f64>() / n as f64).sqrt();
        let over = errors
            .iter()
            .filter(|&&e| e > ERROR_THRESHOLD as f64)
            .count();
        let equal = errors.iter().filter(|&&e| e == 0.0).count();
        errors.sort_by(f64::total_cmp);
        let rank = ((0.99 * n as f64).ceil() as usize).clamp(1, n) - 1;
        Metrics {
            pixels: n,
            mae,
            rmse,
            p99: errors[rank],
            max: errors[n - 1],
            share_over: over as f64 / n as f64,
            equal: equal as f64 / n as f64,
        }
    }
}

/// The comparison of an image `a` against a reference `b`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Comparison {
    /// Over all pixels.
    pub all: Metrics,
    /// Over the penumbra pixels of `b`, `0.02 < V_b < 0.98`.
    pub penumbra: Metrics,
    /// Mean of `V_a - V_b` over the penumbra pixels of `b`: negative where `a` is too dark.
    pub penumbra_signed: f64,
    /// The umbra pixels of `b`, `V_b <= 0.02`.
    pub umbra_pixels: usize,
    /// The share of them that `a` shows lit, `V_a > 0.5`: shadows lost.
    pub umbra_lit: f64,
}

/// Compares `a` against the reference `b`: all pixels, and penumbra pixels of `b` alone.
///
/// ```
/// use penumbra::geom::{VisibilityImage, compare};
///
/// let truth = VisibilityImage { width: 2, height: 1, data: vec![0.5, 1.0] };
/// let test = VisibilityImage { width: 2, height: 1, data: vec![0.6, 1.0] };
/// let c = compare(&test, &truth)?;
/// assert_eq!(c.penumbra.pixels, 1); // 0.02 < V < 0.98 in the reference
/// assert!((c.all.mae - 0.05).abs() < 1e-6);
/// # Ok::<(), penumbra::geom::ImageError>(())
/// ```
pub fn compare(a: &VisibilityImage, b: &VisibilityImage) -> Result<Comparison, ImageError> {
    if (a.width, a.height) != (b.width, b.height) {
        return Err(ImageError::SizeMismatch {
            a: (a.width, a.height),
            b: (b.width, b.height),
        });
    }
    a.check()?;
    b.check()?;
    let mut all = Vec::with_capacity(a.data.len());
    let mut pen = Vec::new();
    let (mut signed, mut umbra, mut lit) = (0.0, 0usize, 0usize);
    for (&x, &y) in a.data.iter().zip(&b.data) {
        let e = (x as f64 - y as f64).abs();
        all.push(e);
        if y > PENUMBRA.0 && y < PENUMBRA.1 {
            pen.push(e);
            signed += x as f64 - y as f64;
        } else if y <= PENUMBRA.0 {
            umbra += 1;
            lit += usize::from(x > 0.5);
        }
    }
    Ok(Comparison {
        all: Metrics::of(all),
        penumbra_signed: signed / pen.len().max(1) as f64,
        penumbra: Metrics::of(pen),
        umbra_pixels: umbra,
        umbra_lit: lit as f64 / umbra.max(1) as f64,
    })
}

/// An RGB heat map of `|a - b|`: black for no error, through red and yellow to white at an
/// error of `full_scale` or more.
pub fn heatmap(a: &VisibilityImage, b: &VisibilityImage, full_scale: f32) -> Vec<u8> {
    a.data
        .iter()
        .zip(&b.data)
        .flat_map(|(&x, &y)| {
            let e = ((x - y).abs() / full_scale).clamp(0.0, 1.0) * 3.0;
            let r = e.min(1.0);
            let g = (e - 1.0).clamp(0.0, 1.0);
            let b = (e - 2.0).clamp(0.0, 1.0);
            [r, g, b].map(|c| (c * 255.0 + 0.5) as u8)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn metrics_by_hand() {
        let m = Metrics::of(vec![0.0, 0.1, 0.0, 0.02]);
        assert!((m.mae - 0.03).abs() < 1e-12);
        assert!((m.share_over - 0.25).abs() < 1e-12);
        assert_eq!(m.p99, 0.1);
        let a = VisibilityImage {
            width: 2,
            height: 1,
            data: vec![0.5, 1.0],
        };
        let b = VisibilityImage {
            width: 2,
            height: 1,
            data: vec![0.4, 1.0],
        };
        let c = compare(&a, &b).unwrap();
        assert_eq!(c.penumbra.pixels, 1);
        assert!((c.penumbra.mae - 0.1).abs() < 1e-6);
        assert!((c.all.mae - 0.05).abs() < 1e-6);
    }
}
