//! A room lit from its ceiling: a closed room around the light (wound outwards or inwards), a
//! table on a leg, and a panel 3 cm below the ceiling or flush with it; and the interior
//! fixtures (`fixtures/interiors/`), every technique on the CPU and the GPU. A closed mesh
//! around the light and the eye is seen from inside, not as a solid whose outside faces the
//! light.

use penumbra::glam::{DMat4, DVec2, DVec3};
use penumbra::{
    Backend, Camera, LitScene, RectLight, RenderOptions, Renderer, Scene, Technique, TriangleMesh,
    VisibilityImage, compare,
};

use crate::common::gpu_renderer;

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
    let Some(mut gpu) = gpu_renderer() else {
        return;
    };
    let soft = gpu
        .render(&scene, Technique::WedgesBlend, &options)
        .unwrap();
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

/// The interior fixture `name`, at 96 x 72.
fn interior(name: &str) -> LitScene {
    let path = format!(
        "{}/fixtures/interiors/{name}.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut scene = Scene::load(std::path::Path::new(&path)).unwrap().lit(0);
    scene.set_size(96, 72);
    scene
}

/// `technique`'s image of `scene` on `backend`, with no warning.
fn rendered(
    r: &mut Renderer,
    scene: &LitScene,
    technique: Technique,
    options: &RenderOptions,
) -> Result<VisibilityImage, penumbra::RenderError> {
    let frame = r.render_frame(scene, technique, options, None, &|_| {})?;
    assert!(
        frame.warnings.is_empty(),
        "{technique}: {:?}",
        frame.warnings
    );
    Ok(frame.image)
}

const INTERIORS: [&str; 2] = ["interior", "interior-flush"];

/// On the CPU: `hard` the hard reference, `wedges-blend` within 0.05 of the reference over its
/// penumbra, and `depth-complexity` given the reference's samples the reference itself.
#[test]
fn the_interiors_on_the_cpu() {
    let options = RenderOptions::default();
    for name in INTERIORS {
        let scene = interior(name);
        let mut r = Renderer::new(Backend::Cpu);
        let mut render = |t, o: &RenderOptions| rendered(&mut r, &scene, t, o).unwrap();
        let truth = render(Technique::Reference, &options);
        let hard = compare(
            &render(Technique::Hard, &options),
            &render(Technique::HardReference, &options),
        )
        .unwrap();
        assert!(
            hard.all.equal >= 0.995,
            "{name}: hard {:.4} equal",
            hard.all.equal
        );
        let soft = compare(&render(Technique::WedgesBlend, &options), &truth).unwrap();
        assert!(
            soft.penumbra.pixels > 300,
            "{name}: {} penumbra pixels",
            soft.penumbra.pixels
        );
        assert!(
            soft.penumbra.mae <= 0.05 && soft.umbra_lit <= 0.02,
            "{name}: wedges-blend penumbra MAE {:.3}, umbra lit {:.3}",
            soft.penumbra.mae,
            soft.umbra_lit
        );
        let jittered = RenderOptions {
            jitter: true,
            ..options
        };
        let exact = compare(&render(Technique::DepthComplexity, &jittered), &truth).unwrap();
        assert!(
            exact.all.equal >= 0.999,
            "{name}: depth-complexity {:.4} equal to the reference",
            exact.all.equal
        );
    }
}

/// On the GPU: `hard` the hard reference, `wedges-blend` and `depth-complexity` as on the CPU,
/// and every shadow-map technique within 0.05 of the reference over the whole image with at
/// most 2% of the umbra lit.
#[test]
fn the_interiors_on_the_gpu() {
    let options = RenderOptions::default();
    let Some(mut gpu) = gpu_renderer() else {
        return;
    };
    let mut cpu = Renderer::new(Backend::Cpu);
    for name in INTERIORS {
        let scene = interior(name);
        let hard = rendered(&mut gpu, &scene, Technique::Hard, &options).unwrap();
        let mut on_cpu = |t| rendered(&mut cpu, &scene, t, &options).unwrap();
        let truth = on_cpu(Technique::Reference);
        let c = compare(&hard, &on_cpu(Technique::HardReference)).unwrap();
        assert!(
            c.all.equal >= 0.995,
            "{name}: GPU hard {:.4} equal",
            c.all.equal
        );
        let mut on_gpu = |t| rendered(&mut gpu, &scene, t, &options).unwrap();
        for t in [Technique::WedgesBlend, Technique::DepthComplexity] {
            let c = compare(&on_gpu(t), &truth).unwrap();
            assert!(
                c.penumbra.mae <= 0.05 && c.umbra_lit <= 0.02,
                "{name}: GPU {t} penumbra MAE {:.3}, umbra lit {:.3}",
                c.penumbra.mae,
                c.umbra_lit
            );
        }
        for t in [
            Technique::Pcf,
            Technique::Pcss,
            Technique::FractionalDisk,
            Technique::Mdsm,
            Technique::Gaussian,
        ] {
            let c = compare(&on_gpu(t), &truth).unwrap();
            println!(
                "{name}: {t} MAE {:.4}, umbra lit {:.4}",
                c.all.mae, c.umbra_lit
            );
            assert!(
                c.all.mae <= 0.05 && c.umbra_lit <= 0.02,
                "{name}: {t} MAE {:.3}, umbra lit {:.3}",
                c.all.mae,
                c.umbra_lit
            );
        }
    }
}

/// A lamp flush with a ceiling at 3.3, the room's vertices rounded to `f32` as OBJ, PLY and
/// glTF store them: the ceiling then lies 5e-8 in front of the lamp, where it would hide the
/// whole lamp (the reference 0.6 at random, the exact evaluator 0). Within `f32` rounding of the
/// lamp's plane it is in that plane.
#[test]
fn a_lamp_flush_with_a_ceiling_stored_in_f32() {
    let mut scene = room(true, 3.3);
    let room = {
        let m = &scene.meshes[0].mesh;
        let mut m = m.clone();
        for p in &mut m.positions {
            if p.y > 2.0 {
                p.y = 3.3f32 as f64;
            }
        }
        m
    };
    assert!(
        (3.3f32 as f64) < 3.3,
        "the ceiling should lie in front of the lamp"
    );
    scene.meshes = std::sync::Arc::new(
        scene
            .meshes
            .iter()
            .enumerate()
            .map(|(i, m)| {
                let mut m = m.clone();
                if i == 0 {
                    m.mesh = room.clone();
                }
                m
            })
            .collect(),
    );
    let options = RenderOptions {
        samples: 64,
        jitter: true,
    };
    let mut r = Renderer::new(Backend::Cpu);
    let truth = r.render(&scene, Technique::Reference, &options).unwrap();
    let lit = truth.data.iter().filter(|&&v| v > 0.99).count();
    assert!(
        lit * 2 > truth.data.len(),
        "{lit} of {} pixels lit",
        truth.data.len()
    );
    for (t, o) in [
        (Technique::DepthComplexity, options),
        (Technique::WedgesBlend, RenderOptions::default()),
    ] {
        let c = compare(&r.render(&scene, t, &o).unwrap(), &truth).unwrap();
        assert!(
            c.all.mae <= 0.01,
            "{t}: MAE {:.3} against the reference",
            c.all.mae
        );
    }
    let defaults = RenderOptions::default();
    let hard = compare(
        &r.render(&scene, Technique::Hard, &defaults).unwrap(),
        &r.render(&scene, Technique::HardReference, &defaults)
            .unwrap(),
    )
    .unwrap();
    assert!(hard.all.equal >= 0.995, "hard {:.4} equal", hard.all.equal);
}

/// A room 5 x 3 x 5 with a recess 1.4 x 0.3 x 1.0 in its ceiling, wound outwards, and a block
/// on its floor, lit by a 1.2 x 0.8 lamp 0.15 into the recess: the lamp's plane cuts the
/// recess's walls, and the ceiling around the recess hides the lamp from the upper walls.
fn recessed_room() -> Scene {
    let (x, y, z, rx, rz, top) = (2.5, 3.0, 2.5, 0.7, 0.5, 3.3);
    let mut positions: Vec<DVec3> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut quad = |q: [DVec3; 4]| {
        let index = |p: DVec3, positions: &mut Vec<DVec3>| {
            positions.iter().position(|&v| v == p).unwrap_or_else(|| {
                positions.push(p);
                positions.len() - 1
            }) as u32
        };
        let i = q.map(|p| index(p, &mut positions));
        triangles.extend([[i[0], i[1], i[2]], [i[0], i[2], i[3]]]);
    };
    let c = DVec3::new;
    quad([c(-x, 0.0, -z), c(x, 0.0, -z), c(x, 0.0, z), c(-x, 0.0, z)]);
    let outer = [(-x, -z), (x, -z), (x, z), (-x, z)];
    let inner = [(-rx, -rz), (rx, -rz), (rx, rz), (-rx, rz)];
    for k in 0..4 {
        let (a, b) = (outer[k], outer[(k + 1) % 4]);
        let (p, q) = (inner[k], inner[(k + 1) % 4]);
        quad([
            c(a.0, 0.0, a.1),
            c(a.0, y, a.1),
            c(b.0, y, b.1),
            c(b.0, 0.0, b.1),
        ]);
        quad([
            c(a.0, y, a.1),
            c(p.0, y, p.1),
            c(q.0, y, q.1),
            c(b.0, y, b.1),
        ]);
        quad([
            c(p.0, y, p.1),
            c(p.0, top, p.1),
            c(q.0, top, q.1),
            c(q.0, y, q.1),
        ]);
    }
    quad([
        c(-rx, top, -rz),
        c(-rx, top, rz),
        c(rx, top, rz),
        c(rx, top, -rz),
    ]);
    let room = TriangleMesh::from_raw("recessed room", &positions, &triangles).unwrap();
    let camera = Camera::look_at(
        DVec3::new(2.2, 1.6, 2.2),
        DVec3::new(-1.0, 0.6, -1.2),
        DVec3::Y,
        60.0,
        64,
        48,
    )
    .unwrap();
    let lamp = RectLight::new(
        DVec3::new(0.0, 3.15, 0.0),
        DVec3::NEG_Y,
        DVec3::X,
        DVec2::new(1.2, 0.8),
    )
    .unwrap();
    Scene::new(camera)
        .with_light(lamp)
        .with_mesh("room", &room, DMat4::IDENTITY)
        .with_mesh(
            "block",
            &block(
                DVec3::new(-0.9, 0.0, -0.83),
                DVec3::new(0.3, 0.45, -0.03),
                false,
            ),
            DMat4::IDENTITY,
        )
}

/// Under the recessed lamp: `hard` is the hard reference on the CPU and the GPU (the room keeps
/// the rule of closed meshes though the lamp's plane cuts it, and a point facing away from the
/// lamp's centre is in its hard shadow), and `depth-complexity` on the GPU is the CPU's within
/// a sample (every pixel is counted again in a room).
#[test]
fn a_recessed_lamp() {
    let scene = recessed_room();
    let options = RenderOptions::default();
    let mut cpu = Renderer::new(Backend::Cpu);
    let hard_reference = cpu
        .render(&scene, Technique::HardReference, &options)
        .unwrap();
    let shadowed = hard_reference.data.iter().filter(|&&v| v == 0.0).count();
    assert!(shadowed > 200, "{shadowed} pixels in the hard shadow");
    let hard = compare(
        &cpu.render(&scene, Technique::Hard, &options).unwrap(),
        &hard_reference,
    )
    .unwrap();
    assert_eq!(hard.all.equal, 1.0, "CPU hard");
    let exact = cpu
        .render(&scene, Technique::DepthComplexity, &options)
        .unwrap();
    let Some(mut gpu) = gpu_renderer() else {
        return;
    };
    let gpu_hard = gpu.render(&scene, Technique::Hard, &options).unwrap();
    let c = compare(&gpu_hard, &hard_reference).unwrap();
    assert!(c.all.equal >= 0.995, "GPU hard {:.4} equal", c.all.equal);
    let dc = compare(
        &gpu.render(&scene, Technique::DepthComplexity, &options)
            .unwrap(),
        &exact,
    )
    .unwrap();
    assert!(
        dc.all.max <= 1.0 / 256.0 + 1e-6,
        "GPU depth-complexity off the CPU's by {}",
        dc.all.max
    );
    // The recess's rim, 0.15 in front of the lamp, casts penumbrae wider than the shadow maps'
    // filters: they say so, and the volumes do not.
    let pcss = gpu
        .render_frame(&scene.lit(0), Technique::Pcss, &options, None, &|_| {})
        .unwrap();
    assert!(
        matches!(
            pcss.warnings[..],
            [penumbra::Warning::NearLight { mesh: 0, .. }]
        ),
        "{:?}",
        pcss.warnings
    );
    let wedges = gpu
        .render_frame(
            &scene.lit(0),
            Technique::WedgesBlend,
            &options,
            None,
            &|_| {},
        )
        .unwrap();
    assert!(wedges.warnings.is_empty(), "{:?}", wedges.warnings);
}
