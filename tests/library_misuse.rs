//! The library given any values, finite or not: its public constructors, a scene built in code
//! (transforms, lights, meshes and triangles as a program may set them, fields written
//! directly included), the front door's renders and the image writers and metrics. Each call
//! either succeeds with a sound result (V finite, in [0, 1], one value per pixel) or returns an
//! error; a panic fails the test with the values that caused it.

use std::panic::{AssertUnwindSafe, catch_unwind};

use glam::{DMat4, DQuat, DVec2, DVec3};
use penumbra::Technique;
use penumbra::geom::{
    Camera, DistantLight, RectLight, Rng, Scene, TriangleMesh, VisibilityImage, compare,
};
use penumbra::{Backend, RenderOptions, Renderer};

/// Values a program can hand the library: ordinary ones, boundaries and non-finite ones.
const VALUES: [f64; 16] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.5,
    3.0,
    1e-300,
    1e-9,
    1e9,
    1e15,
    1e300,
    f64::MAX,
    f64::MIN_POSITIVE,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
];

/// A value: half the time an ordinary one in [-4, 4], else one of [`VALUES`].
fn value(rng: &mut Rng) -> f64 {
    if rng.next_f64() < 0.5 {
        rng.next_f64() * 8.0 - 4.0
    } else {
        VALUES[(rng.next_f64() * VALUES.len() as f64) as usize % VALUES.len()]
    }
}

fn vec3(rng: &mut Rng) -> DVec3 {
    DVec3::new(value(rng), value(rng), value(rng))
}

/// A vector, mostly a sound one (so that the scene often renders), else any.
fn mostly(rng: &mut Rng, sound: DVec3) -> DVec3 {
    if rng.next_f64() < 0.7 {
        sound
    } else {
        vec3(rng)
    }
}

/// The values of one case, printed when it panics.
#[derive(Debug)]
struct Case {
    eye: DVec3,
    light: (DVec3, DVec3, DVec3, DVec2),
    sun: (f64, f64, f64),
    transform: (DVec3, f64, DVec3),
    corners: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    field: usize,
}

fn case(rng: &mut Rng) -> Case {
    let corners: Vec<DVec3> = (0..4)
        .map(|k| {
            let sound = DVec3::new((k & 1) as f64 - 0.5, 0.0, (k >> 1) as f64 - 0.5);
            mostly(rng, sound)
        })
        .collect();
    let index = |rng: &mut Rng| {
        if rng.next_f64() < 0.9 {
            (rng.next_f64() * 4.0) as u32 % 4
        } else {
            [4, 7, u32::MAX][(rng.next_f64() * 3.0) as usize % 3]
        }
    };
    let triangles = (0..2)
        .map(|_| [index(rng), index(rng), index(rng)])
        .collect();
    Case {
        eye: mostly(rng, DVec3::new(0.0, 3.0, 4.0)),
        light: (
            mostly(rng, DVec3::new(0.0, 4.0, 0.0)),
            mostly(rng, DVec3::NEG_Y),
            mostly(rng, DVec3::X),
            DVec2::new(value(rng).abs(), value(rng).abs()),
        ),
        sun: (value(rng) * 40.0, value(rng) * 20.0, value(rng).abs()),
        transform: (
            mostly(rng, DVec3::ONE),
            value(rng),
            mostly(rng, DVec3::new(0.0, 1.0, 0.0)),
        ),
        corners,
        triangles,
        field: (rng.next_f64() * 6.0) as usize,
    }
}

/// Every render of the front door on `scene` is an image of sound values or an error.
fn render_all(scene: &Scene) {
    let mut renderer = Renderer::new(Backend::Cpu);
    for t in [
        Technique::Hard,
        Technique::WedgesBlend,
        Technique::DepthComplexity,
        Technique::Reference,
    ] {
        let options = RenderOptions {
            samples: 4,
            jitter: false,
        };
        if let Ok(image) = renderer.render(scene, t, &options) {
            assert!(image.check().is_ok(), "{t}: {:?}", image.check());
            assert!(
                image.data.iter().all(|v| (0.0..=1.0).contains(v)),
                "{t}: V out of [0, 1]"
            );
        }
    }
}

/// The scene of `c`: any light, any mesh, any transform, and fields a program may write
/// directly after the constructors checked them.
fn run(c: &Case) {
    let camera = Camera::look_at(c.eye, DVec3::ZERO, DVec3::Y, 45.0, 8, 6);
    let light = RectLight::new(c.light.0, c.light.1, c.light.2, c.light.3);
    let sun = DistantLight::sun(c.sun.0, c.sun.1, c.sun.2);
    let _ = DistantLight::new(c.light.1, c.light.2, c.light.3);
    let mesh = TriangleMesh::from_raw("m", &c.corners, &c.triangles);
    let transform = DMat4::from_scale_rotation_translation(
        c.transform.0,
        DQuat::from_axis_angle(DVec3::Y, c.transform.1),
        c.transform.2,
    );
    let (Ok(camera), Ok(mesh)) = (camera, mesh) else {
        return;
    };
    let mut scene = Scene::new(camera).with_mesh("ground", &TriangleMesh::quad(), DMat4::IDENTITY);
    scene = scene.with_mesh("m", &mesh, transform);
    if let Ok(l) = light {
        scene = scene.with_light(l);
    }
    if let Ok(s) = sun {
        scene = scene.with_light(s);
    }
    render_all(&scene);
    // Fields written directly, past the constructors' checks.
    let mut s = scene.clone();
    match c.field {
        0 => s.camera.eye.x = c.light.3.x * f64::NAN,
        1 => {
            let mut m = TriangleMesh::quad();
            m.triangles[0] = c.triangles[0];
            m.positions[1] = c.corners[1];
            s = s.with_mesh("raw", &m, transform);
        }
        2 => {
            if let Some(l) = s.lights.first_mut() {
                l.light = match l.light {
                    penumbra::geom::Light::Rect(mut r) => {
                        r.center = c.light.0 * value(&mut Rng::new(7));
                        r.size = c.light.3;
                        r.into()
                    }
                    penumbra::geom::Light::Distant(mut d) => {
                        d.direction = c.light.1;
                        d.into()
                    }
                };
            }
        }
        3 => s.camera.fov_y_deg = c.sun.0,
        4 => s.camera.forward = c.light.1,
        _ => s.lights.clear(),
    }
    render_all(&s);
    if s.lights.len() > 1 {
        let _ = Renderer::new(Backend::Cpu).render_lights(&s, Technique::Hard, &Default::default());
    }
}

#[test]
fn no_value_given_to_the_library_panics_it() {
    let mut rng = Rng::new(0x5eed);
    let mut rendered = 0;
    for k in 0..400 {
        let c = case(&mut rng);
        if let Err(e) = catch_unwind(AssertUnwindSafe(|| run(&c))) {
            let why = e
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            panic!("case {k} panicked ({why}): {c:#?}");
        }
        rendered += 1;
    }
    assert_eq!(rendered, 400);
}

/// Images of any shape and any values: written, compared and measured, or refused; a refused
/// write leaves no file, not even its temporary.
#[test]
fn images_of_any_shape_are_written_and_compared_or_refused() {
    let dir = std::env::temp_dir().join(format!("penumbra-images-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut rng = Rng::new(11);
    for k in 0..200 {
        let dims = [0u32, 1, 2, 5];
        let pick = |rng: &mut Rng| dims[(rng.next_f64() * 4.0) as usize % 4];
        let (w, h) = (pick(&mut rng), pick(&mut rng));
        let len = match k % 3 {
            0 => (w * h) as usize,
            1 => (w * h) as usize / 2,
            _ => (w * h) as usize + 1,
        };
        let data: Vec<f32> = (0..len).map(|_| value(&mut rng) as f32).collect();
        let image = VisibilityImage {
            width: w,
            height: h,
            data,
        };
        let sound = image.check().is_ok();
        let path = dir.join(format!("{k}.exr"));
        let written = catch_unwind(AssertUnwindSafe(|| image.write_exr(&path)))
            .unwrap_or_else(|_| panic!("write_exr panicked on {w} x {h}, {len} values"));
        assert_eq!(
            written.is_ok(),
            sound,
            "{w} x {h}, {len} values: {written:?}"
        );
        let png = catch_unwind(AssertUnwindSafe(|| image.write_png(&dir.join("p.png"))))
            .unwrap_or_else(|_| panic!("write_png panicked on {w} x {h}, {len} values"));
        assert_eq!(png.is_ok(), image.check_shape().is_ok(), "{png:?}");
        let other = VisibilityImage::filled(w, h, 0.5);
        let c = catch_unwind(AssertUnwindSafe(|| compare(&image, &other)))
            .unwrap_or_else(|_| panic!("compare panicked on {w} x {h}, {len} values"));
        assert_eq!(c.is_ok(), sound && other.check().is_ok(), "{c:?}");
        if let Ok(c) = c {
            assert!(c.all.mae.is_finite() && c.all.max.is_finite());
        }
    }
    // Nothing but the sound images' files: no temporary left by a refused write.
    for e in std::fs::read_dir(&dir).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!name.starts_with('.'), "left behind: {name}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
