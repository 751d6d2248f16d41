//! Occluders that hold the light's centre where the light's plane cuts them: the techniques
//! built from the centre cannot be right there, and the front door says so.

use glam::{DMat4, DVec2, DVec3};
use penumbra::{Backend, RenderOptions, Renderer, Technique};
use penumbra_geom::Camera;
use penumbra_geom::{RectLight, Scene, TriangleMesh};
use penumbra_volumes::Volumes;

/// A ground under a 1 x 1 light 3 above it, and `occluder` (in the light's frame: its plane
/// y = 3, its centre at the origin).
fn scene(occluder: &TriangleMesh) -> Scene {
    let c = DVec3::new;
    let ground = penumbra_testkit::square(0.0, 6.0);
    let camera = Camera::look_at(c(0.0, 6.0, 8.0), c(0.0, 0.5, 0.0), DVec3::Y, 45.0, 16, 12);
    let light = RectLight::new(c(0.0, 3.0, 0.0), DVec3::NEG_Y, DVec3::X, DVec2::ONE).unwrap();
    Scene::new(camera.unwrap())
        .with_light(light)
        .with_mesh("ground", &ground, DMat4::IDENTITY)
        .with_mesh(
            "occluder",
            occluder,
            DMat4::from_translation(c(0.0, 3.0, 0.0)),
        )
}

/// A sphere of radius 0.6 centred `x` beside the light's centre, in the light's plane.
fn sphere(x: f64) -> TriangleMesh {
    TriangleMesh::uv_sphere(16, 24).transformed(
        &(DMat4::from_translation(DVec3::new(x, 0.0, 0.0)) * DMat4::from_scale(DVec3::splat(0.6))),
    )
}

fn warnings(scene: &Scene, technique: Technique) -> Vec<String> {
    Renderer::new(Backend::Cpu)
        .render_frame(
            &scene.lit(0),
            technique,
            &RenderOptions::default(),
            None,
            &|_| {},
        )
        .unwrap()
        .warnings
        .iter()
        .map(ToString::to_string)
        .collect()
}

#[test]
fn a_closed_mesh_around_the_light_centre_is_warned_of() {
    let around = scene(&sphere(0.3));
    assert_eq!(Volumes::build(&around.lit(0)).enclosing_light_centre(), [1]);
    for t in [Technique::Hard, Technique::Wedges, Technique::WedgesBlend] {
        let w = warnings(&around, t);
        assert_eq!(w.len(), 1, "{t}: {w:?}");
        assert!(
            w[0].starts_with("mesh 1 (occluder) holds the light's centre")
                && w[0].contains(&format!("{t} builds its shadow from that centre"))
                && w[0].contains("depth-complexity is exact there"),
            "{}",
            w[0]
        );
    }
    // The techniques that sample the light have nothing to warn of.
    for t in [Technique::DepthComplexity, Technique::Reference] {
        assert_eq!(warnings(&around, t), Vec::<String>::new(), "{t}");
    }
    // Cut by the plane, but beside the centre; and the same sphere wound inwards.
    let beside = scene(&sphere(0.9));
    assert!(
        Volumes::build(&beside.lit(0))
            .enclosing_light_centre()
            .is_empty()
    );
    assert!(warnings(&beside, Technique::WedgesBlend).is_empty());
    let inward = scene(&sphere(-0.3).flipped());
    assert_eq!(warnings(&inward, Technique::Wedges).len(), 1);
}

#[test]
fn an_open_mesh_whose_cut_surrounds_the_light_centre_is_warned_of() {
    // The sphere without its cap above y = 0.3: open, its cut by the plane still a circle
    // around the centre.
    let s = sphere(0.2);
    let cap = |t: &[u32; 3]| t.iter().all(|&v| s.positions[v as usize].y > 0.3);
    let keep: Vec<[u32; 3]> = s.triangles.iter().filter(|t| !cap(t)).copied().collect();
    let open = TriangleMesh::from_raw("bowl", &s.positions, &keep).unwrap();
    let around = scene(&open);
    assert_eq!(Volumes::build(&around.lit(0)).enclosing_light_centre(), [1]);
    assert_eq!(warnings(&around, Technique::WedgesBlend).len(), 1);
    // Half of it (x > 0.2): its cut a half circle that does not go round the centre.
    let half: Vec<[u32; 3]> = keep
        .iter()
        .filter(|t| t.iter().all(|&v| s.positions[v as usize].x >= 0.2))
        .copied()
        .collect();
    let half = TriangleMesh::from_raw("half", &s.positions, &half).unwrap();
    assert!(warnings(&scene(&half), Technique::WedgesBlend).is_empty());
}

#[test]
fn the_box_through_the_light_plane_beside_its_centre_is_not_warned_of() {
    let scene = penumbra_testkit::through_the_light();
    assert!(
        Volumes::build(&scene.lit(0))
            .enclosing_light_centre()
            .is_empty()
    );
    assert!(warnings(&scene, Technique::WedgesBlend).is_empty());
}
