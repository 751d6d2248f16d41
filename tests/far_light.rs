//! A light far from the scene (the sun modelled as a rectangle): a quad over a ground under a
//! light 1e5 and 1e9 away, of the same angular size. The CPU techniques keep the shadow and the
//! penumbra; the offsets of their rays once grew with the light's distance and lost both.

use glam::{DMat4, DVec2, DVec3};
use penumbra::Technique;
use penumbra::geom::Camera;
use penumbra::geom::compare;
use penumbra::geom::{LightSamples, Reference};
use penumbra::geom::{RectLight, Scene, VisibilityImage};
use penumbra::volumes::{CpuRenderer, DepthComplexity, SamplePattern};
use penumbra_testkit::square;

fn scene(distance: f64) -> Scene {
    let camera = Camera::look_at(
        DVec3::new(0.0, 3.0, 4.0),
        DVec3::ZERO,
        DVec3::Y,
        45.0,
        48,
        32,
    )
    .unwrap();
    // A side of a quarter of the distance: the penumbra is about a quarter of the quad's height
    // above the ground wide.
    let light = RectLight::new(
        DVec3::new(0.0, distance, 0.0),
        -DVec3::Y,
        DVec3::X,
        DVec2::splat(distance / 4.0),
    )
    .unwrap();
    Scene::new(camera)
        .with_light(light)
        .with_mesh("ground", &square(0.0, 2.0), DMat4::IDENTITY)
        .with_mesh("quad", &square(1.0, 0.5), DMat4::IDENTITY)
}

fn differing(a: &VisibilityImage, b: &VisibilityImage) -> usize {
    a.data.iter().zip(&b.data).filter(|(x, y)| x != y).count()
}

#[test]
fn a_far_light_keeps_its_shadow_and_penumbra_on_the_cpu() {
    for distance in [1e5, 1e9] {
        let s = scene(distance);
        let truth =
            Reference::new(&s.lit(0)).render(LightSamples::Stratified { per_axis: 16 }, &|_| {});
        let hard_truth = Reference::new(&s.lit(0)).render(LightSamples::Centre, &|_| {});
        let umbra = truth.data.iter().filter(|&&v| v == 0.0).count();
        assert!(
            umbra > 20,
            "{distance}: the reference has {umbra} umbra pixels"
        );
        let cpu = CpuRenderer::new(&s.lit(0));
        let hard = cpu.render(Technique::Hard, &|_| {});
        assert_eq!(
            differing(&hard, &hard_truth),
            0,
            "{distance}: pixels where hard differs from hard-reference"
        );
        let pattern = SamplePattern {
            per_axis: 16,
            jitter: true,
        };
        let exact = DepthComplexity::new(&s.lit(0)).render(pattern, &|_| {});
        assert_eq!(
            exact, truth,
            "{distance}: depth-complexity --jitter against the reference"
        );
        let blend = cpu.render(Technique::WedgesBlend, &|_| {});
        let c = compare(&blend, &truth).unwrap();
        println!(
            "{distance:e}: umbra {umbra} px; wedges-blend MAE {:.4}, penumbra {:.4} over {} px, umbra lit {:.2}%",
            c.all.mae,
            c.penumbra.mae,
            c.penumbra.pixels,
            100.0 * c.umbra_lit
        );
        assert!(c.penumbra.pixels > 20, "{distance}: no penumbra");
        assert!(
            c.umbra_lit == 0.0 && c.penumbra.mae < 0.03,
            "{distance}: {c:?}"
        );
    }
}
