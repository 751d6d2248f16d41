//! Distant lights (the sun): a rectangle of directions. Its reference image is the limit of a
//! rectangle light of the same angular size moved ever farther away, the exact evaluator agrees
//! with it, and the CPU techniques render it as they render a rectangle light.

use glam::{DMat4, DVec2, DVec3};
use penumbra::Technique;
use penumbra::geom::{
    Camera, DistantLight, LightSamples, LitScene, REFERENCE_SEED, RectLight, Reference, Rng, Scene,
    Tracer, VisibilityImage, compare,
};
use penumbra::volumes::{CpuRenderer, DepthComplexity, SamplePattern};
use penumbra_testkit::square;

use crate::common::{gpu_renderer, load};

/// The light's direction, tangent and full angles: wide enough for a penumbra of several
/// pixels, two different sides.
fn sun() -> DistantLight {
    let d = DVec3::new(0.3, 1.0, 0.2).normalize();
    let t = d.cross(DVec3::Z).normalize();
    DistantLight::new(d, t, DVec2::new(14.0, 8.0)).unwrap()
}

/// A quad over a ground, 96 x 64 pixels, its light left to the caller.
fn world() -> Scene {
    let camera = Camera::look_at(
        DVec3::new(0.0, 3.0, 4.0),
        DVec3::ZERO,
        DVec3::Y,
        45.0,
        96,
        64,
    )
    .unwrap();
    Scene::new(camera)
        .with_mesh("ground", &square(0.0, 2.0), DMat4::IDENTITY)
        .with_mesh("quad", &square(1.0, 0.5), DMat4::IDENTITY)
}

/// The rectangle light of the sun's angles at `distance` from the origin along its direction.
fn far_rectangle(distance: f64) -> RectLight {
    let l = sun();
    RectLight::new(
        l.direction * distance,
        -l.direction,
        l.tangent,
        l.half_tangents() * (2.0 * distance),
    )
    .unwrap()
}

fn mean_difference(a: &VisibilityImage, b: &VisibilityImage) -> f64 {
    a.data
        .iter()
        .zip(&b.data)
        .map(|(x, y)| (x - y).abs() as f64)
        .sum::<f64>()
        / a.data.len() as f64
}

#[test]
fn a_distant_light_is_the_limit_of_ever_farther_rectangles() {
    let samples = LightSamples::Stratified { per_axis: 16 };
    let distant = world().with_light(sun());
    let truth = Reference::new(&distant.lit(0)).render(samples, &|_| {});
    let umbra = truth.data.iter().filter(|&&v| v == 0.0).count();
    let penumbra = truth.data.iter().filter(|&&v| v > 0.0 && v < 1.0).count();
    println!("umbra {umbra} px, penumbra {penumbra} px");
    assert!(umbra > 50 && penumbra > 50);
    // The scene is about 4 across: the rectangle 1e2, 1e3 and 1e4 times that away. Both images
    // take the same (u, v) samples per pixel, so they differ only where a sample's direction
    // from the far rectangle's point still differs from the distant light's.
    let errors: Vec<f64> = [4e2, 4e3, 4e4]
        .iter()
        .map(|&d| {
            let s = world().with_light(far_rectangle(d));
            let far = Reference::new(&s.lit(0)).render(samples, &|_| {});
            mean_difference(&far, &truth)
        })
        .collect();
    println!("mean |far rectangle - distant| at 1e2, 1e3, 1e4 times the scene: {errors:?}");
    // The directions differ by about the scene's size over the distance: the error falls
    // about tenfold with each tenfold distance (measured 1.1e-4, 1.0e-5, 6.4e-7).
    assert!(errors[0] > 0.0, "{errors:?}");
    assert!(
        errors[1] < errors[0] / 5.0 && errors[2] < errors[1] / 5.0,
        "{errors:?}"
    );
    assert!(errors[2] < 1e-5, "{errors:?}");
}

#[test]
fn the_distant_reference_agrees_with_the_exact_evaluator() {
    let scene = world().with_light(sun());
    let tracer = Tracer::new(&scene.lit(0));
    let cam = &scene.camera;
    let mut checked = 0;
    for j in (0..cam.height).step_by(2) {
        for i in (0..cam.width).step_by(2) {
            let Some(p) = tracer.surface_point(cam.eye, cam.ray_dir(i, j)) else {
                continue;
            };
            let exact = tracer.exact_visibility(&p);
            if !(0.02..0.98).contains(&exact) {
                continue;
            }
            let mut rng = Rng::stream(REFERENCE_SEED, (j * cam.width + i) as u64);
            let sampled = tracer.sampled_visibility(&p, 32, &mut rng);
            // Stratified sampling of a region bounded by lines: well within 4 sigma of the
            // unstratified bound.
            let sigma = (exact * (1.0 - exact) / 1024.0).sqrt();
            assert!(
                (sampled - exact).abs() <= 4.0 * sigma,
                "pixel {i},{j}: sampled {sampled}, exact {exact}"
            );
            checked += 1;
        }
    }
    assert!(checked >= 10, "{checked} penumbra points");
}

/// `depth-complexity --jitter` against the reference, `hard` against `hard-reference` and
/// `wedges-blend`'s penumbra MAE against the 256-sample reference, on `scene`.
fn check_techniques(name: &str, scene: &Scene, blend_bound: f64) {
    let truth =
        Reference::new(&scene.lit(0)).render(LightSamples::Stratified { per_axis: 16 }, &|_| {});
    let dc = DepthComplexity::new(&scene.lit(0)).render(
        SamplePattern {
            per_axis: 16,
            jitter: true,
        },
        &|_| {},
    );
    let differ: Vec<f32> = dc
        .data
        .iter()
        .zip(&truth.data)
        .filter(|(a, b)| a != b)
        .map(|(a, b)| (a - b).abs())
        .collect();
    assert!(
        differ.len() as f64 <= 1e-3 * dc.data.len() as f64
            && differ.iter().all(|&d| d <= 2.0 / 256.0 + 1e-6),
        "{name}: depth-complexity differs from the reference on {differ:?}"
    );
    let cpu = CpuRenderer::new(&scene.lit(0));
    let hard_truth = Reference::new(&scene.lit(0)).render(LightSamples::Centre, &|_| {});
    assert_eq!(
        cpu.render(Technique::Hard, &|_| {}),
        hard_truth,
        "{name}: hard"
    );
    let blend = compare(&cpu.render(Technique::WedgesBlend, &|_| {}), &truth).unwrap();
    println!(
        "{name}: wedges-blend penumbra MAE {:.4} over {} px, umbra lit {:.2}%",
        blend.penumbra.mae,
        blend.penumbra.pixels,
        100.0 * blend.umbra_lit
    );
    assert!(blend.penumbra.pixels > 20, "{name}: no penumbra");
    assert!(
        blend.penumbra.mae <= blend_bound && blend.umbra_lit == 0.0,
        "{name}: {blend:?}"
    );
}

#[test]
fn the_cpu_techniques_render_a_distant_light() {
    check_techniques("quad", &world().with_light(sun()), 0.05);
    // The sun fixture at half size: a real mesh at a low sun, the sun's own angle.
    let mut scene = load("sun");
    assert!(scene.lit(0).distant.is_some());
    scene.camera.width /= 2;
    scene.camera.height /= 2;
    check_techniques("sun", &scene, 0.05);
}

/// The sun exactly on the horizon (its centre's direction in the ground's plane, the sun's
/// angular size) over a ground of 200 triangles, a sphere on it. Every segment from a point of
/// the ground to the sun's centre runs along the ground: it grazes the other triangles of the
/// ground without crossing them, so the ground sees the whole sun (it is open: the half of the
/// sun below the horizon shines through the sheet P lies on). The hard shadow is the hard
/// reference's on the CPU and the GPU, `depth-complexity` given the reference's samples is the
/// reference, and `wedges-blend` is within 0.01 of it.
#[test]
fn the_sun_exactly_on_the_horizon_over_a_tessellated_ground() {
    let n = 10u32;
    let positions: Vec<DVec3> = (0..=n)
        .flat_map(|j| {
            (0..=n).map(move |i| {
                DVec3::new(
                    -3.0 + 6.0 * i as f64 / n as f64,
                    0.0,
                    -3.0 + 6.0 * j as f64 / n as f64,
                )
            })
        })
        .collect();
    let triangles: Vec<[u32; 3]> = (0..n)
        .flat_map(|j| {
            (0..n).flat_map(move |i| {
                let a = j * (n + 1) + i;
                let (b, c) = (a + 1, a + n + 1);
                [[a, c, b], [b, c, c + 1]]
            })
        })
        .collect();
    let ground = penumbra::TriangleMesh::from_raw("grid", &positions, &triangles).unwrap();
    let camera = Camera::look_at(
        DVec3::new(0.0, 3.0, 6.0),
        DVec3::ZERO,
        DVec3::Y,
        50.0,
        64,
        48,
    )
    .unwrap();
    let sun = DistantLight::new(DVec3::X, DVec3::Z, DVec2::splat(0.53)).unwrap();
    let scene = Scene::new(camera)
        .with_light(sun)
        .with_mesh("ground", &ground, DMat4::IDENTITY)
        .with_mesh(
            "sphere",
            &penumbra::TriangleMesh::uv_sphere(12, 16),
            DMat4::from_translation(DVec3::new(0.0, 0.5, 0.0))
                * DMat4::from_scale(DVec3::splat(0.5)),
        );
    let lit = scene.lit(0);
    let cpu = CpuRenderer::new(&lit);
    let hard_reference = Reference::new(&lit).render(LightSamples::Centre, &|_| {});
    let lit_share = hard_reference.data.iter().filter(|&&v| v == 1.0).count() as f64
        / hard_reference.data.len() as f64;
    assert!(
        lit_share > 0.8,
        "hard reference lit on {lit_share:.3} of the image"
    );
    let hard = compare(&cpu.render(Technique::Hard, &|_| {}), &hard_reference).unwrap();
    assert_eq!(hard.all.equal, 1.0, "CPU hard against the hard reference");
    let (truth, exact, _) = reference_and_depth_complexity(&lit);
    let c = compare(&exact, &truth).unwrap();
    assert!(
        c.all.equal >= 0.995 && c.all.max <= 1.0 / 64.0,
        "depth-complexity: {:.4} equal, max {}",
        c.all.equal,
        c.all.max
    );
    let soft = compare(&cpu.render(Technique::WedgesBlend, &|_| {}), &truth).unwrap();
    assert!(soft.all.mae <= 0.01, "wedges-blend MAE {}", soft.all.mae);
    let Some(mut gpu) = gpu_renderer() else {
        return;
    };
    let v = gpu
        .render(&scene, Technique::Hard, &penumbra::RenderOptions::default())
        .unwrap();
    let c = compare(&v, &hard_reference).unwrap();
    assert!(c.all.equal >= 0.995, "GPU hard {:.4} equal", c.all.equal);
}

/// A sun 90 degrees long and 1e-9 degrees wide over the quad: its samples lie within rounding
/// of one line in light space, where the edges' crossings between them hang on rounding.
/// `depth-complexity` casts them ([`penumbra::volumes::THIN_LIGHT`]) and, given the
/// reference's samples, is the reference.
#[test]
fn a_sun_one_billionth_of_a_degree_wide() {
    let d = DVec3::new(0.3, 1.0, 0.2).normalize();
    let t = d.cross(DVec3::Z).normalize();
    let scene = world().with_light(DistantLight::new(d, t, DVec2::new(90.0, 1e-9)).unwrap());
    let lit = scene.lit(0);
    let (truth, exact, cast) = reference_and_depth_complexity(&lit);
    let c = compare(&exact, &truth).unwrap();
    assert!(
        c.penumbra.pixels > 100,
        "{} penumbra pixels",
        c.penumbra.pixels
    );
    assert_eq!(c.all.equal, 1.0, "max difference {}", c.all.max);
    assert!(cast > 0);
}

/// The reference of `lit` at 256 samples, `depth-complexity` given the reference's own samples,
/// and how many pixels `depth-complexity` cast.
fn reference_and_depth_complexity(lit: &LitScene) -> (VisibilityImage, VisibilityImage, u64) {
    let truth = Reference::new(lit).render(LightSamples::Stratified { per_axis: 16 }, &|_| {});
    let dc = DepthComplexity::new(lit);
    let pattern = SamplePattern {
        per_axis: 16,
        jitter: true,
    };
    let exact = dc.render(pattern, &|_| {});
    (truth, exact, dc.cast_pixels())
}

/// A sun below the horizon, and a lamp below the ground facing up, under a plain ground (two
/// triangles) with a sphere above it: the open ground sees the light through itself, and the
/// GPU's `hard` and `wedges-blend` draw what the CPU's do, with no band of false shadow.
#[test]
fn lights_below_a_plain_ground_on_the_gpu() {
    let d = DVec3::new(0.6, -0.3, 0.5).normalize();
    let t = DVec3::new(d.z, 0.0, -d.x).normalize();
    let below = DistantLight::new(d, t, DVec2::splat(0.53)).unwrap();
    let lamp = RectLight::new(DVec3::new(0.5, -2.0, 0.3), DVec3::Y, DVec3::X, DVec2::ONE).unwrap();
    let sphere = penumbra::TriangleMesh::uv_sphere(12, 16);
    let scenes = [
        world().with_light(below),
        world().with_light(lamp),
        world().with_light(lamp).with_mesh(
            "sphere",
            &sphere,
            DMat4::from_translation(DVec3::new(0.0, 1.0, 0.0)),
        ),
    ];
    let options = penumbra::RenderOptions::default();
    let Some(mut gpu) = gpu_renderer() else {
        return;
    };
    let mut cpu = penumbra::Renderer::new(penumbra::Backend::Cpu);
    for (k, scene) in scenes.iter().enumerate() {
        for t in [Technique::Hard, Technique::WedgesBlend] {
            let on_gpu = gpu.render(scene, t, &options).unwrap();
            let c = compare(&on_gpu, &cpu.render(scene, t, &options).unwrap()).unwrap();
            assert!(
                c.all.mae <= 0.005 && c.all.equal >= 0.99,
                "scene {k}: {t}: MAE {:.4}, {:.4} equal",
                c.all.mae,
                c.all.equal
            );
        }
    }
}
