//! `penumbra accuracy`: every technique against the reference, on every scene of a folder (on
//! each light alone of a scene of several, a row `scene/light` each).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use penumbra::geom::compare;
use penumbra::volumes::Volumes;
use penumbra::{Backend, RenderOptions, Renderer, Runs, Scene, Technique};

use crate::cli::ParamArgs;
use crate::words::{InCommandWords, render_error};

pub(crate) fn accuracy(
    dir: &Path,
    samples: usize,
    sampling: RenderOptions,
    techniques: &[Technique],
    backend: Backend,
    params: &ParamArgs,
) -> Result<()> {
    let truth_options = RenderOptions {
        samples,
        jitter: false,
    };
    truth_options.pattern().in_command_words()?;
    sampling
        .pattern()
        .map_err(|e| render_error(e, "--technique-samples"))?;
    // Each technique's back end, decided (and any GPU opened) before the first render: the
    // back end asked for where a technique can take it, the CPU for the CPU-only techniques and
    // the truth.
    let mut renderer = Renderer::new(backend);
    let mut cpu = Renderer::new(penumbra::Backend::Cpu);
    for &t in techniques {
        if Runs::of(t) != Runs::CpuOnly {
            renderer.uses_gpu(t).in_command_words()?;
        }
    }
    let mut scenes: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("reading {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    scenes.sort();
    if scenes.is_empty() {
        bail!("{}: no scene files", dir.display());
    }
    println!(
        "Errors against the {samples}-sample reference (penumbra: reference 0.02 < V < 0.98); `reference` and `depth-complexity` with {} samples{}; GPU techniques on {}.\n",
        sampling.samples,
        if sampling.jitter {
            ", depth-complexity's jittered"
        } else {
            ""
        },
        renderer
            .gpu_description()
            .unwrap_or_else(|| "the CPU".to_string())
    );
    println!(
        "| scene | technique | MAE | p99 | > 0.05 | penumbra px | penumbra MAE | penumbra p99 | penumbra signed | umbra lit | time (s) |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for path in scenes {
        let mut scene = Scene::load(&path)?;
        params.apply(&mut scene)?;
        let name = path
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned();
        // A scene of several lights: a row per light and technique, the light alone.
        let rows: Vec<(String, Scene)> = if scene.lights.is_empty() {
            vec![(name, scene)]
        } else {
            scene
                .lights
                .iter()
                .enumerate()
                .map(|(k, l)| (format!("{name}/{}", l.name), scene.for_light(k)))
                .collect()
        };
        for (name, scene) in &rows {
            accuracy_rows(
                name,
                scene,
                techniques,
                (sampling, &truth_options),
                (&mut renderer, &mut cpu),
            )?;
        }
    }
    Ok(())
}

/// The rows of `penumbra accuracy`'s table of `scene` (of one light), named `name`: each of
/// `techniques` (with the `sampling` options; the truth with `truth`) against the reference,
/// the CPU-only ones rendered by `cpu`, the others by `renderer`.
fn accuracy_rows(
    name: &str,
    scene: &Scene,
    techniques: &[Technique],
    (sampling, truth_options): (RenderOptions, &RenderOptions),
    (renderer, cpu): (&mut Renderer, &mut Renderer),
) -> Result<()> {
    let truth = cpu
        .render(scene, Technique::Reference, truth_options)
        .in_command_words()?;
    // Built before the timed renders.
    let volumes = Volumes::build(scene);
    for &t in techniques {
        let options = RenderOptions {
            samples: sampling.samples,
            jitter: sampling.jitter && t.takes_samples(),
        };
        let r = if Runs::of(t) == Runs::CpuOnly {
            &mut *cpu
        } else {
            &mut *renderer
        };
        // Each technique's time with its whole set-up, as a render of its own takes it: not
        // with the ray-casting hierarchy of the truth's render or of the technique before.
        r.release_kept();
        let start = std::time::Instant::now();
        let img = r
            .render_frame(scene, t, &options, Some(&volumes), &|_| {})
            .map_err(|e| render_error(e, "--technique-samples"))?
            .image;
        let secs = start.elapsed().as_secs_f64();
        let c = compare(&img, &truth)?;
        println!(
            "| {name} | {} | {:.5} | {:.4} | {:.2}% | {} | {:.5} | {:.4} | {:+.5} | {:.2}% | {secs:.2} |",
            t.name(),
            c.all.mae,
            c.all.p99,
            100.0 * c.all.share_over,
            c.penumbra.pixels,
            c.penumbra.mae,
            c.penumbra.p99,
            c.penumbra_signed,
            100.0 * c.umbra_lit
        );
    }
    Ok(())
}
