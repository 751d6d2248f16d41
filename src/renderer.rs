//! The front door: one renderer for every technique, placed on the GPU or the CPU by the
//! back-end policy ([`crate::backend`]), with each back end's renderers built once and kept.

use std::sync::Arc;

use penumbra_geom::{Channel, ImageError, ShadedImage, VisibilityChannels, VisibilityImage};
use penumbra_geom::{Interruption, LitScene, RangeError, Scene, Technique, TracerGeometry};
use penumbra_gpu::{GpuContext, GpuRenderer, Rendered, ShadowMapRenderer};
use penumbra_volumes::SunSeries;
use penumbra_volumes::Volumes;

use crate::backend::{self, Backend, GpuOffer, Machine, Placement, Reason, Request};
use crate::error::{MissingGpu, RenderError};
use crate::options::RenderOptions;
use crate::rendered_frame::{self, Frame};
use crate::runs::Runs;

/// Whether the GPU has been looked for yet, and what was found.
enum GpuState {
    Untried,
    Ready(Box<GpuContext>),
    Unavailable(MissingGpu),
}

impl GpuState {
    /// The GPU context, opened on first use; why there is none otherwise.
    fn open(&mut self) -> Result<&GpuContext, MissingGpu> {
        if let GpuState::Untried = self {
            *self = match GpuContext::new() {
                Ok(ctx) => GpuState::Ready(Box::new(ctx)),
                Err(error) => GpuState::Unavailable(MissingGpu::Unavailable {
                    error: Arc::new(error),
                }),
            };
        }
        match self {
            GpuState::Ready(ctx) => Ok(ctx),
            GpuState::Unavailable(missing) => Err(missing.clone()),
            GpuState::Untried => unreachable!("looked for above"),
        }
    }

    /// What the GPU offers the back-end policy, opened on first use.
    fn offer(&mut self) -> Result<GpuOffer, MissingGpu> {
        let ctx = self.open()?;
        Ok(GpuOffer {
            adapter: ctx.describe(),
            max_texture_side: ctx.device.limits().max_texture_dimension_2d,
            max_storage_binding: penumbra_gpu::storage_binding_limit(&ctx.device.limits()),
        })
    }
}

/// What the machine offers one render of `scene`: the GPU, the scene's volumes (the caller's,
/// or built here on first ask and kept for the GPU's render), its extent ratio (measured on
/// first ask and kept for the frame's warnings), the memory.
struct Offers<'a> {
    gpu: &'a mut GpuState,
    scene: &'a LitScene,
    volumes: Option<&'a Volumes>,
    built: &'a mut Option<Volumes>,
    extent: &'a mut Option<f64>,
}

impl Machine for Offers<'_> {
    fn gpu(&mut self) -> Result<GpuOffer, MissingGpu> {
        self.gpu.offer()
    }

    fn blend_units(&mut self) -> usize {
        match self.volumes {
            Some(v) => v.unit_count(),
            None => self
                .built
                .get_or_insert_with(|| Volumes::build(self.scene))
                .unit_count(),
        }
    }

    fn extent_ratio(&mut self) -> f64 {
        *self
            .extent
            .get_or_insert_with(|| backend::extent_ratio(self.scene))
    }

    fn available_memory(&mut self) -> Option<u64> {
        penumbra_geom::available_memory()
    }
}

/// Renders scenes with any [`Technique`], keeping its GPU context and GPU renderers from one
/// render to the next. The GPU is looked for the first time a technique could use it.
///
/// On the CPU it keeps the last render's ray-casting hierarchy, which depends on the triangles
/// alone: the next render of the same triangles (another light of the scene, another camera,
/// another technique casting as many rays) takes it instead of building it again, with the
/// same image. Until then it holds that hierarchy's memory ([`Renderer::release_kept`]).
///
/// ```
/// use penumbra::{Backend, RenderOptions, Renderer, Scene, Technique};
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
    counters: bool,
    wedge_pass: Option<penumbra_gpu::WedgePass>,
    /// The last CPU render's ray-casting hierarchy, for the next one over the same triangles.
    pub(crate) kept: Option<TracerGeometry>,
    /// The last sun study's shared state ([`SunSeries`]), for the next study of the same meshes
    /// and camera.
    pub(crate) series: Option<SunSeries>,
}

impl Renderer {
    /// A renderer choosing the GPU or the CPU by `backend`.
    pub fn new(backend: Backend) -> Self {
        Renderer {
            backend,
            gpu: GpuState::Untried,
            volumes: None,
            shadow_maps: Vec::new(),
            counters: false,
            wedge_pass: None,
            kept: None,
            series: None,
        }
    }

    /// Whether the GPU frames of [`Renderer::render_frame`] count what each pass does
    /// ([`Frame::counters`]): its shaders' invocations where the device has pipeline-statistics
    /// queries, and the bytes it binds. Off by default.
    pub fn set_counters(&mut self, on: bool) {
        self.counters = on;
    }

    /// How `wedges` and `wedges-blend` evaluate their wedges on the GPU; `None` (the default):
    /// the faster on the device (`penumbra::gpu::WedgePass::for_device`: rasterised on a CPU
    /// device such as lavapipe, tiled on a GPU). The images are the same, bit for bit for
    /// `wedges` and within rounding for `wedges-blend`.
    pub fn set_wedge_pass(&mut self, pass: Option<penumbra_gpu::WedgePass>) {
        self.wedge_pass = pass;
    }

    /// A renderer on the caller's device, for the techniques that can use it.
    pub fn with_context(ctx: GpuContext) -> Self {
        Renderer {
            gpu: GpuState::Ready(Box::new(ctx)),
            ..Renderer::new(Backend::Gpu)
        }
    }

    /// Drops the ray-casting hierarchy kept from the last CPU render and what the last sun
    /// study kept, and their memory: the next CPU render builds its own, and costs what a
    /// render of a renderer of its own does.
    pub fn release_kept(&mut self) {
        self.kept = None;
        self.series = None;
    }

    /// The shaded preview of `scene` from its lights' visibility images
    /// ([`ShadedImage::render`]), taking the ray-casting hierarchy the last CPU render kept where
    /// it serves (the same triangles, cast for few rays: a volume technique's), and keeping the
    /// one it builds otherwise.
    pub fn shaded(
        &mut self,
        scene: &Scene,
        images: &VisibilityChannels,
    ) -> Result<ShadedImage, ImageError> {
        ShadedImage::render_reusing(scene, images, &mut self.kept)
    }

    /// The GPU's description, once one has been opened.
    pub fn gpu_description(&self) -> Option<String> {
        match &self.gpu {
            GpuState::Ready(ctx) => Some(ctx.describe()),
            _ => None,
        }
    }

    /// Whether `technique` runs on the GPU with this renderer's back end (opening it if need
    /// be), or an error where it cannot run at all: the first two rules of the back-end policy
    /// ([`crate::backend`]), before the options and the scene have their say.
    pub fn uses_gpu(&mut self, technique: Technique) -> Result<bool, RenderError> {
        let (placement, _, _) =
            backend::place_technique(technique, self.backend, &mut || self.gpu.offer())?;
        Ok(placement == Placement::Gpu)
    }

    /// The visibility image of `scene` by `technique` under its first light
    /// ([`Renderer::render_lights`] renders each); refused for a scene without a light.
    pub fn render(
        &mut self,
        scene: &Scene,
        technique: Technique,
        options: &RenderOptions,
    ) -> Result<VisibilityImage, RenderError> {
        if scene.lights.is_empty() {
            return Err(RenderError::OutOfRange {
                problem: RangeError::NoLights,
            });
        }
        self.render_lit(&scene.lit(0), technique, options)
    }

    /// The visibility image of one light's view of a scene ([`Scene::lit`]) by `technique`.
    pub fn render_lit(
        &mut self,
        scene: &LitScene,
        technique: Technique,
        options: &RenderOptions,
    ) -> Result<VisibilityImage, RenderError> {
        Ok(self
            .render_frame(scene, technique, options, None, &|_| {})?
            .image)
    }

    /// The visibility image of each of `scene`'s lights by `technique`, in the scene's order:
    /// the one channel `V` of a scene of one light, or a channel `<name>.V` for each of
    /// [`Scene::lights`], the image [`Renderer::render`] makes of [`Scene::for_light`] (the
    /// lights are rendered one after the other, the GPU renderers kept between them).
    ///
    /// ```
    /// use penumbra::{Backend, RenderOptions, Renderer, Scene, Technique};
    ///
    /// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/scenes/two-lights.toml");
    /// let scene = Scene::load(std::path::Path::new(path))?;
    /// let mut renderer = Renderer::new(Backend::Cpu);
    /// let v = renderer.render_lights(&scene, Technique::Hard, &RenderOptions::default())?;
    /// assert_eq!(v.names(), ["key.V", "fill.V"]);
    /// let fill = renderer.render(&scene.for_light(1), Technique::Hard, &RenderOptions::default())?;
    /// assert_eq!(v.get("fill.V"), Some(&fill));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn render_lights(
        &mut self,
        scene: &Scene,
        technique: Technique,
        options: &RenderOptions,
    ) -> Result<VisibilityChannels, RenderError> {
        if scene.lights.is_empty() {
            return Err(RenderError::OutOfRange {
                problem: RangeError::NoLights,
            });
        }
        penumbra_geom::check_light_names(&scene.lights)
            .map_err(|error| RenderError::BadLights { error })?;
        let mut channels = Vec::with_capacity(scene.lights.len());
        for (k, name) in scene.channel_names().into_iter().enumerate() {
            let image = self.render_lit(&scene.lit(k), technique, options)?;
            channels.push(Channel { name, image });
        }
        Ok(VisibilityChannels::new(channels)
            .expect("valid, unique light names and one camera make valid channels"))
    }

    /// [`Renderer::render_lit`] with the GPU pass times and a description of the run. A volume
    /// technique on the GPU takes the scene's silhouettes, volumes and wedges from `volumes`
    /// when given (so that several frames build them once), and builds them otherwise. The CPU
    /// renderers call `progress` with the number of image rows finished so far.
    pub fn render_frame(
        &mut self,
        scene: &LitScene,
        technique: Technique,
        options: &RenderOptions,
        volumes: Option<&Volumes>,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Frame, RenderError> {
        if let Some(problem) = scene.out_of_range() {
            return Err(RenderError::OutOfRange { problem });
        }
        let pattern = options.pattern_for(technique)?;
        let stop = Interruption::since();
        // Only the techniques built from the light's centre look at lamps shut in meshes.
        let sealing = if technique.is_volume() || Runs::of(technique) == Runs::GpuOnly {
            rendered_frame::sealing_meshes(scene)
        } else {
            Vec::new()
        };
        if technique == Technique::Hard && !sealing.is_empty() {
            // Every point in view is outside a closed mesh the light's centre is shut in: the
            // hard shadow is the hard reference's, one ray a pixel.
            let mut frame = crate::cpu::render(
                scene,
                Technique::HardReference,
                pattern,
                progress,
                &mut self.kept,
            );
            frame.detail = format!(
                "{}: the hard reference, the light's centre being shut in mesh {} seen from outside",
                frame.detail, sealing[0]
            );
            if stop.happened() {
                return Err(RenderError::Interrupted);
            }
            return Ok(frame);
        }
        let request = Request {
            technique,
            backend: self.backend,
            options,
            width: scene.camera.width,
            height: scene.camera.height,
        };
        let (mut built, mut extent) = (None, None);
        let choice = backend::choose(
            &request,
            &mut Offers {
                gpu: &mut self.gpu,
                scene,
                volumes,
                built: &mut built,
                extent: &mut extent,
            },
        )?;
        let mut frame = match choice.placement {
            Placement::Gpu => {
                if volumes.is_none() && built.is_none() && technique.is_volume() {
                    built = Some(Volumes::build(scene));
                }
                let volumes = volumes.or(built.as_ref());
                self.render_gpu(scene, &request, volumes)?
            }
            Placement::Cpu => {
                let mut frame =
                    crate::cpu::render(scene, technique, pattern, progress, &mut self.kept);
                if let Reason::WideTriangle { .. } = choice.reason {
                    frame.detail = format!("{}; {}", frame.detail, choice.reason);
                }
                frame
            }
        };
        if stop.happened() {
            return Err(RenderError::Interrupted);
        }
        frame.warnings =
            rendered_frame::warnings(scene, technique, (choice.placement, &sealing), extent);
        Ok(frame)
    }

    /// Renders on the GPU the policy placed it on.
    fn render_gpu(
        &mut self,
        scene: &LitScene,
        request: &Request,
        volumes: Option<&Volumes>,
    ) -> Result<Frame, RenderError> {
        let (technique, options) = (request.technique, request.options);
        let ctx = match &self.gpu {
            GpuState::Ready(ctx) => GpuContext::clone(ctx),
            _ => unreachable!("the policy placed the render on an open GPU"),
        };
        let frame = |r: Rendered, detail| Frame {
            image: r.image,
            times: r.times,
            counters: r.counters,
            detail,
            warnings: Vec::new(),
        };
        if Runs::of(technique) == Runs::GpuOnly {
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
            self.shadow_maps[i].set_counters(self.counters);
            let rendered = self.shadow_maps[i].render_timed(scene)?;
            return Ok(frame(rendered, format!("gpu: {}", ctx.describe())));
        }
        let r = self
            .volumes
            .get_or_insert_with(|| GpuRenderer::with_context(&ctx));
        r.set_counters(self.counters);
        r.set_wedge_pass(self.wedge_pass);
        if technique == Technique::DepthComplexity {
            let out = r.render_depth_complexity(scene, options.samples as u32)?;
            let mut detail = format!(
                "gpu: {}, {} multi-jittered samples, {} potential silhouette edges of {}, \
                 {} edge-list entries",
                ctx.describe(),
                options.samples,
                out.potential_edges,
                out.all_edges,
                out.list_entries
            );
            if out.redone > 0 {
                detail += &format!(
                    ", rendered {} more time(s): the edge list overflowed",
                    out.redone
                );
            }
            let rendered = Rendered {
                image: out.image,
                times: out.times,
                counters: out.counters,
            };
            return Ok(frame(rendered, detail));
        }
        let volumes = volumes.expect("built above for a volume technique on the GPU");
        let rendered = r.render_timed(scene, volumes, technique)?;
        Ok(frame(rendered, format!("gpu: {}", ctx.describe())))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::RenderOptions;

    /// A CPU render keeps its hierarchy, a GPU-only technique's render leaves it, and
    /// [`Renderer::release_kept`] drops it.
    #[test]
    fn a_cpu_render_keeps_its_hierarchy_until_released() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/fixtures/scenes/quad-over-plane.toml"
        );
        let mut scene = Scene::load(std::path::Path::new(path)).unwrap();
        scene.camera.width = 16;
        scene.camera.height = 12;
        let options = RenderOptions {
            samples: 4,
            jitter: false,
        };
        let mut r = Renderer::new(Backend::Cpu);
        assert!(r.kept.is_none());
        r.render(&scene, Technique::Hard, &options).unwrap();
        let kept = r.kept.clone().expect("kept after a CPU render");
        assert!(kept.serves(&scene.triangles(), penumbra_geom::Rays::Few));
        assert!(r.render(&scene, Technique::Pcf, &options).is_err());
        assert!(r.kept.is_some());
        r.release_kept();
        assert!(r.kept.is_none());
    }
}
