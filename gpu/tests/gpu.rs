//! GPU tests. They need an adapter: in CI that is Mesa's lavapipe, and a missing adapter fails
//! the run when `CI` is set; on a developer's machine without one they print a skip.

use std::path::PathBuf;

use penumbra_geom::Scene;
use penumbra_geom::image::compare;
use penumbra_geom::reference::{self, Reference, Tracer};
use penumbra_gpu::{GpuContext, GpuRenderer, GpuTechnique};
use penumbra_volumes::Volumes;
use penumbra_volumes::{CpuRenderer, Technique};

fn context() -> Option<GpuContext> {
    match GpuContext::new() {
        Ok(c) => {
            println!("adapter: {}", c.describe());
            Some(c)
        }
        Err(e) if std::env::var_os("CI").is_some() => panic!("CI needs a GPU adapter: {e}"),
        Err(e) => {
            println!("SKIPPED (no adapter): {e}");
            None
        }
    }
}

fn fixtures() -> Vec<(String, Scene)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scenes");
    let mut v: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| {
            let name = p.file_stem().unwrap().to_string_lossy().into_owned();
            (name, Scene::load(&p).unwrap())
        })
        .collect();
    v.sort_by(|a, b| a.0.cmp(&b.0));
    assert!(v.len() >= 8, "fixtures missing");
    v
}

#[test]
fn every_wgsl_file_validates_with_naga() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src/shaders");
    let mut n = 0;
    for e in std::fs::read_dir(&dir).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_none_or(|x| x != "wgsl") {
            continue;
        }
        // Each pass's shader is compiled with frame.wgsl prepended (`passes::shader`).
        let src = format!(
            "{}\n{}",
            penumbra_gpu::passes::FRAME_WGSL,
            std::fs::read_to_string(&p).unwrap()
        );
        if p.ends_with("frame.wgsl") {
            continue;
        }
        let module = naga::front::wgsl::parse_str(&src)
            .unwrap_or_else(|e| panic!("{}: {}", p.display(), e.emit_to_string(&src)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}: {e:?}", p.display()));
        n += 1;
    }
    assert!(
        n >= 3,
        "expected the pass shaders in {}, found {n}",
        dir.display()
    );
}

#[test]
fn gpu_hard_matches_the_hard_reference() {
    let Some(ctx) = context() else { return };
    let r = GpuRenderer::new(&ctx);
    for (name, scene) in fixtures() {
        let volumes = Volumes::build(&scene);
        let img = r.render(&scene, &volumes, GpuTechnique::Hard).unwrap();
        let tracer = Tracer::new(&scene);
        let want = reference::render(&scene, &tracer, Reference::Hard, &|_| {});
        let differ = img
            .data
            .iter()
            .zip(&want.data)
            .filter(|(a, b)| a != b)
            .count();
        let share = differ as f64 / img.data.len() as f64;
        println!(
            "{name:>18}: GPU hard differs from the hard reference on {differ} pixels ({:.3}%)",
            100.0 * share
        );
        if share > 0.005 {
            let dir = std::env::temp_dir();
            let _ = img.write_exr(&dir.join(format!("{name}-gpu-hard-actual.exr")));
        }
        assert!(share <= 0.005, "{name}: {differ} pixels differ");
    }
}

#[test]
fn gpu_wedges_match_the_cpu_oracle() {
    gpu_matches_cpu(GpuTechnique::Wedges, Technique::Wedges);
}

#[test]
fn gpu_wedges_blend_matches_the_cpu_oracle() {
    gpu_matches_cpu(GpuTechnique::WedgesBlend, Technique::WedgesBlend);
}

fn gpu_matches_cpu(gt: GpuTechnique, t: Technique) {
    let Some(ctx) = context() else { return };
    let r = GpuRenderer::new(&ctx);
    for (name, scene) in fixtures() {
        let volumes = Volumes::build(&scene);
        let gpu = r.render(&scene, &volumes, gt).unwrap();
        let cpu = CpuRenderer::new(&scene).render(&scene, t, &|_| {});
        let c = compare(&gpu, &cpu).unwrap();
        println!(
            "{name:>18}: GPU {t:?} vs CPU: MAE {:.2e}, p99 {:.2e}, max {:.2e}; penumbra MAE {:.2e}",
            c.all.mae, c.all.p99, c.all.max, c.penumbra.mae
        );
        if c.all.mae > 1e-3 || c.all.p99 > 0.02 {
            let dir = std::env::temp_dir();
            let _ = gpu.write_exr(&dir.join(format!("{name}-gpu-{t:?}-actual.exr")));
        }
        assert!(c.all.mae <= 1e-3, "{name}: MAE {}", c.all.mae);
        assert!(c.all.p99 <= 0.02, "{name}: p99 {}", c.all.p99);
    }
}

/// Issue 4's memory bound: seed 004's four `RGBA32F`, 64 bytes per pixel, for the silhouette and
/// final buffers of `wedges-blend` together.
#[test]
fn blend_visibility_buffers_take_at_most_64_bytes_per_pixel() {
    let bytes = penumbra_gpu::passes::blend::bytes_per_pixel();
    assert!(bytes <= 64, "{bytes} bytes per pixel");
    assert_eq!(bytes, 40 + 24);
}
