//! Where a render runs: the one policy [`crate::Renderer`] consults for each render, given the
//! technique, the back end asked for, the options, the image's size and what the machine offers
//! (a GPU, found or not, with its limits; the scene's blending units; the memory available).
//!
//! The rules, in the order they apply:
//!
//! 1. The technique: the shadow-map techniques run on a GPU only, the references on the CPU
//!    only; the others (`hard`, `wedges`, `wedges-blend`, `depth-complexity`) on either.
//! 2. The back end: [`Backend::Cpu`] and [`Backend::Gpu`] are obeyed or the render is refused;
//!    [`Backend::Auto`] takes the GPU where one opens, except for `depth-complexity`, which it
//!    renders on the CPU without opening one: the CPU renderer is faster than the GPU's
//!    counting pass on every device measured, lavapipe and an NVIDIA H200 alike
//!    (`docs/benchmarks.md`).
//! 3. Under [`Backend::Auto`], the CPU renders what the GPU cannot or renders slowly: an image
//!    wider than the GPU's textures, `wedges-blend` with more than [`MAX_GPU_BLEND_UNITS`]
//!    blending units, a triangle wider than [`MAX_GPU_EXTENT_RATIO`] times the eye's distance
//!    to the light's centre ([`extent_ratio`]: the GPU's 32-bit floats misplace shadows
//!    beyond). Under [`Backend::Gpu`] the first is refused, as are more depth-complexity
//!    samples than [`MAX_GPU_SAMPLES`] or jittered ones, and the last renders on the GPU with a
//!    warning ([`crate::Warning::GpuExtent`]).
//! 4. An image the memory available would not hold is refused, before anything is allocated.

use std::fmt;

use penumbra_geom::{LitScene, Technique};

use crate::error::{MissingGpu, RenderError};
use crate::options::RenderOptions;
use crate::runs::Runs;

/// Where the techniques that run on both the GPU and the CPU (`hard`, `wedges`,
/// `wedges-blend`, `depth-complexity`) run. The shadow-map techniques always need a GPU; the
/// references always run on the CPU.
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

/// Most light samples per pixel of depth-complexity sampling on the GPU.
pub const MAX_GPU_SAMPLES: u32 = penumbra_gpu::MAX_SAMPLES;

/// Most blending units (caster patches, [`penumbra_volumes::Volumes::unit_count`]) of a
/// `wedges-blend` scene that [`Backend::Auto`] renders on the GPU; beyond, it renders on the
/// CPU. The GPU blends one silhouette after the other, a few passes each; with thousands of them
/// over few pixels the CPU, whose cost grows with the silhouettes covering each pixel, is far
/// quicker.
pub const MAX_GPU_BLEND_UNITS: usize = 1024;

/// The widest triangle, against the eye's distance to the light's centre, up to which the
/// GPU renders `hard`, `wedges`, `wedges-blend` and `depth-complexity` under [`Backend::Auto`].
/// Measured on a 10-unit scene over one huge triangle, 7.3 from the light: at 1.9e4 (the
/// triangle 1e5 wide) the GPU renders as the CPU does; at 1.9e5, 0.3% of the hard shadow's
/// pixels are wrong, at 1.9e6 3.4% (`docs/scene-format.md`, "Supported range").
pub const MAX_GPU_EXTENT_RATIO: f64 = 5e4;

/// The widest triangle of `scene` (the diagonal of its bounding box) against the distance from
/// the eye to the light's centre: where it passes [`MAX_GPU_EXTENT_RATIO`], the GPU's 32-bit
/// floats misplace shadows.
///
/// ```
/// use penumbra::backend::extent_ratio;
///
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/scenes/quad-over-plane.toml");
/// let scene = penumbra::Scene::load(std::path::Path::new(path))?;
/// // A 20 x 20 ground seen from about 7 units from the light.
/// assert!((extent_ratio(&scene.lit(0)) - 28.28 / 7.28).abs() < 0.01);
/// # Ok::<(), penumbra::SceneError>(())
/// ```
pub fn extent_ratio(scene: &LitScene) -> f64 {
    let widest = scene
        .meshes
        .iter()
        .flat_map(|m| {
            let p = &m.mesh.positions;
            m.mesh.triangles.iter().map(move |t| {
                let [a, b, c] = t.map(|i| p[i as usize]);
                (a.max(b).max(c) - a.min(b).min(c)).length()
            })
        })
        .fold(0.0, f64::max);
    let distance = (scene.light.center - scene.camera.eye).length();
    if distance > 0.0 {
        widest / distance
    } else {
        f64::INFINITY
    }
}

/// Bytes per pixel a CPU render holds: V (4) and the row buffers around it, with room.
const CPU_BYTES_PER_PIXEL: u64 = 16;

/// Bytes per pixel a GPU render holds on the device and in the readback: depth-stencil (8),
/// positions (16), normals (8), V (4), the silhouette buffer (40), the final buffer (24), the
/// readback (4) and V on the CPU (4), with room. Depth-complexity sampling holds its receiver
/// candidates (8) in place of the silhouette and final buffers, and its counting pass's buffer
/// besides ([`gpu_bytes`]).
const GPU_BYTES_PER_PIXEL: u64 = 128;

/// Bytes a GPU render of `technique` at `width x height` holds: [`GPU_BYTES_PER_PIXEL`] per
/// pixel, and for depth-complexity sampling at `samples` samples the counting pass's buffer
/// (V, and each pixel's state and counts, bounded by one storage binding of `max_binding`
/// bytes: [`penumbra_gpu::count_buffer_bytes`], the figure its allocation uses). A frame whose
/// buffer would not fit one binding is refused by the GPU before it allocates it
/// ([`penumbra_gpu::GpuError::TooLarge`]), and adds nothing here.
fn gpu_bytes(
    technique: Technique,
    (width, height): (u32, u32),
    samples: usize,
    max_binding: u64,
) -> u64 {
    let targets = width as u64 * height as u64 * GPU_BYTES_PER_PIXEL;
    if technique != Technique::DepthComplexity {
        return targets;
    }
    let samples = u32::try_from(samples).unwrap_or(u32::MAX);
    targets + penumbra_gpu::count_buffer_bytes((width, height), samples, max_binding).unwrap_or(0)
}

/// The processor a render runs on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Placement {
    /// The GPU.
    Gpu,
    /// The CPU.
    Cpu,
}

/// Why the policy placed a render where it did.
#[derive(Clone, Debug)]
pub enum Reason {
    /// The back end asked for (under [`Backend::Auto`], the GPU found) renders it.
    Chosen,
    /// Only a GPU renders the technique (the shadow maps).
    GpuOnlyTechnique,
    /// Only the CPU renders the technique (the references).
    CpuOnlyTechnique,
    /// Under [`Backend::Auto`]: no GPU.
    NoGpu {
        /// Why there is none.
        missing: MissingGpu,
    },
    /// Under [`Backend::Auto`]: depth-complexity sampling, which the CPU renders faster than
    /// the GPU's counting pass (`docs/benchmarks.md`: on lavapipe the pass takes 19 to 28 times
    /// the CPU renderer's frame; an NVIDIA H200's frame is 2 to 3 times the CPU renderer's on
    /// a 2-core machine, and its render of a 209,388-triangle scene 12 times).
    CountingOnCpu,
    /// Under [`Backend::Auto`]: an image wider or taller than the GPU's textures.
    TooLargeForGpu {
        /// The GPU's largest texture side.
        max_side: u32,
    },
    /// Under [`Backend::Auto`]: `wedges-blend` with more blending units than
    /// [`MAX_GPU_BLEND_UNITS`].
    ManyBlendUnits {
        /// The scene's blending units.
        units: usize,
    },
    /// Under [`Backend::Auto`]: a triangle wider than [`MAX_GPU_EXTENT_RATIO`] times the
    /// eye's distance to the light's centre.
    WideTriangle {
        /// [`extent_ratio`] of the scene.
        ratio: f64,
    },
}

impl fmt::Display for Reason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Reason::Chosen => f.write_str("the back end chosen"),
            Reason::GpuOnlyTechnique => f.write_str("a shadow-map technique runs on a GPU only"),
            Reason::CpuOnlyTechnique => f.write_str("the references run on the CPU only"),
            Reason::NoGpu { missing } => write!(f, "no GPU: {missing}"),
            Reason::CountingOnCpu => {
                f.write_str("the CPU renders depth-complexity faster than a GPU's counting pass")
            }
            Reason::TooLargeForGpu { max_side } => write!(
                f,
                "the GPU's textures are at most {max_side} pixels on a side"
            ),
            Reason::ManyBlendUnits { units } => write!(
                f,
                "{units} blending units, more than the GPU blends quickly ({MAX_GPU_BLEND_UNITS})"
            ),
            Reason::WideTriangle { ratio } => write!(
                f,
                "a triangle {ratio:.1e} times as wide as the eye is far from the light, more than \
                 the GPU's 32-bit floats hold ({MAX_GPU_EXTENT_RATIO:.0e})"
            ),
        }
    }
}

/// What the policy decided for one render.
#[derive(Clone, Debug)]
pub struct Choice {
    /// Where it runs.
    pub placement: Placement,
    /// Why there.
    pub reason: Reason,
}

/// What a render asks of the policy.
#[derive(Clone, Copy, Debug)]
pub struct Request<'a> {
    /// The technique.
    pub technique: Technique,
    /// The back end asked for.
    pub backend: Backend,
    /// The options.
    pub options: &'a RenderOptions,
    /// The image's width in pixels.
    pub width: u32,
    /// The image's height in pixels.
    pub height: u32,
}

/// What an open GPU offers a render.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GpuOffer {
    /// The adapter's description (`GpuContext::describe`).
    pub adapter: String,
    /// The largest texture side it takes.
    pub max_texture_side: u32,
    /// The most bytes one storage binding holds ([`penumbra_gpu::storage_binding_limit`]):
    /// what bounds the buffer of depth-complexity's counting pass.
    pub max_storage_binding: u64,
}

/// What the machine offers the policy, each looked at only when a rule needs it.
pub trait Machine {
    /// The GPU, opened on first call; why there is none otherwise.
    fn gpu(&mut self) -> Result<GpuOffer, MissingGpu>;
    /// The scene's blending units ([`penumbra_volumes::Volumes::unit_count`]).
    fn blend_units(&mut self) -> usize;
    /// [`extent_ratio`] of the scene.
    fn extent_ratio(&mut self) -> f64;
    /// The bytes this process can still allocate, where known
    /// ([`penumbra_geom::available_memory`]).
    fn available_memory(&mut self) -> Option<u64>;
}

/// Whether `technique` can run under `backend` at all, by the first two rules, without looking
/// for a GPU: a shadow-map technique not on the CPU back end, a reference not on the GPU one.
///
/// ```
/// use penumbra::backend::check;
/// use penumbra::{Backend, Technique};
///
/// assert!(check(Technique::Pcss, Backend::Auto).is_ok());
/// assert!(check(Technique::Pcss, Backend::Cpu).is_err());
/// assert!(check(Technique::Reference, Backend::Gpu).is_err());
/// ```
pub fn check(technique: Technique, backend: Backend) -> Result<(), RenderError> {
    match (Runs::of(technique), backend) {
        (Runs::GpuOnly, Backend::Cpu) => Err(RenderError::NeedsGpu {
            technique,
            missing: MissingGpu::CpuChosen,
        }),
        (Runs::CpuOnly, Backend::Gpu) => Err(RenderError::CpuOnly { technique }),
        _ => Ok(()),
    }
}

/// Where `technique` runs under `backend` by the first two rules (the technique, the back end),
/// opening the GPU if it may use one; an error where it cannot run at all.
pub(crate) fn place_technique(
    technique: Technique,
    backend: Backend,
    gpu: &mut dyn FnMut() -> Result<GpuOffer, MissingGpu>,
) -> Result<(Placement, Reason, Option<GpuOffer>), RenderError> {
    check(technique, backend)?;
    match (Runs::of(technique), backend) {
        (Runs::GpuOnly, _) => match gpu() {
            Ok(offer) => Ok((Placement::Gpu, Reason::GpuOnlyTechnique, Some(offer))),
            Err(missing) => Err(RenderError::NeedsGpu { technique, missing }),
        },
        (Runs::CpuOnly, _) => Ok((Placement::Cpu, Reason::CpuOnlyTechnique, None)),
        (Runs::Either, Backend::Cpu) => Ok((Placement::Cpu, Reason::Chosen, None)),
        (Runs::Either, Backend::Auto) if technique == Technique::DepthComplexity => {
            Ok((Placement::Cpu, Reason::CountingOnCpu, None))
        }
        (Runs::Either, Backend::Auto) => match gpu() {
            Ok(offer) => Ok((Placement::Gpu, Reason::Chosen, Some(offer))),
            Err(missing) => Ok((Placement::Cpu, Reason::NoGpu { missing }, None)),
        },
        (Runs::Either, Backend::Gpu) => match gpu() {
            Ok(offer) => Ok((Placement::Gpu, Reason::Chosen, Some(offer))),
            Err(missing) => Err(RenderError::NoGpu { missing }),
        },
    }
}

/// Where the render `request` asks for runs, and why; an error where it cannot run. The rules
/// are the module's.
pub fn choose(request: &Request, machine: &mut dyn Machine) -> Result<Choice, RenderError> {
    let Request {
        technique,
        backend,
        width,
        height,
        ..
    } = *request;
    let (mut placement, mut reason, offer) =
        place_technique(technique, backend, &mut || machine.gpu())?;
    let mut max_binding = 0;
    if let Some(offer) = offer {
        max_binding = offer.max_storage_binding;
        if let Some(why) = gpu_limits(request, offer, machine)? {
            placement = Placement::Cpu;
            reason = why;
        }
    }
    let needed = match placement {
        Placement::Gpu => gpu_bytes(
            technique,
            (width, height),
            request.options.samples,
            max_binding,
        ),
        Placement::Cpu => width as u64 * height as u64 * CPU_BYTES_PER_PIXEL,
    };
    if let Some(available) = machine.available_memory().filter(|&a| needed > a) {
        return Err(RenderError::OutOfMemory {
            width,
            height,
            needed,
            available,
        });
    }
    Ok(Choice { placement, reason })
}

/// The third rule, for a render the first two placed on the GPU that `offer` describes: why the
/// CPU renders it instead (under [`Backend::Auto`]), `None` where the GPU does, or an error.
fn gpu_limits(
    request: &Request,
    offer: GpuOffer,
    machine: &mut dyn Machine,
) -> Result<Option<Reason>, RenderError> {
    let Request {
        technique,
        backend,
        options,
        width,
        height,
    } = *request;
    let auto = backend == Backend::Auto;
    // Under Auto the first two rules placed depth-complexity on the CPU.
    let counting = technique == Technique::DepthComplexity;
    if counting && (options.jitter || options.samples > MAX_GPU_SAMPLES as usize) {
        return Err(RenderError::GpuSamples {
            samples: options.samples,
            jitter: options.jitter,
            max: MAX_GPU_SAMPLES,
        });
    }
    let max_side = offer.max_texture_side;
    if width > max_side || height > max_side {
        if !auto || Runs::of(technique) == Runs::GpuOnly {
            return Err(RenderError::TooLargeForGpu {
                technique,
                width,
                height,
                max_side,
                adapter: offer.adapter,
            });
        }
        return Ok(Some(Reason::TooLargeForGpu { max_side }));
    }
    if auto && technique == Technique::WedgesBlend {
        let units = machine.blend_units();
        if units > MAX_GPU_BLEND_UNITS {
            return Ok(Some(Reason::ManyBlendUnits { units }));
        }
    }
    if auto && Runs::of(technique) == Runs::Either {
        let ratio = machine.extent_ratio();
        if ratio > MAX_GPU_EXTENT_RATIO {
            return Ok(Some(Reason::WideTriangle { ratio }));
        }
    }
    Ok(None)
}
