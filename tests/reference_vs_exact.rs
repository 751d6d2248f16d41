//! On every fixture, the exact evaluator and the 4096-sample reference agree at 200 random
//! pixels within the sampling error.
//!
//! The bound: the reference at a pixel is `(1/N) Σ_k X_k`, one Bernoulli `X_k` per stratum `k`
//! of the light, independent across strata, with `Σ_k E[X_k] = N·V`. Its variance is
//! `(1/N²) Σ_k p_k(1 - p_k) <= V(1 - V)/N` (stratification never adds variance to plain Monte
//! Carlo: by Jensen, `Σ p_k² >= N·V²`). So `σ <= sqrt(V(1 - V)/N) <= 1/(2·64)` for `N = 4096`.
//! We allow `5σ + 1/N` per pixel: a false failure has probability below 1e-6 per pixel (the
//! count is a sum of many independent strata, close to normal), about 1e-3 over the 1600 pixels
//! of all fixtures, and the seed is fixed, so a pass is reproducible; the `1/N` covers a single
//! sample lost to the shadow rays' start offset. The mean signed difference over the 200 pixels
//! must also stay within 5 standard errors of zero, which catches a bias far smaller than any
//! single-pixel bound.

use penumbra::geom::Rng;
use penumbra::geom::{REFERENCE_SEED, Tracer};
use rayon::prelude::*;

use crate::common::{fixture_names, load_lit};

const N_PER_AXIS: usize = 64;
const PIXELS: usize = 200;

#[test]
fn exact_and_4096_sample_reference_agree_on_every_fixture() {
    let n = (N_PER_AXIS * N_PER_AXIS) as f64;
    for name in fixture_names() {
        let scene = load_lit(&name);
        let tracer = Tracer::new(&scene);
        let cam = scene.camera;
        // 200 random pixels whose ray hits the scene (a miss is V = 1 by definition for both).
        let mut rng = Rng::new(0xF1A7 ^ name.len() as u64);
        let mut points = Vec::new();
        while points.len() < PIXELS {
            let (i, j) = (
                rng.below(cam.width as usize) as u32,
                rng.below(cam.height as usize) as u32,
            );
            if let Some(p) = tracer.surface_point(cam.eye, cam.ray_dir(i, j)) {
                points.push((i, j, p));
            }
        }
        let results: Vec<(f64, f64)> = points
            .par_iter()
            .map(|(i, j, p)| {
                let exact = tracer.exact_visibility(p);
                let pixel = *j as u64 * cam.width as u64 + *i as u64;
                let mut rng = Rng::stream(REFERENCE_SEED, pixel);
                (exact, tracer.sampled_visibility(p, N_PER_AXIS, &mut rng))
            })
            .collect();
        let mut sum = 0.0;
        let mut var = 0.0;
        let mut worst_sigmas: f64 = 0.0;
        let mut penumbra = 0;
        for (k, &(exact, sampled)) in results.iter().enumerate() {
            assert!(
                exact.is_finite() && (0.0..=1.0).contains(&exact),
                "{name}: exact V {exact}"
            );
            let sigma = (exact * (1.0 - exact) / n).sqrt();
            let (i, j, p) = &points[k];
            assert!(
                (exact - sampled).abs() <= 5.0 * sigma + 1.0 / n,
                "{name}: pixel {i},{j} at {}: exact {exact}, reference {sampled}, sigma {sigma}",
                p.position
            );
            if sigma > 0.0 {
                worst_sigmas = worst_sigmas.max((exact - sampled).abs() / sigma);
                penumbra += 1;
            }
            sum += sampled - exact;
            var += exact * (1.0 - exact) / n;
        }
        let mean = sum / PIXELS as f64;
        let se = var.sqrt() / PIXELS as f64;
        println!(
            "{name:>18}: {penumbra:>3} penumbra pixels, worst |diff| = {worst_sigmas:.2} sigma, mean diff {mean:+.2e} (se {se:.1e})"
        );
        assert!(mean.abs() <= 5.0 * se + 1.0 / n, "{name}: biased by {mean}");
    }
}
