//! Scenes shared by the tests of several crates (the volumes' CPU oracle, the GPU's, and the
//! workspace's), built in code.
#![warn(missing_docs)]

use glam::{DMat4, DVec2, DVec3};
use penumbra_geom::{Camera, RectLight, Scene, TriangleMesh};

/// A scene that the light's plane cuts, where the volume techniques clip what lies behind the
/// light: a closed box standing up through the light's plane beside its centre, and a quad
/// tilted through it, over a ground, under a tilted 2.5 x 2 light, seen by a 64 x 48 camera.
pub fn through_the_light() -> Scene {
    let c = DVec3::new;
    let mesh = |p: &[DVec3], t: &[[u32; 3]]| TriangleMesh::from_raw("memory", p, t).unwrap();
    let ground = mesh(
        &[
            c(-6., 0., -6.),
            c(-6., 0., 6.),
            c(6., 0., 6.),
            c(6., 0., -6.),
        ],
        &[[0, 1, 2], [0, 2, 3]],
    );
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
    );
    let mut scene = Scene::new(camera.unwrap(), light);
    for (name, m) in [("ground", ground), ("box", cube), ("quad", quad)] {
        scene = scene.with_mesh(name, &m, DMat4::IDENTITY);
    }
    scene
}
