//! `penumbra`: render visibility images, probe single pixels, compare images, and generate the
//! fixtures.

mod fixtures;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result, bail};
use clap::builder::TypedValueParser as _;
use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use penumbra::geom::image::{self, VisibilityImage};
use penumbra::geom::params::{GaussianVariant, MdsmExtra};
use penumbra::geom::reference::{self, Tracer};
use penumbra::geom::{Rng, Scene};
use penumbra::gpu::PassTimes;
use penumbra::volumes::{DepthComplexity, SamplePattern, Volumes};
use penumbra::{RenderOptions, Renderer, Technique};

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

/// Parses a technique by its name, listing every name (with its description) in the help.
fn technique_parser() -> impl clap::builder::TypedValueParser<Value = Technique> {
    clap::builder::PossibleValuesParser::new(
        Technique::ALL.map(|t| clap::builder::PossibleValue::new(t.name()).help(t.description())),
    )
    .map(|name| {
        name.parse::<Technique>()
            .expect("one of the possible values")
    })
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum MdsmExtraArg {
    /// The neighbourhood's maximum.
    Max,
    /// The neighbourhood's minimum.
    Min,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum GaussianVariantArg {
    /// PCF of the hard-shadow bit, size from D.
    Pcf,
    /// One separable Gaussian, size from D.
    Single,
    /// Several Poisson-tap Gaussian passes.
    Multi,
}

/// Parameters of the shadow-map techniques: each overrides the key of the same name in the
/// scene's optional table (`[shadow_map]`, `[pcf]`, `[pcss]`, `[fractional_disk]`, `[mdsm]`,
/// `[gaussian]`; see docs/scene-format.md for the defaults).
#[derive(clap::Args, Clone, Debug, Default)]
struct ParamArgs {
    /// Shadow map texels per side [shadow_map.resolution, 2048].
    #[arg(long, help_heading = "Shadow maps")]
    shadow_map_resolution: Option<u32>,
    /// Constant depth bias, fraction of the receiver's light depth [shadow_map.depth_bias, 0.001].
    #[arg(long, help_heading = "Shadow maps")]
    depth_bias: Option<f64>,
    /// Slope bias in texels of the receiver's plane [shadow_map.slope_bias, 1].
    #[arg(long, help_heading = "Shadow maps")]
    slope_bias: Option<f64>,
    /// pcf: kernel side, 3, 4 or 5 [pcf.kernel, 3].
    #[arg(long, help_heading = "Shadow maps")]
    pcf_kernel: Option<u32>,
    /// pcss: blocker-search taps per side [pcss.search, 8].
    #[arg(long, help_heading = "Shadow maps")]
    pcss_search: Option<u32>,
    /// pcss: most filter taps per side [pcss.filter_max, 16].
    #[arg(long, help_heading = "Shadow maps")]
    pcss_filter_max: Option<u32>,
    /// pcss: dithered 4-of-16 sampling, Shinde 2022, section 4.4 [pcss.dither, false].
    #[arg(long, help_heading = "Shadow maps")]
    pcss_dither: Option<bool>,
    /// fractional-disk: Eq. 2's a [fractional_disk.a, 2].
    #[arg(long, help_heading = "Shadow maps")]
    fd_a: Option<f64>,
    /// fractional-disk: most samples per pixel [fractional_disk.max_samples, 50].
    #[arg(long, help_heading = "Shadow maps")]
    fd_max_samples: Option<u32>,
    /// fractional-disk: largest disk radius, texels [fractional_disk.max_radius, 16].
    #[arg(long, help_heading = "Shadow maps")]
    fd_max_radius: Option<f64>,
    /// fractional-disk: propagation passes [fractional_disk.passes, 16].
    #[arg(long, help_heading = "Shadow maps")]
    fd_passes: Option<u32>,
    /// fractional-disk: edge detection's relative depth jump [fractional_disk.edge_threshold, 0.05].
    #[arg(long, help_heading = "Shadow maps")]
    fd_edge_threshold: Option<f64>,
    /// fractional-disk: the disk re-test against false self-occlusion [fractional_disk.retest, true].
    #[arg(long, help_heading = "Shadow maps")]
    fd_retest: Option<bool>,
    /// mdsm: depths per texel n, 1 to 3 [mdsm.depths, 3].
    #[arg(long, help_heading = "Shadow maps")]
    mdsm_depths: Option<u32>,
    /// mdsm: PCF side, k = side² [mdsm.kernel, 3].
    #[arg(long, help_heading = "Shadow maps")]
    mdsm_kernel: Option<u32>,
    /// mdsm: neighbourhood radius, texels [mdsm.radius, 1].
    #[arg(long, help_heading = "Shadow maps")]
    mdsm_radius: Option<u32>,
    /// mdsm: extra depth of a 2-depth map [mdsm.extra, max].
    #[arg(long, value_enum, help_heading = "Shadow maps")]
    mdsm_extra: Option<MdsmExtraArg>,
    /// gaussian: filter [gaussian.variant, multi].
    #[arg(
        long,
        visible_alias = "variant",
        value_enum,
        help_heading = "Shadow maps"
    )]
    gaussian_variant: Option<GaussianVariantArg>,
    /// gaussian: distance power Dp [gaussian.dp; 3 for pcf and multi, 1.9 for single].
    #[arg(long, help_heading = "Shadow maps")]
    gaussian_dp: Option<f64>,
    /// gaussian: distance multiplier Dm [gaussian.dm, 200].
    #[arg(long, help_heading = "Shadow maps")]
    gaussian_dm: Option<f64>,
    /// gaussian: largest kernel, odd [gaussian.max_kernel, 19].
    #[arg(long, help_heading = "Shadow maps")]
    gaussian_max_kernel: Option<u32>,
    /// gaussian: passes of the multi variant [gaussian.passes, 10].
    #[arg(long, help_heading = "Shadow maps")]
    gaussian_passes: Option<u32>,
    /// gaussian: Poisson taps per multi pass [gaussian.taps, 20].
    #[arg(long, help_heading = "Shadow maps")]
    gaussian_taps: Option<u32>,
    /// gaussian: dilation kernel, odd, 0 = off [gaussian.dilation, 0].
    #[arg(long, help_heading = "Shadow maps")]
    gaussian_dilation: Option<u32>,
}

impl ParamArgs {
    /// `scene`'s parameters with these flags applied, checked.
    fn apply(&self, scene: &mut Scene) -> Result<()> {
        let p = &mut scene.params;
        macro_rules! set {
            ($flag:ident => $($dst:tt)+) => {
                if let Some(v) = self.$flag {
                    p.$($dst)+ = v;
                }
            };
        }
        set!(shadow_map_resolution => shadow_map.resolution);
        set!(depth_bias => shadow_map.depth_bias);
        set!(slope_bias => shadow_map.slope_bias);
        set!(pcf_kernel => pcf.kernel);
        set!(pcss_search => pcss.search);
        set!(pcss_filter_max => pcss.filter_max);
        set!(pcss_dither => pcss.dither);
        set!(fd_a => fractional_disk.a);
        set!(fd_max_samples => fractional_disk.max_samples);
        set!(fd_max_radius => fractional_disk.max_radius);
        set!(fd_passes => fractional_disk.passes);
        set!(fd_edge_threshold => fractional_disk.edge_threshold);
        set!(fd_retest => fractional_disk.retest);
        set!(mdsm_depths => mdsm.depths);
        set!(mdsm_kernel => mdsm.kernel);
        set!(mdsm_radius => mdsm.radius);
        set!(gaussian_dm => gaussian.dm);
        set!(gaussian_max_kernel => gaussian.max_kernel);
        set!(gaussian_passes => gaussian.passes);
        set!(gaussian_taps => gaussian.taps);
        set!(gaussian_dilation => gaussian.dilation);
        if let Some(v) = self.gaussian_dp {
            p.gaussian.dp = Some(v);
        }
        if let Some(e) = self.mdsm_extra {
            p.mdsm.extra = match e {
                MdsmExtraArg::Max => MdsmExtra::Max,
                MdsmExtraArg::Min => MdsmExtra::Min,
            };
        }
        if let Some(v) = self.gaussian_variant {
            p.gaussian.variant = match v {
                GaussianVariantArg::Pcf => GaussianVariant::Pcf,
                GaussianVariantArg::Single => GaussianVariant::Single,
                GaussianVariantArg::Multi => GaussianVariant::Multi,
            };
        }
        p.validate().map_err(|e| {
            anyhow::anyhow!(
                "{}: {e} (after the command line's flags, e.g. --{}-{})",
                scene.path.display(),
                e.table.replace('_', "-").replace("fractional-disk", "fd"),
                e.key.replace('_', "-")
            )
        })
    }
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

impl From<Backend> for penumbra::Backend {
    fn from(b: Backend) -> Self {
        match b {
            Backend::Auto => penumbra::Backend::Auto,
            Backend::Gpu => penumbra::Backend::Gpu,
            Backend::Cpu => penumbra::Backend::Cpu,
        }
    }
}

#[derive(Subcommand)]
enum Command {
    /// Render the visibility image V of a scene to a one-channel (`V`) float EXR.
    Render {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Technique.
        #[arg(long, value_parser = technique_parser(), default_value = "wedges-blend")]
        technique: Technique,
        /// Output EXR file.
        #[arg(long)]
        out: PathBuf,
        /// Light samples per pixel for `reference` and `depth-complexity`: a perfect square.
        #[arg(long, default_value_t = 256)]
        samples: usize,
        /// `depth-complexity`: the reference's own jittered points, pixel for pixel, instead of
        /// its correlated multi-jittered ones.
        #[arg(long)]
        jitter: bool,
        /// Also write an 8-bit greyscale PNG.
        #[arg(long)]
        png: Option<PathBuf>,
        /// Where the volume techniques (`hard`, `wedges`, `wedges-blend`) run; the references
        /// always run on the CPU, the shadow-map techniques on the GPU.
        #[arg(long, value_enum, default_value = "auto")]
        backend: Backend,
        #[command(flatten)]
        params: ParamArgs,
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
        /// Light samples per pixel of the sampled techniques measured (`reference`,
        /// `depth-complexity`): a perfect square.
        #[arg(long, default_value_t = 256)]
        technique_samples: usize,
        /// `depth-complexity`: jitter its samples as the reference does.
        #[arg(long)]
        jitter: bool,
        /// Techniques to measure.
        #[arg(
            long,
            value_parser = technique_parser(),
            value_delimiter = ',',
            default_value = "hard,wedges,wedges-blend"
        )]
        techniques: Vec<Technique>,
        /// Where the volume techniques run.
        #[arg(long, value_enum, default_value = "auto")]
        backend: Backend,
        #[command(flatten)]
        params: ParamArgs,
    },
    /// Time a technique: the median over N frames of each GPU pass (timestamp queries) and of
    /// the whole frame (wall clock, CPU setup and readback included). Given several techniques,
    /// times them in turn, `--rounds` times, and prints each one's frame time as a ratio to the
    /// first's, per round and over all frames.
    Bench {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Technique, or a comma-separated list compared with the first (e.g.
        /// `wedges,wedges-blend`).
        #[arg(
            long,
            value_parser = technique_parser(),
            value_delimiter = ',',
            default_value = "wedges-blend"
        )]
        technique: Vec<Technique>,
        /// Frames to time per technique and round (after one warm-up frame).
        #[arg(long, default_value_t = 10)]
        frames: usize,
        /// Rounds: the techniques take turns this many times, so that a slow minute on a shared
        /// machine falls on all of them.
        #[arg(long, default_value_t = 1)]
        rounds: usize,
        /// Where to run it.
        #[arg(long, value_enum, default_value = "auto")]
        backend: Backend,
        /// Light samples per pixel for `reference` and `depth-complexity`.
        #[arg(long, default_value_t = 256)]
        samples: usize,
        /// `depth-complexity`: jitter its samples as the reference does.
        #[arg(long)]
        jitter: bool,
        /// Print JSON.
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        params: ParamArgs,
    },
    /// Regenerate the fixture meshes and scenes.
    GenFixtures {
        /// Fixture folder.
        #[arg(long, default_value = "fixtures")]
        out: PathBuf,
    },
}

fn main() -> ExitCode {
    quiet_device_select();
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

/// Turns off Mesa's device-select layer, an implicit Vulkan layer that connects to a Wayland or
/// X11 display to choose a default GPU and, on a machine without one, prints "XDG_RUNTIME_DIR is
/// invalid or not set" twice per instance. The command chooses its adapter itself
/// (`penumbra_gpu::GpuContext`), so the layer has nothing to add. A value the user set is kept.
fn quiet_device_select() {
    if std::env::var_os("NODEVICE_SELECT").is_none() {
        // Safe: no other thread exists yet to read the environment concurrently.
        #[allow(unsafe_code)] // `set_var` is unsafe since edition 2024; see the line above.
        unsafe {
            std::env::set_var("NODEVICE_SELECT", "1")
        };
    }
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render {
            scene,
            technique,
            out,
            samples,
            jitter,
            png,
            backend,
            params,
        } => render(
            &scene,
            technique,
            &out,
            Sampling { samples, jitter },
            png.as_deref(),
            backend,
            &params,
        ),
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
            rounds,
            backend,
            samples,
            jitter,
            json,
            params,
        } => bench(
            &scene,
            &technique,
            Timing { frames, rounds },
            backend,
            Sampling { samples, jitter },
            json,
            &params,
        ),
        Command::Accuracy {
            scenes,
            samples,
            technique_samples,
            jitter,
            techniques,
            backend,
            params,
        } => accuracy(
            &scenes,
            samples,
            Sampling {
                samples: technique_samples,
                jitter,
            },
            &techniques,
            backend,
            &params,
        ),
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

/// Light samples per pixel of the sampled techniques, and whether `depth-complexity` jitters
/// them as the reference does.
#[derive(Clone, Copy, Debug)]
struct Sampling {
    samples: usize,
    jitter: bool,
}

fn render(
    scene_path: &Path,
    technique: Technique,
    out: &Path,
    sampling: Sampling,
    png: Option<&Path>,
    backend: Backend,
    params: &ParamArgs,
) -> Result<()> {
    samples_per_axis(sampling.samples)?;
    if sampling.jitter && !technique.takes_samples() {
        bail!(
            "--jitter: {technique:?} takes no light samples (depth-complexity does; the reference always jitters)"
        );
    }
    let mut outputs = vec![out];
    outputs.extend(png);
    // Checked before and after loading: the scene names the meshes.
    check_outputs(&[scene_path.to_path_buf()], &outputs)?;
    let mut scene = load_scene(scene_path)?;
    params.apply(&mut scene)?;
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
    let options = RenderOptions {
        samples: sampling.samples,
        jitter: sampling.jitter,
    };
    let frame =
        Renderer::new(backend.into()).render_frame(&scene, technique, &options, None, &progress)?;
    let (img, triangles, detail) = (
        frame.image,
        scene.triangle_count(),
        format!(" ({})", frame.detail),
    );
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
            let dc = DepthComplexity::new(&scene);
            let pattern = SamplePattern {
                per_axis,
                jitter: true,
            };
            let pixel = y as u64 * scene.camera.width as u64 + x as u64;
            let v = dc.visibility(&p, pattern, pixel, &mut Default::default());
            println!(
                "V depth    = {:.9} (depth complexity, the reference's {samples} samples; {} edges touched it, {} triangles towards the centre)",
                v.visibility, v.edges, v.centre_count
            );
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

fn accuracy(
    dir: &Path,
    samples: usize,
    sampling: Sampling,
    techniques: &[Technique],
    backend: Backend,
    params: &ParamArgs,
) -> Result<()> {
    samples_per_axis(samples)?;
    samples_per_axis(sampling.samples)?;
    let truth_options = RenderOptions {
        samples,
        jitter: false,
    };
    // Each technique's back end, decided (and any GPU opened) before the first render.
    let mut renderer = Renderer::new(backend.into());
    for &t in techniques {
        renderer.uses_gpu(t)?;
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
        "| scene | technique | MAE | p99 | > 0.05 | penumbra px | penumbra MAE | penumbra p99 | time (s) |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for path in scenes {
        let mut scene = load_scene(&path)?;
        params.apply(&mut scene)?;
        let name = path
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned();
        let truth = renderer.render(&scene, Technique::Reference, &truth_options)?;
        // Built before the timed renders.
        let volumes = Volumes::build(&scene);
        for &t in techniques {
            let options = RenderOptions {
                samples: sampling.samples,
                jitter: sampling.jitter && t.takes_samples(),
            };
            let start = std::time::Instant::now();
            let img = renderer
                .render_frame(&scene, t, &options, Some(&volumes), &|_| {})?
                .image;
            let secs = start.elapsed().as_secs_f64();
            let c = image::compare(&img, &truth)?;
            println!(
                "| {name} | {} | {:.5} | {:.4} | {:.2}% | {} | {:.5} | {:.4} | {secs:.2} |",
                t.name(),
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

/// How `penumbra bench` times: frames per technique and round, and rounds.
#[derive(Clone, Copy)]
struct Timing {
    frames: usize,
    rounds: usize,
}

/// The passes `penumbra bench` reports, in order.
const BENCH_PASSES: [&str; 10] = [
    "depth",
    "stencil",
    "wedge",
    "blend",
    "light_map",
    "preprocess",
    "filter",
    "resolve",
    "gpu_total",
    "frame_wall",
];

fn bench(
    scene_path: &Path,
    techniques: &[Technique],
    timing: Timing,
    backend: Backend,
    sampling: Sampling,
    json: bool,
    params: &ParamArgs,
) -> Result<()> {
    if timing.frames == 0 {
        bail!("--frames must be at least 1");
    }
    if timing.rounds == 0 {
        bail!("--rounds must be at least 1");
    }
    if let Some(t) = techniques
        .iter()
        .find(|t| backend == Backend::Gpu && t.cpu_only())
    {
        bail!("--backend gpu: {t:?} runs on the CPU only (the GPU renders the volume techniques)");
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
        backend,
        sampling,
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
fn bench_one(
    scene_path: &Path,
    technique: Technique,
    frames: usize,
    backend: Backend,
    sampling: Sampling,
    params: &ParamArgs,
) -> Result<serde_json::Value> {
    samples_per_axis(sampling.samples)?;
    let options = RenderOptions {
        samples: sampling.samples,
        jitter: sampling.jitter,
    };
    let mut scene = load_scene(scene_path)?;
    params.apply(&mut scene)?;
    let mut renderer = Renderer::new(backend.into());
    let on_gpu = renderer.uses_gpu(technique)?;
    // Built once, outside the timed frames: the frames time the GPU's work.
    let volumes = (on_gpu && technique.is_volume()).then(|| Volumes::build(&scene));
    let mut wall = Vec::new();
    let mut passes: Vec<PassTimes> = Vec::new();
    for k in 0..=frames {
        let start = std::time::Instant::now();
        let frame =
            renderer.render_frame(&scene, technique, &options, volumes.as_ref(), &|_| {})?;
        if k > 0 {
            wall.push(start.elapsed().as_secs_f64() * 1e3);
            passes.extend(frame.times);
        }
    }
    let device = match renderer.gpu_description() {
        Some(d) if on_gpu => d,
        _ => format!("cpu, {} threads", rayon::current_num_threads()),
    };
    let pass = |f: fn(&PassTimes) -> f64| {
        (!passes.is_empty()).then(|| median(passes.iter().map(f).collect()))
    };
    Ok(serde_json::json!({
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
            "light_map": pass(|p| p.light_map),
            "preprocess": pass(|p| p.preprocess),
            "filter": pass(|p| p.filter),
            "gpu_total": pass(|p| p.total()),
            "frame_wall": median(wall),
        }
    }))
}

/// Prints a report of [`bench_one`] (or of [`bench_compare`]'s medians) of `technique` as text.
fn print_bench(report: &serde_json::Value, technique: Technique, what: &str) {
    let [w, h] = [0, 1].map(|i| report["resolution"][i].as_u64().unwrap_or(0));
    println!(
        "{} {} on {} at {w}x{h}, {what}:",
        report["scene"].as_str().unwrap_or_default(),
        report["technique"].as_str().unwrap_or_default(),
        report["device"].as_str().unwrap_or_default(),
    );
    let volume = technique.is_volume();
    for k in BENCH_PASSES {
        let relevant = match k {
            "stencil" | "wedge" | "blend" => volume,
            "light_map" | "preprocess" | "filter" => !volume,
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
fn bench_compare(techniques: &[Technique], timing: Timing, json: bool) -> Result<()> {
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

fn min_of(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}
