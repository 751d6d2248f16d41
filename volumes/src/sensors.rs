//! Visibility at sensor points: any points with the normals of the surfaces they stand for (a
//! grid on a facade, a courtyard's floor), not only the surface points of camera pixels.
//!
//! A sensor at `P` with normal `n` sees a light sample `s` when `s` lies strictly on the side
//! of its plane that `n` points to and the open segment from `P` to `s` crosses no triangle.
//! A sensor within [`Tracer::epsilon`] of a triangle (a point of the floor, of a wall) stands
//! on the nearest such triangle along its normal, which never counts as crossing, as the
//! triangle of a camera pixel's surface point never does; one farther from every triangle (a
//! work plane in a room) stands on none. Sensor `k` (its index in the whole query) takes the
//! light samples of camera pixel `k`: by depth-complexity sampling its pattern's points are
//! counted, exactly ([`crate::DepthComplexity`]); by the reference's rule they are cast
//! ([`penumbra_geom::Tracer::sampled_visibility`]). Where the sensor's plane cuts the light,
//! the samples behind it count as unseen, and those in front are cast by the reference's rule:
//! the same samples, the same answer.
//!
//! Under a distant light the points and normals are carried to the rendered scene by its warp
//! (normals by the inverse transpose of its derivative).

use glam::{DVec2, DVec3};
use penumbra_geom::{
    Interruption, LitScene, REFERENCE_SEED, RectLight, Rng, SurfacePoint, Tracer, TracerGeometry,
};
use rayon::prelude::*;

use crate::depth_complexity::{DepthComplexity, SamplePattern, Scratch};

/// The triangle index of a sensor that stands on no triangle.
const NO_TRIANGLE: u32 = u32::MAX;

/// Sensors per task of the parallel loop, and between two looks for an interruption.
const CHUNK: usize = 256;

/// How a sensor's light samples are tested.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SensorSamples {
    /// Counted by depth-complexity sampling, at the samples of `pattern`.
    Counted(SamplePattern),
    /// Cast by the reference's rule: `per_axis x per_axis` stratified-jittered samples.
    Cast {
        /// Samples per axis.
        per_axis: usize,
    },
}

/// What [`SensorVisibility`] tests the samples with.
enum Method {
    Counted(Box<DepthComplexity>, SamplePattern),
    Cast(Box<Tracer>, usize),
}

/// The visibility of sensor points under one light of a scene: its ray-casting hierarchy and,
/// for depth-complexity sampling, its potential silhouette edges, built once for any number of
/// [`SensorVisibility::fill`] calls.
pub struct SensorVisibility {
    method: Method,
    /// The warp of a distant light's scene, `None` under a rectangle light.
    warp: Option<penumbra_geom::Warp>,
}

/// One sensor, in the rendered scene: its surface point and its plane's normal.
struct Placed {
    point: SurfacePoint,
    normal: DVec3,
}

impl SensorVisibility {
    /// The sensors' renderer of `scene`, taking the ray-casting hierarchy from `kept` where it
    /// serves and keeping the one it builds there otherwise.
    pub fn new(
        scene: &LitScene,
        samples: SensorSamples,
        kept: &mut Option<TracerGeometry>,
    ) -> SensorVisibility {
        let method = match samples {
            SensorSamples::Counted(pattern) => {
                Method::Counted(Box::new(DepthComplexity::new_reusing(scene, kept)), pattern)
            }
            SensorSamples::Cast { per_axis } => Method::Cast(
                Box::new(Tracer::new_reusing(scene, penumbra_geom::Rays::Many, kept)),
                per_axis,
            ),
        };
        SensorVisibility {
            method,
            warp: scene.warp().copied(),
        }
    }

    fn tracer(&self) -> &Tracer {
        match &self.method {
            Method::Counted(dc, _) => &dc.tracer,
            Method::Cast(t, _) => t,
        }
    }

    /// Into `out`, the visibility of the sensors at `positions` with `normals` (world space,
    /// normals of any non-zero length), the first of them sensor `first` of the query (which
    /// chooses its samples). Interrupted ([`penumbra_geom::Interrupter`]), it returns
    /// `false` with the sensors not yet reached left as they were; `progress` gets the number
    /// of sensors done so far.
    ///
    /// # Panics
    ///
    /// If the three slices differ in length.
    pub fn fill(
        &self,
        positions: &[DVec3],
        normals: &[DVec3],
        first: u64,
        out: &mut [f32],
        progress: &(dyn Fn(u64) + Sync),
    ) -> bool {
        assert!(positions.len() == normals.len() && normals.len() == out.len());
        let stop = Interruption::since();
        let done = std::sync::atomic::AtomicU64::new(0);
        out.par_chunks_mut(CHUNK).enumerate().for_each_init(
            Scratch::default,
            |scratch, (c, chunk)| {
                let start = c * CHUNK;
                for (k, v) in chunk.iter_mut().enumerate() {
                    if stop.happened() {
                        return;
                    }
                    let i = start + k;
                    *v =
                        self.visibility(positions[i], normals[i], first + i as u64, scratch) as f32;
                }
                let n = done.fetch_add(chunk.len() as u64, std::sync::atomic::Ordering::Relaxed);
                progress(n + chunk.len() as u64);
            },
        );
        !stop.happened()
    }

    /// The sensor at `p` with normal `n` in the rendered scene, on its triangle if it stands
    /// on one.
    fn place(&self, p: DVec3, n: DVec3) -> Placed {
        let (p, n) = match &self.warp {
            Some(w) => (w.point(p), w.jacobian(p).inverse().transpose() * n),
            None => (p, n),
        };
        let n = n.normalize();
        let t = self.tracer();
        let mut near = Vec::new();
        let free = SurfacePoint {
            position: p,
            triangle: NO_TRIANGLE,
        };
        t.near_triangles(&free, &mut near);
        // The nearest triangle within `epsilon` whose plane's foot of `p` lies on it: by the
        // box tree rather than a ray along the normal, which a flat box misses when the ray
        // runs along an axis.
        let point = near
            .iter()
            .filter_map(|&k| {
                let [a, b, c] = t.triangles[k as usize];
                let m = (b - a).cross(c - a).normalize_or_zero();
                let dist = (p - a).dot(m);
                let q = p - m * dist;
                (m != DVec3::ZERO && dist.abs() <= t.epsilon && on_triangle(q, [a, b, c], m))
                    .then_some((
                        dist.abs(),
                        SurfacePoint {
                            position: q,
                            triangle: k,
                        },
                    ))
            })
            .min_by(|x, y| x.0.total_cmp(&y.0))
            .map_or(free, |(_, point)| point);
        Placed { point, normal: n }
    }

    /// The visibility of one sensor, `index` choosing its samples.
    fn visibility(&self, p: DVec3, n: DVec3, index: u64, scratch: &mut Scratch) -> f64 {
        let placed = self.place(p, n);
        let tracer = self.tracer();
        let light = &tracer.light;
        let at = placed.point.position;
        if !light.is_lit_side(at) {
            return 0.0;
        }
        let in_front = |q: DVec3| placed.normal.dot(q - at) > 0.0;
        let corners = light.corners();
        let front = corners.iter().filter(|&&q| in_front(q)).count();
        if front == 0 {
            return 0.0;
        }
        let uvs: Vec<DVec2> = match &self.method {
            Method::Counted(dc, pattern) => {
                if front == 4 {
                    return dc
                        .visibility(&placed.point, *pattern, index, scratch)
                        .visibility;
                }
                let mut uvs = Vec::new();
                pattern.points(index, &mut uvs);
                uvs
            }
            Method::Cast(_, per_axis) => {
                let mut rng = Rng::stream(REFERENCE_SEED, index);
                RectLight::stratified_samples(*per_axis, &mut rng)
            }
        };
        let mut near = Vec::new();
        tracer.near_triangles(&placed.point, &mut near);
        let seen = uvs
            .iter()
            .map(|&uv| light.point(uv))
            .filter(|&q| in_front(q) && tracer.sees(&placed.point, q, &near))
            .count();
        seen as f64 / uvs.len() as f64
    }
}

/// Whether `q`, in the plane of `tri` (unit normal `m`), lies on it, edges included.
fn on_triangle(q: DVec3, [a, b, c]: [DVec3; 3], m: DVec3) -> bool {
    let side = |u: DVec3, v: DVec3| (v - u).cross(q - u).dot(m) >= 0.0;
    side(a, b) && side(b, c) && side(c, a)
}
