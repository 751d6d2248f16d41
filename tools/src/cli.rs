//! The command line: its subcommands, arguments and flags (clap).

use std::path::PathBuf;

use anyhow::Result;
use clap::builder::TypedValueParser as _;
use clap::{Parser, Subcommand, ValueEnum};
use penumbra::Technique;
use penumbra::geom::Scene;
use penumbra::geom::params::{GaussianVariant, MdsmExtra};

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

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum MdsmExtraArg {
    /// The neighbourhood's maximum.
    Max,
    /// The neighbourhood's minimum.
    Min,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum GaussianVariantArg {
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
pub(crate) struct ParamArgs {
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
    pub(crate) fn apply(&self, scene: &mut Scene) -> Result<()> {
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
pub(crate) enum Backend {
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
pub(crate) enum Command {
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
