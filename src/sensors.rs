//! Visibility at sensor points ([`Renderer::sensors`], [`Renderer::visibility_at`]): the
//! share of a light that points with normals see (a grid on a facade, a courtyard's floor),
//! by depth-complexity sampling (exact for its samples) or by the ray-cast reference. The
//! rules are those of `penumbra_volumes::SensorVisibility`: a sensor sees the samples in front
//! of its plane that nothing hides, and one within rounding of a surface stands on it.

use glam::DVec3;
use penumbra_geom::{Scene, Technique, within_coordinates};
use penumbra_volumes::{SensorSamples, SensorVisibility};

use crate::error::RenderError;
use crate::options::RenderOptions;
use crate::renderer::Renderer;

/// The sensors' renderer of one light of a scene, built by [`Renderer::sensors`] once for any
/// number of [`Sensors::fill`] calls (a million points in slices, say).
pub struct Sensors {
    inner: SensorVisibility,
}

impl Sensors {
    /// Into `out`, the visibility of the sensors at `positions` with `normals` (world space;
    /// normals of any length but zero), the first of them sensor `first` of the whole query,
    /// which chooses its light samples: the result does not depend on how the query is cut into
    /// slices. `progress` gets the number of sensors of this call done so far.
    ///
    /// Refused, before any work, where the slices differ in length or a point or a normal is
    /// not finite, beyond the supported coordinates or (a normal) zero, naming its index in the
    /// query; an interruption ([`penumbra_geom::Interrupter`]) is
    /// [`RenderError::Interrupted`].
    pub fn fill(
        &self,
        positions: &[DVec3],
        normals: &[DVec3],
        first: u64,
        out: &mut [f32],
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<(), RenderError> {
        if positions.len() != normals.len() || positions.len() != out.len() {
            return Err(RenderError::BadSensor {
                index: first,
                problem: format!(
                    "{} points, {} normals and {} results: the three must be as many",
                    positions.len(),
                    normals.len(),
                    out.len()
                ),
            });
        }
        for (k, (p, n)) in positions.iter().zip(normals).enumerate() {
            let index = first + k as u64;
            let bad = |problem: String| Err(RenderError::BadSensor { index, problem });
            if !within_coordinates(*p) {
                return bad(format!(
                    "point [{:?}, {:?}, {:?}] is not finite or beyond the supported coordinates (up to {:e})",
                    p.x,
                    p.y,
                    p.z,
                    penumbra_geom::MAX_COORDINATE
                ));
            }
            // Not normal: zero, subnormal, infinite or NaN.
            if !n.length_squared().is_normal() {
                return bad(format!(
                    "normal [{:?}, {:?}, {:?}] has no direction",
                    n.x, n.y, n.z
                ));
            }
        }
        if !self.inner.fill(positions, normals, first, out, progress) {
            return Err(RenderError::Interrupted);
        }
        Ok(())
    }
}

impl Renderer {
    /// The sensors' renderer of `scene`'s light `light` by `technique`
    /// ([`Technique::DepthComplexity`], exact for its samples, or [`Technique::Reference`],
    /// rays), with the samples of `options`. It runs on the CPU, taking the ray-casting
    /// hierarchy this renderer kept where it serves, and keeping the one it builds.
    ///
    /// ```
    /// use penumbra::glam::{DMat4, DVec2, DVec3};
    /// use penumbra::{Backend, Camera, RectLight, RenderOptions, Renderer, Scene, Technique, TriangleMesh};
    ///
    /// let camera = Camera::look_at(DVec3::new(0.0, 4.0, 5.0), DVec3::ZERO, DVec3::Y, 45.0, 64, 48)?;
    /// let lamp = RectLight::aimed(DVec3::new(0.0, 5.0, 0.0), DVec3::ZERO, DVec2::splat(1.0))?;
    /// let scene = Scene::new(camera)
    ///     .with_light(lamp)
    ///     .with_mesh("ground", &TriangleMesh::quad(), DMat4::from_scale(DVec3::splat(8.0)))
    ///     .with_mesh("roof", &TriangleMesh::quad(), DMat4::from_translation(DVec3::new(0.0, 1.0, 0.0)));
    /// // Three points of the floor, facing up: under the roof, in its penumbra, far from it.
    /// let points = [DVec3::ZERO, DVec3::new(0.625, 0.0, 0.0), DVec3::new(3.0, 0.0, 0.0)];
    /// let up = [DVec3::Y; 3];
    /// let options = RenderOptions { samples: 256, jitter: false };
    /// let mut renderer = Renderer::new(Backend::Cpu);
    /// let v = renderer.visibility_at(&scene, 0, &points, &up, Technique::DepthComplexity, &options)?;
    /// assert_eq!(v[0], 0.0);
    /// assert!(v[1] > 0.2 && v[1] < 0.8);
    /// assert_eq!(v[2], 1.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn sensors(
        &mut self,
        scene: &Scene,
        light: usize,
        technique: Technique,
        options: &RenderOptions,
    ) -> Result<Sensors, RenderError> {
        if let Some(problem) = scene.out_of_range() {
            return Err(RenderError::OutOfRange { problem });
        }
        if light >= scene.lights.len() {
            return Err(RenderError::NoSuchLight {
                light,
                lights: scene.lights.len(),
            });
        }
        let lit = scene.lit(light);
        if let Some(problem) = lit.out_of_range() {
            return Err(RenderError::OutOfRange { problem });
        }
        let pattern = options.pattern_for(technique)?;
        let samples = match technique {
            Technique::DepthComplexity => SensorSamples::Counted(pattern),
            Technique::Reference => SensorSamples::Cast {
                per_axis: pattern.per_axis,
            },
            _ => return Err(RenderError::SensorTechnique { technique }),
        };
        Ok(Sensors {
            inner: SensorVisibility::new(&lit, samples, &mut self.kept),
        })
    }

    /// The visibility of the sensors at `positions` with `normals` under `scene`'s light
    /// `light`: [`Renderer::sensors`] then [`Sensors::fill`] of them all, sensor `k` taking the
    /// samples of index `k`.
    pub fn visibility_at(
        &mut self,
        scene: &Scene,
        light: usize,
        positions: &[DVec3],
        normals: &[DVec3],
        technique: Technique,
        options: &RenderOptions,
    ) -> Result<Vec<f32>, RenderError> {
        let sensors = self.sensors(scene, light, technique, options)?;
        let mut out = vec![0.0; positions.len()];
        sensors.fill(positions, normals, 0, &mut out, &|_| {})?;
        Ok(out)
    }
}
