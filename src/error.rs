//! Why a render could not run, each case naming what was asked and what stood in the way.

use std::sync::Arc;

use penumbra_geom::RangeError;
use penumbra_geom::Technique;
use penumbra_gpu::GpuError;

/// Why a render could not run.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// A shadow-map technique without a GPU.
    #[error("{technique} is a shadow-map technique and runs on a GPU only: {missing}")]
    NeedsGpu {
        /// The technique.
        technique: Technique,
        /// Why there is no GPU.
        missing: MissingGpu,
    },
    /// A CPU-only technique asked for on the GPU.
    #[error(
        "{technique} runs on the CPU only (the GPU renders the volume and shadow-map techniques and depth-complexity)"
    )]
    CpuOnly {
        /// The technique.
        technique: Technique,
    },
    /// A sample count that is not a positive perfect square up to [`crate::MAX_SAMPLES`].
    #[error(
        "{samples} samples: the count must be a positive perfect square (64, 256, 1024, ...) up to {max}",
        max = crate::MAX_SAMPLES
    )]
    BadSamples {
        /// The count given.
        samples: usize,
    },
    /// Jittered samples asked of a technique that takes none.
    #[error(
        "jitter: {technique} takes no light samples (depth-complexity does; the reference always jitters)"
    )]
    NoSamples {
        /// The technique.
        technique: Technique,
    },
    /// A scene with a value outside the supported range (a scene made in code: the loader
    /// refuses those of scene files with their line).
    #[error("{problem}")]
    OutOfRange {
        /// The first value outside the range ([`crate::Scene::out_of_range`]).
        problem: RangeError,
    },
    /// A scene of several lights ([`crate::Scene::lights`]) whose names are not valid and
    /// unique ([`penumbra_geom::check_light_names`]; a scene file's are checked as it loads).
    #[error("the scene's lights: {error}")]
    BadLights {
        /// What is wrong with the names.
        error: penumbra_geom::LightNameError,
    },
    /// The GPU back end chosen, and no GPU.
    #[error("no GPU: {missing}")]
    NoGpu {
        /// Why there is none.
        missing: MissingGpu,
    },
    /// Light samples that the GPU's depth-complexity sampling does not take, asked of the GPU
    /// back end (the CPU back end renders them).
    #[error(
        "depth-complexity on the GPU takes up to {max} multi-jittered samples per pixel, not {samples}{}",
        if *.jitter { " jittered" } else { "" }
    )]
    GpuSamples {
        /// The samples asked for.
        samples: usize,
        /// Whether jittered.
        jitter: bool,
        /// The most the GPU takes ([`crate::MAX_GPU_SAMPLES`]).
        max: u32,
    },
    /// An image wider or taller than the GPU's textures, asked of the GPU back end (or of a
    /// shadow-map technique, which has no other).
    #[error(
        "the image is {width} x {height} pixels, too large: the GPU's textures are at most {max_side} pixels on a side ({adapter})"
    )]
    TooLargeForGpu {
        /// The technique.
        technique: Technique,
        /// The image's width.
        width: u32,
        /// The image's height.
        height: u32,
        /// The GPU's largest texture side.
        max_side: u32,
        /// The GPU's description.
        adapter: String,
    },
    /// An image that the memory available would not hold, refused before anything is
    /// allocated.
    #[error(
        "the image is {width} x {height} pixels, too large: it needs about {:.1} GB and {:.1} GB of memory are available",
        *.needed as f64 / 1e9,
        *.available as f64 / 1e9
    )]
    OutOfMemory {
        /// The image's width.
        width: u32,
        /// The image's height.
        height: u32,
        /// The bytes the render would take, roughly.
        needed: u64,
        /// The bytes available ([`penumbra_geom::available_memory`]).
        available: u64,
    },
    /// Visibility at points asked of a technique that does not give it.
    #[error(
        "visibility at points is given by depth-complexity (exact for its samples) or reference (rays), not {technique}"
    )]
    SensorTechnique {
        /// The technique.
        technique: Technique,
    },
    /// A light index past the scene's lights.
    #[error("light {light}: the scene has {lights} light(s), numbered from 0")]
    NoSuchLight {
        /// The index asked for.
        light: usize,
        /// The scene's lights.
        lights: usize,
    },
    /// A sensor point or normal that cannot be used.
    #[error("sensor {index}: {problem}")]
    BadSensor {
        /// Its index in the query.
        index: u64,
        /// What is wrong.
        problem: String,
    },
    /// A sun study's step that gives no sun: its angles or hours not finite, or an elevation
    /// outside [-90, 90] degrees.
    #[error("sun study: {problem}")]
    BadSun {
        /// What is wrong.
        problem: String,
    },
    /// The render was interrupted ([`penumbra_geom::Interrupter`], Ctrl-C in Python)
    /// before it finished: no image.
    #[error("interrupted")]
    Interrupted,
    /// The GPU failed.
    #[error(transparent)]
    Gpu {
        /// What failed.
        #[from]
        source: GpuError,
    },
}

/// Why a render has no GPU.
#[derive(Clone, Debug, thiserror::Error)]
pub enum MissingGpu {
    /// The CPU back end was chosen.
    #[error("the CPU back end was chosen")]
    CpuChosen,
    /// Opening one failed (the failure is kept: the renderer does not look again).
    #[error("{error} (Mesa's lavapipe serves without a GPU: mesa-vulkan-drivers, libvulkan1)")]
    Unavailable {
        /// Why it failed.
        error: Arc<GpuError>,
    },
}
