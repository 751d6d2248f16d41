//! Occluders that hold the light's centre where the light's plane cuts them. A closed one that
//! shuts the centre in from the eye is a solid the light shines into: `hard` is the hard
//! reference there, and the front door warns of the soft techniques built from the centre. An
//! open one (a bowl, a lampshade) is right.

use glam::{DMat4, DVec2, DVec3};
use penumbra::{Backend, RenderOptions, Renderer, Technique, compare};
use penumbra_geom::Camera;
use penumbra_geom::{RectLight, Scene, TriangleMesh};
use penumbra_volumes::{Enclosure, enclosure};

/// A ground under a 1 x 1 light 3 above it, and `occluder` (in the light's frame: its plane
/// y = 3, its centre at the origin).
fn scene(occluder: &TriangleMesh) -> Scene {
    let c = DVec3::new;
    let ground = penumbra_testkit::square(0.0, 6.0);
    let camera = Camera::look_at(c(0.0, 6.0, 8.0), c(0.0, 0.5, 0.0), DVec3::Y, 45.0, 64, 48);
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

fn render(scene: &Scene, technique: Technique) -> penumbra::VisibilityImage {
    Renderer::new(Backend::Cpu)
        .render(scene, technique, &RenderOptions::default())
        .unwrap()
}

#[test]
fn a_light_shut_in_a_closed_mesh_seen_from_outside_is_warned_of() {
    let around = scene(&sphere(0.3));
    let lit = around.lit(0);
    let tris = |m: &penumbra_geom::SceneMesh| {
        (0..m.mesh.triangles.len())
            .map(|t| m.mesh.triangle(t))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        enclosure(tris(&lit.meshes[1]), &lit.light, lit.camera.eye),
        Enclosure::Sealed
    );
    assert_eq!(
        enclosure(tris(&lit.meshes[0]), &lit.light, lit.camera.eye),
        Enclosure::Apart
    );
    for t in [Technique::Wedges, Technique::WedgesBlend] {
        let w = warnings(&around, t);
        assert_eq!(w.len(), 1, "{t}: {w:?}");
        assert!(
            w[0].starts_with(
                "mesh 1 (occluder) closes round the light's centre and the eye is outside it"
            ) && w[0].contains(&format!("{t} builds its shadow from that centre"))
                && w[0].contains("hard, depth-complexity and the reference are exact here"),
            "{}",
            w[0]
        );
    }
    // The hard shadow is the hard reference's, and the techniques that sample the light have
    // nothing to warn of.
    for t in [
        Technique::Hard,
        Technique::DepthComplexity,
        Technique::Reference,
    ] {
        assert_eq!(warnings(&around, t), Vec::<String>::new(), "{t}");
    }
    assert_eq!(
        render(&around, Technique::Hard),
        render(&around, Technique::HardReference)
    );
    // Cut by the plane beside the centre, through the light's rectangle (warned of as such),
    // and beside the rectangle (nothing to warn of); and the first sphere wound inwards.
    let w = warnings(&scene(&sphere(0.9)), Technique::WedgesBlend);
    assert!(
        w.len() == 1 && w[0].starts_with("mesh 1 (occluder) passes through the light's rectangle"),
        "{w:?}"
    );
    assert!(warnings(&scene(&sphere(1.2)), Technique::WedgesBlend).is_empty());
    let inward = scene(&sphere(-0.3).flipped());
    assert_eq!(warnings(&inward, Technique::Wedges).len(), 1);
}

#[test]
fn open_meshes_whose_cut_surrounds_the_light_centre() {
    // The sphere without its cap above y = 0.3: open, its cut by the plane still a circle
    // around the centre. Its hard shadow is right.
    let s = sphere(0.2);
    let cap = |t: &[u32; 3]| t.iter().all(|&v| s.positions[v as usize].y > 0.3);
    let keep: Vec<[u32; 3]> = s.triangles.iter().filter(|t| !cap(t)).copied().collect();
    let open = TriangleMesh::from_raw("bowl", &s.positions, &keep).unwrap();
    let around = scene(&open);
    let hard = compare(
        &render(&around, Technique::Hard),
        &render(&around, Technique::HardReference),
    )
    .unwrap();
    assert!(hard.all.equal >= 0.995, "hard {:.4} equal", hard.all.equal);
    // The light reaches past the bowl's rim: the bowl passes through the light's rectangle,
    // and the soft techniques built from the centre are warned of.
    let w = warnings(&around, Technique::WedgesBlend);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].starts_with("mesh 1 (occluder) passes through the light's rectangle"),
        "{}",
        w[0]
    );
    // A lampshade: a tube open at both ends around a light wholly inside it (0.4 across, the
    // tube 1 across) is right.
    let tube = TriangleMesh::from_raw(
        "tube",
        &(0..48)
            .map(|i| {
                let a = std::f64::consts::TAU * (i / 2) as f64 / 24.0;
                DVec3::new(
                    0.5 * a.cos(),
                    if i % 2 == 0 { -1.0 } else { 0.5 },
                    0.5 * a.sin(),
                )
            })
            .collect::<Vec<_>>(),
        &(0..24u32)
            .flat_map(|i| {
                let (a, b, c, d) = (2 * i, 2 * i + 1, (2 * i + 2) % 48, (2 * i + 3) % 48);
                [[a, c, b], [b, c, d]]
            })
            .collect::<Vec<_>>(),
    )
    .unwrap();
    let mut shaded = scene(&tube);
    shaded.lights[0].light = RectLight::new(
        DVec3::new(0.0, 3.0, 0.0),
        DVec3::NEG_Y,
        DVec3::X,
        DVec2::splat(0.4),
    )
    .unwrap()
    .into();
    assert!(warnings(&shaded, Technique::WedgesBlend).is_empty());
    let truth = render(&shaded, Technique::Reference);
    let soft = compare(&render(&shaded, Technique::WedgesBlend), &truth).unwrap();
    println!(
        "lampshade: wedges-blend MAE {:.4}, penumbra {:.4} over {} pixels",
        soft.all.mae, soft.penumbra.mae, soft.penumbra.pixels
    );
    assert!(
        soft.penumbra.pixels > 100,
        "{} penumbra pixels",
        soft.penumbra.pixels
    );
    assert!(
        soft.all.mae <= 0.05 && soft.penumbra.mae <= 0.05,
        "wedges-blend MAE {:.3}, penumbra {:.3}",
        soft.all.mae,
        soft.penumbra.mae
    );
}

#[test]
fn meshes_through_the_light_s_rectangle_are_warned_of() {
    let scene = penumbra_testkit::through_the_light();
    let w = warnings(&scene, Technique::WedgesBlend);
    assert!(
        !w.is_empty()
            && w.iter()
                .all(|w| w.contains("passes through the light's rectangle")),
        "{w:?}"
    );
    // The light's plane cuts the ground, far from the light: nothing to warn of.
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/fixtures/scenes/tilted-light.toml"
    );
    let tilted = Scene::load(std::path::Path::new(path)).unwrap();
    assert!(warnings(&tilted, Technique::WedgesBlend).is_empty());
}
