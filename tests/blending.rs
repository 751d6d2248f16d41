//! Blending: `wedges-blend` against the additive wedges and the exact evaluator where penumbrae
//! overlap, and on the real meshes against the reference.

use penumbra::Technique;
use penumbra::geom::Rng;
use penumbra::geom::compare;
use penumbra::geom::{LightSamples, Reference};
use penumbra::volumes::CpuRenderer;
use rayon::prelude::*;

use crate::common::load_lit;

/// Mean absolute error of `wedges` and `wedges-blend` against the exact evaluator at penumbra
/// points seen by the camera.
fn overlap_errors(name: &str, points: usize) -> (f64, f64, usize) {
    let scene = load_lit(name);
    let r = CpuRenderer::new(&scene);
    let cam = scene.camera;
    let mut rng = Rng::new(31);
    let mut candidates = Vec::new();
    while candidates.len() < points * 6 {
        let (i, j) = (
            rng.below(cam.width as usize) as u32,
            rng.below(cam.height as usize) as u32,
        );
        if let Some(p) = r.tracer.surface_point(cam.eye, cam.ray_dir(i, j)) {
            candidates.push(p);
        }
    }
    let rows: Vec<(f64, f64, f64)> = candidates
        .par_iter()
        .map(|p| {
            (
                r.tracer.exact_visibility(p),
                r.visibility(p, Technique::Wedges),
                r.visibility(p, Technique::WedgesBlend),
            )
        })
        .collect();
    let pen: Vec<_> = rows
        .into_iter()
        .filter(|r| r.0 > 0.02 && r.0 < 0.98)
        .take(points)
        .collect();
    let n = pen.len() as f64;
    let mae =
        |f: fn(&(f64, f64, f64)) -> f64| pen.iter().map(|r| (f(r) - r.0).abs()).sum::<f64>() / n;
    (mae(|r| r.1), mae(|r| r.2), pen.len())
}

#[test]
fn blending_beats_additive_wedges_where_penumbrae_overlap() {
    for name in ["overlapping-quads", "spheres-9x9"] {
        let (w, b, n) = overlap_errors(name, 600);
        println!(
            "{name:>18}: penumbra MAE against exact over {n} points: wedges {w:.5}, wedges-blend {b:.5}"
        );
        assert!(n >= 300, "{name}: only {n} penumbra points");
        assert!(
            b < w,
            "{name}: blending ({b}) is not better than additive wedges ({w})"
        );
    }
}

/// Penumbra MAE of `wedges-blend` on the real-mesh fixtures with one visibility buffer per mesh
/// and the even spread of Forest et al. over the rectangles, before per-patch blending, the
/// tangent-plane cap and the cores (320x240, 1024-sample reference; docs/accuracy.md).
const PER_MESH_BLEND: [(&str, f64); 4] = [
    ("beetle", 0.0856),
    ("cheburashka", 0.0365),
    ("fandisk", 0.0916),
    ("spot", 0.0535),
];

#[test]
fn wedges_blend_on_real_meshes_is_within_0_6_of_blending_per_mesh() {
    for (name, before) in PER_MESH_BLEND {
        // A quarter of the pixels and 256 samples: the bound has room for the reference's noise
        // (about 0.006 over penumbra pixels).
        let mut scene = load_lit(name);
        scene.camera.width /= 2;
        scene.camera.height /= 2;
        let truth =
            Reference::new(&scene).render(LightSamples::Stratified { per_axis: 16 }, &|_| {});
        let img = CpuRenderer::new(&scene).render(Technique::WedgesBlend, &|_| {});
        let c = compare(&img, &truth).unwrap();
        println!(
            "{name:>12}: wedges-blend penumbra MAE {:.4} over {} pixels, per mesh {before}: {:.2}x",
            c.penumbra.mae,
            c.penumbra.pixels,
            c.penumbra.mae / before
        );
        assert!(c.penumbra.pixels > 1000, "{name}: too few penumbra pixels");
        assert!(
            c.penumbra.mae <= 0.6 * before,
            "{name}: penumbra MAE {} above 0.6 x {before}",
            c.penumbra.mae
        );
    }
}

#[test]
fn wedges_blend_is_exact_on_the_planar_real_mesh() {
    // Woody is one planar cut-out: one silhouette, exact for the wedges, whose error against the
    // reference image is that image's own noise.
    let (w, b, n) = overlap_errors("woody", 300);
    println!(
        "       woody: penumbra MAE against exact over {n} points: wedges {w:.2e}, wedges-blend {b:.2e}"
    );
    assert!(n >= 100, "woody: only {n} penumbra points");
    assert!(
        b <= 1e-6,
        "woody: wedges-blend {b} against the exact evaluator"
    );
}
