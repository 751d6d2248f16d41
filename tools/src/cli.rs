//! The command line: its subcommands, arguments and flags (clap).

use std::path::PathBuf;

use anyhow::Result;
use clap::builder::TypedValueParser as _;
use clap::{Parser, Subcommand};
use penumbra::geom::Scene;
use penumbra::gpu::WedgePass;
use penumbra::params::{Kind, PARAMS, Param, Value};
use penumbra::{Backend, Technique};

#[derive(Parser)]
#[command(
    name = "penumbra",
    version,
    about = "Soft shadows from geometry, measured against a ray-cast reference"
)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
}

/// Parses a technique by its name, listing every name (with its description) in the help.
pub(crate) fn technique_parser() -> impl clap::builder::TypedValueParser<Value = Technique> {
    clap::builder::PossibleValuesParser::new(
        Technique::ALL.map(|t| clap::builder::PossibleValue::new(t.name()).help(t.description())),
    )
    .map(|name| {
        name.parse::<Technique>()
            .expect("one of the possible values")
    })
}

/// Parses the techniques that give visibility at points (`depth-complexity`, `reference`) by
/// name, listing them (with their descriptions) in the help.
pub(crate) fn sensor_technique_parser() -> impl clap::builder::TypedValueParser<Value = Technique> {
    const SENSORS: [Technique; 2] = [Technique::DepthComplexity, Technique::Reference];
    clap::builder::PossibleValuesParser::new(
        SENSORS.map(|t| clap::builder::PossibleValue::new(t.name()).help(t.description())),
    )
    .map(|name| {
        name.parse::<Technique>()
            .expect("one of the possible values")
    })
}

/// Parameters of the shadow-map techniques, one flag per key of `penumbra::params::PARAMS`
/// (`--pcf-kernel 5`, `--gaussian-dm 150`, ...): each overrides the key of the same name in the
/// scene's optional table (`[shadow_map]`, `[pcf]`, `[pcss]`, `[fractional_disk]`, `[mdsm]`,
/// `[gaussian]`; see docs/scene-format.md).
#[derive(Clone, Debug, Default)]
pub(crate) struct ParamArgs {
    /// The flags given, in `PARAMS` order.
    values: Vec<(&'static Param, Value)>,
}

impl clap::FromArgMatches for ParamArgs {
    fn from_arg_matches(matches: &clap::ArgMatches) -> Result<Self, clap::Error> {
        let mut args = ParamArgs::default();
        args.update_from_arg_matches(matches)?;
        Ok(args)
    }

    fn update_from_arg_matches(&mut self, matches: &clap::ArgMatches) -> Result<(), clap::Error> {
        for p in &PARAMS {
            let value = match p.kind {
                Kind::Int { .. } => matches.get_one::<u32>(p.flag).map(|&v| Value::Int(v)),
                Kind::Real { .. } => matches.get_one::<f64>(p.flag).map(|&v| Value::Real(v)),
                Kind::Bool => matches.get_one::<bool>(p.flag).map(|&v| Value::Bool(v)),
                Kind::Choice(names) => matches
                    .get_one::<String>(p.flag)
                    .and_then(|v| names.iter().find(|n| *n == v))
                    .map(|n| Value::Choice(n)),
            };
            if let Some(v) = value {
                self.values.retain(|(q, _)| q.flag != p.flag);
                self.values.push((p, v));
            }
        }
        Ok(())
    }
}

impl clap::Args for ParamArgs {
    fn augment_args(cmd: clap::Command) -> clap::Command {
        cmd.args(PARAMS.iter().map(|p| {
            let arg = clap::Arg::new(p.flag)
                .long(p.flag)
                .help(p.help())
                .help_heading("Shadow maps")
                .allow_negative_numbers(true);
            match p.kind {
                Kind::Int { .. } => arg.value_parser(clap::value_parser!(u32)).value_name("N"),
                Kind::Real { .. } => arg.value_parser(clap::value_parser!(f64)).value_name("X"),
                Kind::Bool => arg
                    .value_parser(clap::value_parser!(bool))
                    .value_name("BOOL"),
                Kind::Choice(names) => arg.value_parser(clap::builder::PossibleValuesParser::new(
                    names.iter().copied(),
                )),
            }
        }))
    }

    fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
        Self::augment_args(cmd)
    }
}

impl ParamArgs {
    /// `scene`'s parameters with these flags applied, checked.
    pub(crate) fn apply(&self, scene: &mut Scene) -> Result<()> {
        for (param, value) in &self.values {
            scene.params.set(param, *value);
        }
        scene.params.validate().map_err(|e| {
            let flag = PARAMS
                .iter()
                .find(|p| p.table == e.table && p.key == e.key)
                .map_or(String::new(), |p| format!(", e.g. --{}", p.flag));
            anyhow::anyhow!(
                "{}: {e} (after the command line's flags{flag})",
                scene.path.display(),
            )
        })
    }
}

/// The back ends by their names on the command line, with their help.
const BACKENDS: [(&str, Backend, &str); 3] = [
    (
        "auto",
        Backend::Auto,
        "The GPU when an adapter exists, else the CPU",
    ),
    ("gpu", Backend::Gpu, "wgpu (fails without an adapter)"),
    (
        "cpu",
        Backend::Cpu,
        "The CPU evaluation of the `volumes` crate",
    ),
];

/// Parses the library's [`Backend`] by its name, listing every name (with its help).
pub(crate) fn backend_parser() -> impl clap::builder::TypedValueParser<Value = Backend> {
    clap::builder::PossibleValuesParser::new(
        BACKENDS.map(|(name, _, help)| clap::builder::PossibleValue::new(name).help(help)),
    )
    .map(|name| {
        BACKENDS
            .into_iter()
            .find(|(n, _, _)| *n == name)
            .expect("one of the possible values")
            .1
    })
}

/// `--wedge-pass`'s values.
pub(crate) fn wedge_pass_parser() -> impl clap::builder::TypedValueParser<Value = WedgePass> {
    clap::builder::PossibleValuesParser::new(["tiled", "rasterised"]).map(|name| {
        match name.as_str() {
            "tiled" => WedgePass::Tiled,
            _ => WedgePass::Rasterised,
        }
    })
}

#[derive(Subcommand)]
pub(crate) enum Command {
    /// Render the visibility image V of a scene to a float EXR: one channel `V`, or for a scene
    /// of several lights (`[[light]]`) one channel `<name>.V` per light, each light alone.
    Render {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Technique.
        #[arg(long, value_parser = technique_parser(), default_value = "wedges-blend")]
        technique: Technique,
        /// Output EXR file; missing folders are created (and said on stderr).
        #[arg(long)]
        out: PathBuf,
        /// Light samples per pixel for `reference` and `depth-complexity`: a perfect square up to 65536.
        #[arg(long, default_value_t = 256)]
        samples: usize,
        /// `depth-complexity`: the reference's own jittered points, pixel for pixel, instead of
        /// its correlated multi-jittered ones.
        #[arg(long)]
        jitter: bool,
        /// Also write an 8-bit greyscale PNG; for a scene of several lights one per light,
        /// `PNG.<name>.png` (`--png v.png` writes `v.key.png`, `v.fill.png`, ...).
        #[arg(long)]
        png: Option<PathBuf>,
        /// Also write a shaded preview, an 8-bit RGB PNG: each surface point grey by
        /// `A + (1 - A) · mean over the lights of max(0, n · ω) · V` (n the surface's normal
        /// towards the camera, ω the direction to the light's centre, A = 0.1 ambient), sRGB
        /// encoded; where the camera sees nothing, a flat blue-grey. See docs/scene-format.md.
        #[arg(long)]
        shaded: Option<PathBuf>,
        /// Where the volume techniques (`hard`, `wedges`, `wedges-blend`) run; the references
        /// always run on the CPU, the shadow-map techniques on the GPU.
        #[arg(long, value_parser = backend_parser(), default_value = "auto")]
        backend: Backend,
        #[command(flatten)]
        params: ParamArgs,
    },
    /// Visibility at sensor points read from a .npy or .csv file: one value per point, or per
    /// point and light.
    ///
    /// Each point sees the light samples on the side of its plane that its normal points to,
    /// where nothing hides them (a grid on a facade, a courtyard's floor); a point on a surface
    /// stands on it. Written as a float32 .npy array or a .csv file (docs/scene-format.md,
    /// "Sensor points").
    Points {
        /// Scene file (TOML).
        scene: PathBuf,
        /// The points: a NumPy `.npy` array of shape (n, 6), `<f8` or `<f4`, a row
        /// x, y, z, nx, ny, nz per point, or a `.csv` file of such rows (an optional header
        /// line of names; `#` comments and blank lines skipped). Of shape (n, 3), or 3
        /// columns, positions only, with `--normal`.
        #[arg(long)]
        points: PathBuf,
        /// Output: a float32 `.npy` array, shape (n,), or (n, lights) for several lights; or a
        /// `.csv` file, a header line (`V`, or the lights' names) then a row per point.
        /// Missing folders are created (and said on stderr).
        #[arg(long)]
        out: PathBuf,
        /// Only the light of this name (of a scene of several; its names as in the scene
        /// file); every light when not given.
        #[arg(long)]
        light: Option<String>,
        /// The normal of every point, for a points file of positions only.
        #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
        normal: Option<String>,
        /// Light samples per point: a perfect square up to 65536. Sensor k takes the samples
        /// of camera pixel k.
        #[arg(long, default_value_t = 256)]
        samples: usize,
        /// Technique.
        #[arg(long, value_parser = sensor_technique_parser(), default_value = "depth-complexity")]
        technique: Technique,
        /// `depth-complexity`: the reference's own jittered samples, point for point, instead
        /// of its correlated multi-jittered ones.
        #[arg(long)]
        jitter: bool,
    },
    /// Hours of direct sun at every pixel from --start to --end: the scene's lights replaced by
    /// the sun at each step (NREL's Solar Position Algorithm, refraction included), the sun's
    /// visibility summed times each step's hours. Written as a float EXR with one channel
    /// `hours`, and with --png a colour map with its legend. The scene's north is -z and its up
    /// +y unless --north and --up say otherwise (docs/sun-studies.md).
    SunHours {
        /// Scene file (TOML); its lights are replaced by the sun.
        scene: PathBuf,
        /// Latitude in degrees, north positive.
        #[arg(long, allow_hyphen_values = true)]
        lat: f64,
        /// Longitude in degrees, east positive.
        #[arg(long, allow_hyphen_values = true)]
        lon: f64,
        /// First step: RFC 3339 with its offset (2026-06-21T06:00:00+02:00), or a date and time
        /// or a date in UTC (2026-06-21T04:00, 2026-06-21).
        #[arg(long)]
        start: String,
        /// End, excluded, as --start.
        #[arg(long)]
        end: String,
        /// Step: minutes (60m, 15m, 15min, 30) or hours (1h).
        #[arg(long, default_value = "60m")]
        step: String,
        /// Output: an EXR file (channel `hours`), or with --points a float32 `.npy` array or a
        /// `.csv` file (a header `hours`, then a row per point). Missing folders are created.
        #[arg(long)]
        out: PathBuf,
        /// Also write a colour map of the hours with a legend, an 8-bit RGB PNG.
        #[arg(long)]
        png: Option<PathBuf>,
        /// Sensor points instead of the camera's pixels, as `penumbra points` reads them: a
        /// `.npy` array or `.csv` file of rows x, y, z, nx, ny, nz (or x, y, z with --normal).
        #[arg(long)]
        points: Option<PathBuf>,
        /// The normal of every point, for a points file of positions only.
        #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
        normal: Option<String>,
        /// Technique: depth-complexity (exact for its samples) or reference (rays).
        #[arg(long, value_parser = sensor_technique_parser(), default_value = "depth-complexity")]
        technique: Technique,
        /// Light samples per pixel and step: a perfect square up to 65536.
        #[arg(long, default_value_t = 64)]
        samples: usize,
        /// The sun's full angle in degrees.
        #[arg(long, default_value_t = 0.53)]
        angular_size: f64,
        /// Where depth-complexity runs.
        #[arg(long, value_parser = backend_parser(), default_value = "cpu")]
        backend: Backend,
        /// The scene's north, a direction along its ground (0,0,-1 for a scene modelled +y up;
        /// 0,1,0 for one modelled +z up).
        #[arg(
            long,
            value_name = "X,Y,Z",
            allow_hyphen_values = true,
            default_value = "0,0,-1"
        )]
        north: String,
        /// The scene's up (0,1,0, or 0,0,1 for a scene modelled +z up).
        #[arg(
            long,
            value_name = "X,Y,Z",
            allow_hyphen_values = true,
            default_value = "0,1,0"
        )]
        up: String,
    },
    /// Print the surface point seen through one pixel, its exact V and its reference V (of each
    /// light in turn, for a scene of several).
    Probe {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Pixel as X,Y (column, row; row 0 the top).
        #[arg(long)]
        pixel: String,
        /// Light samples for the reference value: a perfect square up to 65536.
        #[arg(long, default_value_t = 4096)]
        samples: usize,
    },
    /// Compare image A against reference B: errors over all pixels and over B's penumbra. Images
    /// of several lights are compared channel by channel (`<light>.V`), each in turn.
    Compare {
        /// Image under test.
        a: PathBuf,
        /// Reference image.
        b: PathBuf,
        /// Compare only this channel of both images (`V`, or `<light>.V` of an image of
        /// several lights); all of them in turn when not given.
        #[arg(long)]
        channel: Option<String>,
        /// Write a heat map of |A - B| (black 0, red, yellow, white >= 0.1); of several
        /// channels, one per light, `HEATMAP.<light>.png`.
        #[arg(long)]
        heatmap: Option<PathBuf>,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Print the volume geometry of a scene: silhouette edges, loops, wedges and shadow-volume
    /// triangles, and for each mesh that had any, the triangles dropped on loading (of zero
    /// area, or repeating another).
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
        /// Reference light samples per pixel: a perfect square up to 65536.
        #[arg(long, default_value_t = 1024)]
        samples: usize,
        /// Light samples per pixel of the sampled techniques measured (`reference`,
        /// `depth-complexity`): a perfect square up to 65536, or a comma-separated list of them,
        /// a row for each (the truth rendered once).
        #[arg(long, value_delimiter = ',', default_value = "256")]
        technique_samples: Vec<usize>,
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
        #[arg(long, value_parser = backend_parser(), default_value = "auto")]
        backend: Backend,
        /// On the GPU, how `wedges` and `wedges-blend` evaluate their wedges: `tiled` (one
        /// compute pass over screen tiles) or `rasterised`; the device's faster by default.
        #[arg(long, value_parser = wedge_pass_parser())]
        wedge_pass: Option<WedgePass>,
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
        #[arg(long, value_parser = backend_parser(), default_value = "auto")]
        backend: Backend,
        /// Light samples per pixel for `reference` and `depth-complexity`.
        #[arg(long, default_value_t = 256)]
        samples: usize,
        /// `depth-complexity`: jitter its samples as the reference does.
        #[arg(long)]
        jitter: bool,
        /// Instead of timing, render one frame of each technique on the GPU and print per pass
        /// its vertex, primitive (clipper output), fragment and compute shader invocations
        /// (pipeline-statistics queries, where the device has them: lavapipe does) and the bytes
        /// of the buffers and textures it binds for reading and writing, each in total and per
        /// pixel. Counts do not depend on the device's speed (docs/gpu.md, "Pass counters").
        #[arg(long)]
        counters: bool,
        /// How `wedges` and `wedges-blend` evaluate their wedges on the GPU: `tiled` (one
        /// compute pass over screen tiles) or `rasterised` (each wedge's solid drawn; for
        /// `wedges-blend` a stencil, a wedge and a blend pass per group of silhouettes); by
        /// default the faster on the device (rasterised on a CPU device such as lavapipe, tiled
        /// on a GPU). The same image, within rounding.
        #[arg(long, value_parser = wedge_pass_parser())]
        wedge_pass: Option<WedgePass>,
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

/// A direction given as `X,Y,Z` to `flag` (`--normal`, `--north`, `--up`): three finite
/// numbers, not all zero.
pub(crate) fn parse_direction(flag: &str, text: &str) -> anyhow::Result<glam::DVec3> {
    let bad = |why: &str| anyhow::anyhow!("{flag} {text:?}: {why}; expected X,Y,Z, e.g. 0,1,0");
    let v: Vec<f64> = text
        .split(',')
        .map(|c| c.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad("not three numbers"))?;
    let [x, y, z] = v[..] else {
        return Err(bad("not three numbers"));
    };
    let n = glam::DVec3::new(x, y, z);
    if !n.is_finite() {
        return Err(bad("not finite"));
    }
    if n == glam::DVec3::ZERO {
        return Err(bad("a zero vector has no direction"));
    }
    Ok(n)
}
