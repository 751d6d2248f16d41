//! Depth-complexity sampling is exact for its samples: with the reference's jittered points it
//! gives the reference's image, pixel for pixel, on every fixture.
//!
//! The two can differ only where a sample lies within rounding of a projected edge (the
//! reference casts `f32` rays) or where the reference's start offset hides a triangle crossed
//! right next to the receiver: at most a couple of samples, on a few pixels. So: equal on at
//! least 99.9% of pixels, and off by at most two samples (`2/N`) anywhere.

use penumbra::geom::VisibilityImage;
use penumbra::geom::{LightSamples, Reference};
use penumbra::geom::{LitScene, Scene};
use penumbra::volumes::{DepthComplexity, SamplePattern};

use crate::common::{fixture_names, load_lit};

/// Renders `scene` both ways with `samples` jittered samples; returns the pixels that differ as
/// `(x, y, depth complexity, reference)`, and the number of pixels.
fn differences(scene: &LitScene, samples: usize) -> (Vec<(u32, u32, f32, f32)>, usize) {
    let per_axis = (samples as f64).sqrt() as usize;
    assert_eq!(per_axis * per_axis, samples);
    let dc = DepthComplexity::new(scene);
    let got = dc.render(
        SamplePattern {
            per_axis,
            jitter: true,
        },
        &|_| {},
    );
    let want = Reference::new(scene).render(LightSamples::Stratified { per_axis }, &|_| {});
    (diff(&got, &want), got.data.len())
}

fn diff(got: &VisibilityImage, want: &VisibilityImage) -> Vec<(u32, u32, f32, f32)> {
    let w = got.width;
    got.data
        .iter()
        .zip(&want.data)
        .enumerate()
        .filter(|(_, (a, b))| a != b)
        .map(|(k, (a, b))| (k as u32 % w, k as u32 / w, *a, *b))
        .collect()
}

fn check(name: &str, scene: &LitScene, samples: usize) {
    let (differ, pixels) = differences(scene, samples);
    let worst = differ
        .iter()
        .map(|d| (d.2 - d.3).abs())
        .fold(0.0f32, f32::max);
    println!(
        "{name:>18} at {samples:>4} samples: {} of {pixels} pixels differ, by at most {worst} ({:.2} samples)",
        differ.len(),
        worst * samples as f32
    );
    for d in differ.iter().take(8) {
        println!(
            "    pixel {},{}: depth complexity {}, reference {}",
            d.0, d.1, d.2, d.3
        );
    }
    assert!(
        differ.len() as f64 <= 1e-3 * pixels as f64,
        "{name}: {} pixels differ",
        differ.len()
    );
    assert!(
        worst <= 2.0 / samples as f32 + 1e-6,
        "{name}: off by {worst} somewhere"
    );
}

#[test]
fn depth_complexity_equals_the_reference_sample_for_sample_on_every_fixture() {
    for name in fixture_names() {
        check(&name, &load_lit(&name), 64);
    }
}

#[test]
fn depth_complexity_equals_the_256_sample_reference_on_three_fixtures() {
    for name in ["spheres-9x9", "nonmanifold", "sphere-over-plane"] {
        check(name, &load_lit(name), 256);
    }
}

#[test]
fn depth_complexity_equals_the_reference_on_the_scale_scene() {
    // Six real meshes, 209,388 triangles, a light as large as the group: tens of thousands of
    // potential silhouette edges near each penumbra point. At 160x120 (a quarter of its
    // pixels) and 64 samples, so that the reference's rays stay few.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/scale/scale.toml");
    let mut scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    scene.camera.width = 160;
    scene.camera.height = 120;
    check("scale", &scene.lit(0), 64);
}
