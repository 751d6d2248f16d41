//! Hours of direct sun: a scene's lights replaced by the sun at each step of a study, and the
//! visibility of its disk summed over the steps, times each step's hours, at every pixel or
//! sensor point. The sun's positions come from the caller (a solar-position library: NREL's
//! SPA); a step whose sun is wholly below the horizon costs nothing.

use glam::{DVec2, DVec3};
use penumbra_geom::{DistantLight, Interruption, Light, NamedLight, Scene, Technique};
use penumbra_volumes::SunSeries;

use crate::error::RenderError;
use crate::options::RenderOptions;
use crate::renderer::Renderer;

/// One step of a sun study: where the sun stands and the hours it stands for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunStep {
    /// Degrees clockwise from north, seen from above.
    pub azimuth_deg: f64,
    /// Degrees above the horizon (negative below it).
    pub elevation_deg: f64,
    /// The step's weight: its length in hours, or that times an irradiance.
    pub hours: f64,
}

/// How a sun study lights and samples its scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunStudy {
    /// The scene's north, a direction along its ground (`-z` for a scene modelled `+y` up).
    pub north: DVec3,
    /// The scene's up (`+y`, or `+z` for a scene modelled so).
    pub up: DVec3,
    /// The sun's full angular diameter in degrees (0.53 seen from the Earth).
    pub angular_size_deg: f64,
    /// `depth-complexity` (exact for its samples) or `reference` (rays); for pixels any
    /// technique.
    pub technique: Technique,
    /// Samples per pixel or point.
    pub options: RenderOptions,
}

impl Default for SunStudy {
    fn default() -> Self {
        SunStudy {
            north: DVec3::NEG_Z,
            up: DVec3::Y,
            angular_size_deg: 0.53,
            technique: Technique::DepthComplexity,
            options: RenderOptions {
                samples: 64,
                jitter: false,
            },
        }
    }
}

/// Where a sun study measures: the camera's pixels, or sensor points with their normals.
#[derive(Clone, Copy, Debug)]
pub enum SunTarget<'a> {
    /// Every pixel of the scene's camera, rows from the top.
    Pixels,
    /// Sensor points and their normals, as many of each.
    Points {
        /// The points, world space.
        points: &'a [DVec3],
        /// One normal per point.
        normals: &'a [DVec3],
    },
}

impl SunStudy {
    /// Whether the sun at `step` shows any of its disk above the horizon: its centre's
    /// elevation above minus its radius. The others are night and are not rendered.
    pub fn is_day(&self, step: &SunStep) -> bool {
        step.elevation_deg > -0.5 * self.angular_size_deg && step.hours != 0.0
    }

    /// `scene` with its lights replaced by the sun of `step`.
    pub fn scene_at(&self, scene: &Scene, step: &SunStep) -> Result<Scene, RenderError> {
        let sun = DistantLight::sun_in(
            self.north,
            self.up,
            step.azimuth_deg,
            step.elevation_deg,
            DVec2::splat(self.angular_size_deg),
        )
        .map_err(|error| RenderError::BadSun {
            problem: error.to_string(),
        })?;
        let mut lit = scene.clone();
        lit.lights = vec![NamedLight {
            name: "sun".to_string(),
            light: Light::Distant(sun),
        }];
        lit.named_channels = false;
        Ok(lit)
    }
}

impl Renderer {
    /// The hours of direct sun over `steps`: for each pixel or point of `target`, the sum over
    /// the daylight steps ([`SunStudy::is_day`]) of the sun's visibility times the step's
    /// hours, added in the steps' order in f64 (so that the same steps give the same bits,
    /// however a caller splits a study into runs of steps and adds their sums in order).
    /// `progress` is called with the number of steps done. The ray-casting hierarchy, the GPU
    /// context and its pipelines are kept from step to step, and for depth-complexity sampling
    /// of pixels on the CPU what the steps share ([`penumbra_volumes::SunSeries`]) is kept for
    /// the next study of the same meshes and camera ([`Renderer::release_kept`] drops it).
    ///
    /// ```
    /// use penumbra::{Backend, Renderer, Scene, SunStep, SunStudy, SunTarget};
    ///
    /// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/scenes/sun.toml");
    /// let mut scene = Scene::load(std::path::Path::new(path))?;
    /// (scene.camera.width, scene.camera.height) = (32, 24);
    /// let steps = [
    ///     SunStep { azimuth_deg: 120.0, elevation_deg: 40.0, hours: 1.0 },
    ///     SunStep { azimuth_deg: 200.0, elevation_deg: -5.0, hours: 1.0 }, // night: skipped
    /// ];
    /// let mut r = Renderer::new(Backend::Cpu);
    /// let h = r.sun_hours(&scene, &SunStudy::default(), &steps, SunTarget::Pixels, &|_| {})?;
    /// assert_eq!(h.len(), 32 * 24);
    /// assert!(h.iter().all(|&v| (0.0..=1.0).contains(&v)));
    /// assert!(h.iter().any(|&v| v == 1.0) && h.iter().any(|&v| v < 0.5));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn sun_hours(
        &mut self,
        scene: &Scene,
        study: &SunStudy,
        steps: &[SunStep],
        target: SunTarget<'_>,
        progress: &(dyn Fn(usize) + Sync),
    ) -> Result<Vec<f64>, RenderError> {
        if let Some(problem) = scene.out_of_range() {
            return Err(RenderError::OutOfRange { problem });
        }
        for step in steps {
            if !(step.hours.is_finite()
                && step.azimuth_deg.is_finite()
                && (-90.0..=90.0).contains(&step.elevation_deg))
            {
                return Err(RenderError::BadSun {
                    problem: format!(
                        "step at azimuth {} and elevation {} weighs {} hours: give finite \
                         numbers, the elevation in [-90, 90]",
                        step.azimuth_deg, step.elevation_deg, step.hours
                    ),
                });
            }
        }
        let len = match target {
            SunTarget::Pixels => scene.camera.width as usize * scene.camera.height as usize,
            SunTarget::Points { points, normals } => {
                if points.len() != normals.len() {
                    return Err(RenderError::BadSensor {
                        index: 0,
                        problem: format!(
                            "{} points and {} normals: give one normal per point",
                            points.len(),
                            normals.len()
                        ),
                    });
                }
                points.len()
            }
        };
        let mut sum = vec![0.0f64; len];
        // Depth-complexity sampling of pixels on the CPU shares more than the hierarchies from
        // one step to the next (`SunSeries`).
        let mut series = match target {
            SunTarget::Pixels
                if study.technique == Technique::DepthComplexity
                    && !self.uses_gpu(study.technique)? =>
            {
                let series = self.series.take();
                Some(series.unwrap_or_else(|| SunSeries::reusing(self.kept.take())))
            }
            _ => None,
        };
        let pattern = study.options.pattern_for(study.technique)?;
        let stop = Interruption::since();
        for (done, step) in steps.iter().enumerate() {
            if study.is_day(step) {
                let lit = study.scene_at(scene, step)?;
                let v = match (target, &mut series) {
                    (SunTarget::Pixels, Some(series)) => {
                        let image = series.render(&lit.lit(0), pattern, &|_| {});
                        if stop.happened() {
                            return Err(RenderError::Interrupted);
                        }
                        image.data
                    }
                    (SunTarget::Pixels, None) => {
                        self.render(&lit, study.technique, &study.options)?.data
                    }
                    (SunTarget::Points { points, normals }, _) => self.visibility_at(
                        &lit,
                        0,
                        points,
                        normals,
                        study.technique,
                        &study.options,
                    )?,
                };
                for (s, v) in sum.iter_mut().zip(v) {
                    *s += f64::from(v) * step.hours;
                }
            }
            progress(done + 1);
        }
        if let Some(series) = series {
            self.kept = series.kept().cloned();
            self.series = Some(series);
        }
        Ok(sum)
    }
}
