//! Scenes shared by the tests of several crates (the volumes' CPU oracle, the GPU's, and the
//! workspace's), built in code.
#![warn(missing_docs)]

use glam::{DMat4, DQuat, DVec2, DVec3};
use penumbra_geom::{Camera, RectLight, Scene, TriangleMesh};

/// A horizontal square of side `2 half` at height `y`, facing up (`+y`), as two triangles: the
/// unit quad ([`TriangleMesh::quad`]) scaled and lifted.
pub fn square(y: f64, half: f64) -> TriangleMesh {
    let place = DMat4::from_translation(DVec3::new(0.0, y, 0.0))
        * DMat4::from_scale(DVec3::splat(2.0 * half));
    TriangleMesh::quad().transformed(&place)
}

/// A scene that the light's plane cuts, where the volume techniques clip what lies behind the
/// light: a closed box standing up through the light's plane beside its centre, and a quad
/// tilted through it, over a ground, under a tilted 2.5 x 2 light, seen by a 64 x 48 camera.
pub fn through_the_light() -> Scene {
    let c = DVec3::new;
    let mesh = |p: &[DVec3], t: &[[u32; 3]]| TriangleMesh::from_raw("memory", p, t).unwrap();
    let ground = square(0.0, 6.0);
    let cube = mesh(
        &[
            c(-0.1, 3.0, -0.7),
            c(0.5, 3.0, -0.7),
            c(0.5, 3.0, -0.1),
            c(-0.1, 3.0, -0.1),
            c(-0.1, 6.0, -0.7),
            c(0.5, 6.0, -0.7),
            c(0.5, 6.0, -0.1),
            c(-0.1, 6.0, -0.1),
        ],
        &[
            [0, 2, 1],
            [0, 3, 2],
            [4, 5, 6],
            [4, 6, 7],
            [0, 1, 5],
            [0, 5, 4],
            [1, 2, 6],
            [1, 6, 5],
            [2, 3, 7],
            [2, 7, 6],
            [3, 0, 4],
            [3, 4, 7],
        ],
    );
    let quad = mesh(
        &[
            c(-2.2, 4.0, -1.0),
            c(-1.0, 6.0, -1.0),
            c(-1.0, 6.0, 0.2),
            c(-2.2, 4.0, 0.2),
        ],
        &[[0, 1, 2], [0, 2, 3]],
    );
    let normal = c(0.25, -1.0, 0.15).normalize();
    let camera = Camera::look_at(c(1.0, 3.5, 4.5), c(-0.5, 0.5, -0.3), DVec3::Y, 45.0, 64, 48);
    let light = RectLight::new(
        c(-0.8, 5.0, -0.4),
        normal,
        normal.cross(DVec3::Z).normalize(),
        DVec2::new(2.5, 2.0),
    )
    .unwrap();
    let mut scene = Scene::new(camera.unwrap()).with_light(light);
    for (name, m) in [("ground", ground), ("box", cube), ("quad", quad)] {
        scene = scene.with_mesh(name, &m, DMat4::IDENTITY);
    }
    scene
}

/// The scene of `examples/scene_in_code.rs`: a ground, a sphere and a tilted box under a square
/// 2.5 x 2.5 light, seen by a 320 x 240 camera. Its pixel (191, 90) has its centre 0.0006 pixels
/// outside the box's outline, where two of the box's lit faces fold over; the rasteriser, which
/// snaps corners to a fraction of a pixel, puts it on the box.
pub fn scene_in_code() -> Scene {
    let p = DVec3::new;
    let ground = square(0.0, 6.0);
    let cube = TriangleMesh::cube();
    let camera = Camera::look_at(p(0.0, 5.0, 7.0), p(0.0, 0.5, 0.0), DVec3::Y, 45.0, 320, 240);
    let light =
        RectLight::new(p(-1.0, 6.0, 0.5), DVec3::NEG_Y, DVec3::X, DVec2::splat(2.5)).unwrap();
    let sphere = DMat4::from_scale_rotation_translation(
        DVec3::splat(0.8),
        DQuat::IDENTITY,
        p(-0.8, 1.2, 0.0),
    );
    let tilted = DMat4::from_rotation_translation(
        DQuat::from_axis_angle(DVec3::new(1.0, 1.0, 0.0).normalize(), 0.6),
        p(1.0, 1.0, 0.6),
    );
    Scene::new(camera.unwrap())
        .with_light(light)
        .with_mesh("ground", &ground, DMat4::IDENTITY)
        .with_mesh("sphere", &TriangleMesh::uv_sphere(20, 24), sphere)
        .with_mesh("box", &cube, tilted)
}
