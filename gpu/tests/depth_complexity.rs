//! Depth-complexity sampling on the GPU against its CPU oracle (`penumbra_volumes::DepthComplexity`):
//! the same samples, the same counts, so the same V on (nearly) every pixel of every fixture; and
//! an edge list too small for its frame, which must lose nothing. They need an adapter (lavapipe
//! in CI), as `gpu.rs` does.

mod common;
use common::{against_the_oracle, agreement, context, fixtures, texture, view};

use glam::DMat4;
use penumbra_geom::VisibilityImage;
use penumbra_geom::{LitScene, Scene, Technique};
use penumbra_gpu::wgpu;
use penumbra_gpu::{
    ComplexityReport, FrameCamera, FrameInputs, GBuffer, GpuContext, GpuRenderer, GpuScene,
    SOFTWARE_LOOP_BUDGET, count_buffer_bytes, read_r32f, read_texels, storage_binding_limit,
    visibility_target,
};
use penumbra_volumes::{DepthComplexity, SamplePattern};

/// `scene` at `w x h` pixels, the same view.
fn at_size(mut scene: LitScene, (w, h): (u32, u32)) -> LitScene {
    scene.set_size(w, h);
    scene
}

/// Renders each fixture that `which` takes at `size` (its own where `None`) on the GPU and by
/// the oracle, at 64 and 256 samples, and checks the share of equal pixels and the number
/// beyond one sample.
fn check_fixtures(
    which: impl Fn(&str) -> bool,
    size: Option<(u32, u32)>,
    min_equal: f64,
    max_beyond: usize,
) {
    let Some(ctx) = context() else {
        return;
    };
    let r = GpuRenderer::with_context(&ctx);
    let mut report = Vec::new();
    for (name, scene) in fixtures().into_iter().filter(|(name, _)| which(name)) {
        let scene = scene.lit(0);
        let scene = match size {
            Some(size) => at_size(scene, size),
            None => scene,
        };
        for (samples, cpu, gpu) in against_the_oracle(&r, &name, &scene) {
            let (equal, beyond) = agreement(&cpu, &gpu.image, 1.0 / samples as f32);
            report.push(format!(
                "{name} {samples}: {:.3}% equal, {beyond} pixels beyond one sample",
                100.0 * equal
            ));
            assert!(
                equal >= min_equal && beyond <= max_beyond,
                "{name} at {samples} samples: {report:#?}"
            );
        }
    }
    assert!(!report.is_empty(), "no fixture");
    println!("{report:#?}");
}

/// The acceptance of GPU depth complexity: every fixture at its own 320x240, 64 and 256
/// samples, equal to the oracle on at least 99.95% of its pixels (99.979% measured, on
/// `spheres-9x9`) and nowhere more than one sample apart. A single sample flips where it lies
/// within the f32 rounding of a projected edge. What holds the rest: P taken where the pixel's
/// ray lands (the receiver and its centre count again where the rasteriser's snapping put the
/// pixel's centre on another face), and the side tests from the receiver's corners in twice
/// f32's precision near a plane. Without that precision (the shader compiler free to fold the
/// error-free transformations), 3, 8 and 2 pixels of `fandisk`, `spheres-9x9` and `beetle` are
/// more than a sample apart. Minutes on lavapipe: `.ci/run` runs it among the slower tests,
/// `cargo test` the same check at 80x60 (below).
#[test]
#[ignore = "minutes on lavapipe: one of the slower tests that .ci/run runs"]
fn gpu_depth_complexity_equals_the_cpu_oracle_on_every_fixture() {
    check_fixtures(|_| true, None, 0.9995, 0);
}

/// The same at half the fixtures' size, where the pixels fall elsewhere: a ground pixel of
/// `spot` whose stencil count was two above the oracle's (the segment to the centre through a
/// crack of the mesh within 1e-4 of two triangles, decided against the oracle's `f64` by the
/// rasterised volumes) is counted again since its count differs from a neighbour's, and a
/// pixel of `cheburashka` at a junction of several triangles whose hit none of the
/// neighbouring pixels' triangles held is found by the receiver candidates (`candidates.wgsl`).
/// Two minutes on lavapipe: among the slower tests, as the acceptance.
#[test]
#[ignore = "minutes on lavapipe: one of the slower tests that .ci/run runs"]
fn gpu_depth_complexity_equals_the_cpu_oracle_at_half_size() {
    check_fixtures(|_| true, Some((160, 120)), 0.9998, 0);
}

/// The acceptance's check at 80x60, a sixteenth of the fixtures' pixels, on every fixture but
/// `spheres-9x9` (next): what `cargo test` runs of the two above, in half a minute on lavapipe
/// (100% equal measured on each, at both sample counts).
#[test]
fn gpu_depth_complexity_equals_the_cpu_oracle_at_80x60() {
    check_fixtures(|name| name != "spheres-9x9", Some((80, 60)), 0.9995, 0);
}

/// `spheres-9x9` at 40x30: with its 81 spheres' potential edges a render takes seconds on
/// lavapipe at any size (8 s at 40x30, 18 s at 80x60, 38 s at 160x120), so it is checked
/// smaller than the rest (100% equal measured, at both counts).
#[test]
fn gpu_depth_complexity_equals_the_cpu_oracle_on_spheres_9x9_at_40x30() {
    check_fixtures(|name| name == "spheres-9x9", Some((40, 30)), 0.9995, 0);
}

/// Renders `scene` by depth complexity in a [`GpuScene`] with an edge list of `capacity`
/// entries (none: as the scene sized it), returning V and the frame's report.
fn frame(
    ctx: &GpuContext,
    gpu_scene: &mut GpuScene,
    scene: &LitScene,
    capacity: Option<u32>,
) -> (VisibilityImage, ComplexityReport) {
    if let Some(c) = capacity {
        gpu_scene.set_edge_list_capacity(c);
    }
    let size = (scene.camera.width, scene.camera.height);
    let gbuffer = GBuffer::new(&ctx.device, size);
    let (mut enc, target) = record_frame(ctx, gpu_scene, scene, &gbuffer).expect("frame");
    let v = read_r32f(ctx, &mut enc, &target, size.0, size.1).expect("readback");
    let report = gpu_scene.complexity_report().expect("report");
    let image = VisibilityImage {
        width: size.0,
        height: size.1,
        data: v,
    };
    (image, report.expect("a depth-complexity frame"))
}

/// Records the depth pre-pass and a depth-complexity frame of `scene` into `gbuffer` and a new
/// V target, in an encoder not yet submitted.
fn record_frame(
    ctx: &GpuContext,
    gpu_scene: &mut GpuScene,
    scene: &LitScene,
    gbuffer: &GBuffer,
) -> Result<(wgpu::CommandEncoder, wgpu::Texture), penumbra_gpu::GpuError> {
    let device = &ctx.device;
    let camera = FrameCamera::of_scene(scene);
    let target = visibility_target(device, gbuffer.size());
    let inputs = FrameInputs {
        camera,
        technique: Technique::DepthComplexity,
    };
    let mut enc = device.create_command_encoder(&Default::default());
    gpu_scene.record_depth(&mut enc, &camera, gbuffer)?;
    gpu_scene.record(&mut enc, &inputs, gbuffer, &view(&target))?;
    Ok((enc, target))
}

/// Sizes `gpu_scene`'s edge list for a frame of `scene` into `gbuffer`, as a one-shot render
/// does (`GpuRenderer::render_depth_complexity`): the first frame then fits, where a list too
/// small would make every tile read every potential edge.
fn size_the_edge_list(
    ctx: &GpuContext,
    gpu_scene: &mut GpuScene,
    scene: &LitScene,
    gbuffer: &GBuffer,
) {
    let inputs = FrameInputs {
        camera: FrameCamera::of_scene(scene),
        technique: Technique::DepthComplexity,
    };
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    gpu_scene
        .record_edge_lists(&mut enc, &inputs, gbuffer)
        .expect("edge lists");
    ctx.queue.submit([enc.finish()]);
    gpu_scene.complexity_report().expect("report");
    assert!(gpu_scene.edge_list_capacity() > 0);
}

/// A fixture's meshes in a [`GpuScene`] (each placed by the identity, in the world) under its
/// light (a distant light warped by the scene itself) with `samples` samples.
fn gpu_scene(r: &GpuRenderer, scene: &LitScene, samples: u32) -> GpuScene {
    let meshes: Vec<_> = scene
        .world_meshes()
        .iter()
        .map(|m| (&m.mesh, DMat4::IDENTITY))
        .collect();
    let mut s = GpuScene::new(r, &meshes, scene.world_light());
    s.set_light_samples(samples).unwrap();
    s
}

fn fixture(name: &str) -> LitScene {
    fixtures()
        .into_iter()
        .find(|(n, _)| n == name)
        .expect("fixture")
        .1
        .lit(0)
}

/// The counting pass's buffer that a frame allocates is the figure `count_buffer_bytes` gives
/// (which the back-end policy charges): V, and each pixel's state and counts.
#[test]
fn the_counting_buffer_allocated_is_the_figure_given() {
    let Some(ctx) = context() else {
        return;
    };
    let r = GpuRenderer::with_context(&ctx);
    let limit = storage_binding_limit(&ctx.device.limits());
    let scene = at_size(fixture("quad-over-plane"), (40, 30));
    for samples in [64, 256] {
        let mut gpu_scene = gpu_scene(&r, &scene, samples);
        assert_eq!(gpu_scene.count_buffer_bytes(), None);
        frame(&ctx, &mut gpu_scene, &scene, None);
        let given = count_buffer_bytes((40, 30), samples, limit);
        assert_eq!(gpu_scene.count_buffer_bytes(), given, "{samples}");
        let per_pixel = 4 + 4 * (8 + samples as u64 / 4);
        assert_eq!(given, Some(40 * 30 * per_pixel), "{samples}");
    }
}

#[test]
fn an_edge_list_too_small_loses_no_edge_and_grows() {
    let Some(ctx) = context() else {
        return;
    };
    let r = GpuRenderer::with_context(&ctx);
    // Few potential silhouette edges, so that reading them all for every pixel stays within
    // lavapipe's loop limit.
    let scene = at_size(fixture("sphere-over-plane"), (96, 72));
    let mut gpu_scene = gpu_scene(&r, &scene, 64);
    // Ten entries for a frame that needs thousands: every tile but the first reads all edges.
    let (small, report) = frame(&ctx, &mut gpu_scene, &scene, Some(10));
    assert!(report.overflowed, "ten entries were enough: {report:?}");
    assert_eq!(report.cut_short, 0);
    let grown = gpu_scene.edge_list_capacity();
    assert!(
        grown >= report.demand && report.demand > 1000,
        "{report:?}, grew to {grown}"
    );
    let (fitting, report) = frame(&ctx, &mut gpu_scene, &scene, None);
    assert!(
        !report.overflowed,
        "the grown list overflowed again: {report:?}"
    );
    assert_eq!(gpu_scene.edge_list_capacity(), grown);
    let differ = small
        .data
        .iter()
        .zip(&fitting.data)
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(differ, 0, "the overflowing frame lost edges");
    // And both are the oracle's image.
    let oracle = DepthComplexity::new(&scene).render(
        SamplePattern {
            per_axis: 8,
            jitter: false,
        },
        &|_| {},
    );
    let (equal, _) = agreement(&oracle, &fitting, 1.0 / 64.0);
    assert!(equal >= 0.999, "{:.3}% equal", 100.0 * equal);
    // Light samples the GPU does not take are refused.
    for bad in [0, 1000, 4096] {
        assert!(gpu_scene.set_light_samples(bad).is_err(), "{bad}");
    }
}

#[test]
fn pixels_beyond_the_loop_budget_are_reported() {
    let Some(ctx) = context() else {
        return;
    };
    let r = GpuRenderer::with_context(&ctx);
    let scene = at_size(fixture("sphere-over-plane"), (48, 36));
    let mut gpu_scene = gpu_scene(&r, &scene, 256);
    if ctx.info.device_type == wgpu::DeviceType::Cpu {
        assert_eq!(gpu_scene.loop_budget(), SOFTWARE_LOOP_BUDGET);
    }
    let (_, report) = frame(&ctx, &mut gpu_scene, &scene, None);
    assert_eq!(report.cut_short, 0, "{report:?}");
    // A budget below what counting a pixel's 256 samples alone takes: every pixel whose
    // samples were counted one by one, each penumbra pixel among them, is reported.
    gpu_scene.set_loop_budget(200);
    let (image, report) = frame(&ctx, &mut gpu_scene, &scene, None);
    let penumbra = image.data.iter().filter(|&&v| v > 0.0 && v < 1.0).count();
    assert!(penumbra > 100, "{penumbra}");
    assert!(
        report.cut_short as usize >= penumbra,
        "{report:?}, {penumbra} in penumbra"
    );
}

/// A stencil count two too many on one pixel, as a crack between two shadow volumes' faces
/// leaves it (seen under a light four times the scale scene's), differs from a neighbour's and
/// is counted again: the image is the one without the error, amid lit pixels and next to a
/// hard shadow's outline, where the wrong count equals the far side's, alike.
#[test]
fn a_wrong_stencil_count_is_counted_again() {
    let Some(ctx) = context() else {
        return;
    };
    let r = GpuRenderer::with_context(&ctx);
    let scene = at_size(fixture("sphere-over-plane"), (48, 36));
    let mut gpu_scene = gpu_scene(&r, &scene, 64);
    let (clean, _) = frame(&ctx, &mut gpu_scene, &scene, None);
    let w = scene.camera.width as usize;
    // A lit pixel amid lit ones and a penumbra pixel amid penumbra ones.
    let lit = (1..clean.data.len() - w)
        .find(|&i| clean.data[i - 1..=i + 1].iter().all(|&v| v == 1.0) && clean.data[i + w] == 1.0)
        .expect("a lit pixel");
    let penumbra = (w..clean.data.len() - w)
        .find(|&i| {
            [i - w, i - 1, i, i + 1, i + w]
                .iter()
                .all(|&k| clean.data[k] > 0.2 && clean.data[k] < 0.8)
        })
        .expect("a penumbra pixel");
    for i in [lit, penumbra] {
        let pixel = [(i % w) as u32, (i / w) as u32];
        gpu_scene.set_stencil_error(Some(pixel));
        let (hurt, report) = frame(&ctx, &mut gpu_scene, &scene, None);
        assert_eq!(report.unfinished + report.cut_short, 0, "{report:?}");
        let differ: Vec<_> = (0..clean.data.len())
            .filter(|&k| clean.data[k] != hurt.data[k])
            .map(|k| (k % w, k / w, clean.data[k], hurt.data[k]))
            .collect();
        assert!(differ.is_empty(), "error at {pixel:?}: {differ:?}");
    }
    gpu_scene.set_stencil_error(None);
}

/// A [`GBuffer`] whose depth target can be copied out (`GBuffer::new`'s, plus `COPY_SRC`).
fn readable_gbuffer(device: &wgpu::Device, size: (u32, u32)) -> GBuffer {
    use penumbra_gpu::{DEPTH_FORMAT, NORMAL_FORMAT, POSITION_FORMAT};
    let sampled = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
    let depth = texture(
        device,
        "depth",
        size,
        DEPTH_FORMAT,
        sampled | wgpu::TextureUsages::COPY_SRC,
    );
    let position = texture(device, "position", size, POSITION_FORMAT, sampled);
    let normal = texture(device, "normal", size, NORMAL_FORMAT, sampled);
    GBuffer {
        depth_view: view(&depth),
        stencil_view: depth.create_view(&wgpu::TextureViewDescriptor {
            format: Some(wgpu::TextureFormat::Stencil8),
            aspect: wgpu::TextureAspect::StencilOnly,
            ..Default::default()
        }),
        position_view: view(&position),
        normal_view: view(&normal),
        depth,
        position,
        normal,
    }
}

#[test]
fn the_stencil_counts_the_triangles_towards_the_centre_as_the_oracle_does() {
    let Some(ctx) = context() else {
        return;
    };
    let r = GpuRenderer::with_context(&ctx);
    // Open sheets, an edge of three pages, closed meshes through each other's shadows.
    for name in ["nonmanifold", "fence", "spheres-9x9", "beetle"] {
        let scene = at_size(fixture(name), (96, 72));
        let mut gpu_scene = gpu_scene(&r, &scene, 64);
        let size = (scene.camera.width, scene.camera.height);
        let gbuffer = readable_gbuffer(&ctx.device, size);
        // The stencil is the same either way; with a list too small, `spheres-9x9`'s counting
        // pass reads every potential edge in every tile (95 s on lavapipe, against 15).
        size_the_edge_list(&ctx, &mut gpu_scene, &scene, &gbuffer);
        let (mut enc, _) = record_frame(&ctx, &mut gpu_scene, &scene, &gbuffer).unwrap();
        let stencil = read_texels(
            &ctx,
            &mut enc,
            (&gbuffer.depth, wgpu::TextureAspect::StencilOnly),
            size,
            1,
        )
        .expect("stencil");
        let oracle = DepthComplexity::new(&scene);
        let cam = &scene.camera;
        let (mut lit, mut equal, mut deep) = (0, 0, 0);
        let (mut near, mut hits) = (Vec::new(), Vec::new());
        for j in 0..size.1 {
            for i in 0..size.0 {
                let Some(p) = oracle.tracer.surface_point(cam.eye, cam.ray_dir(i, j)) else {
                    continue;
                };
                if !(oracle.tracer.light.to_light_space(p.position).z > 0.0) {
                    continue;
                }
                oracle.tracer.near_triangles(&p, &mut near);
                let count = oracle.centre_count(&p, &near, &mut hits);
                lit += 1;
                equal += usize::from(stencil[(j * size.0 + i) as usize] as u32 == count);
                deep += usize::from(count >= 2);
            }
        }
        let share = equal as f64 / lit as f64;
        println!("{name}: {equal} of {lit} equal, {deep} behind two or more triangles");
        assert!(share >= 0.995, "{name}: {equal} of {lit} counts equal");
        // The sheets folded over each other put receivers behind two triangles and more.
        assert!(
            name != "nonmanifold" || deep > 100,
            "{name}: {deep} receivers behind two triangles"
        );
    }
}

#[test]
fn a_moved_mesh_and_a_moved_light_are_counted_anew() {
    let Some(ctx) = context() else {
        return;
    };
    let r = GpuRenderer::with_context(&ctx);
    let base = at_size(fixture("sphere-over-plane"), (96, 72));
    let mut gpu_scene = gpu_scene(&r, &base, 64);
    let pattern = SamplePattern {
        per_axis: 8,
        jitter: false,
    };
    // The same meshes moved in code: the sphere by a transform, then the light.
    let moved =
        DMat4::from_translation(glam::DVec3::new(0.4, -0.2, 0.3)) * DMat4::from_rotation_y(0.5);
    let mut light = base.light;
    light.center += glam::DVec3::new(-0.7, 0.2, 0.5);
    let world = |transform: DMat4, light| {
        base.meshes.iter().enumerate().fold(
            Scene::new(base.camera).with_light(light),
            |s, (i, m)| {
                s.with_mesh(
                    &format!("mesh {i}"),
                    &m.mesh,
                    if i == 1 { transform } else { DMat4::IDENTITY },
                )
            },
        )
    };
    for (step, scene) in [
        (0, world(DMat4::IDENTITY, base.light)),
        (1, world(moved, base.light)),
        (2, world(moved, light)),
    ] {
        if step == 1 {
            gpu_scene.set_transform(1, moved);
        }
        if step == 2 {
            gpu_scene.set_light(light);
        }
        let scene = scene.lit(0);
        let (gpu, report) = frame(&ctx, &mut gpu_scene, &scene, None);
        assert_eq!(report.cut_short, 0);
        let oracle = DepthComplexity::new(&scene).render(pattern, &|_| {});
        let (equal, beyond) = agreement(&oracle, &gpu, 1.0 / 64.0);
        assert!(
            equal >= 0.998 && beyond as f64 <= 0.001 * gpu.data.len() as f64,
            "step {step}: {:.3}% equal, {beyond} pixels beyond one sample",
            100.0 * equal
        );
    }
}

#[test]
fn an_edge_list_beyond_the_device_is_refused() {
    let Some(ctx) = context() else {
        return;
    };
    let r = GpuRenderer::with_context(&ctx);
    let scene = at_size(fixture("quad-over-plane"), (32, 24));
    let mut gpu_scene = gpu_scene(&r, &scene, 64);
    // Sixteen gigabytes of entries: no device binds that much.
    gpu_scene.set_edge_list_capacity(u32::MAX);
    let gbuffer = GBuffer::new(&ctx.device, (scene.camera.width, scene.camera.height));
    let Err(err) = record_frame(&ctx, &mut gpu_scene, &scene, &gbuffer) else {
        panic!("a 16 GB edge list was recorded");
    };
    assert!(
        matches!(err, penumbra_gpu::GpuError::TooLarge { .. }),
        "{err}"
    );
    assert!(err.to_string().contains("4294967295 entries"), "{err}");
}
