//! `GpuScene`: a scene uploaded once, recorded per frame from a camera given as matrices, with
//! meshes and light that move. Checked against the CPU oracle of the same scene built with
//! `Scene::with_mesh`, and by the bytes each frame writes. They need an adapter (lavapipe in
//! CI), as `gpu.rs` does.

mod common;
use common::{context, l_shaped_room};

use common::{texture, view as texture_view};
use glam::dcamera::rh::{proj::directx, view};
use glam::{DMat4, DQuat, DVec2, DVec3};
use penumbra_geom::{
    Camera, DistantLight, RectLight, Scene, Technique, TriangleMesh, VisibilityImage, compare,
};
use penumbra_gpu::{
    FrameCamera, FrameInputs, GBuffer, GpuContext, GpuError, GpuRenderer, GpuScene, ShadowBuilder,
    read_r32f, visibility_target,
};
use penumbra_testkit::square;
use penumbra_volumes::{CpuRenderer, DepthComplexity, SamplePattern};

const SIZE: (u32, u32) = (96, 72);
const EYE: DVec3 = DVec3::new(0.5, 5.0, 6.5);
const TARGET: DVec3 = DVec3::new(0.0, 0.5, 0.0);
const FOV_DEG: f64 = 45.0;

/// A ground, a sphere and a box, each in its own space, with their transforms.
fn meshes() -> Vec<(TriangleMesh, DMat4)> {
    let p = DVec3::new;
    vec![
        (square(0.0, 6.0), DMat4::IDENTITY),
        (
            TriangleMesh::uv_sphere(12, 16),
            DMat4::from_scale_rotation_translation(
                DVec3::splat(0.7),
                DQuat::IDENTITY,
                p(-0.8, 1.2, 0.0),
            ),
        ),
        (TriangleMesh::cube(), box_transform(0.3)),
    ]
}

fn box_transform(angle: f64) -> DMat4 {
    DMat4::from_rotation_translation(DQuat::from_rotation_y(angle), DVec3::new(1.1, 0.9, 0.4))
}

fn light(x: f64) -> RectLight {
    RectLight::new(
        DVec3::new(x, 6.0, 0.5),
        DVec3::NEG_Y,
        DVec3::X,
        DVec2::splat(2.5),
    )
    .unwrap()
}

/// The same scene for the CPU oracle, with `transforms` and `light`.
fn cpu_scene(
    meshes: &[(TriangleMesh, DMat4)],
    transforms: &[DMat4],
    light: impl Into<penumbra_geom::Light>,
) -> Scene {
    let camera = Camera::look_at(EYE, TARGET, DVec3::Y, FOV_DEG, SIZE.0, SIZE.1).unwrap();
    meshes.iter().zip(transforms).enumerate().fold(
        Scene::new(camera).with_light(light),
        |s, (i, ((m, _), t))| s.with_mesh(&format!("mesh{i}"), m, *t),
    )
}

fn camera() -> FrameCamera {
    let view = view::look_at_mat4(EYE, TARGET, DVec3::Y);
    let aspect = SIZE.0 as f64 / SIZE.1 as f64;
    let projection = directx::perspective_infinite_reverse(FOV_DEG.to_radians(), aspect, 0.01);
    FrameCamera::from_matrices(&view, &projection, SIZE).unwrap()
}

/// Records one frame of `scene` by `technique` and reads V back.
fn frame(
    ctx: &GpuContext,
    scene: &mut GpuScene,
    camera: &FrameCamera,
    technique: Technique,
) -> VisibilityImage {
    let gbuffer = GBuffer::new(&ctx.device, camera.size);
    let target = visibility_target(&ctx.device, camera.size);
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    scene.record_depth(&mut enc, camera, &gbuffer).unwrap();
    let inputs = FrameInputs {
        camera: *camera,
        technique,
    };
    scene
        .record(&mut enc, &inputs, &gbuffer, &texture_view(&target))
        .unwrap();
    let (w, h) = camera.size;
    let data = read_r32f(ctx, &mut enc, &target, w, h).unwrap();
    VisibilityImage {
        width: w,
        height: h,
        data,
    }
}

fn assert_matches_cpu(image: &VisibilityImage, scene: &Scene, technique: Technique, what: &str) {
    let cpu = CpuRenderer::new(&scene.lit(0)).render(technique, &|_| {});
    let c = compare(image, &cpu).unwrap();
    println!(
        "{what}, {technique}: MAE {:.2e}, p99 {:.2e}",
        c.all.mae, c.all.p99
    );
    let shadowed = cpu.data.iter().filter(|&&v| v < 0.5).count();
    assert!(shadowed > 100, "{what}: no shadow in view");
    assert!(c.all.mae <= 1e-3, "{what}, {technique}: MAE {}", c.all.mae);
    assert!(c.all.p99 <= 0.02, "{what}, {technique}: p99 {}", c.all.p99);
}

#[test]
fn recorded_frames_match_the_cpu_oracle_as_meshes_and_light_move() {
    let Some(ctx) = context() else { return };
    let renderer = GpuRenderer::new(&ctx.device, &ctx.queue).unwrap();
    let meshes = meshes();
    let refs: Vec<(&TriangleMesh, DMat4)> = meshes.iter().map(|(m, t)| (m, *t)).collect();
    let mut scene = GpuScene::new(&renderer, &refs, light(-1.0));
    let camera = camera();
    let mut transforms: Vec<DMat4> = meshes.iter().map(|m| m.1).collect();
    for t in [Technique::Hard, Technique::Wedges, Technique::WedgesBlend] {
        let image = frame(&ctx, &mut scene, &camera, t);
        assert_matches_cpu(
            &image,
            &cpu_scene(&meshes, &transforms, light(-1.0)),
            t,
            "start",
        );
    }
    // The box turns and the light moves: the same images as a scene built that way.
    transforms[2] = box_transform(1.1);
    scene.set_transform(2, transforms[2]);
    scene.set_light(light(0.8));
    let moved = cpu_scene(&meshes, &transforms, light(0.8));
    for t in [Technique::Hard, Technique::WedgesBlend] {
        let image = frame(&ctx, &mut scene, &camera, t);
        assert_matches_cpu(&image, &moved, t, "moved");
    }
}

/// A distant light from above towards `x`, 12 by 6 degrees.
fn sun(x: f64) -> DistantLight {
    let d = DVec3::new(x, 1.0, 0.3).normalize();
    DistantLight::new(d, d.cross(DVec3::Z).normalize(), DVec2::new(12.0, 6.0)).unwrap()
}

#[test]
fn a_distant_light_matches_the_cpu_oracle_as_the_sun_and_the_meshes_move() {
    let Some(ctx) = context() else { return };
    let renderer = GpuRenderer::new(&ctx.device, &ctx.queue).unwrap();
    let meshes = meshes();
    let refs: Vec<(&TriangleMesh, DMat4)> = meshes.iter().map(|(m, t)| (m, *t)).collect();
    let mut scene = GpuScene::new(&renderer, &refs, sun(-0.6));
    assert_eq!(scene.light(), sun(-0.6).into());
    let camera = camera();
    let mut transforms: Vec<DMat4> = meshes.iter().map(|m| m.1).collect();
    // The oracle warps the scene its own way (around every vertex and the eye); the images are
    // the world's under the sun either way.
    let oracle = |transforms: &[DMat4], x: f64| cpu_scene(&meshes, transforms, sun(x));
    for t in [Technique::Hard, Technique::Wedges, Technique::WedgesBlend] {
        let image = frame(&ctx, &mut scene, &camera, t);
        assert_matches_cpu(&image, &oracle(&transforms, -0.6), t, "sun");
    }
    // Depth complexity against its oracle's samples.
    let image = frame(&ctx, &mut scene, &camera, Technique::DepthComplexity);
    let exact = DepthComplexity::new(&(oracle(&transforms, -0.6)).lit(0)).render(
        SamplePattern {
            per_axis: 16,
            jitter: false,
        },
        &|_| {},
    );
    let c = compare(&image, &exact).unwrap();
    println!(
        "sun, depth-complexity: MAE {:.2e}, max {:.2e}",
        c.all.mae, c.all.max
    );
    assert!(c.all.mae <= 1e-4 && c.all.p99 <= 1.0 / 256.0, "{c:?}");
    // The box turns and the sun moves; then a rectangle light again.
    transforms[2] = box_transform(1.1);
    scene.set_transform(2, transforms[2]);
    scene.set_light(sun(0.7));
    for t in [Technique::Hard, Technique::WedgesBlend] {
        let image = frame(&ctx, &mut scene, &camera, t);
        assert_matches_cpu(&image, &oracle(&transforms, 0.7), t, "sun moved");
    }
    scene.set_light(light(0.8));
    let image = frame(&ctx, &mut scene, &camera, Technique::Hard);
    assert_matches_cpu(
        &image,
        &cpu_scene(&meshes, &transforms, light(0.8)),
        Technique::Hard,
        "a rectangle again",
    );
}

#[test]
fn several_lights_render_one_target_each_and_are_built_once() {
    let Some(ctx) = context() else { return };
    let renderer = GpuRenderer::new(&ctx.device, &ctx.queue).unwrap();
    let meshes = meshes();
    let refs: Vec<(&TriangleMesh, DMat4)> = meshes.iter().map(|(m, t)| (m, *t)).collect();
    let lights = [light(-1.0).into(), sun(0.6).into(), light(0.8).into()];
    let camera = camera();
    let gbuffer = GBuffer::new(&ctx.device, camera.size);
    for technique in [Technique::WedgesBlend, Technique::DepthComplexity] {
        let mut scene = GpuScene::new(&renderer, &refs, light(0.0));
        let inputs = FrameInputs { camera, technique };
        let targets: Vec<wgpu::Texture> = lights
            .iter()
            .map(|_| visibility_target(&ctx.device, camera.size))
            .collect();
        let views: Vec<wgpu::TextureView> = targets.iter().map(texture_view).collect();
        let view_refs: Vec<&wgpu::TextureView> = views.iter().collect();
        scene
            .render_lights(&lights, &inputs, &gbuffer, &view_refs)
            .unwrap();
        scene.take_uploads();
        // Again: every light's shadows were kept (depth complexity keeps its own per frame).
        scene
            .render_lights(&lights, &inputs, &gbuffer, &view_refs)
            .unwrap();
        if technique != Technique::DepthComplexity {
            assert_eq!(scene.take_uploads().shadows, 0, "{technique}");
        }
        for (k, (l, target)) in lights.iter().zip(&targets).enumerate() {
            let (w, h) = camera.size;
            let mut enc = ctx.device.create_command_encoder(&Default::default());
            let got = read_r32f(&ctx, &mut enc, target, w, h).unwrap();
            let mut alone = GpuScene::new(&renderer, &refs, *l);
            let want = frame(&ctx, &mut alone, &camera, technique);
            assert_eq!(got, want.data, "{technique}: light {k}");
        }
    }
    let mut scene = GpuScene::new(&renderer, &refs, light(0.0));
    let inputs = FrameInputs {
        camera,
        technique: Technique::Hard,
    };
    assert!(
        scene
            .render_lights(&lights, &inputs, &gbuffer, &[])
            .is_err()
    );
}

#[test]
fn only_what_changed_is_uploaded() {
    let Some(ctx) = context() else { return };
    let renderer = GpuRenderer::with_context(&ctx);
    let meshes = meshes();
    let refs: Vec<(&TriangleMesh, DMat4)> = meshes.iter().map(|(m, t)| (m, *t)).collect();
    let mut scene = GpuScene::new(&renderer, &refs, light(-1.0));
    let mut camera = camera();
    let t = Technique::WedgesBlend;
    let triangles: usize = meshes.iter().map(|m| m.0.triangles.len()).sum();
    frame(&ctx, &mut scene, &camera, t);
    let first = scene.take_uploads();
    assert_eq!(first.geometry, (triangles * 3 * 12) as u64, "{first:?}");
    assert!(first.shadows > 0 && first.frame > 0, "{first:?}");

    // The same frame again: nothing but the blend's tile lists.
    frame(&ctx, &mut scene, &camera, t);
    let again = scene.take_uploads();
    assert_eq!((again.geometry, again.shadows), (0, 0), "{again:?}");
    // The camera moves: uniforms and model matrices (192 + 3 x 64 bytes), and the tiles.
    let view = view::look_at_mat4(EYE + DVec3::X, TARGET, DVec3::Y);
    let projection = directx::perspective_infinite_reverse(0.8, 96.0 / 72.0, 0.01);
    camera = FrameCamera::from_matrices(&view, &projection, SIZE).unwrap();
    // `hard` builds its shadows on the GPU: the meshes' topology goes up once, with their
    // vertices indexed (positions 12 bytes a vertex, faces 16 a face, edges 16 an edge,
    // and the faces on each edge 4 bytes each).
    frame(&ctx, &mut scene, &camera, Technique::Hard);
    let moved = scene.take_uploads();
    let topology: usize = meshes
        .iter()
        .map(|(m, _)| {
            let he = penumbra_geom::HalfEdgeMesh::build(m);
            12 * m.positions.len()
                + 16 * m.triangles.len()
                + 16 * he.edges.len()
                + 4 * 3 * m.triangles.len()
        })
        .sum();
    assert_eq!(moved.geometry, topology as u64, "{moved:?}");
    assert_eq!(moved.shadows, 0);
    assert_eq!(moved.frame, 192 + 3 * 64, "{moved:?}");
    // A mesh turns: `hard` builds its shadows again on the GPU, uploading nothing but the
    // model matrices; `wedges-blend` builds them on the CPU and uploads them.
    scene.set_transform(1, box_transform(0.5));
    frame(&ctx, &mut scene, &camera, Technique::Hard);
    let turned = scene.take_uploads();
    assert_eq!((turned.geometry, turned.shadows), (0, 0), "{turned:?}");
    assert_eq!(turned.frame, 3 * 64, "{turned:?}");
    scene.set_transform(1, box_transform(0.7));
    frame(&ctx, &mut scene, &camera, Technique::WedgesBlend);
    let blended = scene.take_uploads();
    assert_eq!(blended.geometry, 0);
    assert!(blended.shadows > 0, "{blended:?}");
    // Under the CPU builder `hard` uploads its shadows too.
    scene.set_shadow_builder(ShadowBuilder::Cpu);
    scene.set_transform(1, box_transform(0.9));
    frame(&ctx, &mut scene, &camera, Technique::Hard);
    assert!(scene.take_uploads().shadows > 0);
}

/// The sphere of [`meshes`] squashed and bulged by `t`, in its own space.
fn deformed(sphere: &TriangleMesh, t: f64) -> Vec<DVec3> {
    sphere
        .positions
        .iter()
        .map(|p| DVec3::new(p.x * (1.0 + 0.4 * t * p.y), p.y * (1.0 - 0.3 * t), p.z))
        .collect()
}

#[test]
fn a_deforming_mesh_is_built_on_the_gpu_from_its_uploaded_vertices() {
    let Some(ctx) = context() else { return };
    let renderer = GpuRenderer::with_context(&ctx);
    let mut meshes = meshes();
    let refs: Vec<(&TriangleMesh, DMat4)> = meshes.iter().map(|(m, t)| (m, *t)).collect();
    let mut scene = GpuScene::new(&renderer, &refs, light(-1.0));
    let camera = camera();
    frame(&ctx, &mut scene, &camera, Technique::Wedges);
    scene.take_uploads();
    let sphere = meshes[1].0.clone();
    for (k, t) in [0.5, 1.0].into_iter().enumerate() {
        let moved = deformed(&sphere, t);
        scene.set_positions(1, &moved).unwrap();
        meshes[1].0.positions = moved;
        let transforms: Vec<DMat4> = meshes.iter().map(|m| m.1).collect();
        let oracle = cpu_scene(&meshes, &transforms, light(-1.0 + k as f64));
        scene.set_light(light(-1.0 + k as f64));
        for technique in [Technique::Hard, Technique::Wedges, Technique::WedgesBlend] {
            let image = frame(&ctx, &mut scene, &camera, technique);
            assert_matches_cpu(&image, &oracle, technique, &format!("deformed by {t}"));
        }
        // Only the sphere's vertices went up for `hard` and `wedges`, and the frame's; the
        // CPU-built `wedges-blend` uploaded its own shadows.
        let up = scene.take_uploads();
        assert_eq!(up.geometry, 12 * sphere.positions.len() as u64, "{up:?}");
        // The GPU's build and the CPU's give the same images.
        for technique in [Technique::Hard, Technique::Wedges] {
            scene.set_shadow_builder(ShadowBuilder::Cpu);
            let cpu_built = frame(&ctx, &mut scene, &camera, technique);
            scene.set_shadow_builder(ShadowBuilder::Gpu);
            let gpu_built = frame(&ctx, &mut scene, &camera, technique);
            let c = compare(&gpu_built, &cpu_built).unwrap();
            assert!(
                c.all.max <= 0.02 && c.all.mae <= 1e-5,
                "{technique}: GPU-built against CPU-built: {c:?}"
            );
            if technique == Technique::Hard {
                assert_eq!(gpu_built.data, cpu_built.data);
            }
        }
    }
    // Another count of vertices, or a vertex that is not finite, is refused.
    let err = scene.set_positions(1, &sphere.positions[1..]).unwrap_err();
    assert!(
        matches!(err, GpuError::PositionCount { mesh: 1, .. }),
        "{err}"
    );
    let mut bad = sphere.positions.clone();
    bad[3].y = f64::NAN;
    let err = scene.set_positions(1, &bad).unwrap_err();
    assert!(
        matches!(err, GpuError::NonFinitePosition { mesh: 1, vertex: 3 }),
        "{err}"
    );
}

#[test]
fn a_mesh_through_the_light_s_plane_is_built_on_the_cpu() {
    let Some(ctx) = context() else { return };
    let renderer = GpuRenderer::with_context(&ctx);
    let meshes = meshes();
    let refs: Vec<(&TriangleMesh, DMat4)> = meshes.iter().map(|(m, t)| (m, *t)).collect();
    // The light at the height of the box's middle: the box reaches behind its plane.
    let low = RectLight::new(
        DVec3::new(-2.0, 0.9, 0.5),
        DVec3::X,
        DVec3::Z,
        DVec2::splat(0.5),
    )
    .unwrap();
    let mut scene = GpuScene::new(&renderer, &refs, low);
    let camera = camera();
    let image = frame(&ctx, &mut scene, &camera, Technique::Wedges);
    assert!(scene.take_uploads().shadows > 0);
    let transforms: Vec<DMat4> = meshes.iter().map(|m| m.1).collect();
    let oracle = CpuRenderer::new(&cpu_scene(&meshes, &transforms, low).lit(0))
        .render(Technique::Wedges, &|_| {});
    let c = compare(&image, &oracle).unwrap();
    assert!(c.all.mae <= 1e-3, "MAE {}", c.all.mae);
}

#[test]
fn frames_that_do_not_fit_are_refused() {
    let Some(ctx) = context() else { return };
    let renderer = GpuRenderer::with_context(&ctx);
    let meshes = meshes();
    let refs: Vec<(&TriangleMesh, DMat4)> = meshes.iter().map(|(m, t)| (m, *t)).collect();
    let mut scene = GpuScene::new(&renderer, &refs, light(0.0));
    let camera = camera();
    let gbuffer = GBuffer::new(&ctx.device, SIZE);
    let small = GBuffer::new(&ctx.device, (SIZE.0, SIZE.1 - 1));
    let target = visibility_target(&ctx.device, SIZE);
    let rgba = texture(
        &ctx.device,
        "rgba",
        SIZE,
        wgpu::TextureFormat::Rgba8Unorm,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    let err = scene.record_depth(&mut enc, &camera, &small).unwrap_err();
    assert!(err.to_string().contains("96 x 71"), "{err}");
    let inputs = |technique| FrameInputs { camera, technique };
    let err = scene
        .record(
            &mut enc,
            &inputs(Technique::Pcss),
            &gbuffer,
            &texture_view(&target),
        )
        .unwrap_err();
    assert!(err.to_string().contains("pcss"), "{err}");
    let err = scene
        .record(
            &mut enc,
            &inputs(Technique::Hard),
            &gbuffer,
            &texture_view(&rgba),
        )
        .unwrap_err();
    assert!(err.to_string().contains("R32Float"), "{err}");
}

/// A rippled sheet of `n` x `n` quads over the ground of [`meshes`], in its own space.
fn sheet(n: u32) -> TriangleMesh {
    let positions: Vec<DVec3> = (0..=n)
        .flat_map(|j| (0..=n).map(move |i| (i, j)))
        .map(|(i, j)| {
            let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
            let h = 1.5 + 0.2 * (17.0 * u).sin() * (13.0 * v).cos();
            DVec3::new(-2.0 + 3.0 * u, h, -1.5 + 3.0 * v)
        })
        .collect();
    let w = n + 1;
    let triangles: Vec<[u32; 3]> = (0..n)
        .flat_map(|j| (0..n).map(move |i| j * w + i))
        .flat_map(|a| [[a, a + 1, a + w + 1], [a, a + w + 1, a + w]])
        .collect();
    TriangleMesh::from_raw("sheet", &positions, &triangles).unwrap()
}

#[test]
#[ignore = "a million triangles: a minute on lavapipe"]
fn a_million_triangles_are_built_on_the_gpu() {
    let Some(ctx) = context() else { return };
    let renderer = GpuRenderer::with_context(&ctx);
    // 720 x 720 quads: 1,036,800 triangles and 1.56 million edges, room for more wedges than
    // one binding of 128 MiB holds (1.2 million): the build binds them in two parts.
    let mut meshes = meshes();
    meshes.push((sheet(720), DMat4::IDENTITY));
    let refs: Vec<(&TriangleMesh, DMat4)> = meshes.iter().map(|(m, t)| (m, *t)).collect();
    let mut scene = GpuScene::new(&renderer, &refs, light(-1.0));
    let camera = camera();
    for technique in [Technique::Hard, Technique::Wedges] {
        let gpu_built = frame(&ctx, &mut scene, &camera, technique);
        assert_eq!(
            scene.take_uploads().shadows,
            0,
            "{technique}: built on the CPU"
        );
        scene.set_shadow_builder(ShadowBuilder::Cpu);
        let cpu_built = frame(&ctx, &mut scene, &camera, technique);
        // Built on the CPU and uploaded for the first technique, kept for the second.
        assert_eq!(
            scene.take_uploads().shadows > 0,
            technique == Technique::Hard
        );
        scene.set_shadow_builder(ShadowBuilder::Gpu);
        let c = compare(&gpu_built, &cpu_built).unwrap();
        println!("{technique}: GPU-built against CPU-built: {:?}", c.all);
        let shadowed = cpu_built.data.iter().filter(|&&v| v < 0.5).count();
        assert!(shadowed > 300, "{technique}: {shadowed} shadowed pixels");
        assert!(
            c.all.mae <= 1e-4 && c.all.share_over <= 1e-3,
            "{technique}: {c:?}"
        );
    }
}

#[test]
fn a_room_lit_by_a_lamp_flush_with_its_ceiling_is_built_on_the_gpu() {
    let Some(ctx) = context() else { return };
    let renderer = GpuRenderer::with_context(&ctx);
    // An L-shaped room seen from inside (its depth pre-pass takes it as a room: its normals'
    // sign turned), the lamp flush with its ceiling in one arm: the inner corner's wall faces
    // the lamp from outside and shades the other arm, which the eye sees.
    let p = DVec3::new;
    let room = l_shaped_room(3.0);
    let meshes = [(room, DMat4::IDENTITY)];
    let refs: Vec<(&TriangleMesh, DMat4)> = meshes.iter().map(|(m, t)| (m, *t)).collect();
    let lamp = RectLight::new(p(3.2, 3.0, 0.8), DVec3::NEG_Y, DVec3::X, DVec2::splat(0.6)).unwrap();
    let mut scene = GpuScene::new(&renderer, &refs, lamp);
    let (eye, target) = (p(0.4, 2.6, 0.4), p(1.2, 0.0, 3.4));
    let view = view::look_at_mat4(eye, target, DVec3::Y);
    let projection = directx::perspective_infinite_reverse(1.2, 96.0 / 72.0, 0.01);
    let camera = FrameCamera::from_matrices(&view, &projection, SIZE).unwrap();
    let c = Camera::look_at(eye, target, DVec3::Y, 1.2f64.to_degrees(), SIZE.0, SIZE.1).unwrap();
    let oracle = Scene::new(c)
        .with_light(lamp)
        .with_mesh("room", &meshes[0].0, DMat4::IDENTITY);
    for technique in [Technique::Hard, Technique::Wedges] {
        let image = frame(&ctx, &mut scene, &camera, technique);
        assert_eq!(
            scene.take_uploads().shadows,
            0,
            "{technique}: built on the CPU"
        );
        assert_matches_cpu(
            &image,
            &oracle,
            technique,
            "an L-shaped room under a flush lamp",
        );
        scene.set_shadow_builder(ShadowBuilder::Cpu);
        let cpu_built = frame(&ctx, &mut scene, &camera, technique);
        scene.set_shadow_builder(ShadowBuilder::Gpu);
        scene.take_uploads();
        let c = compare(&image, &cpu_built).unwrap();
        assert!(
            c.all.max <= 1e-3,
            "{technique}: GPU-built against CPU-built: {c:?}"
        );
    }
}
