//! `penumbra points`: the visibility of a scene's light at sensor points read from a file (a
//! `.npy` array or a CSV file of positions and normals), written as a float32 `.npy` array or
//! a CSV file: one value per point, or for a scene of several lights one column per light
//! ([`penumbra::Renderer::sensors`]).

use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

use anyhow::{Result, anyhow, bail};
use indicatif::{ProgressBar, ProgressStyle};
use penumbra::{Backend, RenderOptions, Renderer, Scene, Technique};

use crate::outputs::{check_outputs, prepare};
use crate::points_file::{Format, read_points, sensor_error, write_values};
use crate::words::render_error;

/// What `penumbra points` is asked.
pub(crate) struct PointsArgs<'a> {
    /// The scene file.
    pub(crate) scene: &'a Path,
    /// `--points`: the sensor points.
    pub(crate) points: &'a Path,
    /// `--out`: the visibility written.
    pub(crate) out: &'a Path,
    /// `--light`: the one light rendered, by name; all of them when not given.
    pub(crate) light: Option<&'a str>,
    /// `--normal X,Y,Z`: the normal of every point of a file of positions only.
    pub(crate) normal: Option<&'a str>,
    /// `--technique`: `depth-complexity` or `reference`.
    pub(crate) technique: Technique,
    /// `--samples` and `--jitter`.
    pub(crate) options: RenderOptions,
}

pub(crate) fn points(args: PointsArgs<'_>) -> Result<()> {
    let PointsArgs {
        scene: scene_path,
        points: points_path,
        out,
        light,
        normal,
        technique,
        options,
    } = args;
    // The renderer's own check of the options, asked before any file is read.
    options
        .pattern_for(technique)
        .map_err(|e| render_error(e, "--samples"))?;
    let out_format = Format::of(out).ok_or_else(|| {
        anyhow!(
            "--out {}: {}, but --out writes a float32 .npy array or a .csv file, chosen by its extension: name it .npy or .csv",
            out.display(),
            named(out)
        )
    })?;
    let in_format = Format::of(points_path).ok_or_else(|| {
        anyhow!(
            "--points {}: {}, but the points are read from a .npy array or a .csv file, known by the extension: name it .npy or .csv",
            points_path.display(),
            named(points_path)
        )
    })?;
    let normal = normal
        .map(|n| crate::cli::parse_direction("--normal", n))
        .transpose()?;
    // Checked before and after loading: the scene names the meshes.
    check_outputs(
        &[scene_path.to_path_buf(), points_path.to_path_buf()],
        &[out],
    )?;
    let scene = Scene::load(scene_path)?;
    let mut inputs = scene.input_files();
    inputs.push(points_path.to_path_buf());
    check_outputs(&inputs, &[out])?;
    let names = scene.light_names();
    let lights: Vec<usize> = match light {
        None => (0..scene.light_count()).collect(),
        Some(name) => match names.iter().position(|n| *n == name) {
            Some(k) => vec![k],
            None => bail!(
                "--light {name}: {} has no light of that name; its lights: {}",
                scene_path.display(),
                names.join(", ")
            ),
        },
    };
    // The output's missing folders are made and it is checked writable before the points are
    // read; they are removed again should anything fail.
    let prepared = prepare(&[out])?;
    let points = read_points(points_path, in_format, normal, lights.len())?;
    let n = points.len() as u64;
    let bar = ProgressBar::new(n * lights.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} points, {elapsed} (eta {eta})")
            .expect("static template")
            .progress_chars("=> "),
    );
    bar.set_message(format!("{technique:?}"));
    let start = std::time::Instant::now();
    let mut renderer = Renderer::new(Backend::Cpu);
    let mut columns = Vec::with_capacity(lights.len());
    for (j, &k) in lights.iter().enumerate() {
        let sensors = renderer
            .sensors(&scene, k, technique, &options)
            .map_err(|e| render_error(e, "--samples"))?;
        let mut values = vec![0.0f32; points.len()];
        // The most points done reported so far: the parallel loop reports out of order.
        let high = AtomicU64::new(0);
        let done = j as u64 * n;
        let progress = |d: u64| {
            let most = high.fetch_max(d, Ordering::Relaxed).max(d);
            bar.set_position(done + most);
        };
        sensors
            .fill(
                &points.positions,
                &points.normals,
                0,
                &mut values,
                &progress,
            )
            .map_err(|e| sensor_error(e, points_path, in_format, normal))?;
        let column = if scene.single_channel() {
            penumbra::geom::CHANNEL.to_string()
        } else {
            names[k].to_string()
        };
        columns.push((column, values));
    }
    bar.finish_and_clear();
    write_values(out, out_format, &columns)?;
    for d in prepared.keep() {
        eprintln!("created folder {}", d.display());
    }
    let lit = match (&lights[..], light) {
        ([_], Some(name)) => format!("light {name}"),
        ([_], None) => "1 light".to_string(),
        (all, _) => format!("{} lights ({})", all.len(), names.join(", ")),
    };
    // The reference always jitters; `--jitter` changes depth-complexity's samples.
    let jittered = if options.jitter && technique == Technique::DepthComplexity {
        ", the reference's samples"
    } else {
        ""
    };
    eprintln!(
        "{}: {n} point{} from {}, {lit}, {technique} ({} samples{jittered}), {:.2} s -> {}",
        scene_path.display(),
        if n == 1 { "" } else { "s" },
        points_path.display(),
        options.samples,
        start.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(())
}

/// What a file's extension says, for a message: "names a .txt file", "has no extension".
fn named(path: &Path) -> String {
    match path.extension() {
        Some(e) => format!("names a .{} file", e.to_string_lossy()),
        None => "has no extension".to_string(),
    }
}
