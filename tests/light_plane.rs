//! Occluders through the light's plane: only their part in front of it hides light.

use glam::{DQuat, DVec3};
use penumbra::Technique;
use penumbra::geom::Rng;
use penumbra::geom::compare;
use penumbra::geom::{LightSamples, Reference};
use penumbra::volumes::CpuRenderer;

use crate::volumes::{exact_in_the_air, planar_shapes, single_occluder_scene};

#[test]
fn planar_occluders_through_the_light_plane_stay_exact() {
    // A quad and an L, tilted 20 to 70 degrees about a horizontal axis through a point near the
    // light's plane (y = 5): part of each lies behind the light and hides nothing. The light's
    // plane cuts them, and the wedges of the cut, with the clipped outline, stay exact.
    let mut rng = Rng::new(9);
    for (shape, pts, tris) in planar_shapes() {
        let (mut worst, mut penumbra, mut cut) = (0.0f64, 0, 0);
        for case in 0..10 {
            let axis = DVec3::new(rng.range(-1., 1.), 0.0, rng.range(-1., 1.)).normalize();
            let tilt = rng.range(20f64, 70.) * if rng.range(0., 1.) < 0.5 { -1. } else { 1. };
            let rot = DQuat::from_axis_angle(axis, tilt.to_radians());
            let at = DVec3::new(rng.range(-0.5, 0.5), 5.0 + rng.range(-0.2, 0.2), 0.0);
            let moved: Vec<DVec3> = pts.iter().map(|&p| rot * p + at).collect();
            let scene = single_occluder_scene(&moved, &tris);
            let r = CpuRenderer::new(&scene.lit(0));
            cut += r
                .volumes
                .wedges
                .iter()
                .filter(|w| w.caster.is_some())
                .count();
            let lowest = moved.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
            let (w, n) = exact_in_the_air(
                &r,
                &mut rng,
                lowest,
                &[Technique::Wedges, Technique::WedgesBlend],
                &format!("{shape}, case {case}"),
            );
            worst = worst.max(w);
            penumbra += n;
        }
        println!(
            "{shape} through the light: wedges and wedges-blend vs exact, max |error| {worst:.2e} over 1000 points ({penumbra} in penumbra), {cut} wedges of cut meshes"
        );
        assert!(penumbra > 150, "{shape}: too few penumbra points");
        assert!(
            cut >= 30,
            "{shape}: the light's plane should cut every case"
        );
    }
}

#[test]
fn a_box_and_a_quad_through_the_light_plane() {
    let scene = penumbra_testkit::through_the_light();
    let r = CpuRenderer::new(&scene.lit(0));
    assert!(
        r.volumes.wedges.iter().any(|w| w.caster.is_some()),
        "the light's plane should cut the box and the quad"
    );
    // The hard shadow is the centre's count, exact whatever crosses the plane.
    let hard = r.render(Technique::Hard, &|_| {});
    let want = Reference::new(&scene.lit(0)).render(LightSamples::Centre, &|_| {});
    let differ = hard
        .data
        .iter()
        .zip(&want.data)
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(
        differ, 0,
        "hard differs from the hard reference on {differ} pixels"
    );
    // The soft ones: the silhouette from the light's centre is a poor guess of the box's from
    // the rest of a light it touches, but nothing behind the light's plane hides any light.
    let truth =
        Reference::new(&scene.lit(0)).render(LightSamples::Stratified { per_axis: 16 }, &|_| {});
    for (t, bound) in [(Technique::Wedges, 0.16), (Technique::WedgesBlend, 0.09)] {
        let img = r.render(t, &|_| {});
        assert!(img.data.iter().all(|v| (0.0..=1.0).contains(v)));
        let c = compare(&img, &truth).unwrap();
        println!(
            "through the light: {t} penumbra MAE {:.4} over {} pixels",
            c.penumbra.mae, c.penumbra.pixels
        );
        assert!(
            c.penumbra.mae <= bound,
            "{t}: penumbra MAE {}",
            c.penumbra.mae
        );
    }
}

/// A box whose top face lies in the light's plane, under the light's centre and beside it, and a
/// sphere with a ring of vertices on the plane around the centre: the sides' edges on the plane
/// bound what hides the light, and the faces on the plane hide nothing. `depth-complexity` with
/// the reference's samples is the reference, pixel for pixel.
#[test]
fn faces_and_rings_on_the_light_plane() {
    use glam::{DMat4, DVec2};
    use penumbra::geom::Camera;
    use penumbra::geom::{RectLight, Scene, TriangleMesh};
    use penumbra::volumes::{DepthComplexity, SamplePattern};
    let c = DVec3::new;
    let mesh = |p: &[DVec3], t: &[[u32; 3]]| TriangleMesh::from_raw("memory", p, t).unwrap();
    let ground = penumbra_testkit::square(0.0, 4.0);
    let (lo, hi) = (c(-0.3, 1.0, -0.3), c(0.3, 2.0, 0.3));
    let corner = |i: u32| {
        c(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    };
    let quads = [
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
        [0, 2, 3, 1],
        [4, 5, 7, 6],
    ];
    let tris: Vec<[u32; 3]> = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    let cube = mesh(&(0..8).map(corner).collect::<Vec<_>>(), &tris);
    // The fixture sphere has a ring of vertices on its equator: centred on the light's plane.
    let sphere = TriangleMesh::uv_sphere(20, 20);
    let camera = Camera::look_at(c(0., 3., 6.), DVec3::ZERO, DVec3::Y, 60.0, 40, 30).unwrap();
    let light = RectLight::new(c(0., 2., 0.), -DVec3::Y, DVec3::X, DVec2::ONE).unwrap();
    let pattern = SamplePattern {
        per_axis: 16,
        jitter: true,
    };
    for (name, occluder, at) in [
        ("box under the centre", &cube, DMat4::IDENTITY),
        (
            "box beside the centre",
            &cube,
            DMat4::from_translation(c(0.5, 0., 0.)),
        ),
        (
            "sphere around the centre",
            &sphere,
            DMat4::from_scale_rotation_translation(
                DVec3::splat(0.6),
                Default::default(),
                c(0.3, 2., 0.),
            ),
        ),
    ] {
        let scene = Scene::new(camera)
            .with_light(light)
            .with_mesh("ground", &ground, DMat4::IDENTITY)
            .with_mesh(name, occluder, at);
        let truth = Reference::new(&scene.lit(0))
            .render(LightSamples::Stratified { per_axis: 16 }, &|_| {});
        let exact = DepthComplexity::new(&scene.lit(0)).render(pattern, &|_| {});
        let differ = exact
            .data
            .iter()
            .zip(&truth.data)
            .filter(|(a, b)| a != b)
            .count();
        let c = compare(&exact, &truth).unwrap();
        println!(
            "{name}: {differ} pixels differ, {} penumbra pixels",
            c.penumbra.pixels
        );
        assert!(c.penumbra.pixels > 50, "{name}: no penumbra");
        assert_eq!(
            differ, 0,
            "{name}: depth-complexity differs from the reference"
        );
    }
}

/// A 1 x 2 x 1 box from y = 1 to y = 3 on a ground, under a 1.5 x 1.5 light facing down whose
/// plane (y = 3) holds the box's top face, the light's centre at `centre`; seen at `size`.
fn box_in_the_light_plane(centre: DVec3, (width, height): (u32, u32)) -> penumbra::Scene {
    use penumbra::glam::{DMat4, DVec2};
    use penumbra::{Camera, RectLight, Scene, TriangleMesh};
    let camera = Camera::look_at(
        DVec3::new(0.0, 5.0, 7.0),
        DVec3::ZERO,
        DVec3::Y,
        45.0,
        width,
        height,
    )
    .unwrap();
    let block = DMat4::from_translation(DVec3::new(0.0, 2.0, 0.0))
        * DMat4::from_scale(DVec3::new(1.0, 2.0, 1.0));
    let light = RectLight::new(centre, DVec3::NEG_Y, DVec3::X, DVec2::splat(1.5)).unwrap();
    Scene::new(camera)
        .with_light(light)
        .with_mesh(
            "ground",
            &TriangleMesh::quad(),
            DMat4::from_scale(DVec3::splat(12.0)),
        )
        .with_mesh("block", &TriangleMesh::cube(), block)
}

/// A box whose top face is the light's plane, the light's centre on that face's edge, on its
/// vertex, or 1e-7 outside the edge: the count at the centre and the crossings through it hang
/// on rounding there, and depth complexity, given the reference's samples, stays its equal.
#[test]
fn depth_complexity_with_the_lights_centre_on_a_face_in_its_plane() {
    use penumbra::{Backend, RenderOptions, Renderer};
    let options = RenderOptions {
        samples: 256,
        jitter: true,
    };
    for (case, centre) in [
        ("the edge", DVec3::new(0.5, 3.0, 0.0)),
        ("the vertex", DVec3::new(0.5, 3.0, 0.5)),
        ("1e-7 outside the edge", DVec3::new(0.5 + 1e-7, 3.0, 0.0)),
    ] {
        let scene = box_in_the_light_plane(centre, (64, 48));
        let mut r = Renderer::new(Backend::Cpu);
        let counted = r
            .render(&scene, Technique::DepthComplexity, &options)
            .unwrap();
        let cast = r.render(&scene, Technique::Reference, &options).unwrap();
        let c = compare(&counted, &cast).unwrap();
        assert!(
            c.penumbra.pixels > 100,
            "{case}: {} penumbra pixels",
            c.penumbra.pixels
        );
        assert!(
            c.all.equal >= 0.999,
            "centre on {case}: {:.4} equal",
            c.all.equal
        );
    }
}

/// The exact evaluator (`penumbra probe`'s `V exact`) with the light's centre on a face in the
/// light's plane, on that face's edge, on its vertex and 1e-7 outside the edge: at every
/// fourth pixel of the box's scene, within the 1024-sample reference's sampling error
/// (`5 sigma + 1/N`, as `tests/reference_vs_exact.rs` argues).
#[test]
fn the_exact_evaluator_with_the_lights_centre_on_a_face_in_its_plane() {
    use penumbra::geom::{REFERENCE_SEED, Tracer};
    let n = 32usize;
    for (case, centre) in [
        ("the face", DVec3::new(0.0, 3.0, 0.0)),
        ("the edge", DVec3::new(0.5, 3.0, 0.0)),
        ("the vertex", DVec3::new(0.5, 3.0, 0.5)),
        ("1e-7 outside the edge", DVec3::new(0.5 + 1e-7, 3.0, 0.0)),
    ] {
        let scene = box_in_the_light_plane(centre, (48, 36));
        let camera = scene.camera;
        let lit = scene.lit(0);
        let tracer = Tracer::new(&lit);
        let mut penumbra = 0;
        for j in (0..camera.height).step_by(2) {
            for i in (0..camera.width).step_by(2) {
                let Some(p) = tracer.surface_point(camera.eye, camera.ray_dir(i, j)) else {
                    continue;
                };
                let exact = tracer.exact_visibility(&p);
                let mut rng = Rng::stream(REFERENCE_SEED, (j * camera.width + i) as u64);
                let sampled = tracer.sampled_visibility(&p, n, &mut rng);
                let sigma = (exact * (1.0 - exact) / (n * n) as f64).sqrt();
                assert!(
                    (exact - sampled).abs() <= 5.0 * sigma + 1.0 / (n * n) as f64,
                    "centre on {case}: pixel {i},{j} at {}: exact {exact}, reference {sampled}",
                    p.position
                );
                penumbra += usize::from(sigma > 0.0);
            }
        }
        assert!(
            penumbra > 30,
            "centre on {case}: {penumbra} penumbra points"
        );
    }
}
