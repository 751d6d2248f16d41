//! The wedge grid of a whole image against the lookup of a single point, on a scene whose
//! receivers reach far beyond what the camera sees: a ground 400 units wide, which the light's
//! tilted plane crosses, under a sphere a unit wide. The image's grid then covers only the box of
//! the pixels' points, and its cells hold far fewer wedges; every pixel must stay what the grid
//! over all receivers gives.

use glam::{DMat4, DVec2, DVec3};
use penumbra::Technique;
use penumbra::geom::{Camera, RectLight, Scene, SceneMesh, TriangleMesh};
use penumbra::volumes::{CpuRenderer, ReceiverCells, WedgeGrid, receiver_box};

/// The ground, the light tilted so that its plane cuts the ground a few units from the sphere,
/// and a sphere of `stacks` x `slices` over the ground, seen by a camera of `width` x `height`.
fn wide_ground(stacks: u32, slices: u32, (width, height): (u32, u32)) -> Scene {
    let h = 200.0;
    let ground = TriangleMesh::from_raw(
        "ground",
        &[
            DVec3::new(-h, 0.0, -h),
            DVec3::new(h, 0.0, -h),
            DVec3::new(h, 0.0, h),
            DVec3::new(-h, 0.0, h),
        ],
        &[[0, 2, 1], [0, 3, 2]],
    )
    .unwrap();
    let sphere = TriangleMesh::uv_sphere(stacks, slices);
    let normal = DVec3::new(0.5, -0.75f64.sqrt(), 0.0);
    Scene {
        path: "memory".into(),
        camera: Camera::look_at(
            DVec3::new(3.0, 3.0, 4.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::Y,
            45.0,
            width,
            height,
        )
        .unwrap(),
        lights: vec![
            penumbra::NamedLight::new(
                "light0",
                RectLight::new(
                    DVec3::new(0.0, 1.5, 0.0),
                    normal,
                    DVec3::Z,
                    DVec2::new(1.0, 1.5),
                )
                .unwrap(),
            )
            .unwrap(),
        ],
        named_channels: false,
        meshes: std::sync::Arc::new(vec![
            SceneMesh {
                source: "ground".into(),
                transform: DMat4::IDENTITY,
                mesh: ground,
            },
            SceneMesh {
                source: "sphere".into(),
                transform: DMat4::from_translation(DVec3::new(1.0, 0.6, 0.0))
                    * DMat4::from_scale(DVec3::splat(0.4)),
                mesh: sphere,
            },
        ]),
        params: Default::default(),
    }
}

#[test]
fn an_image_whose_grid_covers_only_its_pixels_equals_the_lookup_over_every_receiver() {
    // A whole grid of few entries for the pixels (13 wedges, 160 x 120: filled but for a glance
    // at the pixels, which finds the camera looking at a small part of the receivers), and one
    // of many (165 wedges, 48 x 36: the pixels' cells at once).
    for (stacks, slices, size, few) in [(6, 8, (160, 120), true), (48, 160, (48, 36), false)] {
        let scene = wide_ground(stacks, slices, size);
        let r = CpuRenderer::new(&scene.lit(0));
        let cam = &scene.camera;
        let light = &r.tracer.light;
        // The premise: the pixels' points fill a far smaller box than the receivers'.
        let (lo, hi) = receiver_box(light, &r.tracer.triangles);
        let mut cells = ReceiverCells::new(lo, hi);
        let mut points = Vec::new();
        for j in 0..cam.height {
            for i in 0..cam.width {
                let p = r.tracer.surface_point(cam.eye, cam.ray_dir(i, j));
                if let Some(p) = &p {
                    cells.add(light.to_light_space(p.position));
                }
                points.push(p);
            }
        }
        let (tlo, thi) = cells.tighter().expect("the pixels fill a far smaller box");
        let volume = |d: DVec3| d.x * d.y * d.z;
        assert!(
            volume(thi - tlo) < 1e-3 * volume(hi - lo),
            "the pixels' box {tlo} {thi} against the receivers' {lo} {hi}"
        );
        let wedges = r.volumes.wedges.len();
        // 32 entries per pixel: where the renderer stops filling the whole grid.
        let entries = WedgeGrid::entries(&r.volumes.wedges, lo, hi);
        assert_eq!(
            entries < 32 * points.len() as u64,
            few,
            "{entries} entries for {} pixels",
            points.len()
        );
        for t in [Technique::Wedges, Technique::WedgesBlend] {
            let img = r.render(t, &|_| {});
            let (mut penumbra, mut differ) = (0, 0);
            for (k, p) in points.iter().enumerate() {
                let want = p.as_ref().map_or(1.0, |p| r.visibility(p, t) as f32);
                penumbra += usize::from(want > 0.0 && want < 1.0);
                differ += usize::from(img.data[k].to_bits() != want.to_bits());
            }
            assert_eq!(
                differ, 0,
                "{t} with {wedges} wedges: {differ} pixels differ from the lookup"
            );
            assert!(penumbra > 50, "{t}: only {penumbra} penumbra pixels");
        }
    }
}
