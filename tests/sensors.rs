//! Visibility at sensor points ([`Renderer::sensors`]): sensors at the surface points of camera
//! pixels see what those pixels see, by both methods and under a distant light; depth
//! complexity agrees with many more rays on real meshes; a sensor's plane hides the light
//! behind it; bad points are named; an interrupter stops a query.

use std::time::{Duration, Instant};

use penumbra::geom::{Interrupter, SceneBvh};
use penumbra::glam::{DMat4, DVec2, DVec3};
use penumbra::{
    Backend, Camera, RectLight, RenderError, RenderOptions, Renderer, Scene, Technique,
    TriangleMesh,
};

use crate::common::load;

/// The world surface points and their normals (facing the camera) that `scene`'s camera sees,
/// at `w x h` pixels, with their pixel indices.
fn seen_points(scene: &Scene) -> Vec<(u64, DVec3, DVec3)> {
    let cam = &scene.camera;
    let triangles = scene.triangles();
    let bvh = SceneBvh::build(&triangles);
    let mut out = Vec::new();
    for j in 0..cam.height {
        for i in 0..cam.width {
            let dir = cam.ray_dir(i, j);
            let Some(hit) = bvh.closest_hit(cam.eye, dir, f64::MAX) else {
                continue;
            };
            let [a, b, c] = triangles[hit.triangle as usize];
            let mut n = (b - a).cross(c - a).normalize();
            if n.dot(dir) > 0.0 {
                n = -n;
            }
            let pixel = u64::from(j) * u64::from(cam.width) + u64::from(i);
            out.push((pixel, cam.eye + dir * hit.t, n));
        }
    }
    out
}

/// The sensors' values at `points` (each with the samples of its pixel) by `technique`.
fn at_pixels(
    scene: &Scene,
    points: &[(u64, DVec3, DVec3)],
    technique: Technique,
    options: &RenderOptions,
) -> Vec<f32> {
    let mut renderer = Renderer::new(Backend::Cpu);
    let sensors = renderer.sensors(scene, 0, technique, options).unwrap();
    points
        .iter()
        .map(|&(pixel, p, n)| {
            let mut v = [0.0];
            sensors.fill(&[p], &[n], pixel, &mut v, &|_| {}).unwrap();
            v[0]
        })
        .collect()
}

/// On the ground of `name` (points with an upward normal), the share of sensors equal to their
/// pixel, and the mean difference, for the reference and for depth complexity.
fn ground_against_pixels(name: &str) -> [(f64, f64); 2] {
    let mut scene = load(name);
    scene.camera.width = 40;
    scene.camera.height = 30;
    let points: Vec<_> = seen_points(&scene)
        .into_iter()
        .filter(|(_, p, n)| n.y > 0.999 && p.y.abs() < 1e-4)
        .collect();
    assert!(points.len() > 300, "{name}: {} ground points", points.len());
    let options = RenderOptions {
        samples: 64,
        jitter: true,
    };
    [Technique::Reference, Technique::DepthComplexity].map(|t| {
        let image = Renderer::new(Backend::Cpu)
            .render(&scene, t, &options)
            .unwrap();
        let v = at_pixels(&scene, &points, t, &options);
        let (mut equal, mut diff) = (0, 0.0);
        for ((pixel, ..), v) in points.iter().zip(&v) {
            let d = (image.data[*pixel as usize] - v).abs();
            equal += usize::from(d == 0.0);
            diff += f64::from(d);
        }
        let n = points.len() as f64;
        (equal as f64 / n, diff / n)
    })
}

#[test]
fn sensors_on_the_ground_see_what_its_pixels_see() {
    // A rectangle light, and the sun (a distant light: points carried by its warp).
    for name in ["quad-over-plane", "sun"] {
        let [reference, counted] = ground_against_pixels(name);
        println!("{name}: reference {reference:?}, depth complexity {counted:?}");
        assert!(
            reference.0 >= 0.995 && reference.1 < 1e-3,
            "{name}: reference {reference:?}"
        );
        assert!(
            counted.0 >= 0.995 && counted.1 < 1e-3,
            "{name}: depth complexity {counted:?}"
        );
    }
}

#[test]
fn counted_sensors_on_real_meshes_agree_with_many_rays() {
    // Two scanned meshes, a PLY and a glTF, under a large light; points on the ground, the
    // meshes and the faces turned from the light, as the camera sees them at 24 x 18.
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/fixtures/meshfiles/igea-and-spot.toml"
    );
    let mut scene = Scene::load(std::path::Path::new(path)).unwrap();
    scene.camera.width = 24;
    scene.camera.height = 18;
    let points = seen_points(&scene);
    let (p, n): (Vec<DVec3>, Vec<DVec3>) = points.iter().map(|&(_, p, n)| (p, n)).unzip();
    let mut renderer = Renderer::new(Backend::Cpu);
    let mut run = |t, samples| {
        let options = RenderOptions {
            samples,
            jitter: false,
        };
        renderer
            .visibility_at(&scene, 0, &p, &n, t, &options)
            .unwrap()
    };
    let counted = run(Technique::DepthComplexity, 1024);
    let cast = run(Technique::Reference, 4096);
    let mean = counted
        .iter()
        .zip(&cast)
        .map(|(a, b)| f64::from((a - b).abs()))
        .sum::<f64>()
        / p.len() as f64;
    let penumbra = cast.iter().filter(|v| **v > 0.02 && **v < 0.98).count();
    println!(
        "{} sensors, {penumbra} in the penumbra: mean difference {mean}",
        p.len()
    );
    assert!(penumbra > 20, "{penumbra} sensors in the penumbra");
    assert!(mean < 0.01, "mean difference {mean}");
}

/// A 2 x 2 lamp 5 above a far ground, and nothing else.
fn open_scene() -> Scene {
    let camera =
        Camera::look_at(DVec3::new(0.0, 4.0, 5.0), DVec3::ZERO, DVec3::Y, 45.0, 8, 6).unwrap();
    let lamp = RectLight::new(
        DVec3::new(0.0, 5.0, 0.0),
        DVec3::NEG_Y,
        DVec3::X,
        DVec2::splat(2.0),
    )
    .unwrap();
    Scene::new(camera).with_light(lamp).with_mesh(
        "ground",
        &TriangleMesh::quad(),
        DMat4::from_scale(DVec3::splat(8.0)),
    )
}

#[test]
fn a_sensor_sees_only_the_light_in_front_of_its_plane() {
    let scene = open_scene();
    let points = [DVec3::new(0.0, 2.0, 0.0); 3];
    // Up, down, and sideways: the plane x = 0 halves the light.
    let normals = [DVec3::Y, DVec3::NEG_Y, DVec3::new(2.0, 0.0, 0.0)];
    for t in [Technique::DepthComplexity, Technique::Reference] {
        let options = RenderOptions {
            samples: 256,
            jitter: false,
        };
        let v = Renderer::new(Backend::Cpu)
            .visibility_at(&scene, 0, &points, &normals, t, &options)
            .unwrap();
        assert_eq!(v, [1.0, 0.0, 0.5], "{t}");
    }
}

/// Sensors at round coordinates under edges at round coordinates (lines from a sensor to the
/// light's centre through an edge): counted as the rays see the same samples.
#[test]
fn sensors_at_round_coordinates_are_counted_right() {
    let scene = open_scene().with_mesh(
        "roof",
        &TriangleMesh::quad(),
        DMat4::from_translation(DVec3::new(0.0, 1.0, 0.0)),
    );
    let p: Vec<DVec3> = (0..17 * 17)
        .map(|k| {
            DVec3::new(
                (k % 17) as f64 / 8.0 - 1.0,
                0.0,
                (k / 17) as f64 / 8.0 - 1.0,
            )
        })
        .collect();
    let n = vec![DVec3::Y; p.len()];
    let options = RenderOptions {
        samples: 256,
        jitter: true,
    };
    let mut r = Renderer::new(Backend::Cpu);
    let counted = r
        .visibility_at(&scene, 0, &p, &n, Technique::DepthComplexity, &options)
        .unwrap();
    let cast = r
        .visibility_at(&scene, 0, &p, &n, Technique::Reference, &options)
        .unwrap();
    let worst = counted
        .iter()
        .zip(&cast)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f32::max);
    assert!(worst <= 2.0 / 256.0, "{worst}");
    assert!(cast.iter().filter(|v| **v > 0.0 && **v < 1.0).count() > 40);
}

#[test]
fn a_query_in_slices_is_the_query_whole() {
    let scene = open_scene().with_mesh(
        "roof",
        &TriangleMesh::quad(),
        DMat4::from_translation(DVec3::new(0.3, 1.0, 0.0)),
    );
    let p: Vec<DVec3> = (0..300)
        .map(|k| DVec3::new(k as f64 / 100.0 - 1.5, 0.0, 0.1))
        .collect();
    let n = vec![DVec3::Y; p.len()];
    let options = RenderOptions::default();
    let mut renderer = Renderer::new(Backend::Cpu);
    let whole = renderer
        .visibility_at(&scene, 0, &p, &n, Technique::DepthComplexity, &options)
        .unwrap();
    let sensors = renderer
        .sensors(&scene, 0, Technique::DepthComplexity, &options)
        .unwrap();
    let mut sliced = vec![0.0; p.len()];
    let (a, b) = sliced.split_at_mut(120);
    sensors.fill(&p[..120], &n[..120], 0, a, &|_| {}).unwrap();
    sensors.fill(&p[120..], &n[120..], 120, b, &|_| {}).unwrap();
    assert_eq!(whole, sliced);
    assert!(whole.contains(&0.0) && whole.iter().any(|&v| v > 0.0 && v < 1.0));
}

#[test]
fn bad_sensors_and_requests_are_named() {
    let scene = open_scene();
    let mut r = Renderer::new(Backend::Cpu);
    let o = RenderOptions::default();
    let t = Technique::DepthComplexity;
    let err = |e: RenderError| e.to_string();
    let nan = DVec3::new(f64::NAN, 0.0, 0.0);
    let cases = [
        (vec![DVec3::ZERO, nan], vec![DVec3::Y; 2], "sensor 1: point"),
        (vec![DVec3::ZERO], vec![DVec3::ZERO], "sensor 0: normal"),
        (vec![DVec3::ZERO], vec![nan], "sensor 0: normal"),
        (vec![DVec3::ZERO; 2], vec![DVec3::Y], "2 points, 1 normals"),
    ];
    for (p, n, want) in cases {
        let e = err(r.visibility_at(&scene, 0, &p, &n, t, &o).unwrap_err());
        assert!(e.contains(want), "{e}");
    }
    let one = ([DVec3::ZERO], [DVec3::Y]);
    let e = err(r
        .visibility_at(&scene, 0, &one.0, &one.1, Technique::Wedges, &o)
        .unwrap_err());
    assert!(e.contains("not wedges"), "{e}");
    let e = err(r
        .visibility_at(&scene, 3, &one.0, &one.1, t, &o)
        .unwrap_err());
    assert!(e.contains("light 3: the scene has 1 light"), "{e}");
}

#[test]
fn an_interrupter_stops_a_query_and_a_render() {
    let scene = load("spheres-9x9");
    let p = vec![DVec3::new(0.0, 0.0, 0.0); 200_000];
    let n = vec![DVec3::Y; p.len()];
    let options = RenderOptions {
        samples: 4096,
        jitter: false,
    };
    let stop = Interrupter::new();
    let start = Instant::now();
    let query = {
        let (stop, scene) = (stop.clone(), scene.clone());
        std::thread::spawn(move || {
            stop.run(|| {
                Renderer::new(Backend::Cpu).visibility_at(
                    &scene,
                    0,
                    &p,
                    &n,
                    Technique::Reference,
                    &options,
                )
            })
        })
    };
    std::thread::sleep(Duration::from_millis(300));
    stop.interrupt();
    let r = query.join().unwrap();
    assert!(matches!(r, Err(RenderError::Interrupted)), "{r:?}");
    assert!(
        start.elapsed() < Duration::from_secs(10),
        "{:?}",
        start.elapsed()
    );
    // A render under an interrupter already interrupted stops before its first row.
    for t in [
        Technique::Reference,
        Technique::DepthComplexity,
        Technique::WedgesBlend,
    ] {
        let r = stop.run(|| Renderer::new(Backend::Cpu).render(&scene, t, &options));
        assert!(matches!(r, Err(RenderError::Interrupted)), "{t}");
    }
}
