//! The shadow-map techniques on every fixture, real meshes included, at their default
//! parameters, against the exact depth-complexity image at 256 light samples (the reference's
//! accuracy, several times faster): how much of the umbra (V <= 0.02) each leaves lit (V > 0.5),
//! and `pcss`'s penumbra error. They need an adapter (lavapipe in CI), as `gpu.rs` does.

mod common;
use common::{context, fixtures};

use penumbra_geom::Technique;
use penumbra_geom::image::compare;
use penumbra_gpu::ShadowMapRenderer;
use penumbra_volumes::{DepthComplexity, SamplePattern};

/// Most of the umbra a technique may leave lit.
const UMBRA_LIT: f64 = 0.02;

/// `pcss`'s largest penumbra mean absolute error.
const PCSS_PENUMBRA_MAE: f64 = 0.13;

/// The (technique, fixture) pairs above `UMBRA_LIT`, with the share they are held to: thin
/// creases of beetle's open body, where the maps' depth bias lets light through a sheet that
/// folds in front of the receiver, for every technique; parts of a closed mesh shadowing another
/// part close behind them for `fractional-disk` (7.7% on cheburashka, 3.3% on spot: the midpoint
/// of its two maps still lies within the bias there); a crease of spot for `mdsm`. These are the
/// open part of the work: the bounds keep them from getting worse.
const KNOWN: [(Technique, &str, f64); 7] = [
    (Technique::Pcf, "beetle", 0.07),
    (Technique::Pcss, "beetle", 0.065),
    (Technique::Mdsm, "beetle", 0.13),
    (Technique::Mdsm, "spot", 0.03),
    (Technique::FractionalDisk, "beetle", 0.095),
    (Technique::FractionalDisk, "cheburashka", 0.085),
    (Technique::FractionalDisk, "spot", 0.04),
];

#[test]
fn shadow_maps_keep_their_umbrae_and_pcss_its_penumbrae_on_every_fixture() {
    let Some(ctx) = context() else { return };
    let techniques = [
        Technique::Pcf,
        Technique::Pcss,
        Technique::Mdsm,
        Technique::FractionalDisk,
    ];
    let renderers: Vec<_> = techniques
        .iter()
        .map(|&t| ShadowMapRenderer::new(&ctx, t))
        .collect();
    let pattern = SamplePattern {
        per_axis: 16,
        jitter: false,
    };
    let mut failures = Vec::new();
    for (name, scene) in fixtures() {
        let truth = DepthComplexity::new(&scene).render(&scene, pattern, &|_| {});
        for r in &renderers {
            let t = r.technique();
            let img = r.render(&scene).unwrap();
            let c = compare(&img, &truth).unwrap();
            let bound = KNOWN
                .iter()
                .find(|k| k.0 == t && k.1 == name)
                .map_or(UMBRA_LIT, |k| k.2);
            println!(
                "{name:>18} {t:<16} umbra {:>5} px, {:.2}% lit (bound {:.1}%); penumbra MAE {:.4}",
                c.umbra_pixels,
                100.0 * c.umbra_lit,
                100.0 * bound,
                c.penumbra.mae
            );
            if c.umbra_lit > bound {
                failures.push(format!(
                    "{name} {t}: {:.2}% of the umbra lit",
                    100.0 * c.umbra_lit
                ));
            }
            if t == Technique::Pcss && c.penumbra.mae > PCSS_PENUMBRA_MAE {
                failures.push(format!("{name} pcss: penumbra MAE {:.4}", c.penumbra.mae));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
