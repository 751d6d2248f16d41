//! Scenes whose sizes are far apart: an eye a few millimetres above a ground it looks along,
//! and a triangle many orders of magnitude wider than the rest of the scene under it. The GPU's
//! near plane once came from the scene's extent alone (a thousandth of it), which clipped the
//! surfaces near the eye and wrongly shadowed the ground at the horizon (6% of the pixels), or
//! clipped the whole small scene over a huge triangle; the CPU's hard shadow started its rays
//! at an offset that grows with the scene's extent, and lost every shadow of the small scene.

use glam::{DMat4, DVec2, DVec3};
use penumbra::geom::compare;
use penumbra::geom::{Camera, RectLight, Scene, TriangleMesh, VisibilityImage};
use penumbra::{Backend, RenderOptions, Renderer, Technique, Warning};
use penumbra_testkit::square;

fn mesh(positions: &[DVec3], triangles: &[[u32; 3]]) -> TriangleMesh {
    TriangleMesh::from_raw("memory", positions, triangles).unwrap()
}

fn light() -> RectLight {
    RectLight::new(
        DVec3::new(0.0, 6.0, 0.0),
        -DVec3::Y,
        DVec3::X,
        DVec2::splat(2.0),
    )
    .unwrap()
}

fn differing(a: &VisibilityImage, b: &VisibilityImage) -> usize {
    a.data.iter().zip(&b.data).filter(|(x, y)| x != y).count()
}

fn render(backend: Backend, scene: &Scene, technique: Technique) -> VisibilityImage {
    let options = RenderOptions {
        samples: 64,
        ..RenderOptions::default()
    };
    Renderer::new(backend)
        .render(scene, technique, &options)
        .unwrap_or_else(|e| panic!("{technique} on {backend:?}: {e}"))
}

/// The eye `height` above a 40 x 40 ground, looking along it at a square hovering over it
/// (with the eye 3 mm above it, the old near plane drew 6% of the pixels shadowed).
fn eye_on_the_ground(height: f64) -> Scene {
    let camera = Camera::look_at(
        DVec3::new(0.0, height, 15.0),
        DVec3::new(0.0, height, 0.0),
        DVec3::Y,
        45.0,
        64,
        48,
    )
    .unwrap();
    Scene::new(camera)
        .with_light(light())
        .with_mesh("ground", &square(0.0, 20.0), DMat4::IDENTITY)
        .with_mesh("square", &square(1.5, 1.0), DMat4::IDENTITY)
}

#[test]
fn an_eye_just_above_the_ground_sees_the_hard_shadow_on_the_gpu() {
    for height in [3e-3, 3e-6] {
        let scene = eye_on_the_ground(height);
        let truth = render(Backend::Cpu, &scene, Technique::HardReference);
        // At such grazing angles the shadow on the ground folds into the horizon's row; what
        // went wrong was the lit ground near the horizon drawn shadowed.
        let lit = truth.data.iter().filter(|&&v| v == 1.0).count();
        assert!(lit > 1000, "{height}: the reference has {lit} lit pixels");
        let gpu = render(Backend::Gpu, &scene, Technique::Hard);
        assert_eq!(
            differing(&gpu, &truth),
            0,
            "{height}: pixels where the GPU's hard differs from hard-reference"
        );
    }
}

/// A square over a ground under the light, with one triangle `width` wide below the ground.
fn over_a_huge_triangle(width: f64) -> Scene {
    let camera = Camera::look_at(
        DVec3::new(0.0, 6.0, 7.0),
        DVec3::ZERO,
        DVec3::Y,
        45.0,
        64,
        48,
    )
    .unwrap();
    let w = width / 2.0;
    let huge = mesh(
        &[
            DVec3::new(-w, -0.5, -w),
            DVec3::new(0.0, -0.5, w),
            DVec3::new(w, -0.5, -w),
        ],
        &[[0, 1, 2]],
    );
    Scene::new(camera)
        .with_light(light())
        .with_mesh("ground", &square(0.0, 10.0), DMat4::IDENTITY)
        .with_mesh("square", &square(1.0, 1.0), DMat4::IDENTITY)
        .with_mesh("huge", &huge, DMat4::IDENTITY)
}

#[test]
fn a_huge_triangle_leaves_the_small_scene_its_shadows_on_the_cpu() {
    let scene = over_a_huge_triangle(2e8);
    let hard_truth = render(Backend::Cpu, &scene, Technique::HardReference);
    let umbra = hard_truth.data.iter().filter(|&&v| v == 0.0).count();
    assert!(
        umbra > 100,
        "the hard reference has {umbra} shadowed pixels"
    );
    let hard = render(Backend::Cpu, &scene, Technique::Hard);
    assert_eq!(
        differing(&hard, &hard_truth),
        0,
        "pixels where the CPU's hard differs from hard-reference"
    );
    let truth = render(Backend::Cpu, &scene, Technique::Reference);
    let blend = render(Backend::Cpu, &scene, Technique::WedgesBlend);
    let c = compare(&blend, &truth).unwrap();
    assert!(
        c.all.mae < 0.01 && c.umbra_lit < 0.01,
        "wedges-blend against the reference: MAE {}, umbra lit {}",
        c.all.mae,
        c.umbra_lit
    );
}

#[test]
fn a_triangle_1e5_wide_leaves_the_small_scene_its_shadows_on_the_gpu() {
    let scene = over_a_huge_triangle(1e5);
    let hard_truth = render(Backend::Cpu, &scene, Technique::HardReference);
    let hard = render(Backend::Gpu, &scene, Technique::Hard);
    assert_eq!(
        differing(&hard, &hard_truth),
        0,
        "pixels where the GPU's hard differs from hard-reference"
    );
}

#[test]
fn a_triangle_too_wide_for_the_gpu_goes_to_the_cpu_or_is_warned_of() {
    let scene = over_a_huge_triangle(2e8);
    let options = RenderOptions::default();
    let hard_truth = render(Backend::Cpu, &scene, Technique::HardReference);
    let auto = Renderer::new(Backend::Auto)
        .render_frame(&scene.lit(0), Technique::Hard, &options, None, &|_| {})
        .unwrap();
    assert!(auto.detail.starts_with("cpu"), "{}", auto.detail);
    assert!(auto.warnings.is_empty(), "{:?}", auto.warnings);
    assert_eq!(differing(&auto.image, &hard_truth), 0);
    let gpu = Renderer::new(Backend::Gpu)
        .render_frame(&scene.lit(0), Technique::Hard, &options, None, &|_| {})
        .unwrap();
    assert!(
        matches!(gpu.warnings[..], [Warning::GpuExtent { ratio, .. }] if ratio > 1e7),
        "{:?}",
        gpu.warnings
    );
    // The triangle 1e5 wide is within what the GPU holds: no warning.
    let fine = Renderer::new(Backend::Gpu)
        .render_frame(
            &(over_a_huge_triangle(1e5)).lit(0),
            Technique::Hard,
            &options,
            None,
            &|_| {},
        )
        .unwrap();
    assert!(fine.warnings.is_empty(), "{:?}", fine.warnings);
}
