//! The shadow-map techniques, one file each in the order of `docs/shadow-maps.md`: Reeves et
//! al.'s [`pcf`], Fernando's [`pcss`], Valient & de Boer's [`fractional_disk`], Pagot et al.'s
//! multiple-depth shadow maps ([`mdsm`]) and Cherry & Kooima's contact-hardening [`gaussian`];
//! on the same scenes and with the same `V` output as the volume techniques.
//!
//! A render takes the depth pre-pass (receivers' positions and normals), a light map from the
//! light's centre fitted to what can shadow the view ([`light_frustum`]), the technique's own
//! passes, and a full-screen pass writing V. What the techniques share is in [`inputs`] (the
//! uniforms, the casters) and [`resources`] (one render's resources, and the passes every
//! technique starts with).

mod fractional_disk;
mod gaussian;
mod inputs;
mod light_frustum;
mod mdsm;
mod pcf;
mod pcss;
mod pipelines;
mod probe;
mod resources;
mod windows;

use glam::DVec2;
use penumbra_geom::VisibilityImage;
use penumbra_geom::{LitScene, Technique};

use crate::context::{GpuContext, GpuError};
use crate::timing::{Rendered, read_frame};
pub use gaussian::multi_pass_kernel;
pub use inputs::ShadowUniforms;
use inputs::{TechniqueLanes, closed_first};
pub use light_frustum::{LightFrustum, MAX_SLOPE};
use pipelines::{ShadowPipelines, TechniquePasses};
use resources::{ShadowFrame, back_face_casters};
pub use windows::{CORE_SLOPE, Window, windows};

/// The pipelines of one shadow-map technique, built once per device; each
/// [`ShadowMapRenderer::render`] renders a scene with the parameters of its `params`.
pub struct ShadowMapRenderer {
    ctx: GpuContext,
    technique: Technique,
    pipelines: ShadowPipelines,
    counters: bool,
}

/// The shader and passes of `technique`.
fn technique_passes(technique: Technique) -> TechniquePasses {
    match technique {
        Technique::Pcf => pcf::PASSES,
        Technique::Pcss => pcss::PASSES,
        Technique::FractionalDisk => fractional_disk::PASSES,
        Technique::Mdsm => mdsm::PASSES,
        Technique::Gaussian => gaussian::PASSES,
        _ => unreachable!("a shadow-map technique, checked in new"),
    }
}

/// A frustum that no receiver falls in, for a scene with nothing in front of the light (every
/// receiver is then behind the light's plane, V = 0, or lit).
const EMPTY_FRUSTUM: LightFrustum = LightFrustum {
    lo: DVec2::splat(-1.0),
    hi: DVec2::splat(1.0),
    near: 1.0,
    z_min: 1.0,
    z_max: 2.0,
};

impl ShadowMapRenderer {
    /// Builds the pipelines of `technique` on `ctx`'s device.
    ///
    /// # Panics
    ///
    /// If `technique` is not a shadow-map technique ([`Technique::is_shadow_map`]).
    pub fn new(ctx: &GpuContext, technique: Technique) -> Self {
        assert!(
            technique.is_shadow_map(),
            "{technique} is not a shadow-map technique"
        );
        ShadowMapRenderer {
            pipelines: ShadowPipelines::new(&ctx.device, technique, technique_passes(technique)),
            ctx: ctx.clone(),
            technique,
            counters: false,
        }
    }

    /// Whether [`ShadowMapRenderer::render_timed`] counts what each pass does
    /// ([`crate::PassCounters`]); off by default.
    pub fn set_counters(&mut self, on: bool) {
        self.counters = on;
    }

    /// The technique these pipelines render.
    pub fn technique(&self) -> Technique {
        self.technique
    }

    /// The uniforms of the technique for `scene`, its light map fitted to `frustum`, with the
    /// parameters of `scene.params`.
    pub fn uniforms(&self, scene: &LitScene, frustum: &LightFrustum) -> ShadowUniforms {
        let params = &scene.params;
        let lanes: TechniqueLanes = match self.technique {
            Technique::Pcf => pcf::lanes(params),
            Technique::Pcss => pcss::lanes(params),
            Technique::FractionalDisk => fractional_disk::lanes(params),
            Technique::Mdsm => mdsm::lanes(params),
            Technique::Gaussian => gaussian::lanes(params, frustum),
            _ => unreachable!("a shadow-map technique, checked in new"),
        };
        ShadowUniforms::new(scene, frustum, params, lanes)
    }

    /// Renders V of `scene` with the parameters of `scene.params`.
    pub fn render(&self, scene: &LitScene) -> Result<VisibilityImage, GpuError> {
        Ok(self.render_timed(scene)?.image)
    }

    /// [`ShadowMapRenderer::render`], with the GPU time of each kind of pass when the device
    /// has timestamp queries (the light maps, the preprocessing passes, the filter passes, the
    /// read-out), and their counts when [`ShadowMapRenderer::set_counters`] turned them on.
    pub fn render_timed(&self, scene: &LitScene) -> Result<Rendered, GpuError> {
        let (world, closed) = closed_first(scene);
        let fit =
            LightFrustum::fit_view(&scene.light, &world, &scene.camera).unwrap_or(EMPTY_FRUSTUM);
        // One render per window of the light's directions, each receiver V from its own.
        let mut out: Option<Rendered> = None;
        for w in windows(&fit) {
            let mut base = self.uniforms(scene, &w.frustum);
            base.core = w.core;
            let r = self.render_window(scene, (&world, closed), base)?;
            out = Some(match out {
                None => r,
                Some(mut prev) => {
                    for (v, &n) in prev.image.data.iter_mut().zip(&r.image.data) {
                        if *v > NOT_MINE {
                            *v = n;
                        }
                    }
                    prev.times = prev.times.zip(r.times).map(|(a, b)| a.plus(&b));
                    prev
                }
            });
        }
        let mut r = out.expect("every frustum has a window");
        // Every slope lies in some window's core; a receiver in none would be lit.
        for v in &mut r.image.data {
            if *v > NOT_MINE {
                *v = 1.0;
            }
        }
        Ok(r)
    }

    /// Renders the receivers of one window of the light's directions (`base.core`), its map
    /// fitted to `base.frustum`; the others read above [`NOT_MINE`].
    fn render_window(
        &self,
        scene: &LitScene,
        (world, closed): (&[[glam::DVec3; 3]], usize),
        base: ShadowUniforms,
    ) -> Result<Rendered, GpuError> {
        let f = ShadowFrame::new(
            &self.ctx,
            &self.pipelines,
            scene,
            (world, closed),
            base,
            self.counters,
        );
        let mut enc = self.ctx.device.create_command_encoder(&Default::default());
        f.record_depth(&mut enc);
        // The light map: every triangle, or the back faces for fractional-disk.
        if self.technique == Technique::FractionalDisk {
            let casters = back_face_casters(scene, (world, closed));
            let buffer = f.vertex_buffer("light map triangles", &casters);
            f.record_light_map(&mut enc, (&buffer, casters.len() as u32), &f.map);
        } else {
            let buffer = f.vertex_buffer("light map triangles", &f.triangles);
            f.record_light_map(&mut enc, (&buffer, f.triangles.len() as u32), &f.map);
        }
        let mut keep = Vec::new();
        match self.technique {
            Technique::Pcf => pcf::record(&f, &mut enc),
            Technique::Pcss => pcss::record(&f, &mut enc),
            Technique::FractionalDisk => fractional_disk::record(&f, &mut enc),
            Technique::Mdsm => mdsm::record(&f, &mut enc),
            Technique::Gaussian => keep = gaussian::record(&f, &mut enc),
            _ => unreachable!("a shadow-map technique, checked in new"),
        }
        let frame = read_frame(&self.ctx, enc, &f.timer, &f.visibility);
        drop(keep);
        frame
    }
}

/// What a window's render writes where the receiver lies in another window's core (`NOT_MINE`
/// in `shadow.wgsl` is 2): any V above this is not its own.
const NOT_MINE: f32 = 1.5;
