//! Sun studies in the library ([`Renderer::sun_hours`]): the sum of the steps' own renders, bit
//! for bit, at pixels and at sensor points; night steps not rendered; bad steps refused.

use penumbra::glam::DVec3;
use penumbra::{
    Backend, RenderError, RenderOptions, Renderer, Scene, SunStep, SunStudy, SunTarget, Technique,
};

fn scene() -> Scene {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/scenes/sun.toml");
    let mut scene = Scene::load(std::path::Path::new(path)).unwrap();
    (scene.camera.width, scene.camera.height) = (40, 30);
    scene
}

fn steps() -> Vec<SunStep> {
    [
        (100.0, 20.0, 1.0),
        (180.0, 60.0, 0.5),
        (250.0, 0.1, 1.0),
        (300.0, -3.0, 1.0),
    ]
    .map(|(azimuth_deg, elevation_deg, hours)| SunStep {
        azimuth_deg,
        elevation_deg,
        hours,
    })
    .to_vec()
}

#[test]
fn the_hours_are_the_steps_own_renders_summed_and_night_is_skipped() {
    let (scene, steps) = (scene(), steps());
    let study = SunStudy {
        options: RenderOptions {
            samples: 16,
            jitter: false,
        },
        ..SunStudy::default()
    };
    assert!(!study.is_day(&steps[3]), "the sun wholly below the horizon");
    assert!(study.is_day(&steps[2]));
    let mut r = Renderer::new(Backend::Cpu);
    let done = std::sync::Mutex::new(Vec::new());
    let h = r
        .sun_hours(&scene, &study, &steps, SunTarget::Pixels, &|d| {
            done.lock().unwrap().push(d)
        })
        .unwrap();
    assert_eq!(*done.lock().unwrap(), [1, 2, 3, 4]);
    let mut want = vec![0.0f64; 40 * 30];
    for s in &steps[..3] {
        let v = r
            .render(
                &study.scene_at(&scene, s).unwrap(),
                Technique::DepthComplexity,
                &study.options,
            )
            .unwrap();
        for (w, v) in want.iter_mut().zip(&v.data) {
            *w += f64::from(*v) * s.hours;
        }
    }
    assert_eq!(h, want);
    assert!(h.contains(&2.5) && h.iter().any(|&v| v < 1.0));
    // A second study takes what the first kept (the surface points, the meshes' structures),
    // a renderer of its own builds them: the same bits, and for another camera its own.
    let again = r
        .sun_hours(&scene, &study, &steps, SunTarget::Pixels, &|_| {})
        .unwrap();
    assert_eq!(again, h);
    let fresh = Renderer::new(Backend::Cpu)
        .sun_hours(&scene, &study, &steps, SunTarget::Pixels, &|_| {})
        .unwrap();
    assert_eq!(fresh, h);
    let mut moved = scene.clone();
    moved.camera.eye += DVec3::new(0.5, 0.0, 0.0);
    let elsewhere = r
        .sun_hours(&moved, &study, &steps[..1], SunTarget::Pixels, &|_| {})
        .unwrap();
    let own = Renderer::new(Backend::Cpu)
        .sun_hours(&moved, &study, &steps[..1], SunTarget::Pixels, &|_| {})
        .unwrap();
    assert_eq!(elsewhere, own);
    let here = r
        .sun_hours(&scene, &study, &steps[..1], SunTarget::Pixels, &|_| {})
        .unwrap();
    assert_ne!(
        elsewhere, here,
        "the moved camera's surface points, not the kept ones"
    );

    // At sensor points: the sum of the steps' visibility_at.
    let points = [DVec3::new(5.0, 0.0, 5.0), DVec3::new(0.8, 0.0, 0.3)];
    let normals = [DVec3::Y; 2];
    let target = SunTarget::Points {
        points: &points,
        normals: &normals,
    };
    let at = r
        .sun_hours(&scene, &study, &steps, target, &|_| {})
        .unwrap();
    let mut want = [0.0f64; 2];
    for s in &steps[..3] {
        let lit = study.scene_at(&scene, s).unwrap();
        let v = r
            .visibility_at(
                &lit,
                0,
                &points,
                &normals,
                Technique::DepthComplexity,
                &study.options,
            )
            .unwrap();
        for k in 0..2 {
            want[k] += f64::from(v[k]) * s.hours;
        }
    }
    assert_eq!(at, want);
    assert!(at[0] > 2.0, "open ground: {at:?}");
}

#[test]
fn bad_steps_are_refused() {
    let scene = scene();
    let study = SunStudy::default();
    let mut r = Renderer::new(Backend::Cpu);
    let mut bad = steps();
    bad[1].hours = f64::NAN;
    let e = r.sun_hours(&scene, &study, &bad, SunTarget::Pixels, &|_| {});
    assert!(matches!(e, Err(RenderError::BadSun { .. })), "{e:?}");
    let mut bad = steps();
    bad[0].elevation_deg = 95.0;
    let e = r.sun_hours(&scene, &study, &bad, SunTarget::Pixels, &|_| {});
    assert!(
        matches!(&e, Err(RenderError::BadSun { problem }) if problem.contains("elevation")),
        "{e:?}"
    );
    let points = [DVec3::ZERO; 2];
    let target = SunTarget::Points {
        points: &points,
        normals: &[DVec3::Y],
    };
    let e = r.sun_hours(&scene, &study, &steps(), target, &|_| {});
    assert!(matches!(e, Err(RenderError::BadSensor { .. })), "{e:?}");
}
