//! `penumbra`: render visibility images, probe single pixels, compare images, and generate the
//! fixtures.

mod fixtures;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use penumbra_geom::image::{self, VisibilityImage};
use penumbra_geom::reference::{self, Reference, Tracer};
use penumbra_geom::{Rng, Scene};
use penumbra_volumes::{CpuRenderer, Technique as VolumeTechnique};

#[derive(Parser)]
#[command(
    name = "penumbra",
    version,
    about = "Soft shadows from geometry, measured against a ray-cast reference"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Technique {
    /// Ray-cast reference: N stratified-jittered light samples per pixel.
    Reference,
    /// Ray-cast hard shadow of a point light at the light's centre.
    HardReference,
    /// Hard shadow of the light's centre by shadow volumes (the stencil answer).
    Hard,
    /// Additive penumbra wedges (Akenine-Möller & Assarsson 2002).
    Wedges,
    /// Penumbra-wedges blending (Forest, Barthe & Paulin 2006).
    WedgesBlend,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Backend {
    /// The GPU when an adapter exists, else the CPU.
    Auto,
    /// wgpu (fails without an adapter).
    Gpu,
    /// The CPU evaluation of the `volumes` crate.
    Cpu,
}

#[derive(Subcommand)]
enum Command {
    /// Render the visibility image V of a scene to a one-channel (`V`) float EXR.
    Render {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Technique.
        #[arg(long, value_enum, default_value = "wedges-blend")]
        technique: Technique,
        /// Output EXR file.
        #[arg(long)]
        out: PathBuf,
        /// Light samples per pixel for `reference`: a perfect square.
        #[arg(long, default_value_t = 256)]
        samples: usize,
        /// Also write an 8-bit greyscale PNG.
        #[arg(long)]
        png: Option<PathBuf>,
        /// Where the volume techniques (`hard`, `wedges`, `wedges-blend`) run; the references
        /// always run on the CPU.
        #[arg(long, value_enum, default_value = "auto")]
        backend: Backend,
    },
    /// Print the surface point seen through one pixel, its exact V and its reference V.
    Probe {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Pixel as X,Y (column, row; row 0 the top).
        #[arg(long)]
        pixel: String,
        /// Light samples for the reference value: a perfect square.
        #[arg(long, default_value_t = 4096)]
        samples: usize,
    },
    /// Compare image A against reference B: errors over all pixels and over B's penumbra.
    Compare {
        /// Image under test.
        a: PathBuf,
        /// Reference image.
        b: PathBuf,
        /// Write a heat map of |A - B| (black 0, red, yellow, white >= 0.1).
        #[arg(long)]
        heatmap: Option<PathBuf>,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Print the volume geometry of a scene: per mesh, its edges by kind, silhouette edges,
    /// loops, wedges and shadow-volume triangles.
    Geometry {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Print JSON (the format of `fixtures/expected/*.json`).
        #[arg(long)]
        json: bool,
    },
    /// Render every scene of a folder with the reference and with each technique, and print a
    /// Markdown table of their errors against the reference (the table of docs/accuracy.md).
    Accuracy {
        /// Folder of scene files.
        #[arg(long, default_value = "fixtures/scenes")]
        scenes: PathBuf,
        /// Reference light samples per pixel: a perfect square.
        #[arg(long, default_value_t = 1024)]
        samples: usize,
        /// Techniques to measure.
        #[arg(
            long,
            value_enum,
            value_delimiter = ',',
            default_value = "hard,wedges,wedges-blend"
        )]
        techniques: Vec<Technique>,
        /// Where the volume techniques run.
        #[arg(long, value_enum, default_value = "auto")]
        backend: Backend,
    },
    /// Time a technique: the median over N frames of each GPU pass (timestamp queries) and of
    /// the whole frame (wall clock, CPU setup and readback included).
    Bench {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Technique.
        #[arg(long, value_enum, default_value = "wedges-blend")]
        technique: Technique,
        /// Frames to time (after one warm-up frame).
        #[arg(long, default_value_t = 10)]
        frames: usize,
        /// Where to run it.
        #[arg(long, value_enum, default_value = "auto")]
        backend: Backend,
        /// Light samples per pixel for `reference`.
        #[arg(long, default_value_t = 256)]
        samples: usize,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Regenerate the fixture meshes and scenes.
    GenFixtures {
        /// Fixture folder.
        #[arg(long, default_value = "fixtures")]
        out: PathBuf,
    },
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render {
            scene,
            technique,
            out,
            samples,
            png,
            backend,
        } => render(&scene, technique, &out, samples, png.as_deref(), backend),
        Command::Probe {
            scene,
            pixel,
            samples,
        } => probe(&scene, &pixel, samples),
        Command::Compare {
            a,
            b,
            heatmap,
            json,
        } => compare(&a, &b, heatmap.as_deref(), json),
        Command::Geometry { scene, json } => geometry(&scene, json),
        Command::Bench {
            scene,
            technique,
            frames,
            backend,
            samples,
            json,
        } => bench(&scene, technique, frames, backend, samples, json),
        Command::Accuracy {
            scenes,
            samples,
            techniques,
            backend,
        } => accuracy(&scenes, samples, &techniques, backend),
        Command::GenFixtures { out } => {
            for f in fixtures::generate(&out)? {
                println!("wrote {f}");
            }
            Ok(())
        }
    }
}

/// `n` where `samples = n * n`, or an error.
fn samples_per_axis(samples: usize) -> Result<usize> {
    let n = (samples as f64).sqrt().round() as usize;
    if samples == 0 || n * n != samples {
        bail!("--samples {samples} must be a positive perfect square (64, 256, 1024, ...)");
    }
    Ok(n)
}

/// The same file, whether or not it exists yet: compares canonical parent folders and names.
fn same_file(a: &Path, b: &Path) -> bool {
    let canon = |p: &Path| -> Option<PathBuf> {
        let parent = match p.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        Some(parent.canonicalize().ok()?.join(p.file_name()?))
    };
    match (canon(a), canon(b)) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    }
}

/// Refuses outputs that would overwrite an input or each other.
fn check_outputs(inputs: &[PathBuf], outputs: &[&Path]) -> Result<()> {
    for (k, out) in outputs.iter().enumerate() {
        if let Some(i) = inputs.iter().find(|i| same_file(i, out)) {
            bail!(
                "output {} is an input of this run ({}); refusing to overwrite it",
                out.display(),
                i.display()
            );
        }
        if outputs[..k].iter().any(|o| same_file(o, out)) {
            bail!("output {} is named twice", out.display());
        }
    }
    Ok(())
}

fn load_scene(path: &Path) -> Result<Scene> {
    Ok(Scene::load(path)?)
}

fn render(
    scene_path: &Path,
    technique: Technique,
    out: &Path,
    samples: usize,
    png: Option<&Path>,
    backend: Backend,
) -> Result<()> {
    let per_axis = samples_per_axis(samples)?;
    let mut outputs = vec![out];
    outputs.extend(png);
    // Checked before and after loading: the scene names the meshes.
    check_outputs(&[scene_path.to_path_buf()], &outputs)?;
    let scene = load_scene(scene_path)?;
    check_outputs(&scene.input_files(), &outputs)?;
    for o in &outputs {
        if let Some(dir) = o.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("creating the folder of {}", o.display()))?;
        }
    }
    let bar = ProgressBar::new(scene.camera.height as u64);
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} rows, {elapsed} (eta {eta})")
            .expect("static template")
            .progress_chars("=> "),
    );
    bar.set_message(format!("{technique:?}"));
    let start = std::time::Instant::now();
    let progress = |rows| bar.set_position(rows);
    let gpu = select_gpu(technique, backend)?;
    let (img, triangles, detail) = match &gpu {
        Some(ctx) => {
            let gpu_technique = gpu_technique(technique);
            let volumes = penumbra_volumes::Volumes::build(&scene);
            let img =
                penumbra_gpu::GpuRenderer::new(ctx).render(&scene, &volumes, gpu_technique)?;
            (
                img,
                scene.triangle_count(),
                format!(" (gpu: {})", ctx.describe()),
            )
        }
        None => render_image(&scene, technique, per_axis, &progress),
    };
    bar.finish_and_clear();
    img.check_finite()
        .with_context(|| format!("{technique:?} produced a non-finite pixel"))?;
    img.write_exr(out)
        .with_context(|| format!("writing {}", out.display()))?;
    if let Some(png) = png {
        if let Err(e) = img.write_png(png) {
            let _ = std::fs::remove_file(out);
            return Err(e).with_context(|| format!("writing {}", png.display()));
        }
    }
    eprintln!(
        "{}: {}x{} px, {} triangles, {:?}{}, {:.2} s -> {}",
        scene_path.display(),
        img.width,
        img.height,
        triangles,
        technique,
        detail,
        start.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(())
}

/// The GPU version of a volume technique.
fn gpu_technique(t: Technique) -> penumbra_gpu::GpuTechnique {
    match t {
        Technique::Hard => penumbra_gpu::GpuTechnique::Hard,
        Technique::Wedges => penumbra_gpu::GpuTechnique::Wedges,
        _ => penumbra_gpu::GpuTechnique::WedgesBlend,
    }
}

/// The GPU to render `technique` on, or `None` for the CPU, saying which on stderr.
fn select_gpu(technique: Technique, backend: Backend) -> Result<Option<penumbra_gpu::GpuContext>> {
    let on_gpu = matches!(
        technique,
        Technique::Hard | Technique::Wedges | Technique::WedgesBlend
    );
    match backend {
        Backend::Cpu => Ok(None),
        Backend::Gpu if !on_gpu => bail!(
            "--backend gpu: {technique:?} runs on the CPU only (the GPU renders the volume techniques)"
        ),
        Backend::Gpu => Ok(Some(penumbra_gpu::GpuContext::new()?)),
        Backend::Auto if !on_gpu => {
            if !matches!(technique, Technique::Reference | Technique::HardReference) {
                eprintln!("backend: cpu ({technique:?} is a CPU technique)");
            }
            Ok(None)
        }
        Backend::Auto => match penumbra_gpu::GpuContext::new() {
            Ok(c) => {
                eprintln!("backend: gpu, {}", c.describe());
                Ok(Some(c))
            }
            Err(e) => {
                eprintln!("backend: cpu ({e})");
                Ok(None)
            }
        },
    }
}

/// Renders `scene` with `technique`: the image, the triangle count and a note for the log.
fn render_image(
    scene: &Scene,
    technique: Technique,
    per_axis: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> (VisibilityImage, usize, String) {
    let samples = per_axis * per_axis;
    match technique {
        Technique::Reference | Technique::HardReference => {
            let tracer = Tracer::new(scene);
            let (reference, detail) = match technique {
                Technique::Reference => (
                    Reference::Sampled { per_axis },
                    format!(" ({samples} samples)"),
                ),
                _ => (Reference::Hard, String::new()),
            };
            let img = reference::render(scene, &tracer, reference, progress);
            (img, tracer.triangles.len(), detail)
        }
        Technique::Hard | Technique::Wedges | Technique::WedgesBlend => {
            let r = CpuRenderer::new(scene);
            let t = match technique {
                Technique::Hard => VolumeTechnique::Hard,
                Technique::Wedges => VolumeTechnique::Wedges,
                _ => VolumeTechnique::WedgesBlend,
            };
            let img = r.render(scene, t, progress);
            let detail = format!(" (cpu, {} wedges)", r.volumes.wedges.len());
            (img, r.tracer.triangles.len(), detail)
        }
    }
}

fn parse_pixel(s: &str, scene: &Scene) -> Result<(u32, u32)> {
    let (x, y) = s
        .split_once(',')
        .with_context(|| format!("--pixel {s:?}: expected X,Y"))?;
    let x: u32 = x
        .trim()
        .parse()
        .with_context(|| format!("--pixel {s:?}: bad X"))?;
    let y: u32 = y
        .trim()
        .parse()
        .with_context(|| format!("--pixel {s:?}: bad Y"))?;
    let c = &scene.camera;
    if x >= c.width || y >= c.height {
        bail!(
            "--pixel {x},{y} is outside the {}x{} image",
            c.width,
            c.height
        );
    }
    Ok((x, y))
}

fn probe(scene_path: &Path, pixel: &str, samples: usize) -> Result<()> {
    let per_axis = samples_per_axis(samples)?;
    let scene = load_scene(scene_path)?;
    let (x, y) = parse_pixel(pixel, &scene)?;
    let tracer = Tracer::new(&scene);
    let dir = scene.camera.ray_dir(x, y);
    match tracer.surface_point(scene.camera.eye, dir) {
        None => println!("pixel {x},{y}: the ray hits nothing; V = 1"),
        Some(p) => {
            let exact = tracer.exact_visibility(&p);
            let mut rng = Rng::stream(
                reference::REFERENCE_SEED,
                y as u64 * scene.camera.width as u64 + x as u64,
            );
            let sampled = tracer.sampled_visibility(&p, per_axis, &mut rng);
            let q = p.position;
            println!("pixel {x},{y}");
            println!(
                "P          = [{:.9}, {:.9}, {:.9}] (triangle {})",
                q.x, q.y, q.z, p.triangle
            );
            println!("V exact    = {exact:.9}");
            println!(
                "V ref      = {sampled:.9} ({samples} samples, 1-sigma bound {:.4})",
                (sampled * (1.0 - sampled) / samples as f64).sqrt()
            );
            println!("V hard     = {}", tracer.hard_visibility(&p));
        }
    }
    Ok(())
}

fn compare(a: &Path, b: &Path, heatmap: Option<&Path>, json: bool) -> Result<()> {
    if let Some(h) = heatmap {
        check_outputs(&[a.to_path_buf(), b.to_path_buf()], &[h])?;
    }
    let ia = VisibilityImage::read_exr(a)?;
    let ib = VisibilityImage::read_exr(b)?;
    let c = image::compare(&ia, &ib)?;
    if let Some(h) = heatmap {
        let rgb = image::heatmap(&ia, &ib, 0.1);
        image::write_png_bytes(h, ia.width, ia.height, image::PngColor::Rgb, &rgb)?;
    }
    if json {
        println!("{}", serde_json::to_string_pretty(&c)?);
    } else {
        println!(
            "{:<10} {:>8} {:>10} {:>10} {:>10} {:>10} {:>10}",
            "pixels", "count", "MAE", "RMSE", "p99", "max", ">0.05"
        );
        for (name, m) in [("all", c.all), ("penumbra", c.penumbra)] {
            println!(
                "{:<10} {:>8} {:>10.6} {:>10.6} {:>10.6} {:>10.6} {:>9.3}%",
                name,
                m.pixels,
                m.mae,
                m.rmse,
                m.p99,
                m.max,
                100.0 * m.share_over
            );
        }
    }
    Ok(())
}

/// Volume geometry counts of a scene, as `fixtures/expected/*.json` records them.
fn geometry(scene_path: &Path, json: bool) -> Result<()> {
    let scene = load_scene(scene_path)?;
    let v = penumbra_volumes::Volumes::build(&scene);
    let g = penumbra_volumes::render::GeometryCounts::of(&v);
    if json {
        println!("{}", serde_json::to_string_pretty(&g)?);
    } else {
        println!(
            "{}: {} silhouette edges (multiplicity summed: {}), {} loops, {} wedges, {} volume triangles",
            scene_path.display(),
            g.silhouette_edges,
            g.silhouette_multiplicity,
            g.loops,
            g.wedges,
            g.volume_triangles
        );
    }
    Ok(())
}

fn accuracy(dir: &Path, samples: usize, techniques: &[Technique], backend: Backend) -> Result<()> {
    let per_axis = samples_per_axis(samples)?;
    let gpu = select_gpu(Technique::WedgesBlend, backend)?;
    let renderer = gpu.as_ref().map(penumbra_gpu::GpuRenderer::new);
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
        "Errors against the {samples}-sample reference (penumbra: reference 0.02 < V < 0.98); volume techniques on {}.\n",
        gpu.as_ref().map_or("the CPU".to_string(), |c| c.describe())
    );
    println!(
        "| scene | technique | MAE | p99 | > 0.05 | penumbra px | penumbra MAE | penumbra p99 | time (s) |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for path in scenes {
        let scene = load_scene(&path)?;
        let name = path
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned();
        let (truth, _, _) = render_image(&scene, Technique::Reference, per_axis, &|_| {});
        let volumes = penumbra_volumes::Volumes::build(&scene);
        for &t in techniques {
            let start = std::time::Instant::now();
            let volume_technique = matches!(
                t,
                Technique::Hard | Technique::Wedges | Technique::WedgesBlend
            );
            let img = match &renderer {
                Some(r) if volume_technique => r.render(&scene, &volumes, gpu_technique(t))?,
                _ => render_image(&scene, t, per_axis, &|_| {}).0,
            };
            let secs = start.elapsed().as_secs_f64();
            let c = image::compare(&img, &truth)?;
            println!(
                "| {name} | {} | {:.5} | {:.4} | {:.2}% | {} | {:.5} | {:.4} | {secs:.2} |",
                t.to_possible_value()
                    .map(|v| v.get_name().to_string())
                    .unwrap_or_default(),
                c.all.mae,
                c.all.p99,
                100.0 * c.all.share_over,
                c.penumbra.pixels,
                c.penumbra.mae,
                c.penumbra.p99
            );
        }
    }
    Ok(())
}

fn median(mut v: Vec<f64>) -> f64 {
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

fn bench(
    scene_path: &Path,
    technique: Technique,
    frames: usize,
    backend: Backend,
    samples: usize,
    json: bool,
) -> Result<()> {
    if frames == 0 {
        bail!("--frames must be at least 1");
    }
    let per_axis = samples_per_axis(samples)?;
    let scene = load_scene(scene_path)?;
    let gpu = select_gpu(technique, backend)?;
    let mut wall = Vec::new();
    let mut passes: Vec<penumbra_gpu::PassTimes> = Vec::new();
    let device;
    match &gpu {
        Some(ctx) => {
            device = ctx.describe();
            let t = gpu_technique(technique);
            let volumes = penumbra_volumes::Volumes::build(&scene);
            let r = penumbra_gpu::GpuRenderer::new(ctx);
            for k in 0..=frames {
                let start = std::time::Instant::now();
                let (_, times) = r.render_timed(&scene, &volumes, t)?;
                if k > 0 {
                    wall.push(start.elapsed().as_secs_f64() * 1e3);
                    passes.extend(times);
                }
            }
        }
        None => {
            device = format!("cpu, {} threads", rayon::current_num_threads());
            for k in 0..=frames {
                let start = std::time::Instant::now();
                let _ = render_image(&scene, technique, per_axis, &|_| {});
                if k > 0 {
                    wall.push(start.elapsed().as_secs_f64() * 1e3);
                }
            }
        }
    }
    let pass = |f: fn(&penumbra_gpu::PassTimes) -> f64| {
        (!passes.is_empty()).then(|| median(passes.iter().map(f).collect()))
    };
    let report = serde_json::json!({
        "scene": scene_path.display().to_string(),
        "technique": format!("{technique:?}"),
        "device": device,
        "resolution": [scene.camera.width, scene.camera.height],
        "frames": frames,
        "median_ms": {
            "depth": pass(|p| p.depth),
            "stencil": pass(|p| p.stencil),
            "wedge": pass(|p| p.wedge),
            "blend": pass(|p| p.blend),
            "resolve": pass(|p| p.resolve),
            "gpu_total": pass(|p| p.total()),
            "frame_wall": median(wall),
        }
    });
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        println!(
            "{} {:?} on {} at {}x{}, median of {frames} frames:",
            scene_path.display(),
            technique,
            device,
            scene.camera.width,
            scene.camera.height
        );
        for k in [
            "depth",
            "stencil",
            "wedge",
            "resolve",
            "gpu_total",
            "frame_wall",
        ] {
            if let Some(ms) = report["median_ms"][k].as_f64() {
                println!("  {k:<11} {ms:>10.3} ms");
            }
        }
    }
    Ok(())
}
