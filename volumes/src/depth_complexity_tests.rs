//! Depth-complexity sampling against the reference, sample for sample, on the topologies that
//! break per-edge area integration: a sheet folded over itself, an edge with three faces, a mesh
//! with a hole, two closed meshes through each other, and receivers on back-facing triangles.

use glam::{DMat4, DQuat, DVec2, DVec3};
use penumbra_geom::Camera;
use penumbra_geom::SceneMesh;
use penumbra_geom::{LightSamples, Reference};
use penumbra_geom::{RectLight, Scene, TriangleMesh};
use penumbra_params::TechniqueParams;

use crate::depth_complexity::*;
use crate::depth_complexity_image::GRID_FROM_EDGES;

/// Light samples per axis: 64 per pixel.
const PER_AXIS: usize = 8;

fn mesh(positions: &[DVec3], triangles: &[[u32; 3]]) -> TriangleMesh {
    TriangleMesh::from_raw("test", positions, triangles).unwrap()
}

/// `meshes` over the ground under a tilted 2.5 x 2 light, seen by a 64 x 48 camera.
fn scene(meshes: Vec<TriangleMesh>, eye: DVec3, target: DVec3) -> Scene {
    let normal = DVec3::new(0.25, -1.0, 0.15).normalize();
    let tangent = normal.cross(DVec3::Z).normalize();
    let mut all = vec![penumbra_testkit::square(0.0, 6.0)];
    all.extend(meshes);
    Scene {
        path: "memory".into(),
        camera: Camera::look_at(eye, target, DVec3::Y, 45.0, 64, 48).unwrap(),
        lights: vec![
            penumbra_geom::NamedLight::new(
                "light0",
                RectLight::new(
                    DVec3::new(-0.8, 5.0, -0.4),
                    normal,
                    tangent,
                    DVec2::new(2.5, 2.0),
                )
                .unwrap(),
            )
            .unwrap(),
        ],
        named_channels: false,
        meshes: std::sync::Arc::new(
            all.into_iter()
                .map(|mesh| SceneMesh {
                    source: "memory".into(),
                    transform: DMat4::IDENTITY,
                    mesh,
                })
                .collect(),
        ),
        params: TechniqueParams::default(),
    }
}

/// What the camera sees of `scene`: the number of pixels whose surface point lies on a
/// triangle facing away from the camera (by its winding), and the largest centre count
/// `D(P, c)` over the pixels.
fn survey(dc: &DepthComplexity, scene: &Scene) -> (usize, u32) {
    let cam = &scene.camera;
    let (mut back, mut deepest) = (0, 0);
    let mut hits = Vec::new();
    let mut near = Vec::new();
    for j in 0..cam.height {
        for i in 0..cam.width {
            let dir = cam.ray_dir(i, j);
            let Some(p) = dc.tracer.surface_point(cam.eye, dir) else {
                continue;
            };
            let [a, b, c] = dc.tracer.triangles[p.triangle as usize];
            back += usize::from((b - a).cross(c - a).dot(dir) > 0.0);
            dc.tracer.near_triangles(&p, &mut near);
            deepest = deepest.max(dc.centre_count(&p, &near, &mut hits));
        }
    }
    (back, deepest)
}

/// Renders both ways with the reference's 64 jittered samples and checks that they agree on
/// all but a pixel or two, by at most two samples, over an image with a real penumbra; returns
/// [`survey`]'s numbers, for the caller to check that the scene shows what it is meant to.
fn agrees_with_the_reference(name: &str, scene: &Scene) -> (usize, u32) {
    let dc = DepthComplexity::new(&scene.lit(0));
    let pattern = SamplePattern {
        per_axis: PER_AXIS,
        jitter: true,
    };
    let got = dc.render(pattern, &|_| {});
    let want = Reference::new(&scene.lit(0))
        .render(LightSamples::Stratified { per_axis: PER_AXIS }, &|_| {});
    let samples = (PER_AXIS * PER_AXIS) as f32;
    let penumbra = want.data.iter().filter(|&&v| v > 0.0 && v < 1.0).count();
    let differ: Vec<(usize, f32, f32)> = got
        .data
        .iter()
        .zip(&want.data)
        .enumerate()
        .filter(|(_, (a, b))| a != b)
        .map(|(k, (a, b))| (k, *a, *b))
        .collect();
    println!(
        "{name}: {penumbra} penumbra pixels, {} differ: {:?}",
        differ.len(),
        &differ[..differ.len().min(5)]
    );
    assert!(penumbra >= 100, "{name}: too little penumbra to test");
    assert!(differ.len() <= 3, "{name}: {} pixels differ", differ.len());
    for (k, a, b) in differ {
        assert!(
            (a - b).abs() <= 2.0 / samples,
            "{name}: pixel {k}: {a} against {b}"
        );
    }
    survey(&dc, scene)
}

#[test]
fn an_open_sheet_folded_over_itself() {
    // A strip of panels one unit deep: flat at y = 1, up a fold at x = 1, back over itself at
    // y = 1.6, down at x = -0.6 and right again at y = 1.2, between the two: rays under the
    // folds cross the sheet up to three times.
    let x = [-1.0, 1.0, 1.0, -0.6, -0.6, 0.6];
    let y = [1.0, 1.0, 1.6, 1.6, 1.2, 1.2];
    let mut p = Vec::new();
    for k in 0..6 {
        p.push(DVec3::new(x[k], y[k], -0.5));
        p.push(DVec3::new(x[k], y[k], 0.5));
    }
    let mut t = Vec::new();
    for k in 0..5u32 {
        let (a, b, c, d) = (2 * k, 2 * k + 1, 2 * k + 2, 2 * k + 3);
        t.push([a, b, d]);
        t.push([a, d, c]);
    }
    let s = scene(
        vec![mesh(&p, &t)],
        DVec3::new(1.0, 3.5, 4.5),
        DVec3::new(0.0, 0.6, 0.0),
    );
    let (_, deepest) = agrees_with_the_reference("folded sheet", &s);
    assert!(
        deepest >= 3,
        "the centre should see the sheet three times: {deepest}"
    );
}

#[test]
fn an_edge_with_three_faces() {
    // Three pages on one edge, plus a fourth triangle on one page's far edge.
    let p = [
        DVec3::new(-1.0, 1.2, 0.0),
        DVec3::new(1.0, 1.2, 0.0),
        DVec3::new(0.0, 1.2, 1.0),
        DVec3::new(0.0, 2.0, -0.6),
        DVec3::new(0.0, 0.6, -0.7),
        DVec3::new(0.5, 1.9, 1.3),
    ];
    let book = mesh(&p, &[[0, 1, 2], [1, 0, 3], [0, 1, 4], [1, 5, 2]]);
    let h = penumbra_geom::HalfEdgeMesh::build(&book);
    assert_eq!(h.edge_counts()[3], 1, "one edge with three faces");
    let s = scene(
        vec![book],
        DVec3::new(1.5, 3.5, 4.5),
        DVec3::new(0.0, 0.6, 0.0),
    );
    let (_, deepest) = agrees_with_the_reference("three-page book", &s);
    assert!(deepest >= 2, "two pages should hide the centre: {deepest}");
}

/// The five faces of a box without its top, `[-1, 1] x [0.3, 1.5] x [-1, 1]`, tilted.
fn open_box() -> TriangleMesh {
    let c = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    let p = [
        c(-1.0, 0.3, -1.0),
        c(1.0, 0.3, -1.0),
        c(1.0, 0.3, 1.0),
        c(-1.0, 0.3, 1.0),
        c(-1.0, 1.5, -1.0),
        c(1.0, 1.5, -1.0),
        c(1.0, 1.5, 1.0),
        c(-1.0, 1.5, 1.0),
    ];
    let t = [
        [0, 1, 2],
        [0, 2, 3],
        [0, 4, 5],
        [0, 5, 1],
        [1, 5, 6],
        [1, 6, 2],
        [2, 6, 7],
        [2, 7, 3],
        [3, 7, 4],
        [3, 4, 0],
    ];
    let m = DMat4::from_rotation_translation(
        DQuat::from_axis_angle(DVec3::new(1.0, 0.0, 1.0).normalize(), 0.3),
        DVec3::new(0.2, 0.4, 0.0),
    );
    mesh(&p, &t).transformed(&m)
}

#[test]
fn a_mesh_with_a_hole_seen_from_inside() {
    // Looking down into an open box: its floor and walls are seen from inside (back-facing
    // triangles as receivers), lit through the hole, and its walls shadow the floor.
    let b = open_box();
    let h = penumbra_geom::HalfEdgeMesh::build(&b);
    assert_eq!(h.edge_counts()[0], 4, "the open top's four boundary edges");
    let s = scene(
        vec![b],
        DVec3::new(0.8, 6.0, 2.0),
        DVec3::new(0.2, 0.8, 0.0),
    );
    let (back, _) = agrees_with_the_reference("open box", &s);
    assert!(
        back >= 300,
        "the inside should fill the view: {back} pixels"
    );
}

#[test]
fn two_closed_meshes_through_each_other() {
    let sphere = |r: f64, at: DVec3| {
        TriangleMesh::uv_sphere(12, 16).transformed(&DMat4::from_scale_rotation_translation(
            DVec3::splat(r),
            DQuat::IDENTITY,
            at,
        ))
    };
    let s = scene(
        vec![
            sphere(0.7, DVec3::new(-0.3, 1.5, 0.0)),
            sphere(0.5, DVec3::new(0.5, 1.3, 0.2)),
        ],
        DVec3::new(1.0, 3.5, 4.5),
        DVec3::new(0.0, 0.8, 0.0),
    );
    let (_, deepest) = agrees_with_the_reference("two spheres", &s);
    assert!(
        deepest >= 4,
        "the centre should see both spheres: {deepest}"
    );
}

#[test]
fn receivers_on_back_facing_triangles() {
    // A tilted sheet seen from below, its winding facing up, away from the camera, under a small
    // quad. The sheet's own triangle never hides a point on it (the visibility definition), its
    // coplanar neighbour is seen edge-on, and the quad above casts a penumbra onto it.
    let p = [
        DVec3::new(-1.6, 1.0, -1.0),
        DVec3::new(1.6, 1.3, -1.0),
        DVec3::new(1.6, 1.5, 1.0),
        DVec3::new(-1.6, 1.2, 1.0),
    ];
    let sheet = mesh(&p, &[[0, 2, 1], [0, 3, 2]]);
    let q = [
        DVec3::new(-0.4, 2.3, -0.4),
        DVec3::new(0.4, 2.3, -0.4),
        DVec3::new(0.4, 2.4, 0.4),
        DVec3::new(-0.4, 2.4, 0.4),
    ];
    let quad = mesh(&q, &[[0, 2, 1], [0, 3, 2]]);
    let s = scene(
        vec![sheet, quad],
        DVec3::new(0.5, 0.2, 3.0),
        DVec3::new(0.0, 1.3, 0.0),
    );
    let (back, _) = agrees_with_the_reference("back faces", &s);
    assert!(
        back >= 300,
        "the underside should fill the view: {back} pixels"
    );
}

#[test]
fn occluders_through_the_light_plane() {
    // A closed box standing up through the light's plane beside its centre, and a quad tilted
    // through it: their projections on the light end where they cross its plane, not at edges.
    let s = penumbra_testkit::through_the_light();
    assert!(
        penumbra_geom::HalfEdgeMesh::build(&s.meshes[1].mesh).is_closed(),
        "the box is closed"
    );
    let dc = DepthComplexity::new(&s.lit(0));
    assert!(
        dc.edges.crossings.len() >= 4,
        "both should cross the light: {:?}",
        dc.edges.crossings
    );
    agrees_with_the_reference("through the light", &s);
    // And both are right: against the exact evaluator, within the sampling error, at the
    // penumbra pixels (every third).
    let cam = &s.camera;
    let pattern = SamplePattern {
        per_axis: 32,
        jitter: true,
    };
    let mut scratch = Scratch::default();
    let mut checked = 0;
    for k in (0..cam.pixel_count()).step_by(3) {
        let (i, j) = ((k % 64) as u32, (k / 64) as u32);
        let Some(p) = dc.tracer.surface_point(cam.eye, cam.ray_dir(i, j)) else {
            continue;
        };
        let exact = dc.tracer.exact_visibility(&p);
        if !(exact > 0.01 && exact < 0.99) {
            continue;
        }
        let v = dc
            .visibility(&p, pattern, k as u64, &mut scratch)
            .visibility;
        let sigma = (exact * (1.0 - exact) / 1024.0).sqrt();
        assert!(
            (v - exact).abs() <= 5.0 * sigma + 1.0 / 1024.0,
            "pixel {i},{j}: {v} against the exact {exact}"
        );
        checked += 1;
    }
    assert!(checked > 100, "only {checked} penumbra pixels");
}

/// A sheet of 24 x 24 quads with random heights over the ground: hundreds of potential
/// silhouette edges.
fn bumpy_sheet() -> TriangleMesh {
    let n = 24u32;
    let mut rng = penumbra_geom::Rng::stream(11, 0);
    let mut p = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (
                -2.0 + 4.0 * i as f64 / n as f64,
                -2.0 + 4.0 * j as f64 / n as f64,
            );
            p.push(DVec3::new(x, 1.5 + 0.3 * rng.next_f64(), z));
        }
    }
    let at = |i: u32, j: u32| j * (n + 1) + i;
    let mut t = Vec::new();
    for j in 0..n {
        for i in 0..n {
            t.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            t.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    mesh(&p, &t)
}

#[test]
fn tiles_cast_by_rays_give_the_counts_image() {
    let scene = scene(
        vec![bumpy_sheet()],
        DVec3::new(0.5, 6.0, 7.0),
        DVec3::new(0.0, 0.5, 0.0),
    );
    let mut dc = DepthComplexity::new(&scene.lit(0));
    assert!(dc.edges.edges.len() > 300, "{}", dc.edges.edges.len());
    let render = |dc: &DepthComplexity, jitter| {
        dc.render(
            SamplePattern {
                per_axis: PER_AXIS,
                jitter,
            },
            &|_| {},
        )
    };
    dc.cast_from = CastFrom {
        candidates: f64::INFINITY,
        kept: f64::INFINITY,
    };
    let counted = render(&dc, false);
    assert_eq!(dc.cast_pixels(), 0);
    // Every tile with a candidate edge casts: with the reference's points, the reference's
    // image exactly (the same rays by the same rule).
    dc.cast_from = CastFrom {
        candidates: 0.0,
        kept: 0.0,
    };
    let cast = render(&dc, false);
    let lit = cast.data.iter().filter(|&&v| v > 0.0).count() as u64;
    assert!(
        dc.cast_pixels() >= lit / 2,
        "{} of {lit} lit pixels cast",
        dc.cast_pixels()
    );
    let want = Reference::new(&scene.lit(0))
        .render(LightSamples::Stratified { per_axis: PER_AXIS }, &|_| {});
    assert_eq!(render(&dc, true).data, want.data);
    let penumbra = counted.data.iter().filter(|&&v| v > 0.0 && v < 1.0).count();
    let differ: Vec<(usize, f32, f32)> = cast
        .data
        .iter()
        .zip(&counted.data)
        .enumerate()
        .filter(|(_, (a, b))| a != b)
        .map(|(k, (a, b))| (k, *a, *b))
        .collect();
    println!("{penumbra} penumbra pixels; cast and counted differ at {differ:?}");
    assert!(penumbra >= 500, "{penumbra} penumbra pixels");
    assert!(differ.len() <= 3, "{} pixels differ", differ.len());
    let samples = (PER_AXIS * PER_AXIS) as f32;
    assert!(
        differ
            .iter()
            .all(|(_, a, b)| (a - b).abs() <= 2.0 / samples)
    );
}

#[test]
fn the_grid_under_a_distant_light_gives_the_hierarchys_image() {
    use penumbra_geom::{DistantLight, Light, NamedLight};
    let mut scene = scene(
        vec![bumpy_sheet(), open_box()],
        DVec3::new(0.5, 6.0, 7.0),
        DVec3::new(0.0, 0.5, 0.0),
    );
    // Finer pixels: the sun's penumbrae are a hundredth of the sheet's height wide.
    scene.camera = Camera::look_at(
        scene.camera.eye,
        DVec3::new(0.0, 0.5, 0.0),
        DVec3::Y,
        45.0,
        160,
        120,
    )
    .unwrap();
    let pattern = SamplePattern {
        per_axis: PER_AXIS,
        jitter: false,
    };
    // The sun high and low, and distant lights of a few degrees and of half the sky.
    for (azimuth, elevation, size) in [
        (150.0, 60.0, 0.53),
        (250.0, 8.0, 0.53),
        (80.0, 35.0, 4.0),
        (200.0, 45.0, 60.0),
    ] {
        let sun = DistantLight::sun(azimuth, elevation, size).unwrap();
        scene.lights = vec![NamedLight {
            name: "sun".into(),
            light: Light::Distant(sun),
        }];
        let lit = scene.lit(0);
        let mut dc = DepthComplexity::new(&lit);
        // Fewer edges than the grid is built for by default: asked for.
        assert!(!dc.by_grid && dc.edges.edges.len() < GRID_FROM_EDGES);
        dc.by_grid = true;
        let by_grid = dc.render(pattern, &|_| {});
        // Half the sky is too large a light for a grid: each point would read most edges.
        let gridded = dc.gridded.load(std::sync::atomic::Ordering::Relaxed);
        assert_eq!(gridded, size < 10.0, "{size} degrees");
        dc.by_grid = false;
        let by_tree = dc.render(pattern, &|_| {});
        let penumbra = by_tree.data.iter().filter(|&&v| v > 0.0 && v < 1.0).count();
        let dark = by_tree.data.iter().filter(|&&v| v == 0.0).count();
        println!("{size} degrees: {penumbra} penumbra pixels, {dark} dark");
        assert!(
            penumbra > 20 && penumbra + dark > 400,
            "{penumbra} penumbra, {dark} dark at {size} degrees"
        );
        assert_eq!(by_grid.data, by_tree.data, "{azimuth}, {elevation}, {size}");
    }
}
