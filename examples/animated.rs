//! Soft shadows inside an application's own wgpu frame loop: the application makes its device,
//! uploads a scene once as a `GpuScene`, and records 120 frames of a turning mesh and a waving
//! flag (a deforming open mesh whose vertices the application rewrites every frame, as skinning
//! or a cloth simulation does) under a light that circles them, into its own command encoder and
//! its own `R32Float` target. Each frame prints the bytes it wrote to the GPU: every mesh's
//! vertices and the flag's topology in the first; then the flag's vertices, the frame's uniforms
//! and, where the technique builds its shadows on the CPU, the shadow volumes and wedges
//! (rebuilt because the light and the meshes moved). `wedges` (the default) and `hard` build
//! them on the GPU and upload none; `wedges-blend` builds them on the CPU.
//! The first and last frames are read back and written as EXR and PNG.
//!
//! With `--sun`, the light is the sun instead (a distant light of the sun's angle, 0.53
//! degrees), crossing the sky from low in the east to low in the west over the frames.
//!
//! With `--builder cpu`, `hard` and `wedges` build their shadows on the CPU as `wedges-blend`
//! does, to compare.
//!
//! `cargo run --release --example animated [--sun] [--technique T] [--builder gpu|cpu]
//! [OUT_DIR]` (default `out/`).

use std::path::PathBuf;
use std::time::Instant;

use penumbra::glam::dcamera::rh::{proj::directx, view};
use penumbra::glam::{DMat4, DQuat, DVec2, DVec3};
use penumbra::gpu::{
    GpuContext, OPTIONAL_FEATURES, ShadowBuilder, quiet_device_select, read_r32f,
    required_features, required_limits, visibility_target, wgpu,
};
use penumbra::{
    DistantLight, FrameCamera, FrameInputs, GBuffer, GpuRenderer, GpuScene, Light, RectLight,
    Technique, TriangleMesh, VisibilityImage,
};

const FRAMES: usize = 120;
const SIZE: (u32, u32) = (256, 192);
/// Quads along each side of the flag.
const FLAG: usize = 24;

/// The application's device, made as any wgpu application makes one, with what the passes need.
fn device() -> Result<(wgpu::Device, wgpu::Queue), Box<dyn std::error::Error>> {
    // Without a display, Mesa's device-select layer prints an "error:" line: turn it off.
    quiet_device_select();
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle().with_env());
    let adapter = pollster::block_on(instance.request_adapter(&Default::default()))?;
    let device = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("application"),
        required_features: required_features() | (adapter.features() & OPTIONAL_FEATURES),
        required_limits: required_limits(),
        ..Default::default()
    }))?;
    Ok(device)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let args: Vec<String> = std::env::args().skip(1).collect();
    let sun = args.iter().any(|a| a == "--sun");
    let technique = match args.iter().position(|a| a == "--technique") {
        Some(i) => args
            .get(i + 1)
            .ok_or("--technique needs a value")?
            .parse::<Technique>()?,
        None => Technique::Wedges,
    };
    let builder = match args.iter().position(|a| a == "--builder") {
        Some(i) => match args.get(i + 1).map(String::as_str) {
            Some("gpu") => ShadowBuilder::Gpu,
            Some("cpu") => ShadowBuilder::Cpu,
            _ => return Err("--builder takes gpu or cpu".into()),
        },
        None => ShadowBuilder::Gpu,
    };
    let valued = ["--technique", "--builder"];
    let named = |i: usize| {
        args[i] != "--sun"
            && !valued.contains(&args[i].as_str())
            && (i == 0 || !valued.contains(&args[i - 1].as_str()))
    };
    let out = (0..args.len())
        .find(|&i| named(i))
        .map_or_else(|| root.join("out"), |i| PathBuf::from(&args[i]));
    let name = if sun { "animated-sun" } else { "animated" };
    let (device, queue) = device()?;
    let renderer = GpuRenderer::new(&device, &queue)?;

    // A ground and the spot mesh, each in its own space.
    let p = DVec3::new;
    let ground = TriangleMesh::quad().transformed(&DMat4::from_scale(DVec3::splat(10.0)));
    let spot = TriangleMesh::load_obj(&root.join("fixtures/meshes/spot.obj"))?;
    let turn = |frame: usize| {
        let angle = std::f64::consts::TAU * frame as f64 / FRAMES as f64;
        DMat4::from_scale_rotation_translation(
            DVec3::splat(1.4),
            DQuat::from_rotation_y(angle),
            p(0.0, 1.1, 0.0),
        )
    };
    let light = |frame: usize| -> Light {
        let a = 0.5 * std::f64::consts::TAU * frame as f64 / FRAMES as f64;
        if sun {
            // From 20 degrees above the eastern horizon over the south to the west: azimuth 90
            // to 270 degrees, clockwise from north (-z).
            DistantLight::sun(90.0 + a.to_degrees(), 20.0 + 40.0 * a.sin(), 0.53)
                .expect("angles in range")
                .into()
        } else {
            let centre = p(2.5 * a.cos(), 6.0, 2.5 * a.sin());
            RectLight::new(centre, DVec3::NEG_Y, DVec3::X, DVec2::splat(1.5))
                .unwrap()
                .into()
        }
    };
    // The flag: a grid of quads on a pole, its cloth waving along x.
    let flag = |frame: usize| -> Vec<DVec3> {
        let t = std::f64::consts::TAU * frame as f64 / FRAMES as f64;
        (0..=FLAG)
            .flat_map(|j| (0..=FLAG).map(move |i| (i, j)))
            .map(|(i, j)| {
                let (u, v) = (i as f64 / FLAG as f64, j as f64 / FLAG as f64);
                let wave = 0.25 * u * (std::f64::consts::TAU * u - 2.0 * t).sin();
                p(-3.2 + 1.6 * u, 1.2 + 1.0 * v - 0.1 * u * u, -0.8 + wave)
            })
            .collect()
    };
    let flag_mesh = {
        let n = FLAG as u32 + 1;
        let quads = (0..FLAG as u32).flat_map(|j| (0..FLAG as u32).map(move |i| j * n + i));
        let triangles: Vec<[u32; 3]> = quads
            .flat_map(|a| [[a, a + 1, a + n + 1], [a, a + n + 1, a + n]])
            .collect();
        TriangleMesh::from_raw("flag", &flag(0), &triangles)?
    };
    let mut scene = GpuScene::new(
        &renderer,
        &[
            (&ground, DMat4::IDENTITY),
            (&spot, turn(0)),
            (&flag_mesh, DMat4::IDENTITY),
        ],
        light(0),
    );
    scene.set_shadow_builder(builder);

    // The application's camera, its G-buffer and its target.
    let camera = FrameCamera::from_matrices(
        &view::look_at_mat4(p(0.5, 5.5, 6.5), p(0.0, 0.8, 0.0), DVec3::Y),
        &directx::perspective_infinite_reverse(
            45f64.to_radians(),
            SIZE.0 as f64 / SIZE.1 as f64,
            0.05,
        ),
        SIZE,
    )?;
    let gbuffer = GBuffer::new(&device, SIZE);
    let target = visibility_target(&device, SIZE);
    let target_view = target.create_view(&Default::default());
    let inputs = FrameInputs { camera, technique };
    let ctx = GpuContext::from_device(&device, &queue)?;

    let mut kept: Vec<VisibilityImage> = Vec::new();
    let (mut later_geometry, mut later_shadows) = (0, 0);
    let start = Instant::now();
    for frame in 0..FRAMES {
        scene.set_transform(1, turn(frame));
        scene.set_positions(2, &flag(frame))?;
        scene.set_light(light(frame));
        let mut encoder = device.create_command_encoder(&Default::default());
        scene.record_depth(&mut encoder, &camera, &gbuffer)?;
        scene.record(&mut encoder, &inputs, &gbuffer, &target_view)?;
        let bytes = scene.take_uploads();
        if frame > 0 {
            later_geometry += bytes.geometry;
            later_shadows += bytes.shadows;
        }
        println!(
            "frame {frame:3}: geometry {:>7} B, shadow volumes and wedges {:>7} B, frame {:>5} B",
            bytes.geometry, bytes.shadows, bytes.frame
        );
        if frame == 0 || frame == FRAMES - 1 {
            let data = read_r32f(&ctx, &mut encoder, &target, SIZE.0, SIZE.1)?;
            kept.push(VisibilityImage {
                width: SIZE.0,
                height: SIZE.1,
                data,
            });
        } else {
            queue.submit([encoder.finish()]);
        }
    }
    let _ = device.poll(wgpu::PollType::wait_indefinitely());
    let seconds = start.elapsed().as_secs_f64();

    std::fs::create_dir_all(&out)?;
    for (image, which) in kept.iter().zip(["first", "last"]) {
        image.write_exr(&out.join(format!("{name}-{which}.exr")))?;
        image.write_png(&out.join(format!("{name}-{which}.png")))?;
    }
    let (first, last) = (&kept[0], &kept[1]);
    let moved = first
        .data
        .iter()
        .zip(&last.data)
        .filter(|(a, b)| (*a - *b).abs() > 0.05)
        .count();
    let share = moved as f64 / first.data.len() as f64;
    // After the first frame the geometry written is the flag's vertices, each frame.
    let flag_bytes = (FRAMES as u64 - 1)
        * std::mem::size_of::<[f32; 3]>() as u64
        * flag_mesh.positions.len() as u64;
    println!(
        "{FRAMES} frames of {technique} on {} in {seconds:.2} s ({:.1} ms a frame, building \
         included); after the first frame: geometry {later_geometry} B (the flag's vertices), \
         shadow volumes and wedges {later_shadows} B; V differs by more than 0.05 between the \
         first and last frames on {:.1}% of pixels -> {}",
        ctx.describe(),
        1e3 * seconds / FRAMES as f64,
        100.0 * share,
        out.join(format!("{name}-{{first,last}}.{{exr,png}}"))
            .display()
    );
    if later_geometry != flag_bytes || share < 0.01 {
        return Err("geometry beyond the flag's vertices uploaded, or no shadow moved".into());
    }
    let on_gpu = technique != Technique::WedgesBlend && builder == ShadowBuilder::Gpu;
    if on_gpu && later_shadows != 0 {
        return Err("shadow volumes or wedges uploaded after the first frame".into());
    }
    Ok(())
}
