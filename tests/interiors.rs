//! A room lit from its ceiling: a closed room around the light (wound outwards or inwards), a
//! table on a leg, and a panel 3 cm below the ceiling or flush with it. On the CPU, `hard`
//! is the hard reference and `wedges-blend` the soft one: a closed mesh around the light is
//! seen from inside, not as a solid whose outside faces the light.

use penumbra::glam::{DMat4, DVec2, DVec3};
use penumbra::{
    Backend, Camera, RectLight, RenderOptions, Renderer, Scene, Technique, TriangleMesh, compare,
};

/// The box from `lo` to `hi`, wound outwards, or inwards where `inward`.
fn block(lo: DVec3, hi: DVec3, inward: bool) -> TriangleMesh {
    let size = hi - lo;
    let mut m = TriangleMesh::cube()
        .transformed(&(DMat4::from_translation((lo + hi) * 0.5) * DMat4::from_scale(size)));
    if inward {
        for t in &mut m.triangles {
            t.swap(1, 2);
        }
    }
    m
}

/// The room, wound inwards where `inward`, with a table on a leg, lit by a 1.2 x 0.6 panel
/// facing down at `height` (the ceiling is at 3), seen at 64 x 48.
fn room(inward: bool, height: f64) -> Scene {
    let camera = Camera::look_at(
        DVec3::new(2.5, 1.6, 2.0),
        DVec3::new(-1.0, 0.6, -1.5),
        DVec3::Y,
        60.0,
        64,
        48,
    )
    .unwrap();
    let panel = RectLight::new(
        DVec3::new(0.0, height, 0.0),
        DVec3::NEG_Y,
        DVec3::X,
        DVec2::new(1.2, 0.6),
    )
    .unwrap();
    let room = block(
        DVec3::new(-3.0, 0.0, -2.5),
        DVec3::new(3.0, 3.0, 2.5),
        inward,
    );
    let table = block(
        DVec3::new(-0.8, 0.7, -0.5),
        DVec3::new(0.8, 0.75, 0.5),
        false,
    );
    let leg = block(
        DVec3::new(-0.7, 0.0, -0.4),
        DVec3::new(-0.6, 0.7, -0.3),
        false,
    );
    Scene::new(camera)
        .with_light(panel)
        .with_mesh("room", &room, DMat4::IDENTITY)
        .with_mesh("table", &table, DMat4::IDENTITY)
        .with_mesh("leg", &leg, DMat4::IDENTITY)
}

#[test]
fn a_room_lit_from_its_ceiling_on_the_cpu() {
    let options = RenderOptions::default();
    for inward in [false, true] {
        for height in [2.97, 3.0] {
            let scene = room(inward, height);
            let case = format!(
                "room wound {}, panel at {height}",
                if inward { "in" } else { "out" }
            );
            let mut r = Renderer::new(Backend::Cpu);
            let mut render = |t| r.render(&scene, t, &options).unwrap();
            let reference = render(Technique::Reference);
            let hard =
                compare(&render(Technique::Hard), &render(Technique::HardReference)).unwrap();
            assert!(
                hard.all.equal >= 0.995,
                "{case}: hard {:.4} equal",
                hard.all.equal
            );
            let soft = compare(&render(Technique::WedgesBlend), &reference).unwrap();
            assert!(
                soft.penumbra.pixels > 50,
                "{case}: {} penumbra pixels",
                soft.penumbra.pixels
            );
            assert!(
                soft.all.mae <= 0.05 && soft.penumbra.mae <= 0.05,
                "{case}: wedges-blend MAE {:.3}, penumbra {:.3}",
                soft.all.mae,
                soft.penumbra.mae
            );
        }
    }
}

/// The same on the GPU: its terminator takes a closed mesh around the lamp from inside too.
#[test]
fn a_room_lit_from_its_ceiling_on_the_gpu() {
    let scene = room(true, 3.0);
    let options = RenderOptions::default();
    let mut gpu = Renderer::new(Backend::Gpu);
    let soft = match gpu.render(&scene, Technique::WedgesBlend, &options) {
        Ok(v) => v,
        Err(e @ penumbra::RenderError::NoGpu { .. }) if std::env::var_os("CI").is_none() => {
            println!("SKIPPED (no adapter): {e}");
            return;
        }
        Err(e) => panic!("{e}"),
    };
    let reference = Renderer::new(Backend::Cpu)
        .render(&scene, Technique::Reference, &options)
        .unwrap();
    let c = compare(&soft, &reference).unwrap();
    assert!(
        c.penumbra.pixels > 50,
        "{} penumbra pixels",
        c.penumbra.pixels
    );
    assert!(
        c.all.mae <= 0.05 && c.penumbra.mae <= 0.05,
        "GPU wedges-blend MAE {:.3}, penumbra {:.3}",
        c.all.mae,
        c.penumbra.mae
    );
}
