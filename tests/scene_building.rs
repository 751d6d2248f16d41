//! Scenes built in code as users build them: any order of the builder gives the same image, a
//! scene lit by the sun alone renders, and lights aimed by a target or given by the sun's angles
//! render as the lights of their explicit vectors.

use glam::{DMat4, DVec2, DVec3};
use penumbra::{
    Backend, Camera, DistantLight, Light, RectLight, RenderOptions, Renderer, Scene, Technique,
    TriangleMesh, VisibilityImage,
};

fn ground() -> TriangleMesh {
    let corners = [[-4.0, -4.0], [-4.0, 4.0], [4.0, 4.0], [4.0, -4.0]];
    TriangleMesh::from_raw(
        "ground",
        &corners.map(|[x, z]| DVec3::new(x, 0.0, z)),
        &[[0, 1, 2], [0, 2, 3]],
    )
    .unwrap()
}

fn camera() -> Camera {
    Camera::look_at(
        DVec3::new(0.0, 4.0, 5.0),
        DVec3::ZERO,
        DVec3::Y,
        45.0,
        48,
        36,
    )
    .unwrap()
}

fn ball() -> DMat4 {
    DMat4::from_translation(DVec3::new(0.2, 1.0, 0.0)) * DMat4::from_scale(DVec3::splat(0.6))
}

fn render(scene: &Scene, technique: Technique) -> VisibilityImage {
    let options = RenderOptions {
        samples: 64,
        jitter: false,
    };
    Renderer::new(Backend::Cpu)
        .render(scene, technique, &options)
        .unwrap()
}

const TECHNIQUES: [Technique; 3] = [
    Technique::Hard,
    Technique::WedgesBlend,
    Technique::DepthComplexity,
];

#[test]
fn every_order_of_the_builder_gives_the_same_image() {
    let lamp = RectLight::aimed(DVec3::new(0.5, 4.0, 0.0), DVec3::ZERO, DVec2::splat(1.5)).unwrap();
    let sun = DistantLight::sun(135.0, 50.0, 4.0).unwrap();
    for light in [Light::Rect(lamp), Light::Distant(sun)] {
        let sphere = TriangleMesh::uv_sphere(8, 12);
        let orders = [
            Scene::new(camera())
                .with_light(light)
                .with_mesh("ground", &ground(), DMat4::IDENTITY)
                .with_mesh("ball", &sphere, ball()),
            Scene::new(camera())
                .with_mesh("ground", &ground(), DMat4::IDENTITY)
                .with_light(light)
                .with_mesh("ball", &sphere, ball()),
            Scene::new(camera())
                .with_mesh("ground", &ground(), DMat4::IDENTITY)
                .with_mesh("ball", &sphere, ball())
                .with_light(light),
        ];
        for technique in TECHNIQUES {
            let first = render(&orders[0], technique);
            // The ball casts a shadow: the image is not blank.
            let dark = first.data.iter().filter(|&&v| v < 0.5).count();
            assert!(dark > 20, "{light:?} {technique}: {dark} dark pixels");
            for other in &orders[1..] {
                assert_eq!(render(other, technique).data, first.data, "{technique}");
            }
        }
    }
}

#[test]
fn a_scene_without_a_light_is_refused_by_name() {
    let scene = Scene::new(camera()).with_mesh("ground", &ground(), DMat4::IDENTITY);
    let err = Renderer::new(Backend::Cpu)
        .render(&scene, Technique::Hard, &RenderOptions::default())
        .unwrap_err();
    assert!(err.to_string().contains("no light"), "{err}");
}

#[test]
fn aimed_lights_and_the_sun_s_angles_render_as_their_explicit_vectors() {
    let sphere = TriangleMesh::uv_sphere(8, 12);
    let scene = |light: Light| {
        Scene::new(camera())
            .with_mesh("ground", &ground(), DMat4::IDENTITY)
            .with_mesh("ball", &sphere, ball())
            .with_light(light)
    };
    // A lamp over the ball, aimed at the origin: its normal and tangent written out.
    let center = DVec3::new(1.0, 4.0, 0.5);
    let aimed = RectLight::aimed(center, DVec3::ZERO, DVec2::new(1.5, 1.0)).unwrap();
    let normal = -center.normalize();
    let tangent = DVec3::Y.cross(normal).normalize();
    let explicit = RectLight::new(center, normal, tangent, DVec2::new(1.5, 1.0)).unwrap();
    // The sun in the south-east, 50 degrees up: cos(50) (cos(135) N + sin(135) E) + sin(50) U.
    let (c, s) = (50f64.to_radians().cos(), 50f64.to_radians().sin());
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let direction = DVec3::new(c * h, s, c * h);
    let sun = DistantLight::sun(135.0, 50.0, 4.0).unwrap();
    let written = DistantLight::new(
        direction,
        DVec3::Y.cross(direction).normalize(),
        DVec2::splat(4.0),
    )
    .unwrap();
    for (given, vectors) in [
        (Light::Rect(aimed), Light::Rect(explicit)),
        (Light::Distant(sun), Light::Distant(written)),
    ] {
        for technique in TECHNIQUES {
            let (a, b) = (
                render(&scene(given), technique),
                render(&scene(vectors), technique),
            );
            let worst = a
                .data
                .iter()
                .zip(&b.data)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0f32, f32::max);
            assert!(worst <= 1e-4, "{given:?} {technique}: {worst}");
        }
    }
}
