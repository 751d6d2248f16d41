//! One renderer for every technique: the GPU where it helps and there is one, the CPU
//! otherwise, with each back end's renderers built once and kept.

use penumbra_geom::{LightSamples, Reference, Scene, Technique, VisibilityImage};
use penumbra_gpu::{GpuContext, GpuError, GpuRenderer, PassTimes, ShadowMapRenderer};
use penumbra_volumes::{CpuRenderer, DepthComplexity, SamplePattern, Volumes};

use crate::Runs;

/// Where the techniques that run on both the GPU and the CPU (`hard`, `wedges`,
/// `wedges-blend`) run. The shadow-map techniques always need a GPU; the references and
/// `depth-complexity` always run on the CPU.
///
/// ```
/// use penumbra::{Backend, RenderError, Renderer, Technique};
///
/// let mut cpu = Renderer::new(Backend::Cpu);
/// assert!(!cpu.uses_gpu(Technique::WedgesBlend)?);
/// assert!(matches!(cpu.uses_gpu(Technique::Pcss), Err(RenderError::NeedsGpu { .. })));
/// let mut gpu = Renderer::new(Backend::Gpu);
/// assert!(matches!(gpu.uses_gpu(Technique::Reference), Err(RenderError::CpuOnly { .. })));
/// # Ok::<(), RenderError>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Backend {
    /// The GPU when an adapter exists (Mesa's lavapipe counts), else the CPU.
    #[default]
    Auto,
    /// The GPU; an error without an adapter.
    Gpu,
    /// The CPU.
    Cpu,
}

/// The most light samples per pixel (256 x 256): beyond, a 320 x 240 reference would take hours
/// and the sampling error is far below `f32`'s resolution of V anyway.
pub const MAX_SAMPLES: usize = 65536;

/// How the sampled techniques (`reference`, `depth-complexity`) sample the light.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderOptions {
    /// Light samples per pixel, a perfect square (64, 256, 1024, ...).
    pub samples: usize,
    /// `depth-complexity`: the reference's jittered points instead of its own multi-jittered
    /// ones, so that the two images agree pixel for pixel.
    pub jitter: bool,
}

impl Default for RenderOptions {
    /// 256 samples, not jittered.
    fn default() -> Self {
        RenderOptions {
            samples: 256,
            jitter: false,
        }
    }
}

impl RenderOptions {
    /// The sample pattern, or an error for a sample count that is not a positive square.
    ///
    /// ```
    /// use penumbra::RenderOptions;
    ///
    /// let p = RenderOptions { samples: 1024, jitter: true }.pattern().unwrap();
    /// assert_eq!((p.per_axis, p.jitter), (32, true));
    /// assert!(RenderOptions { samples: 1000, jitter: false }.pattern().is_err());
    /// assert!(RenderOptions { samples: 65536 * 4, jitter: false }.pattern().is_err());
    /// ```
    pub fn pattern(&self) -> Result<SamplePattern, RenderError> {
        let n = (self.samples as f64).sqrt().round() as usize;
        if self.samples == 0 || n * n != self.samples || self.samples > MAX_SAMPLES {
            return Err(RenderError::BadSamples {
                samples: self.samples,
            });
        }
        Ok(SamplePattern {
            per_axis: n,
            jitter: self.jitter,
        })
    }
}

/// Why a render could not run.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// A shadow-map technique without a GPU adapter.
    #[error("{technique} is a shadow-map technique and runs on a GPU only: {why}")]
    NeedsGpu {
        /// The technique.
        technique: Technique,
        /// Why there is none.
        why: String,
    },
    /// A CPU-only technique asked for on the GPU.
    #[error(
        "{technique} runs on the CPU only (the GPU renders the volume and shadow-map techniques and depth-complexity)"
    )]
    CpuOnly {
        /// The technique.
        technique: Technique,
    },
    /// A sample count that is not a positive perfect square up to [`MAX_SAMPLES`].
    #[error(
        "{samples} samples: the count must be a positive perfect square (64, 256, 1024, ...) up to 65536"
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
    #[error("{0}")]
    OutOfRange(String),
    /// The GPU back end chosen, and no adapter.
    #[error("no GPU: {why}")]
    NoGpu {
        /// Why there is none.
        why: String,
    },
    /// Light samples the GPU's depth-complexity sampling does not take, asked of the GPU back
    /// end.
    #[error(
        "depth-complexity on the GPU takes up to {max} multi-jittered samples per pixel, not {samples}{}; --backend cpu renders it",
        if *.jitter { " jittered" } else { "" }
    )]
    GpuSamples {
        /// The samples asked for.
        samples: usize,
        /// Whether jittered.
        jitter: bool,
        /// The most the GPU takes.
        max: u32,
    },
    /// An image too large for the back end or the memory.
    #[error("the image is {width} x {height} pixels, too large: {why}")]
    TooLarge {
        /// Its width.
        width: u32,
        /// Its height.
        height: u32,
        /// What it does not fit.
        why: String,
    },
    /// The GPU failed.
    #[error(transparent)]
    Gpu(#[from] GpuError),
}

/// A rendered image, with where it was made.
pub struct Frame {
    /// The visibility image.
    pub image: VisibilityImage,
    /// The GPU passes' times, where the device has timestamp queries.
    pub times: Option<PassTimes>,
    /// `gpu: <adapter>` or `cpu`, and what the technique used (samples, edges, wedges).
    pub detail: String,
    /// What makes the image wrong though it rendered: the hard, wedge and shadow-map techniques
    /// warn of each mesh whose cut by the light's plane holds the light's centre
    /// ([`penumbra_volumes::encloses_light_centre`]), one line each.
    pub warnings: Vec<String>,
}

/// Whether the GPU has been looked for yet, and what was found.
enum GpuState {
    Untried,
    Ready(Box<GpuContext>),
    Unavailable(String),
}

/// Renders scenes with any [`Technique`], keeping its GPU context and GPU renderers from one
/// render to the next. The GPU is looked for the first time a technique could use it.
///
/// ```
/// use penumbra::{Backend, RenderOptions, Renderer, Technique};
/// use penumbra::geom::Scene;
///
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/scenes/quad-over-plane.toml");
/// let scene = Scene::load(std::path::Path::new(path))?;
/// let mut renderer = Renderer::new(Backend::Cpu);
/// let options = RenderOptions { samples: 16, jitter: false };
/// let v = renderer.render(&scene, Technique::DepthComplexity, &options)?;
/// assert_eq!((v.width, v.height), (320, 240));
/// // Lit far from the quad, dark under it.
/// assert_eq!(v.get(5, 235), 1.0);
/// assert_eq!(v.get(160, 120), 0.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Renderer {
    backend: Backend,
    gpu: GpuState,
    volumes: Option<GpuRenderer>,
    shadow_maps: Vec<ShadowMapRenderer>,
}

impl Renderer {
    /// A renderer choosing the GPU or the CPU by `backend`.
    pub fn new(backend: Backend) -> Self {
        Renderer {
            backend,
            gpu: GpuState::Untried,
            volumes: None,
            shadow_maps: Vec::new(),
        }
    }

    /// A renderer on the caller's device, for the techniques that can use it.
    pub fn with_context(ctx: GpuContext) -> Self {
        Renderer {
            gpu: GpuState::Ready(Box::new(ctx)),
            ..Renderer::new(Backend::Gpu)
        }
    }

    /// The GPU's description, once one has been opened.
    pub fn gpu_description(&self) -> Option<String> {
        match &self.gpu {
            GpuState::Ready(ctx) => Some(ctx.describe()),
            _ => None,
        }
    }

    /// The GPU context, opened on first use; `Err` with the reason where there is none.
    /// The device that [`Renderer::uses_gpu`] opened, once it said yes.
    fn opened(&self) -> &GpuContext {
        match &self.gpu {
            GpuState::Ready(ctx) => ctx,
            _ => unreachable!("uses_gpu opened it"),
        }
    }

    fn context(&mut self) -> Result<&GpuContext, String> {
        if let GpuState::Untried = self.gpu {
            self.gpu = match GpuContext::new() {
                Ok(ctx) => GpuState::Ready(Box::new(ctx)),
                Err(e) => GpuState::Unavailable(format!(
                    "{e} (Mesa's lavapipe serves without a GPU: mesa-vulkan-drivers, libvulkan1)"
                )),
            };
        }
        match &self.gpu {
            GpuState::Ready(ctx) => Ok(ctx),
            GpuState::Unavailable(why) => Err(why.clone()),
            GpuState::Untried => unreachable!("looked for above"),
        }
    }

    /// Whether `technique` runs on the GPU with this renderer's back end (opening it if need be),
    /// or an error where it cannot run at all.
    pub fn uses_gpu(&mut self, technique: Technique) -> Result<bool, RenderError> {
        if Runs::of(technique) == Runs::GpuOnly {
            if self.backend == Backend::Cpu {
                return Err(RenderError::NeedsGpu {
                    technique,
                    why: "the CPU back end was chosen".into(),
                });
            }
            return match self.context() {
                Ok(_) => Ok(true),
                Err(why) => Err(RenderError::NeedsGpu { technique, why }),
            };
        }
        if Runs::of(technique) == Runs::CpuOnly {
            return match self.backend {
                Backend::Gpu => Err(RenderError::CpuOnly { technique }),
                _ => Ok(false),
            };
        }
        match self.backend {
            Backend::Cpu => Ok(false),
            Backend::Auto => Ok(self.context().is_ok()),
            Backend::Gpu => match self.context() {
                Ok(_) => Ok(true),
                Err(why) => Err(RenderError::NoGpu { why }),
            },
        }
    }

    /// The visibility image of `scene` by `technique`.
    pub fn render(
        &mut self,
        scene: &Scene,
        technique: Technique,
        options: &RenderOptions,
    ) -> Result<VisibilityImage, RenderError> {
        Ok(self
            .render_frame(scene, technique, options, None, &|_| {})?
            .image)
    }

    /// [`Renderer::render`] with the GPU pass times and a description of the run. A volume
    /// technique on the GPU takes the scene's silhouettes, volumes and wedges from `volumes`
    /// when given (so that several frames build them once), and builds them otherwise. The CPU
    /// renderers call `progress` with the number of image rows finished so far.
    pub fn render_frame(
        &mut self,
        scene: &Scene,
        technique: Technique,
        options: &RenderOptions,
        volumes: Option<&Volumes>,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Frame, RenderError> {
        let mut frame = self.render_image(scene, technique, options, volumes, progress)?;
        frame.warnings = warnings(scene, technique);
        Ok(frame)
    }

    /// [`Renderer::render_frame`] without its warnings.
    fn render_image(
        &mut self,
        scene: &Scene,
        technique: Technique,
        options: &RenderOptions,
        volumes: Option<&Volumes>,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Frame, RenderError> {
        if let Some(why) = scene.out_of_range() {
            return Err(RenderError::OutOfRange(why));
        }
        let pattern = options.pattern()?;
        if options.jitter && !technique.takes_samples() {
            return Err(RenderError::NoSamples { technique });
        }
        let (width, height) = (scene.camera.width, scene.camera.height);
        let mut on_gpu = self.uses_gpu(technique)?;
        // The GPU's depth-complexity sampling takes the multi-jittered pattern up to
        // MAX_SAMPLES; under `auto` the CPU renders the others.
        let gpu_samples = !options.jitter && options.samples <= MAX_GPU_SAMPLES as usize;
        if on_gpu && technique == Technique::DepthComplexity && !gpu_samples {
            if self.backend == Backend::Auto {
                on_gpu = false;
            } else {
                return Err(RenderError::GpuSamples {
                    samples: options.samples,
                    jitter: options.jitter,
                    max: MAX_GPU_SAMPLES,
                });
            }
        }
        // On a software adapter (lavapipe) depth-complexity sampling takes 18 to 22 times the
        // CPU renderer's time (docs/benchmarks.md): under `auto` the CPU renders it.
        let software =
            on_gpu && self.opened().info.device_type == penumbra_gpu::wgpu::DeviceType::Cpu;
        let mut cpu_note = None;
        if software && technique == Technique::DepthComplexity && self.backend == Backend::Auto {
            on_gpu = false;
            cpu_note = Some(format!(
                "{} is a software adapter, on which the CPU renders depth-complexity faster",
                self.opened().describe()
            ));
        }
        if on_gpu {
            let ctx = self.opened();
            let limit = ctx.device.limits().max_texture_dimension_2d;
            if width > limit || height > limit {
                // Under `auto` a technique the CPU also renders goes there.
                if self.backend == Backend::Auto && Runs::of(technique) != Runs::GpuOnly {
                    on_gpu = false;
                } else {
                    return Err(RenderError::TooLarge {
                        width,
                        height,
                        why: format!(
                            "the GPU's textures are at most {limit} pixels on a side ({}){}",
                            ctx.describe(),
                            if Runs::of(technique) == Runs::GpuOnly {
                                ""
                            } else {
                                "; --backend cpu renders it"
                            }
                        ),
                    });
                }
            }
        }
        // The GPU blends one silhouette after the other, a few passes each; with thousands of
        // them over few pixels the CPU, whose cost grows with the silhouettes covering each
        // pixel, is far quicker, and under `auto` it renders them.
        let mut built = None;
        if volumes.is_none() && on_gpu && technique.is_volume() {
            built = Some(Volumes::build(scene));
        }
        if on_gpu
            && self.backend == Backend::Auto
            && technique == Technique::WedgesBlend
            && volumes
                .or(built.as_ref())
                .is_some_and(|v| v.unit_count() > MAX_GPU_BLEND_UNITS)
        {
            on_gpu = false;
            built = None;
        }
        let volumes = volumes.or(built.as_ref());
        check_memory(
            width,
            height,
            if on_gpu {
                GPU_BYTES_PER_PIXEL
            } else {
                CPU_BYTES_PER_PIXEL
            },
        )?;
        if on_gpu {
            let ctx = GpuContext::clone(self.opened());
            let (image, times) = if technique.is_shadow_map() {
                let i = match self
                    .shadow_maps
                    .iter()
                    .position(|r| r.technique() == technique)
                {
                    Some(i) => i,
                    None => {
                        self.shadow_maps
                            .push(ShadowMapRenderer::new(&ctx, technique));
                        self.shadow_maps.len() - 1
                    }
                };
                self.shadow_maps[i].render_timed(scene)?
            } else if technique == Technique::DepthComplexity {
                let r = self
                    .volumes
                    .get_or_insert_with(|| GpuRenderer::with_context(&ctx));
                let out = match r.render_depth_complexity(scene, options.samples as u32) {
                    // A software device that would cut pixels short, or buffers beyond the
                    // device's: under `auto`, the CPU renders it.
                    Err(GpuError::CutShort(why) | GpuError::TooLarge(why))
                        if self.backend == Backend::Auto =>
                    {
                        let mut frame = render_cpu(scene, technique, pattern, progress);
                        frame.detail = format!("{} ({why})", frame.detail);
                        return Ok(frame);
                    }
                    other => other?,
                };
                return Ok(Frame {
                    warnings: Vec::new(),
                    image: out.image,
                    times: out.times,
                    detail: format!(
                        "gpu: {}, {} multi-jittered samples, {} potential silhouette edges of {}, \
                         {} edge-list entries",
                        ctx.describe(),
                        options.samples,
                        out.potential_edges,
                        out.all_edges,
                        out.list_entries
                    ),
                });
            } else {
                let r = self
                    .volumes
                    .get_or_insert_with(|| GpuRenderer::with_context(&ctx));
                let volumes = volumes.expect("built above for a volume technique on the GPU");
                r.render_timed(scene, volumes, technique)?
            };
            return Ok(Frame {
                warnings: Vec::new(),
                image,
                times,
                detail: format!("gpu: {}", ctx.describe()),
            });
        }
        let mut frame = render_cpu(scene, technique, pattern, progress);
        if let Some(note) = cpu_note {
            frame.detail = format!("{}; {note}", frame.detail);
        }
        Ok(frame)
    }
}

/// The warnings of a frame of `technique`: each mesh whose cut by the light's plane holds the
/// light's centre, for the techniques built from the light's centre (hard, wedges, shadow
/// maps).
fn warnings(scene: &Scene, technique: Technique) -> Vec<String> {
    if !(technique.is_volume() || technique.is_shadow_map()) {
        return Vec::new();
    }
    scene
        .meshes
        .iter()
        .enumerate()
        .filter(|(_, m)| {
            penumbra_volumes::encloses_light_centre(
                &m.mesh.positions,
                &m.mesh.triangles,
                &scene.light,
            )
        })
        .map(|(i, m)| {
            format!(
                "mesh {i} ({}) holds the light's centre where the light's plane cuts it: {technique} \
                 builds its shadow from that centre and cannot be right here (see docs/accuracy.md); \
                 depth-complexity is exact there for its samples",
                m.source.display()
            )
        })
        .collect()
}

/// Most light samples per pixel of depth-complexity sampling on the GPU.
pub const MAX_GPU_SAMPLES: u32 = penumbra_gpu::constants::MAX_SAMPLES;

/// Most blending units (caster patches, [`Volumes::unit_count`]) of a `wedges-blend` scene that
/// `--backend auto` renders on the GPU; beyond, it renders on the CPU.
pub const MAX_GPU_BLEND_UNITS: usize = 1024;

/// Bytes per pixel a CPU render holds: V (4) and the row buffers around it, with room.
const CPU_BYTES_PER_PIXEL: u64 = 16;

/// Bytes per pixel a GPU render holds on the device and in the readback: depth-stencil (8),
/// positions (16), normals (8), V (4), the silhouette buffer (56), the final buffer (8), the
/// readback (4) and V on the CPU (4), with room.
const GPU_BYTES_PER_PIXEL: u64 = 128;

/// Refuses an image of `width x height` pixels at `per_pixel` bytes each that would not fit the
/// memory available ([`penumbra_geom::available_memory`]), before anything is allocated.
fn check_memory(width: u32, height: u32, per_pixel: u64) -> Result<(), RenderError> {
    let needed = width as u64 * height as u64 * per_pixel;
    let available = penumbra_geom::available_memory();
    match available {
        Some(a) if needed > a => Err(RenderError::TooLarge {
            width,
            height,
            why: format!(
                "it needs about {:.1} GB and {:.1} GB of memory are available",
                needed as f64 / 1e9,
                a as f64 / 1e9
            ),
        }),
        _ => Ok(()),
    }
}

/// Renders a technique that runs on the CPU.
fn render_cpu(
    scene: &Scene,
    technique: Technique,
    pattern: SamplePattern,
    progress: &(dyn Fn(u64) + Sync),
) -> Frame {
    let (image, detail) = match technique {
        Technique::Reference | Technique::HardReference => {
            let (samples, detail) = match technique {
                Technique::Reference => (
                    LightSamples::Stratified {
                        per_axis: pattern.per_axis,
                    },
                    format!("cpu, {} samples", pattern.per_axis * pattern.per_axis),
                ),
                _ => (LightSamples::Centre, "cpu".to_string()),
            };
            (Reference::new(scene).render(samples, progress), detail)
        }
        Technique::DepthComplexity => {
            let r = DepthComplexity::new(scene);
            let detail = format!(
                "cpu, {} {} samples, {} potential silhouette edges of {}",
                pattern.per_axis * pattern.per_axis,
                if pattern.jitter {
                    "jittered"
                } else {
                    "multi-jittered"
                },
                r.edges.edges.len(),
                r.edges.all_edges
            );
            (r.render(pattern, progress), detail)
        }
        _ => {
            let r = CpuRenderer::new(scene);
            let detail = format!("cpu, {} wedges", r.volumes.wedges.len());
            (r.render(technique, progress), detail)
        }
    };
    Frame {
        image,
        times: None,
        detail,
        warnings: Vec::new(),
    }
}
