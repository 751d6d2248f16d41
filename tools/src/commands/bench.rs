//! `penumbra bench`: frame and pass times of one or several techniques.

use penumbra::gpu::WedgePass;
use std::path::Path;

use anyhow::{Context, Result, bail};
use penumbra::gpu::PassTimes;
use penumbra::volumes::Volumes;
use penumbra::{Backend, LitScene, RenderOptions, Renderer, Scene, Technique};

use crate::cli::ParamArgs;
use crate::words::InCommandWords;

pub(crate) fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// How `penumbra bench` times: frames per technique and round, and rounds.
#[derive(Clone, Copy)]
pub(crate) struct Timing {
    pub(crate) frames: usize,
    pub(crate) rounds: usize,
}

/// The passes `penumbra bench` reports, in order.
pub(crate) const BENCH_PASSES: [&str; 13] = [
    "depth",
    "build",
    "stencil",
    "wedge",
    "blend",
    "edge_lists",
    "count",
    "light_map",
    "preprocess",
    "filter",
    "resolve",
    "gpu_total",
    "frame_wall",
];

pub(crate) fn bench(
    scene_path: &Path,
    techniques: &[Technique],
    timing: Timing,
    (backend, wedge_pass): (Backend, Option<WedgePass>),
    options: RenderOptions,
    json: bool,
    params: &ParamArgs,
) -> Result<()> {
    if timing.frames == 0 {
        bail!("--frames must be at least 1");
    }
    if timing.rounds == 0 {
        bail!("--rounds must be at least 1");
    }
    // Before any technique is timed, each in a process of its own.
    for &t in techniques {
        penumbra::backend::check(t, backend).in_command_words()?;
    }
    let technique = match techniques {
        [] => bail!("--technique: name at least one technique"),
        [t] if timing.rounds == 1 => *t,
        _ => return bench_compare(techniques, timing, json),
    };
    let report = bench_one(
        scene_path,
        technique,
        timing.frames,
        (backend, wedge_pass),
        options,
        params,
    )?;
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print_bench(
            &report,
            technique,
            &format!("median of {} frames", timing.frames),
        );
    }
    Ok(())
}

/// Times `frames` frames of `technique` in this process (after one warm-up frame): the report
/// `penumbra bench --json` prints.
pub(crate) fn bench_one(
    scene_path: &Path,
    technique: Technique,
    frames: usize,
    (backend, wedge_pass): (Backend, Option<WedgePass>),
    options: RenderOptions,
    params: &ParamArgs,
) -> Result<serde_json::Value> {
    options.pattern_for(technique).in_command_words()?;
    let mut scene = Scene::load(scene_path)?;
    params.apply(&mut scene)?;
    let mut renderer = Renderer::new(backend);
    renderer.set_wedge_pass(wedge_pass);
    let on_gpu = renderer.uses_gpu(technique).in_command_words()?;
    // A frame of a scene of several lights renders each light alone, one after the other.
    let lights = scene.light_count();
    let scenes: Vec<LitScene> = (0..lights).map(|k| scene.lit(k)).collect();
    // Built once, outside the timed frames: the frames time the GPU's work.
    let volumes: Vec<Option<Volumes>> = scenes
        .iter()
        .map(|s| (on_gpu && technique.is_volume()).then(|| Volumes::build(s)))
        .collect();
    let mut wall = Vec::new();
    let mut passes: Vec<PassTimes> = Vec::new();
    for k in 0..=frames {
        let start = std::time::Instant::now();
        let mut times: Option<PassTimes> = None;
        for (s, v) in scenes.iter().zip(&volumes) {
            let frame = renderer
                .render_frame(s, technique, &options, v.as_ref(), &|_| {})
                .in_command_words()?;
            times = match (times, frame.times) {
                (Some(a), Some(b)) => Some(a.plus(&b)),
                (a, b) => a.or(b),
            };
        }
        if k > 0 {
            wall.push(start.elapsed().as_secs_f64() * 1e3);
            passes.extend(times);
        }
    }
    let device = match renderer.gpu_description() {
        Some(d) if on_gpu => d,
        _ => format!("cpu, {} threads", rayon::current_num_threads()),
    };
    let pass = |f: fn(&PassTimes) -> f64| {
        (!passes.is_empty()).then(|| median(passes.iter().map(f).collect()))
    };
    let mut report = serde_json::json!({
        "scene": scene_path.display().to_string(),
        "technique": format!("{technique:?}"),
        "device": device,
        "resolution": [scene.camera.width, scene.camera.height],
        "frames": frames,
        "median_ms": {
            "depth": pass(|p| p.depth),
            "build": pass(|p| p.build),
            "stencil": pass(|p| p.stencil),
            "wedge": pass(|p| p.wedge),
            "blend": pass(|p| p.blend),
            "edge_lists": pass(|p| p.edge_lists),
            "count": pass(|p| p.count),
            "resolve": pass(|p| p.resolve),
            "light_map": pass(|p| p.light_map),
            "preprocess": pass(|p| p.preprocess),
            "filter": pass(|p| p.filter),
            "gpu_total": pass(|p| p.total()),
            "frame_wall": median(wall),
        }
    });
    // The lights a frame renders, for a scene of several (whose frame renders each).
    if !scene.single_channel() {
        report["lights"] = serde_json::json!(lights);
    }
    Ok(report)
}

/// Prints a report of [`bench_one`] (or of [`bench_compare`]'s medians) of `technique` as text.
pub(crate) fn print_bench(report: &serde_json::Value, technique: Technique, what: &str) {
    let [w, h] = [0, 1].map(|i| report["resolution"][i].as_u64().unwrap_or(0));
    // A frame of several lights renders each of them.
    let lights = match report["lights"].as_u64() {
        Some(n) if n > 1 => format!(" ({n} lights, each rendered in every frame)"),
        _ => String::new(),
    };
    println!(
        "{} {} on {} at {w}x{h}{lights}, {what}:",
        report["scene"].as_str().unwrap_or_default(),
        report["technique"].as_str().unwrap_or_default(),
        report["device"].as_str().unwrap_or_default(),
    );
    let volume = technique.is_volume();
    let counted = technique == Technique::DepthComplexity;
    for k in BENCH_PASSES {
        let relevant = match k {
            "stencil" => volume || counted,
            "build" => volume,
            "wedge" | "blend" => volume,
            "edge_lists" | "count" => counted,
            "light_map" | "preprocess" | "filter" => technique.is_shadow_map(),
            _ => true,
        };
        if let Some(ms) = report["median_ms"][k].as_f64().filter(|_| relevant) {
            println!("  {k:<11} {ms:>10.3} ms");
        }
    }
}

/// `penumbra bench` over several techniques or rounds: each technique's frames are timed in a
/// process of their own (this program, run again with the one technique), the techniques taking
/// turns round after round, so that neither a slow minute on a shared machine nor what one
/// technique leaves in the process (allocator state, driver caches) falls on one technique
/// alone. Reports each technique's per-pass medians over the rounds and its frame time as a
/// ratio to the first technique's, per round and overall.
pub(crate) fn bench_compare(techniques: &[Technique], timing: Timing, json: bool) -> Result<()> {
    let exe = std::env::current_exe().context("finding this program to time each technique")?;
    // This run's arguments less the techniques, the rounds and the output form.
    let mut args: Vec<std::ffi::OsString> = Vec::new();
    let mut given = std::env::args_os().skip(1);
    while let Some(a) = given.next() {
        let text = a.to_string_lossy();
        if text == "--technique" || text == "--rounds" {
            given.next();
        } else if !(text.starts_with("--technique=")
            || text.starts_with("--rounds=")
            || text == "--json")
        {
            args.push(a);
        }
    }
    let mut rounds: Vec<Vec<serde_json::Value>> = vec![Vec::new(); techniques.len()];
    for _ in 0..timing.rounds {
        for (t, reports) in techniques.iter().zip(&mut rounds) {
            let name = t.name().to_string();
            let out = std::process::Command::new(&exe)
                .args(&args)
                .args(["--technique", &name, "--json"])
                .output()
                .with_context(|| format!("running {} for {name}", exe.display()))?;
            if !out.status.success() {
                bail!("{name}: {}", String::from_utf8_lossy(&out.stderr).trim());
            }
            reports.push(
                serde_json::from_slice(&out.stdout)
                    .with_context(|| format!("{name}: reading its report"))?,
            );
        }
    }
    let wall_of = |r: &serde_json::Value| r["median_ms"]["frame_wall"].as_f64().unwrap_or(f64::NAN);
    // Each technique's frame time in each round.
    let walls: Vec<Vec<f64>> = rounds
        .iter()
        .map(|reports| reports.iter().map(wall_of).collect())
        .collect();
    // Each technique: the first round's report with every pass's median over the rounds.
    let runs: Vec<serde_json::Value> = rounds
        .iter()
        .zip(&walls)
        .map(|(reports, w)| {
            let mut run = reports[0].clone();
            for k in BENCH_PASSES {
                let v: Vec<f64> = reports
                    .iter()
                    .filter_map(|r| r["median_ms"][k].as_f64())
                    .collect();
                run["median_ms"][k] = if v.is_empty() {
                    serde_json::Value::Null
                } else {
                    serde_json::json!(median(v))
                };
            }
            run["rounds"] = serde_json::json!(timing.rounds);
            run["round_frame_wall"] = serde_json::json!(w);
            run
        })
        .collect();
    // Each technique's frame time against the first's: per round (the two timed minutes
    // apart at most), over the medians and over the fastest rounds.
    let ratios: Vec<(Technique, f64, f64, Vec<f64>)> = techniques[1..]
        .iter()
        .zip(&walls[1..])
        .map(|(&t, w)| {
            let per_round = w.iter().zip(&walls[0]).map(|(a, b)| a / b).collect();
            (
                t,
                median(w.clone()) / median(walls[0].clone()),
                min_of(w) / min_of(&walls[0]),
                per_round,
            )
        })
        .collect();
    if json {
        let ratios: Vec<serde_json::Value> = ratios
            .iter()
            .map(|(t, overall, fastest, per_round)| {
                serde_json::json!({
                    "technique": format!("{t:?}"),
                    "to": format!("{:?}", techniques[0]),
                    "frame_wall": overall,
                    "frame_wall_min": fastest,
                    "per_round": per_round,
                })
            })
            .collect();
        let out = serde_json::json!({ "runs": runs, "ratios": ratios });
        println!("{}", serde_json::to_string_pretty(&out)?);
        return Ok(());
    }
    let what = format!(
        "median over {} rounds of the medians of {} frames, each round in a process of its own",
        timing.rounds, timing.frames
    );
    for (r, &t) in runs.iter().zip(techniques) {
        print_bench(r, t, &what);
    }
    for (t, overall, fastest, per_round) in &ratios {
        let per_round: Vec<String> = per_round.iter().map(|x| format!("{x:.2}")).collect();
        println!(
            "{t:?} / {:?} frame time: {overall:.2}x (medians over the rounds), {fastest:.2}x (fastest rounds); per round {}",
            techniques[0],
            per_round.join(", ")
        );
    }
    Ok(())
}

pub(crate) fn min_of(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}
