//! `penumbra bench --counters`: what each GPU pass of a frame did, per pixel: its shaders'
//! invocations and the primitives it rasterised (pipeline-statistics queries, where the device
//! has them) and the bytes of the buffers and textures it binds. Counts, unlike times, do not
//! depend on the device's speed: lavapipe's are those of any Vulkan device.

use std::path::Path;

use anyhow::{Result, bail};
use penumbra::gpu::{PassCounters, WedgePass};
use penumbra::volumes::Volumes;
use penumbra::{Backend, LitScene, RenderOptions, Renderer, Scene, Technique};

use crate::cli::ParamArgs;
use crate::words::InCommandWords;

/// Renders one frame of each of `techniques` on the GPU with its passes counted, and prints
/// their counts (as JSON when `json`); of a scene of several lights, one frame per light, each
/// report naming its light.
pub(crate) fn counters(
    scene_path: &Path,
    techniques: &[Technique],
    (backend, wedge_pass): (Backend, Option<WedgePass>),
    options: RenderOptions,
    json: bool,
    params: &ParamArgs,
) -> Result<()> {
    let mut scene = Scene::load(scene_path)?;
    params.apply(&mut scene)?;
    let mut renderer = Renderer::new(backend);
    renderer.set_counters(true);
    renderer.set_wedge_pass(wedge_pass);
    let mut reports = Vec::new();
    // Each light alone, for a scene of several: one frame, and one report, per light.
    let layered = !scene.single_channel();
    let lights: Vec<(Option<&str>, LitScene)> = scene
        .lights
        .iter()
        .enumerate()
        .map(|(k, l)| (layered.then_some(l.name.as_str()), scene.lit(k)))
        .collect();
    for &technique in techniques {
        options.pattern_for(technique).in_command_words()?;
        if !renderer.uses_gpu(technique).in_command_words()? {
            bail!("--counters: {technique} runs on the CPU here; counters count GPU passes");
        }
        for (light, scene) in &lights {
            let volumes = technique.is_volume().then(|| Volumes::build(scene));
            let frame = renderer
                .render_frame(scene, technique, &options, volumes.as_ref(), &|_| {})
                .in_command_words()?;
            let Some(counts) = frame.counters else {
                bail!(
                    "--counters: {technique} rendered on the CPU ({})",
                    frame.detail
                );
            };
            let device = renderer.gpu_description().unwrap_or_default();
            if json {
                let mut report = serde_json::json!({
                    "scene": scene_path.display().to_string(),
                    "technique": format!("{technique:?}"),
                    "device": device,
                    "resolution": [scene.camera.width, scene.camera.height],
                    "counters": counts,
                });
                if let Some(name) = light {
                    report["light"] = serde_json::json!(name);
                }
                reports.push(report);
            } else {
                println!(
                    "{} {technique}{} on {device} at {}x{}, one frame:",
                    scene_path.display(),
                    light.map(|n| format!(", light {n},")).unwrap_or_default(),
                    scene.camera.width,
                    scene.camera.height
                );
                print!("{}", table(&counts));
            }
        }
    }
    if json {
        let out = match reports.as_slice() {
            [one] => one.clone(),
            _ => serde_json::Value::Array(reports),
        };
        println!("{}", serde_json::to_string_pretty(&out)?);
    }
    Ok(())
}

/// The counts as a table, one row per kind of pass: the totals, then each per pixel.
pub(crate) fn table(c: &PassCounters) -> String {
    let px = c.pixels.max(1) as f64;
    let mut out = format!(
        "  {:<10} {:>6} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}\n",
        "pass", "passes", "vertex", "primitive", "fragment", "compute", "read", "written"
    );
    let per = |v: u64| v as f64 / px;
    for p in &c.passes {
        let stats = |f: fn(&penumbra::gpu::Statistics) -> u64| p.statistics.as_ref().map(f);
        let cols = [
            stats(|s| s.vertices),
            stats(|s| s.primitives),
            stats(|s| s.fragments),
            stats(|s| s.compute),
            Some(p.bytes_read),
            Some(p.bytes_written),
        ];
        let total: Vec<String> = cols
            .iter()
            .map(|v| v.map_or("-".to_string(), |v| v.to_string()))
            .collect();
        let pixel: Vec<String> = cols
            .iter()
            .map(|v| v.map_or("-".to_string(), |v| format!("{:.3}", per(v))))
            .collect();
        out += &format!(
            "  {:<10} {:>6} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}\n",
            p.pass, p.passes, total[0], total[1], total[2], total[3], total[4], total[5]
        );
        out += &format!(
            "  {:<10} {:>6} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}\n",
            "  /pixel", "", pixel[0], pixel[1], pixel[2], pixel[3], pixel[4], pixel[5]
        );
    }
    out += &format!("  passes a frame: {}", c.pass_count());
    if let Some(n) = c.invocations_per_pixel() {
        out += &format!("; shader invocations a pixel: {n:.1}");
    }
    out += "\n";
    if let Some(u) = c.uploads {
        out += &format!(
            "  uploaded: geometry {} B, shadow volumes and wedges {} B, frame {} B\n",
            u.geometry, u.shadows, u.frame
        );
    }
    if c.passes.iter().all(|p| p.statistics.is_none()) {
        out += "  (no pipeline-statistics queries on this device: invocations and primitives \
                are not counted; bytes are)\n";
    }
    out
}
