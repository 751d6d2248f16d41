//! `penumbra accuracy`: every technique against the reference, on every scene of a folder (on
//! each light alone of a scene of several, a row `scene/light` each).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use penumbra::geom::compare;
use penumbra::gpu::WedgePass;
use penumbra::volumes::Volumes;
use penumbra::{Backend, RenderOptions, Renderer, Runs, Scene, Technique};

use crate::cli::ParamArgs;
use crate::words::{InCommandWords, render_error};

pub(crate) fn accuracy(
    dir: &Path,
    samples: usize,
    (counts, jitter): (&[usize], bool),
    techniques: &[Technique],
    (backend, wedge_pass): (Backend, Option<WedgePass>),
    params: &ParamArgs,
) -> Result<()> {
    let truth_options = RenderOptions {
        samples,
        jitter: false,
    };
    truth_options.pattern().in_command_words()?;
    let sampling: Vec<RenderOptions> = counts
        .iter()
        .map(|&samples| RenderOptions { samples, jitter })
        .collect();
    if sampling.is_empty() {
        bail!("--technique-samples: give at least one count");
    }
    for s in &sampling {
        s.pattern()
            .map_err(|e| render_error(e, "--technique-samples"))?;
    }
    // Each technique's back end, decided (and any GPU opened) before the first render: the
    // back end asked for where a technique can take it, the CPU for the CPU-only techniques and
    // the truth.
    let mut renderer = Renderer::new(backend);
    renderer.set_wedge_pass(wedge_pass);
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
        in_words(counts),
        if jitter {
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
    let mut measures = Vec::new();
    for path in scenes {
        let mut scene = Scene::load(&path)?;
        params.apply(&mut scene)?;
        let name = path
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned();
        // A scene of several lights: a row per light and technique, the light alone.
        let rows: Vec<(String, Scene)> = if scene.single_channel() {
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
            let measured = accuracy_rows(
                name,
                scene,
                techniques,
                (&sampling, &truth_options),
                (&mut renderer, &mut cpu),
            )?;
            measures.push((name.clone(), measured));
        }
    }
    print_equal_errors(&measures);
    Ok(())
}

/// One row of the table, as [`print_equal_errors`] reads it.
struct Measured {
    technique: Technique,
    label: String,
    /// The light samples of a sampled technique.
    samples: Option<usize>,
    /// Over the truth's penumbra pixels; `None` where it has none.
    penumbra_mae: Option<f64>,
    secs: f64,
}

/// Where the reference was measured at two sample counts or more: a second table, each other
/// row against the reference of the same penumbra MAE (the table's two rows around it,
/// interpolated: the error's logarithm as a line in the samples' logarithm, the time as a line
/// in the samples).
fn print_equal_errors(measures: &[(String, Vec<Measured>)]) {
    let curve = |rows: &[Measured]| -> Vec<ReferencePoint> {
        let mut c: Vec<ReferencePoint> = rows
            .iter()
            .filter(|m| m.technique == Technique::Reference)
            .filter_map(|m| Some((m.samples? as f64, m.penumbra_mae?, m.secs)))
            .collect();
        c.sort_by(|a, b| a.0.total_cmp(&b.0));
        c
    };
    // Each scene's reference rows, where there are two or more.
    let scenes: Vec<(&String, &Vec<Measured>, Vec<ReferencePoint>)> = measures
        .iter()
        .map(|(name, rows)| (name, rows, curve(rows)))
        .filter(|(_, _, curve)| curve.len() >= 2)
        .collect();
    if scenes.is_empty() {
        return;
    }
    println!("\nAgainst the reference of the same penumbra MAE (interpolated between its rows):\n");
    println!(
        "| scene | technique | penumbra MAE | reference samples of that MAE | their time (s) | time / theirs |"
    );
    println!("| --- | --- | --- | --- | --- | --- |");
    for (name, rows, curve) in scenes {
        for m in rows.iter().filter(|m| m.technique != Technique::Reference) {
            let Some(e) = m.penumbra_mae else { continue };
            // The last three cells.
            let cells = match equal_error(&curve, e) {
                Ok((n, t)) => format!("{n:.0} | {t:.2} | {:.2}", m.secs / t),
                Err(Beyond::Fewer) => format!("fewer than {} | |", curve[0].0),
                Err(Beyond::More) => format!("more than {} | |", curve[curve.len() - 1].0),
            };
            println!("| {name} | {} | {e:.5} | {cells} |", m.label);
        }
    }
}

/// A reference row as [`equal_error`] reads it: samples, penumbra MAE, seconds.
type ReferencePoint = (f64, f64, f64);

/// Which way an error lies outside the reference's measured ones.
#[derive(Debug, PartialEq)]
enum Beyond {
    /// Larger than its fewest samples' error.
    Fewer,
    /// Smaller than its most samples' error.
    More,
}

/// The samples and time of the reference whose penumbra MAE is `e`, from `curve`'s `(samples,
/// penumbra MAE, seconds)` sorted by samples: between the first two neighbours whose errors
/// bracket `e`, `log e` linear in `log samples` and the time linear in the samples.
fn equal_error(curve: &[ReferencePoint], e: f64) -> Result<(f64, f64), Beyond> {
    for w in curve.windows(2) {
        let ((n0, e0, t0), (n1, e1, t1)) = (w[0], w[1]);
        // A count given twice spans no samples.
        if n1 > n0 && (e1..=e0).contains(&e) {
            let f = if e0 > e1 && e > 0.0 && e1 > 0.0 {
                (e0 / e).ln() / (e0 / e1).ln()
            } else {
                0.0
            };
            let n = n0 * (n1 / n0).powf(f);
            let t = t0 + (t1 - t0) * (n - n0) / (n1 - n0);
            return Ok((n, t));
        }
    }
    if e > curve[0].1 {
        Err(Beyond::Fewer)
    } else {
        Err(Beyond::More)
    }
}

/// `16`, `16 and 64`, `16, 64 and 256`.
fn in_words(counts: &[usize]) -> String {
    let all: Vec<String> = counts.iter().map(|n| n.to_string()).collect();
    match all.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => all.concat(),
    }
}

/// The rows of `penumbra accuracy`'s table of `scene` (of one light), named `name`: each of
/// `techniques` (a sampled one with each of the `sampling` options, named with its count where
/// there are several; the truth with `truth`) against the reference, the CPU-only ones rendered
/// by `cpu`, the others by `renderer`.
fn accuracy_rows(
    name: &str,
    scene: &Scene,
    techniques: &[Technique],
    (sampling, truth_options): (&[RenderOptions], &RenderOptions),
    (renderer, cpu): (&mut Renderer, &mut Renderer),
) -> Result<Vec<Measured>> {
    let truth = cpu
        .render(scene, Technique::Reference, truth_options)
        .in_command_words()?;
    // Built before the timed renders.
    let lit = scene.lit(0);
    let volumes = Volumes::build(&lit);
    let runs = techniques.iter().flat_map(|&t| {
        let counts = if t.takes_samples() {
            sampling
        } else {
            &sampling[..1]
        };
        counts.iter().map(move |s| (t, s))
    });
    let mut measured = Vec::new();
    for (t, s) in runs {
        let options = RenderOptions {
            samples: s.samples,
            jitter: s.jitter && t.takes_samples(),
        };
        let label = if t.takes_samples() && sampling.len() > 1 {
            format!("{t} --samples {}", s.samples)
        } else {
            t.name().to_string()
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
            .render_frame(&lit, t, &options, Some(&volumes), &|_| {})
            .map_err(|e| render_error(e, "--technique-samples"))?
            .image;
        let secs = start.elapsed().as_secs_f64();
        let c = compare(&img, &truth)?;
        println!(
            "| {name} | {label} | {:.5} | {:.4} | {:.2}% | {} | {:.5} | {:.4} | {:+.5} | {:.2}% | {secs:.2} |",
            c.all.mae,
            c.all.p99,
            100.0 * c.all.share_over,
            c.penumbra.pixels,
            c.penumbra.mae,
            c.penumbra.p99,
            c.penumbra_signed,
            100.0 * c.umbra_lit
        );
        measured.push(Measured {
            technique: t,
            samples: t.takes_samples().then_some(s.samples),
            penumbra_mae: (c.penumbra.pixels > 0).then_some(c.penumbra.mae),
            secs,
            label,
        });
    }
    Ok(measured)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reference_of_equal_error_is_interpolated_between_its_neighbours() {
        // Error halving for four times the samples: 0.04 at 16, 0.02 at 64, 0.01 at 256.
        let curve = [(16.0, 0.04, 1.0), (64.0, 0.02, 2.0), (256.0, 0.01, 5.0)];
        let near = |(n, t): (f64, f64), (want_n, want_t): (f64, f64)| {
            assert!(
                (n - want_n).abs() < 1e-9 && (t - want_t).abs() < 1e-9,
                "{n} {t}"
            )
        };
        near(equal_error(&curve, 0.02).unwrap(), (64.0, 2.0));
        near(equal_error(&curve, 0.04).unwrap(), (16.0, 1.0));
        // Halfway in the logarithm: 32 samples, a third of the way from 16 to 64 in time.
        near(
            equal_error(&curve, 0.02 * 2f64.sqrt()).unwrap(),
            (32.0, 1.0 + 16.0 / 48.0),
        );
        near(
            equal_error(&curve, 0.01 * 2f64.sqrt()).unwrap(),
            (128.0, 3.0),
        );
        assert_eq!(equal_error(&curve, 0.05), Err(Beyond::Fewer));
        assert_eq!(equal_error(&curve, 0.005), Err(Beyond::More));
        assert_eq!(equal_error(&curve, 0.0), Err(Beyond::More));
        // A count given twice.
        let twice = [(16.0, 0.04, 1.0), (16.0, 0.04, 1.1), (64.0, 0.02, 2.0)];
        near(equal_error(&twice, 0.04).unwrap(), (16.0, 1.1));
    }
}
