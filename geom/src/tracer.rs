//! Ray casting for visibility queries: a scene's triangles, their hierarchies and the rules by
//! which a segment from a surface point to a light point is blocked (see the reference's
//! documentation, `reference.rs`).
//!
//! Under a distant light the renderers work in the warped scene (`distant.rs`), and so do a
//! [`Tracer`]'s points, triangles and light. Its hierarchies, though, are those of the world's
//! triangles, which do not depend on the light's direction: a ray is cast in the world, from
//! the point's preimage along the light direction the light point stands for (the warp sends
//! the world's ray to infinity onto the warped segment to that point, and keeps which triangles
//! it crosses). A sun study takes the same hierarchies for every position of the sun
//! ([`Tracer::new_reusing`]); only the `f32` rounding of a cast differs from a cast in the
//! warped scene.

use std::sync::Arc;

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use crate::boxtree::BoxTree;
use crate::distant::Warp;
use crate::exact::exact_visibility;
use crate::light::RectLight;
use crate::lit_scene::LitScene;
use crate::raycast::{Rays, SceneBvh};
use crate::rng::Rng;

/// Shadow rays start this far from P, relative to the extent of the triangles and the eye: P carries the `f32`
/// rounding of the hit (about 1e-7 of its coordinates), two orders of magnitude below.
pub const SHADOW_EPSILON: f64 = 1e-5;

/// A crossing of a triangle near P closer to P than this (relative to the scene's extent) is
/// P touching that triangle, not the segment crossing it: P is snapped onto its own triangle's
/// plane in `f64`, so a neighbour in that plane lies within rounding of it (about 1e-16).
pub const TOUCH_EPSILON: f64 = 1e-9;

/// A segment lies in a triangle's plane when both its ends lie within this much of it,
/// relative to their distance from the triangle: rounding, far below any gap a scene can mean.
pub const PLANE_HOLDS: f64 = 1e-9;

/// The surface point seen through a pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// World position, snapped onto the plane of its triangle in `f64`.
    pub position: DVec3,
    /// Index of the triangle it lies on (into [`LitScene::triangles`]).
    pub triangle: u32,
}

/// A scene ready for visibility queries: its triangles, their BVH and its scale.
///
/// Its points, triangles, light and distances are those of the scene the renderers render
/// ([`LitScene`]: the warped world under a distant light); under a distant light its
/// hierarchies are the world's (see the module's documentation).
pub struct Tracer {
    /// The triangles the renderers render.
    pub triangles: Arc<[[DVec3; 3]]>,
    /// Their ray-casting hierarchy, or the world's triangles' under a distant light.
    bvh: Arc<SceneBvh>,
    /// The light.
    pub light: RectLight,
    /// Shadow-ray start offset in the units of [`Tracer::triangles`].
    pub epsilon: f64,
    /// [`TOUCH_EPSILON`] in the units of [`Tracer::triangles`].
    pub touch: f64,
    /// The triangles' bounding boxes, to find those near a point (the world's under a distant
    /// light).
    near: Arc<BoxTree>,
    /// Under a distant light, the world's triangles and how rays are cast among them.
    world: Option<World>,
    /// Per triangle, whether it has a vertex strictly in front of the light's plane. The others
    /// can meet a segment from P to a light point only at its end, on the light: a touch, not
    /// a crossing, whichever way `f32` rounds it (a box whose top face is the light's plane).
    in_front: Vec<bool>,
}

/// How a [`Tracer`] under a distant light casts in the world: the warp, the world's offsets
/// and the reach of its rays.
#[derive(Clone, Copy, Debug)]
struct WorldRays {
    warp: Warp,
    /// [`SHADOW_EPSILON`] of the world's extent.
    epsilon: f64,
    /// The half side of the world box around a point's preimage that holds every triangle
    /// within [`Tracer::epsilon`] of the point or within `epsilon` of the preimage: the warp's
    /// inverse stretches lengths at most 2.25 times around the scene (`distant.rs`), so three
    /// times the larger.
    near: f64,
    /// The world's triangles' bounding box.
    bounds: (DVec3, DVec3),
}

impl WorldRays {
    /// The world ray of the warped segment from `p` to `l`: its origin, unit direction and
    /// length. A light point `l` is the image of the point at infinity in direction
    /// `l - o` (the warp's origin), whose ray is cast to beyond the world's triangles; any
    /// other end is the image of a world point, short of which by `touch` the ray stops.
    fn ray(&self, p: DVec3, l: DVec3, touch: f64) -> (DVec3, DVec3, f64) {
        let w = &self.warp;
        let from = w.unwarp(p);
        let e = l - w.origin;
        let depth = w.k - e.dot(w.direction);
        if depth <= 1e-9 * w.k {
            let (lo, hi) = self.bounds;
            let beyond = (from - 0.5 * (lo + hi)).length() + (hi - lo).length();
            (from, e.normalize(), 2.0 * beyond)
        } else {
            let d = w.origin + e * (w.k / depth) - from;
            let dist = d.length();
            (from, d / dist, dist - touch)
        }
    }
}

/// The bounding box of `triangles`.
fn bounds_of(triangles: &[[DVec3; 3]]) -> (DVec3, DVec3) {
    let empty = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    triangles
        .par_iter()
        .fold(
            || empty,
            |(lo, hi), t| {
                (
                    lo.min(t[0]).min(t[1]).min(t[2]),
                    hi.max(t[0]).max(t[1]).max(t[2]),
                )
            },
        )
        .reduce(|| empty, |(l0, h0), (l1, h1)| (l0.min(l1), h0.max(h1)))
}

/// A [`Tracer`]'s world under a distant light.
struct World {
    /// The world's triangles, in the order of [`Tracer::triangles`].
    triangles: Arc<[[DVec3; 3]]>,
    rays: WorldRays,
}

/// What a [`Tracer`] builds from a scene's triangles alone: the triangles, their ray-casting
/// hierarchy for some [`Rays`], the boxes that find the triangles near a point, and their
/// bounds. It depends on neither the light nor the camera, so a scene with the same triangles
/// under another light or seen by another camera can take it as it is
/// ([`Tracer::new_reusing`]); cloning it shares it.
#[derive(Clone)]
pub struct TracerGeometry {
    triangles: Arc<[[DVec3; 3]]>,
    bvh: Arc<SceneBvh>,
    near: Arc<BoxTree>,
    rays: Rays,
    /// The triangles' bounding box.
    bounds: (DVec3, DVec3),
}

/// The first surface point along the ray `origin + t dir` among `triangles`, by `bvh`: the hit
/// projected onto its triangle's plane.
fn surface_point(
    bvh: &SceneBvh,
    triangles: &[[DVec3; 3]],
    origin: DVec3,
    dir: DVec3,
) -> Option<SurfacePoint> {
    let hit = bvh.closest_hit(origin, dir, f64::MAX)?;
    Some(snapped(origin + dir * hit.t, hit.triangle, triangles))
}

/// The point `p` projected onto the plane of `triangles[triangle]`.
fn snapped(p: DVec3, triangle: u32, triangles: &[[DVec3; 3]]) -> SurfacePoint {
    let [a, b, c] = triangles[triangle as usize];
    let n = (b - a).cross(c - a).normalize_or_zero();
    SurfacePoint {
        position: p - n * (p - a).dot(n),
        triangle,
    }
}

impl TracerGeometry {
    /// The hierarchies of `triangles` for `rays`: `kept`'s where it serves them
    /// ([`TracerGeometry::serves`]), else built (the one that does not serve dropped first, so
    /// that the two are never held at once) and kept in `kept` for the next caller.
    pub fn reusing(
        triangles: Vec<[DVec3; 3]>,
        rays: Rays,
        kept: &mut Option<TracerGeometry>,
    ) -> TracerGeometry {
        let geometry = match kept.take().filter(|g| g.serves(&triangles, rays)) {
            Some(g) => g,
            None => TracerGeometry::build(triangles, rays),
        };
        *kept = Some(geometry.clone());
        geometry
    }

    /// The surface point the ray `origin + t dir` meets first ([`Tracer::surface_point`]).
    pub fn surface_point(&self, origin: DVec3, dir: DVec3) -> Option<SurfacePoint> {
        surface_point(&self.bvh, &self.triangles, origin, dir)
    }

    /// The triangles.
    pub fn triangles(&self) -> &[[DVec3; 3]] {
        &self.triangles
    }

    /// Builds the hierarchies of `triangles` for `rays`.
    pub fn build(triangles: Vec<[DVec3; 3]>, rays: Rays) -> Self {
        let bvh = SceneBvh::build_for(&triangles, rays);
        let bounds = bounds_of(&triangles);
        let boxes: Vec<(DVec3, DVec3)> = triangles
            .iter()
            .map(|[a, b, c]| (a.min(*b).min(*c), a.max(*b).max(*c)))
            .collect();
        TracerGeometry {
            triangles: triangles.into(),
            bvh: Arc::new(bvh),
            near: Arc::new(BoxTree::build(&boxes)),
            rays,
            bounds,
        }
    }

    /// Whether it is what [`TracerGeometry::build`] makes of `triangles` for `rays`: the same
    /// triangles, bit for bit (a `-0.0` is not a `0.0`: rays round them alike, but the hierarchy
    /// and the images must not depend on what was rendered before), and the same `rays`, as
    /// the two builds may name different triangles among coincident ones.
    pub fn serves(&self, triangles: &[[DVec3; 3]], rays: Rays) -> bool {
        let bits = |t: &[DVec3; 3]| t.map(|v| v.to_array().map(f64::to_bits));
        self.rays == rays
            && self.triangles.len() == triangles.len()
            && self
                .triangles
                .iter()
                .zip(triangles)
                .all(|(a, b)| bits(a) == bits(b))
    }
}

impl Tracer {
    /// Builds the BVH of a scene for many rays ([`Rays::Many`]).
    pub fn new(scene: &LitScene) -> Self {
        Self::new_for(scene, Rays::Many)
    }

    /// Builds the BVH of a scene for `rays` rays.
    pub fn new_for(scene: &LitScene, rays: Rays) -> Self {
        Self::new_reusing(scene, rays, &mut None)
    }

    /// [`Tracer::new_for`], taking `kept`'s hierarchies where it serves the scene's triangles
    /// for `rays` ([`TracerGeometry::serves`]), and otherwise building them and keeping them in
    /// `kept` for the next scene: the same image either way, without building the hierarchies
    /// again for another light or camera over the same triangles.
    ///
    /// Under a distant light the hierarchies are those of the world's triangles
    /// ([`LitScene::world_triangles`]), which every direction of the light shares.
    pub fn new_reusing(scene: &LitScene, rays: Rays, kept: &mut Option<TracerGeometry>) -> Self {
        let triangles = match &scene.distant {
            None => scene.triangles(),
            Some(_) => scene.world_triangles(),
        };
        Self::with_geometry(scene, TracerGeometry::reusing(triangles, rays, kept))
    }

    /// The tracer of `scene` with the hierarchies `geometry`, which the caller built of the
    /// scene's triangles, or of the world's under a distant light
    /// ([`LitScene::world_triangles`]): the caller that knows the scene's meshes have not changed
    /// since (a sun study) skips [`TracerGeometry::serves`]'s comparison.
    pub fn with_geometry(scene: &LitScene, geometry: TracerGeometry) -> Self {
        // The extent of what P's rounding comes from: the triangles and the eye. Not the light:
        // a far light (the sun as a rectangle 1e5 away) made the offsets as long as the gap
        // between an occluder and its receiver, and the shadow was lost.
        let extent_of =
            |(lo, hi): (DVec3, DVec3), eye: DVec3| (hi.max(eye) - lo.min(eye)).length().max(1e-30);
        let (triangles, bounds) = match &scene.distant {
            None => (geometry.triangles.clone(), geometry.bounds),
            Some(_) => {
                let triangles: Arc<[[DVec3; 3]]> = scene.triangles().into();
                let bounds = bounds_of(&triangles);
                (triangles, bounds)
            }
        };
        let extent = extent_of(bounds, scene.camera.eye);
        let epsilon = SHADOW_EPSILON * extent;
        let world = scene.distant.as_ref().map(|view| {
            let world_epsilon = SHADOW_EPSILON * extent_of(geometry.bounds, view.camera.eye);
            World {
                triangles: geometry.triangles.clone(),
                rays: WorldRays {
                    warp: view.warp,
                    epsilon: world_epsilon,
                    near: 3.0 * world_epsilon.max(epsilon),
                    bounds: geometry.bounds,
                },
            }
        });
        let in_front = triangles
            .par_iter()
            .map(|t| t.iter().any(|&v| scene.light.signed_distance(v) > 0.0))
            .collect();
        Tracer {
            in_front,
            bvh: geometry.bvh,
            light: scene.light,
            epsilon,
            touch: TOUCH_EPSILON * extent,
            near: geometry.near,
            world,
            triangles,
        }
    }

    /// The ray-casting hierarchy: of [`Tracer::triangles`], or of the world's triangles under
    /// a distant light.
    pub fn hierarchy(&self) -> &SceneBvh {
        &self.bvh
    }

    /// Whether triangle `t` has a vertex strictly in front of the light's plane: only those can
    /// block a segment to a light point.
    pub fn in_front(&self, t: u32) -> bool {
        self.in_front[t as usize]
    }

    /// Into `out`, the triangles other than `p`'s that may pass within [`Tracer::epsilon`] of
    /// it: those of the box hierarchy's leaves that reach that far (a superset: [`Tracer::sees`]
    /// tests each exactly).
    pub fn near_triangles(&self, p: &SurfacePoint, out: &mut Vec<u32>) {
        out.clear();
        let (at, r) = match &self.world {
            None => (p.position, self.epsilon),
            Some(w) => (w.rays.warp.unwarp(p.position), w.rays.near),
        };
        let r = DVec3::splat(r);
        self.near.query_box(at - r, at + r, &mut |t| {
            if t != p.triangle {
                out.push(t);
            }
        });
    }

    /// Whether the segment from `p` to `l` crosses triangle `t` in `f64`, farther than
    /// [`Tracer::touch`] from both ends (Möller & Trumbore,
    /// "Fast, Minimum Storage Ray/Triangle Intersection", 1997, edges included); never for a
    /// triangle with no vertex in front of the light's plane.
    pub fn crosses(&self, p: DVec3, l: DVec3, t: u32) -> bool {
        if !self.in_front[t as usize] || self.holds_segment(t, p, l) {
            return false;
        }
        let Some((u, v, along)) = segment_meets_plane(p, l, self.triangles[t as usize]) else {
            return false;
        };
        if !(u >= 0.0 && v >= 0.0 && u + v <= 1.0) {
            return false;
        }
        let dist = (l - p).length();
        let at = along * dist;
        at > self.touch && at < dist - self.touch
    }

    /// First surface hit by the ray `origin + t * dir` (`dir` unit). Under a distant light,
    /// the world's ray whose image it is is cast ([`Tracer::world_surface_point`]).
    pub fn surface_point(&self, origin: DVec3, dir: DVec3) -> Option<SurfacePoint> {
        let Some(w) = &self.world else {
            return surface_point(&self.bvh, &self.triangles, origin, dir);
        };
        // The warp carries a ray's direction at a point by its derivative there.
        let from = w.rays.warp.unwarp(origin);
        let along = (w.rays.warp.jacobian(from).inverse() * dir).normalize();
        self.world_surface_point(from, along)
            .map(|p| self.rendered(p))
    }

    /// The first surface point of the world along the world's ray `origin + t * dir` (`dir`
    /// unit), on its triangle's plane in the world: under a distant light, a point that does
    /// not depend on the light ([`Tracer::rendered`] takes it to the rendered scene); under a
    /// rectangle, [`Tracer::surface_point`].
    pub fn world_surface_point(&self, origin: DVec3, dir: DVec3) -> Option<SurfacePoint> {
        let triangles = self
            .world
            .as_ref()
            .map_or(&self.triangles, |w| &w.triangles);
        surface_point(&self.bvh, triangles, origin, dir)
    }

    /// The surface point of the rendered scene at the world's surface point `p`
    /// ([`Tracer::world_surface_point`]): warped onto its triangle's plane under a distant
    /// light, `p` itself under a rectangle.
    pub fn rendered(&self, p: SurfacePoint) -> SurfacePoint {
        match &self.world {
            None => p,
            Some(w) => snapped(w.rays.warp.point(p.position), p.triangle, &self.triangles),
        }
    }

    /// Calls `f` with each triangle but `exclude` that the `f32` cast of [`Tracer::sees`]
    /// crosses on the segment from `p` to the light point `l`, from [`Tracer::epsilon`] past
    /// `p` to `short` before `l` (in the world under a distant light, to beyond the scene), if
    /// the segment is longer than that; a triangle may be reported more than once.
    pub fn for_each_hit_towards(
        &self,
        p: DVec3,
        l: DVec3,
        short: f64,
        exclude: u32,
        f: impl FnMut(u32),
    ) {
        let (from, dir, tmin, tmax) = self.cast(p, l, short);
        if tmax > tmin {
            self.bvh.for_each_hit(
                from,
                dir.as_vec3().into(),
                tmin as f32,
                tmax as f32,
                exclude,
                f,
            );
        }
    }

    /// The cast from `p` towards `l`: its origin, unit direction and range, stopping `short`
    /// before `l` ([`Tracer::for_each_hit_towards`]).
    #[inline]
    fn cast(&self, p: DVec3, l: DVec3, short: f64) -> (DVec3, DVec3, f64, f64) {
        match &self.world {
            None => {
                let d = l - p;
                let dist = d.length();
                (p, d / dist, self.epsilon, dist - short)
            }
            Some(w) => {
                let (from, dir, reach) = w.rays.ray(p, l, short);
                (from, dir, w.rays.epsilon, reach)
            }
        }
    }

    /// Whether the light point `l` is visible from the surface point `p`, whose
    /// [`Tracer::near_triangles`] are `near`.
    #[inline]
    pub fn sees(&self, p: &SurfacePoint, l: DVec3, near: &[u32]) -> bool {
        self.sees_far(p, l) && !near.iter().any(|&t| self.crosses(p.position, l, t))
    }

    /// The `f32` part of [`Tracer::sees`]: nothing blocks the segment from [`Tracer::epsilon`]
    /// past `p` to [`Tracer::touch`] before `l`.
    #[inline]
    fn sees_far(&self, p: &SurfacePoint, l: DVec3) -> bool {
        let (from, dir, tmin, tmax) = self.cast(p.position, l, self.touch);
        if !(tmax + self.touch > tmin) {
            return true;
        }
        !self
            .bvh
            .occluded_by(from, dir.as_vec3().into(), tmin as f32, tmax as f32, |t| {
                t != p.triangle
                    && self.in_front[t as usize]
                    && !self.holds_segment(t, p.position, l)
            })
    }

    /// Whether the plane of triangle `t` holds the segment from `p` to `l`, within
    /// [`PLANE_HOLDS`] of the segment's reach: the segment runs along the triangle's surface
    /// (a sun on the horizon over a tessellated ground, seen from a point of that ground) and
    /// grazes it without crossing it, as it grazes the triangle `p` lies on.
    pub fn holds_segment(&self, t: u32, p: DVec3, l: DVec3) -> bool {
        let [a, b, c] = self.triangles[t as usize];
        let n = (b - a).cross(c - a);
        let len = n.length();
        let reach = PLANE_HOLDS * ((p - a).length() + (l - a).length()) * len;
        len > 0.0 && n.dot(p - a).abs() <= reach && n.dot(l - a).abs() <= reach
    }

    /// Sampled visibility at `p` from `n x n` stratified-jittered light points drawn from `rng`.
    pub fn sampled_visibility(&self, p: &SurfacePoint, n: usize, rng: &mut Rng) -> f64 {
        if !self.light.is_lit_side(p.position) {
            return 0.0;
        }
        let mut near = Vec::new();
        self.near_triangles(p, &mut near);
        self.share_seen(p, &near, &RectLight::stratified_samples(n, rng))
    }

    /// The share of the light points `uvs` (in the light's `[-1, 1]^2`) that `p` sees, each by
    /// [`Tracer::sees`] (`near`: `p`'s near triangles, [`Tracer::near_triangles`]).
    pub fn share_seen(&self, p: &SurfacePoint, near: &[u32], uvs: &[DVec2]) -> f64 {
        let seen = uvs
            .iter()
            .filter(|&&uv| self.sees(p, self.light.point(uv), near))
            .count();
        seen as f64 / uvs.len() as f64
    }

    /// Hard visibility at `p`: 1 when the light's centre is visible, else 0.
    pub fn hard_visibility(&self, p: &SurfacePoint) -> f64 {
        let mut near = Vec::new();
        self.near_triangles(p, &mut near);
        if self.light.is_lit_side(p.position) && self.sees(p, self.light.center, &near) {
            1.0
        } else {
            0.0
        }
    }

    /// Exact visibility at `p` ([`exact_visibility`]).
    pub fn exact_visibility(&self, p: &SurfacePoint) -> f64 {
        exact_visibility(
            p.position,
            &self.light,
            &self.triangles,
            Some(p.triangle as usize),
        )
        .visibility
    }
}

/// Where the line through `p` and `l` meets the plane of the triangle `[a, b, c]` (Möller &
/// Trumbore, "Fast, Minimum Storage Ray/Triangle Intersection", 1997): the meeting point's
/// barycentric coordinates `(u, v)` of `b` and `c`, and its parameter along the segment (0 at
/// `p`, 1 at `l`); `None` where the line runs parallel to the plane.
#[inline]
pub fn segment_meets_plane(p: DVec3, l: DVec3, [a, b, c]: [DVec3; 3]) -> Option<(f64, f64, f64)> {
    let d = l - p;
    let (e1, e2) = (b - a, c - a);
    let q = d.cross(e2);
    let det = e1.dot(q);
    if det == 0.0 {
        return None;
    }
    let s = p - a;
    let u = s.dot(q) / det;
    let r = s.cross(e1);
    let v = d.dot(r) / det;
    Some((u, v, e2.dot(r) / det))
}

#[cfg(test)]
#[path = "tracer_tests.rs"]
mod tests;
