//! Tests of the tracer: its hierarchies kept for the same triangles, and shared by every
//! direction of a distant light.

use std::sync::Arc;

use glam::{DMat4, DVec2, DVec3};

use super::{Tracer, TracerGeometry};
use crate::camera::Camera;
use crate::light::RectLight;
use crate::mesh::TriangleMesh;
use crate::raycast::Rays;
use crate::scene::Scene;

/// A sphere over a ground, lit from above, the sphere moved by `x`.
fn scene(x: f64) -> Scene {
    let camera =
        Camera::look_at(DVec3::new(0., 3., 4.), DVec3::ZERO, DVec3::Y, 45.0, 8, 6).unwrap();
    let light = RectLight::new(DVec3::new(0., 4., 0.), -DVec3::Y, DVec3::X, DVec2::ONE).unwrap();
    let ground = TriangleMesh::from_raw(
        "ground",
        &[
            DVec3::new(-3., 0., -3.),
            DVec3::new(3., 0., -3.),
            DVec3::new(3., 0., 3.),
            DVec3::new(-3., 0., 3.),
        ],
        &[[0, 2, 1], [0, 3, 2]],
    )
    .unwrap();
    Scene::new(camera)
        .with_light(light)
        .with_mesh("ground", &ground, DMat4::IDENTITY)
        .with_mesh(
            "sphere",
            &TriangleMesh::uv_sphere(6, 8),
            DMat4::from_translation(DVec3::new(x, 1.0, 0.0)),
        )
}

/// The hierarchies are taken again for the same triangles under another light and camera,
/// and built again for other triangles (moved, or a `-0.0` where there was a `0.0`) or
/// another kind of rays; what is kept is the last one built.
#[test]
fn the_hierarchies_are_kept_for_the_same_triangles_and_rays_only() {
    let mut kept = None;
    let first = Tracer::new_reusing(&(scene(0.0)).lit(0), Rays::Many, &mut kept);
    let mut other_light = scene(0.0).lit(0);
    other_light.light = RectLight::new(
        DVec3::new(1., 1.5, 0.),
        -DVec3::Y,
        DVec3::Z,
        DVec2::ONE * 2.0,
    )
    .unwrap();
    other_light.camera.eye = DVec3::new(0., 2., 5.);
    let again = Tracer::new_reusing(&other_light, Rays::Many, &mut kept);
    assert!(Arc::ptr_eq(&first.bvh, &again.bvh));
    assert!(Arc::ptr_eq(&first.triangles, &again.triangles));
    // What depends on the light and the camera is the scene's own.
    let fresh = Tracer::new(&other_light);
    assert_eq!(again.in_front, fresh.in_front);
    assert_ne!(again.in_front, first.in_front);
    assert_eq!((again.epsilon, again.touch), (fresh.epsilon, fresh.touch));
    assert_ne!(again.epsilon, first.epsilon);
    for (moved, rays) in [(scene(0.5), Rays::Many), (scene(0.0), Rays::Few)] {
        let before = kept.clone().unwrap();
        let t = Tracer::new_reusing(&moved.lit(0), rays, &mut kept);
        assert!(!Arc::ptr_eq(&before.bvh, &t.bvh));
        assert!(Arc::ptr_eq(&kept.as_ref().unwrap().bvh, &t.bvh));
        assert_eq!(*t.triangles, *moved.triangles());
    }
    let triangles = scene(0.0).triangles();
    let built = TracerGeometry::build(triangles.clone(), Rays::Few);
    assert!(built.serves(&triangles, Rays::Few));
    assert!(!built.serves(&triangles, Rays::Many));
    assert!(!built.serves(&triangles[1..], Rays::Few));
    // The ground lies at y = 0.
    let mut signed = triangles.clone();
    assert_eq!(signed[0][0].y.to_bits(), 0);
    signed[0][0].y = -0.0;
    assert!(!built.serves(&signed, Rays::Few));
}

/// Under a distant light the hierarchies are the world's, shared by every direction, and
/// a cast in the world blocks what the warped segment does: the sphere's shadow on the
/// ground, seen from a point under it, and not from a point beside it.
#[test]
fn distant_lights_share_the_worlds_hierarchies() {
    use crate::distant::DistantLight;
    use crate::lights::Light;
    let mut kept = None;
    let lit = |azimuth: f64, elevation: f64| {
        let mut s = scene(0.0);
        s.lights[0].light = Light::Distant(DistantLight::sun(azimuth, elevation, 2.0).unwrap());
        s.lit(0)
    };
    let (a, b) = (lit(0.0, 90.0), lit(120.0, 40.0));
    let first = Tracer::new_reusing(&a, Rays::Many, &mut kept);
    let second = Tracer::new_reusing(&b, Rays::Many, &mut kept);
    assert!(Arc::ptr_eq(&first.bvh, &second.bvh));
    assert!(
        kept.as_ref()
            .unwrap()
            .serves(&a.world_triangles(), Rays::Many)
    );
    assert_eq!(*second.triangles, *b.triangles());
    // Under the sun at the zenith: the ground under the sphere (at x = 0, found from below)
    // is shadowed, the ground at x = 2.5 is not, by the world's rays and by the exact
    // evaluator alike.
    let warp = a.warp().unwrap();
    for (x, seen) in [(0.0, false), (2.5, true)] {
        let world = DVec3::new(x, 0.0, 0.3);
        let p = first
            .world_surface_point(world - DVec3::Y, DVec3::Y)
            .unwrap();
        assert!((p.position - world).length() < 1e-9);
        let p = first.rendered(p);
        assert!((p.position - warp.point(world)).length() < 1e-9);
        let mut near = Vec::new();
        first.near_triangles(&p, &mut near);
        assert_eq!(first.sees(&p, first.light.center, &near), seen, "x = {x}");
        assert_eq!(first.exact_visibility(&p) > 0.5, seen, "x = {x}");
    }
}
