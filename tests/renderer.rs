//! The front door: one renderer for every technique, the back end chosen per technique.

use penumbra::{Backend, RenderError, RenderOptions, Renderer, Runs, Scene, Technique};

use crate::common::{differing_pixels, load};

/// Fixture `name` at 64x48, and 16 samples.
fn small(name: &str) -> (Scene, RenderOptions) {
    let mut scene = load(name);
    scene.camera.width = 64;
    scene.camera.height = 48;
    let options = RenderOptions {
        samples: 16,
        jitter: false,
    };
    (scene, options)
}

#[test]
fn each_technique_runs_where_it_can_and_says_why_where_it_cannot() {
    let scene = load("quad-over-plane");
    let small = RenderOptions {
        samples: 16,
        jitter: false,
    };
    let mut cpu = Renderer::new(Backend::Cpu);
    assert!(matches!(
        cpu.render(&scene, Technique::Pcss, &small),
        Err(RenderError::NeedsGpu { .. })
    ));
    let mut gpu = Renderer::new(Backend::Gpu);
    assert!(matches!(
        gpu.render(&scene, Technique::Reference, &small),
        Err(RenderError::CpuOnly { .. })
    ));
    let odd = RenderOptions {
        samples: 15,
        jitter: false,
    };
    assert!(matches!(
        cpu.render(&scene, Technique::Reference, &odd),
        Err(RenderError::BadSamples { samples: 15 })
    ));
    let jitter = RenderOptions {
        samples: 16,
        jitter: true,
    };
    assert!(matches!(
        cpu.render(&scene, Technique::Wedges, &jitter),
        Err(RenderError::NoSamples { .. })
    ));
    // The references never open the GPU; a volume technique does on Auto
    // where there is one, and its image is the CPU renderer's.
    let mut auto = Renderer::new(Backend::Auto);
    auto.render(&scene, Technique::HardReference, &small)
        .unwrap();
    assert!(auto.gpu_description().is_none());
    let on_gpu = auto.render(&scene, Technique::Hard, &small).unwrap();
    let on_cpu = cpu.render(&scene, Technique::Hard, &small).unwrap();
    let differ = on_gpu
        .data
        .iter()
        .zip(&on_cpu.data)
        .filter(|(a, b)| a != b)
        .count();
    assert!(differ <= 8, "{differ} pixels differ");
    if std::env::var_os("CI").is_some() {
        assert!(auto.gpu_description().is_some(), "CI has lavapipe");
    }
    // Depth-complexity sampling on the GPU back end up to 1024 multi-jittered samples, refused
    // beyond or jittered; under Auto always on the CPU, which is faster than the GPU's counting
    // pass on every device measured.
    if auto.gpu_description().is_some() {
        let frame = |r: &mut Renderer, o: &RenderOptions| {
            r.render_frame(&scene.lit(0), Technique::DepthComplexity, o, None, &|_| {})
        };
        let by_auto = frame(&mut auto, &small).unwrap();
        assert!(by_auto.detail.starts_with("cpu"), "{}", by_auto.detail);
        let on_gpu = frame(&mut gpu, &small).unwrap();
        assert!(on_gpu.detail.starts_with("gpu: "), "{}", on_gpu.detail);
        let on_cpu = frame(&mut cpu, &small).unwrap();
        assert!(on_cpu.detail.starts_with("cpu"), "{}", on_cpu.detail);
        let equal = on_gpu
            .image
            .data
            .iter()
            .zip(&on_cpu.image.data)
            .filter(|(a, b)| a == b)
            .count();
        assert!(
            equal * 1000 >= 999 * on_cpu.image.data.len(),
            "{equal} equal"
        );
        let many = RenderOptions {
            samples: 4096,
            jitter: false,
        };
        for o in [&jitter, &many] {
            let f = frame(&mut auto, o).unwrap();
            assert!(f.detail.starts_with("cpu"), "{}", f.detail);
            let Err(err) = frame(&mut gpu, o) else {
                panic!("the GPU rendered {} samples", o.samples);
            };
            assert!(matches!(err, RenderError::GpuSamples { .. }), "{err}");
            // The library names no command-line flag; the command adds its own words.
            assert!(!err.to_string().contains("--"), "{err}");
        }
    }
}

#[test]
fn scenes_made_in_code_outside_the_supported_range_are_refused() {
    use glam::{DMat4, DVec3};
    use penumbra::geom::TriangleMesh;
    let base = load("quad-over-plane");
    let far = TriangleMesh::from_raw(
        "far",
        &[
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(1.0, 1e20, 0.0),
            DVec3::new(0.0, 1.0, 1.0),
        ],
        &[[0, 1, 2]],
    )
    .unwrap();
    let scene = penumbra::Scene::new(base.camera)
        .with_light(base.lit(0).light)
        .with_mesh("far", &far, DMat4::IDENTITY);
    for t in [
        Technique::Hard,
        Technique::WedgesBlend,
        Technique::Reference,
        Technique::DepthComplexity,
    ] {
        let err = Renderer::new(Backend::Cpu)
            .render(&scene, t, &RenderOptions::default())
            .unwrap_err();
        assert!(matches!(err, RenderError::OutOfRange { .. }), "{t}: {err}");
        assert!(err.to_string().contains("mesh 0 (far)"), "{err}");
    }
    let mut wide = base.clone();
    wide.camera.fov_y_deg = 1e-30;
    let err = Renderer::new(Backend::Cpu)
        .render(&wide, Technique::Hard, &RenderOptions::default())
        .unwrap_err();
    assert!(err.to_string().contains("field of view"), "{err}");
    // A light the scene file would refuse (its normal not unit length) is refused here too,
    // where wedges-blend drew a hard-edged, broken shadow.
    let mut tilted = base.clone();
    // The constructors refuse such a light: it is set field by field.
    match &mut tilted.lights[0].light {
        penumbra::Light::Rect(l) => l.normal = DVec3::new(0.0, -1.0, 0.5),
        penumbra::Light::Distant(_) => unreachable!("the base scene's light is a rectangle"),
    }
    let err = Renderer::new(Backend::Cpu)
        .render(&tilted, Technique::WedgesBlend, &RenderOptions::default())
        .unwrap_err();
    assert!(
        matches!(err, RenderError::OutOfRange { .. })
            && err.to_string().contains("not unit length"),
        "{err}"
    );
}

#[test]
fn scenes_far_from_the_origin_render_as_at_it() {
    // The ray caster takes triangles and rays relative to the scene's centre before rounding
    // them to f32: at 1e8 from the origin an f32 coordinate is 8 units apart, and a scene there
    // lost its triangles.
    let (scene, options) = small("quad-over-plane");
    let techniques = [
        Technique::HardReference,
        Technique::Reference,
        Technique::Hard,
        Technique::WedgesBlend,
        Technique::DepthComplexity,
    ];
    let mut cpu = Renderer::new(Backend::Cpu);
    let at_origin: Vec<_> = techniques
        .iter()
        .map(|&t| cpu.render(&scene, t, &options).unwrap())
        .collect();
    for offset in [1e7, 1e8, 1e12] {
        let moved = scene.transformed(&glam::DMat4::from_translation(glam::DVec3::new(
            offset,
            -0.5 * offset,
            offset,
        )));
        for (t, want) in techniques.iter().zip(&at_origin) {
            let img = cpu.render(&moved, *t, &options).unwrap();
            let c = penumbra::geom::compare(&img, want).unwrap();
            println!(
                "offset {offset:e}: {t}: MAE {:.2e}, max {:.2e}",
                c.all.mae, c.all.max
            );
            assert!(
                c.all.mae <= 1e-4,
                "offset {offset:e}: {t}: MAE {}",
                c.all.mae
            );
        }
    }
}

#[test]
fn random_similarity_transforms_leave_every_image_unchanged() {
    // Rotations about random axes, moves up to 1e3 and uniform scales from 1e-2 to 1e2 of a
    // scene and its light: every technique sees the same scene, and must draw the same image
    // up to float noise (a pixel on an outline may see the other surface). The shadow maps
    // sample a grid of texels, and a receiver's f32 rounding moves a tap across a texel's edge:
    // `pcss`'s nested blocker search turns that into a different filter at a few penumbra
    // pixels of `overlapping-quads` (mean error 1.6e-4 at worst, 4 of 3,072 pixels beyond 0.05).
    let noise = |t: Technique| if t.is_shadow_map() { 3e-4 } else { 1e-4 };
    let options = RenderOptions {
        samples: 16,
        jitter: false,
    };
    let mut rng = penumbra::geom::Rng::new(77);
    let mut renderer = Renderer::new(Backend::Auto);
    let gpu = renderer
        .render(&load("quad-over-plane"), Technique::Pcf, &options)
        .is_ok();
    assert!(gpu || std::env::var_os("CI").is_none(), "CI has lavapipe");
    for name in ["overlapping-quads", "sphere-over-plane"] {
        let mut scene = load(name);
        scene.camera.width = 64;
        scene.camera.height = 48;
        let techniques: Vec<Technique> = Technique::ALL
            .into_iter()
            .filter(|&t| gpu || Runs::of(t) != Runs::GpuOnly)
            .collect();
        let base: Vec<_> = techniques
            .iter()
            .map(|&t| renderer.render(&scene, t, &options).unwrap())
            .collect();
        for case in 0..3 {
            let axis = glam::DVec3::new(rng.range(-1., 1.), rng.range(-1., 1.), rng.range(-1., 1.))
                .normalize();
            let m = glam::DMat4::from_scale_rotation_translation(
                glam::DVec3::splat(10f64.powf(rng.range(-2.0, 2.0))),
                glam::DQuat::from_axis_angle(axis, rng.range(0.0, std::f64::consts::TAU)),
                glam::DVec3::new(
                    rng.range(-1e3, 1e3),
                    rng.range(-1e3, 1e3),
                    rng.range(-1e3, 1e3),
                ),
            );
            let moved = scene.transformed(&m);
            for (t, want) in techniques.iter().zip(&base) {
                let img = renderer.render(&moved, *t, &options).unwrap();
                let c = penumbra::geom::compare(&img, want).unwrap();
                println!(
                    "{name} case {case}: {t}: MAE {:.1e}, over 0.05 {:.2}%",
                    c.all.mae,
                    100.0 * c.all.share_over
                );
                assert!(
                    c.all.mae <= noise(*t) && c.all.share_over <= 0.005,
                    "{name} case {case}: {t}: {c:?}"
                );
            }
        }
    }
}

#[test]
fn a_hierarchy_kept_from_one_cpu_render_never_reaches_another_scene_s_image() {
    // The renderer keeps the last CPU render's ray-casting hierarchy for the next render of the
    // same triangles. A scene whose sphere moved, the same scene under another camera, and the
    // same scene again after another: each image is that of a renderer of its own, bit for bit,
    // whatever was rendered before it and whichever kind of hierarchy that took.
    let (scene, options) = small("sphere-over-plane");
    let moved = {
        let mut s = scene.clone();
        let by = glam::DMat4::from_translation(glam::DVec3::new(0.3, 0.0, 0.0));
        let meshes = std::sync::Arc::make_mut(&mut s.meshes);
        meshes[1].mesh = meshes[1].mesh.transformed(&by);
        meshes[1].transform = by * meshes[1].transform;
        s
    };
    let turned = {
        let mut s = scene.clone();
        s.camera.eye += glam::DVec3::new(0.5, 0.0, 0.0);
        s
    };
    assert_eq!(scene.meshes.len(), 2);
    let mut kept = Renderer::new(Backend::Cpu);
    for (s, t) in [
        (&scene, Technique::WedgesBlend),
        (&moved, Technique::WedgesBlend),
        (&scene, Technique::Reference),
        (&turned, Technique::DepthComplexity),
        (&moved, Technique::Hard),
        (&scene, Technique::WedgesBlend),
        (&moved, Technique::Reference),
    ] {
        let got = kept.render(s, t, &options).unwrap();
        let fresh = Renderer::new(Backend::Cpu).render(s, t, &options).unwrap();
        let differ = differing_pixels(&got.data, &fresh.data);
        assert_eq!(differ, 0, "{t}: {differ} pixels differ");
    }
    // The moved sphere's shadow is elsewhere: the images a stale hierarchy would give differ.
    let [a, b] = [&scene, &moved].map(|s| {
        Renderer::new(Backend::Cpu)
            .render(s, Technique::Hard, &options)
            .unwrap()
            .data
    });
    assert!(a.iter().zip(&b).filter(|(x, y)| x != y).count() > 20);
}

#[test]
fn the_renderer_s_shaded_preview_is_the_preview_of_its_own() {
    // The preview takes the hierarchy a volume technique's render kept, builds its own after a
    // reference's (a hierarchy for many rays), and is the same preview either way.
    let (scene, options) = small("sphere-over-plane");
    let mut renderer = Renderer::new(Backend::Cpu);
    for t in [
        Technique::WedgesBlend,
        Technique::Reference,
        Technique::Hard,
    ] {
        let v = penumbra::geom::VisibilityChannels::single(
            renderer.render(&scene, t, &options).unwrap(),
        );
        let got = renderer.shaded(&scene, &v).unwrap();
        let own = penumbra::geom::ShadedImage::render(&scene, &v).unwrap();
        assert_eq!(got, own, "{t}");
        assert!(got.rgb.iter().any(|&p| p != got.rgb[0]), "{t}");
    }
}
