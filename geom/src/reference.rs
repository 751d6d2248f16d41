//! The ray-cast visibility reference: the truth every technique is measured against.
//!
//! For a camera pixel, P is the first hit of its ray (all triangles, both sides). Then
//! `V(P) = (1/N) Σ_k vis(P, L_k)` over `N = n x n` stratified-jittered points `L_k` of the light
//! rectangle (one uniform point per cell of an `n x n` grid over `[-1, 1]^2`), drawn from a
//! per-pixel stream of a fixed seed, so that an image does not depend on thread scheduling.
//! `vis` is 1 when the open segment from P to `L_k` meets no triangle other than the one P lies
//! on. `V = 1` where the ray hits nothing; `V = 0` where P is not strictly on the emitting side.
//!
//! The segment is cast in `f32` from [`Tracer::epsilon`] past P to the light point (less
//! [`Tracer::touch`]: a triangle through the light's plane blocks the samples behind it up to
//! its crossing), so that P's rounding never makes it hit P's own surface. The triangles that pass within that
//! distance of P (its neighbours when P lies near an edge of its triangle, a surface it touches)
//! are tested again over the whole segment in `f64` from P itself, where only a crossing within
//! [`TOUCH_EPSILON`] of P counts as touching rather than crossing: so the segment's start
//! offset never lets light through a fold next to P, such as the terminator of a curved mesh.
//!
//! The hard reference uses the single point `L = light centre`: the hard shadow of a point light
//! there, which shadow volumes must reproduce.

use rayon::prelude::*;

use crate::camera::Camera;
use crate::image::VisibilityImage;
use crate::interrupt::Interruption;
use crate::lit_scene::LitScene;
use crate::raycast::Rays;
use crate::rng::Rng;
#[cfg(doc)]
use crate::tracer::TOUCH_EPSILON;
use crate::tracer::{Tracer, TracerGeometry};

/// Seed of the reference's light samples.
pub const REFERENCE_SEED: u64 = 0x005E_ED0F_5AD0;

/// Which light points the reference samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightSamples {
    /// `n x n` stratified-jittered light samples per pixel.
    Stratified {
        /// Samples per axis, `n`.
        per_axis: usize,
    },
    /// One sample at the light's centre: the hard shadow of a point light there.
    Centre,
}

/// The ray-cast reference renderer of one scene: its [`Tracer`] and its camera.
///
/// ```
/// use penumbra::glam::{DMat4, DVec2, DVec3};
/// use penumbra::geom::{Camera, LightSamples, RectLight, Reference, Scene, TriangleMesh};
///
/// let camera = Camera::look_at(DVec3::new(0.0, 4.0, 5.0), DVec3::ZERO, DVec3::Y, 45.0, 16, 12)?;
/// let light = RectLight::new(DVec3::new(0.0, 5.0, 0.0), DVec3::NEG_Y, DVec3::X, DVec2::splat(2.0)).unwrap();
/// let scene = Scene::new(camera).with_light(light)
///     .with_mesh("ball", &TriangleMesh::uv_sphere(8, 12), DMat4::from_translation(DVec3::Y));
/// let reference = Reference::new(&scene.lit(0));
/// let soft = reference.render(LightSamples::Stratified { per_axis: 4 }, &|_| {});
/// let hard = reference.render(LightSamples::Centre, &|_| {});
/// assert_eq!((soft.width, hard.height), (16, 12));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Reference {
    /// Ray casting.
    pub tracer: Tracer,
    /// The camera whose pixels are rendered.
    camera: Camera,
}

impl Reference {
    /// Builds the BVH of `scene` and keeps its camera.
    pub fn new(scene: &LitScene) -> Self {
        Self::new_reusing(scene, &mut None)
    }

    /// [`Reference::new`], taking the BVH from `kept` where it serves the scene, and keeping
    /// the one built in `kept` otherwise ([`Tracer::new_reusing`]).
    pub fn new_reusing(scene: &LitScene, kept: &mut Option<TracerGeometry>) -> Self {
        Reference {
            tracer: Tracer::new_reusing(scene, Rays::Many, kept),
            camera: scene.camera,
        }
    }

    /// Visibility of every camera pixel by ray casting through `samples`. `progress` is called
    /// with the number of rows finished so far, from any thread. An interruption
    /// ([`crate::Interrupter`]) stops it at the next pixel, the rest left at 1.
    pub fn render(
        &self,
        samples: LightSamples,
        progress: &(dyn Fn(u64) + Sync),
    ) -> VisibilityImage {
        let (cam, tracer) = (&self.camera, &self.tracer);
        let (w, h) = (cam.width, cam.height);
        let mut img = VisibilityImage::filled(w, h, 1.0);
        let done = std::sync::atomic::AtomicU64::new(0);
        let stop = Interruption::since();
        img.data
            .par_chunks_mut(w as usize)
            .enumerate()
            .for_each(|(j, row)| {
                for (i, out) in row.iter_mut().enumerate() {
                    // Pixel by pixel: a row of many samples takes seconds.
                    if stop.happened() {
                        return;
                    }
                    let dir = cam.ray_dir(i as u32, j as u32);
                    let Some(p) = tracer.surface_point(cam.eye, dir) else {
                        continue;
                    };
                    *out = match samples {
                        LightSamples::Centre => tracer.hard_visibility(&p),
                        LightSamples::Stratified { per_axis } => {
                            let pixel = j as u64 * w as u64 + i as u64;
                            let mut rng = Rng::stream(REFERENCE_SEED, pixel);
                            tracer.sampled_visibility(&p, per_axis, &mut rng)
                        }
                    } as f32;
                }
                let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                progress(n);
            });
        img
    }
}
