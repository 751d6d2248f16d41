//! Ray casting over every triangle of a scene with an obvhs compressed wide BVH (CWBVH).
//!
//! The binary hierarchy is built top-down ([`crate::bvh_build`]: obvhs' own PLOC builder is
//! quadratic on coincident faces and fan slivers), then refined, converted and traversed by
//! obvhs; the triangle test is ours: the watertight test of Woop, Benthin & Wald, "Watertight
//! Ray/Triangle Intersection", JCGT 2(1), 2013, with its `f64` fallback on zero edge functions,
//! so that rays through shared edges and vertices never slip between triangles, from either side.
//! Triangles are two-sided.

use glam::{DVec3, Vec3A};
use obvhs::{
    Boundable, BvhBuildParams, bvh2::reinsertion::ReinsertionOptimizer, cwbvh::CwBvh,
    cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh, ray::Ray, triangle::Triangle,
};

use crate::bvh_build::build_bvh2;

/// A ray's closest hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the (unit) direction.
    pub t: f64,
    /// Index of the triangle in the slice the BVH was built from.
    pub triangle: u32,
}

/// Per-ray constants of the watertight test: the axis permutation and the shear.
#[derive(Clone, Copy, Debug)]
pub struct WatertightRay {
    origin: Vec3A,
    k: [usize; 3],
    shear: [f32; 3],
}

impl WatertightRay {
    /// Precomputes the shear for a ray `origin + t * dir`.
    pub fn new(origin: Vec3A, dir: Vec3A) -> Self {
        let a = dir.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if dir[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        WatertightRay {
            origin,
            k: [kx, ky, kz],
            shear: [dir[kx] / dir[kz], dir[ky] / dir[kz], 1.0 / dir[kz]],
        }
    }

    /// Distance to the triangle `v`, or `f32::INFINITY` on a miss (both sides count).
    #[inline(always)]
    pub fn intersect(&self, v: &[Vec3A; 3], tmin: f32, tmax: f32) -> f32 {
        let [kx, ky, kz] = self.k;
        let [sx, sy, sz] = self.shear;
        let a = v[0] - self.origin;
        let b = v[1] - self.origin;
        let c = v[2] - self.origin;
        let ax = a[kx] - sx * a[kz];
        let ay = a[ky] - sy * a[kz];
        let bx = b[kx] - sx * b[kz];
        let by = b[ky] - sy * b[kz];
        let cx = c[kx] - sx * c[kz];
        let cy = c[ky] - sy * c[kz];
        let mut u = cx * by - cy * bx;
        let mut w_ = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if u == 0.0 || w_ == 0.0 || w == 0.0 {
            // Exact enough in double precision (the paper's fallback).
            u = (cx as f64 * by as f64 - cy as f64 * bx as f64) as f32;
            w_ = (ax as f64 * cy as f64 - ay as f64 * cx as f64) as f32;
            w = (bx as f64 * ay as f64 - by as f64 * ax as f64) as f32;
        }
        if (u < 0.0 || w_ < 0.0 || w < 0.0) && (u > 0.0 || w_ > 0.0 || w > 0.0) {
            return f32::INFINITY;
        }
        let det = u + w_ + w;
        if det == 0.0 {
            return f32::INFINITY;
        }
        let az = sz * a[kz];
        let bz = sz * b[kz];
        let cz = sz * c[kz];
        let t = (u * az + w_ * bz + w * cz) / det;
        if t > tmin && t < tmax {
            t
        } else {
            f32::INFINITY
        }
    }
}

/// How many rays a [`SceneBvh`] is built to answer, which decides how much its build refines
/// it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rays {
    /// Many per pixel (the references, depth-complexity sampling's cast tiles): refined by
    /// obvhs' reinsertion optimizer, and the wide nodes' children ordered by cost, which takes
    /// longer and pays back only over many rays (docs/benchmarks.md, "CPU techniques against
    /// the reference").
    Many,
    /// A few per pixel (the camera's, the light centre's): neither refinement, whose time the
    /// rays would not win back. The hits are the same: the closest distance, the triangles
    /// crossed (among coincident triangles, either build may name any at the closest).
    Few,
}

/// A BVH over a triangle soup, answering closest-hit and occlusion queries.
pub struct SceneBvh {
    bvh: Option<CwBvh>,
    /// The centre of the triangles' bounding box: triangles and rays are taken relative to it
    /// before they are rounded to `f32`, so that a scene far from the world's origin keeps the
    /// precision of one at it.
    origin: DVec3,
    /// Triangles in BVH leaf order (so a leaf's triangles are adjacent in memory).
    tris: Vec<[Vec3A; 3]>,
    /// Original triangle index of each entry of `tris`.
    ids: Vec<u32>,
}

impl SceneBvh {
    /// Builds the hierarchy for many rays ([`Rays::Many`]).
    pub fn build(triangles: &[[DVec3; 3]]) -> Self {
        Self::build_for(triangles, Rays::Many)
    }

    /// Builds the hierarchy: a binned-SAH binary BVH (`bvh_build.rs`, O(N log N) even on
    /// coincident or fan-sliver triangles, where obvhs' PLOC builder is quadratic), for
    /// [`Rays::Many`] refined by obvhs' reinsertion optimizer, and converted to its compressed
    /// wide BVH, with the parameters of obvhs' medium-quality build.
    pub fn build_for(triangles: &[[DVec3; 3]], rays: Rays) -> Self {
        if triangles.is_empty() {
            return SceneBvh {
                bvh: None,
                origin: DVec3::ZERO,
                tris: Vec::new(),
                ids: Vec::new(),
            };
        }
        let (lo, hi) = triangles
            .iter()
            .flatten()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        let origin = (lo + hi) * 0.5;
        let origin = if origin.is_finite() {
            origin
        } else {
            DVec3::ZERO
        };
        let soup: Vec<Triangle> = triangles
            .iter()
            .map(|t| Triangle {
                v0: (t[0] - origin).as_vec3().into(),
                v1: (t[1] - origin).as_vec3().into(),
                v2: (t[2] - origin).as_vec3().into(),
            })
            .collect();
        let params = BvhBuildParams::medium_build();
        let mut bvh2 = build_bvh2(soup.iter().map(Boundable::aabb));
        let many = rays == Rays::Many;
        if many {
            ReinsertionOptimizer::default().run(&mut bvh2, params.reinsertion_batch_ratio, None);
        }
        let bvh = bvh2_to_cwbvh(&bvh2, params.max_prims_per_leaf.clamp(1, 3), many, false);
        let ids = bvh.primitive_indices.clone();
        let tris = ids
            .iter()
            .map(|&i| {
                let t = &soup[i as usize];
                [t.v0, t.v1, t.v2]
            })
            .collect();
        SceneBvh {
            bvh: Some(bvh),
            origin,
            tris,
            ids,
        }
    }

    /// `p` relative to [`SceneBvh::origin`], in `f32`.
    #[inline]
    fn local(&self, p: DVec3) -> Vec3A {
        (p - self.origin).as_vec3().into()
    }

    /// Closest hit of `origin + t * dir` (`dir` unit) with `t` in `(0, tmax)`.
    pub fn closest_hit(&self, origin: DVec3, dir: DVec3, tmax: f64) -> Option<Hit> {
        let bvh = self.bvh.as_ref()?;
        let o = self.local(origin);
        let d: Vec3A = dir.as_vec3().into();
        let wt = WatertightRay::new(o, d);
        let ray = Ray::new(o, d, 0.0, tmax as f32);
        let mut hit = obvhs::ray::RayHit::none();
        if bvh.ray_traverse(ray, &mut hit, |r, id| {
            wt.intersect(&self.tris[id], 0.0, r.tmax)
        }) {
            Some(Hit {
                t: hit.t as f64,
                triangle: self.ids[hit.primitive_id as usize],
            })
        } else {
            None
        }
    }

    /// Whether anything but triangle `exclude` blocks `origin + t * dir` for `t` in
    /// `(tmin, tmax)`.
    #[inline]
    pub fn occluded(&self, origin: DVec3, dir: Vec3A, tmin: f32, tmax: f32, exclude: u32) -> bool {
        self.occluded_by(origin, dir, tmin, tmax, |t| t != exclude)
    }

    /// Whether any triangle that `blocks` accepts (given its index) blocks `origin + t * dir`
    /// for `t` in `(tmin, tmax)`.
    #[inline]
    pub fn occluded_by(
        &self,
        origin: DVec3,
        dir: Vec3A,
        tmin: f32,
        tmax: f32,
        blocks: impl Fn(u32) -> bool,
    ) -> bool {
        let Some(bvh) = self.bvh.as_ref() else {
            return false;
        };
        let origin = self.local(origin);
        let wt = WatertightRay::new(origin, dir);
        let ray = Ray::new(origin, dir, tmin, tmax);
        !bvh.ray_traverse_miss(ray, |_, id| {
            if blocks(self.ids[id]) {
                wt.intersect(&self.tris[id], tmin, tmax)
            } else {
                f32::INFINITY
            }
        })
    }
}

impl SceneBvh {
    /// Calls `f` with the index of every triangle but `exclude` that the ray
    /// `origin + t * dir` crosses for `t` in `(tmin, tmax)`, in no particular order (a triangle
    /// may be reported more than once when spatial splits put it in several leaves).
    pub fn for_each_hit(
        &self,
        origin: DVec3,
        dir: Vec3A,
        tmin: f32,
        tmax: f32,
        exclude: u32,
        mut f: impl FnMut(u32),
    ) {
        let Some(bvh) = self.bvh.as_ref() else {
            return;
        };
        let origin = self.local(origin);
        let wt = WatertightRay::new(origin, dir);
        let ray = Ray::new(origin, dir, tmin, tmax);
        bvh.ray_traverse_anyhit(ray, |_, id| {
            let t = self.ids[id];
            if t != exclude && wt.intersect(&self.tris[id], tmin, tmax) < tmax {
                f(t);
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad(y: f64) -> Vec<[DVec3; 3]> {
        let p = [
            DVec3::new(-1., y, -1.),
            DVec3::new(1., y, -1.),
            DVec3::new(1., y, 1.),
            DVec3::new(-1., y, 1.),
        ];
        vec![[p[0], p[1], p[2]], [p[0], p[2], p[3]]]
    }

    #[test]
    fn rays_through_the_shared_diagonal_never_leak() {
        let bvh = SceneBvh::build(&quad(0.0));
        // Rays aimed exactly at points of the shared diagonal x = z, from above and below.
        for k in 0..=200 {
            let s = -0.99 + 1.98 * k as f64 / 200.0;
            for from in [DVec3::new(0.3, 2.0, -0.7), DVec3::new(-0.4, -3.0, 0.2)] {
                let target = DVec3::new(s, 0.0, s);
                let dir = (target - from).normalize();
                let hit = bvh.closest_hit(from, dir, 100.0);
                assert!(hit.is_some(), "leak at {target}");
                assert!(bvh.occluded(from, dir.as_vec3().into(), 0.0, 100.0, u32::MAX));
            }
        }
    }

    #[test]
    fn occlusion_respects_range_and_exclusion() {
        let mut tris = quad(0.0);
        tris.extend(quad(1.0));
        let bvh = SceneBvh::build(&tris);
        let o = DVec3::new(0.1, -1.0, 0.2);
        let up = Vec3A::Y;
        assert!(bvh.occluded(o, up, 0.0, 10.0, u32::MAX));
        assert!(!bvh.occluded(o, up, 0.0, 0.5, u32::MAX));
        assert!(bvh.occluded(o, up, 1.5, 10.0, u32::MAX));
        assert!(!bvh.occluded(o, up, 2.5, 10.0, u32::MAX));
        let hit = bvh
            .closest_hit(DVec3::new(0.1, -1.0, 0.2), DVec3::Y, 10.0)
            .unwrap();
        assert!((hit.t - 1.0).abs() < 1e-6);
        assert!(hit.triangle < 2);
        // Excluding the triangle hit at t = 1 alone still finds the quad above.
        let from_top = DVec3::new(0.1, 0.0, 0.2);
        assert!(bvh.occluded(from_top, up, 0.0, 10.0, hit.triangle));
    }

    /// `n` copies of one quad (as separate meshes give them: not deduplicated) and a convex
    /// `m`-gon fan-triangulated from one vertex, the inputs that made obvhs' PLOC builder
    /// quadratic.
    fn degenerate_soup(n: usize, m: usize) -> Vec<[DVec3; 3]> {
        let mut tris: Vec<[DVec3; 3]> = (0..n).flat_map(|_| quad(0.5)).collect();
        let ring: Vec<DVec3> = (0..m)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / m as f64;
                DVec3::new(1.5 * a.cos(), 1.0, 1.5 * a.sin())
            })
            .collect();
        tris.extend((1..m - 1).map(|i| [ring[0], ring[i], ring[i + 1]]));
        tris
    }

    #[test]
    fn coincident_faces_and_fans_hit_as_brute_force_does() {
        let tris = degenerate_soup(3000, 3000);
        for rays in [Rays::Many, Rays::Few] {
            hits_as_brute_force_does(&SceneBvh::build_for(&tris, rays));
        }
    }

    /// Casts rays through [`degenerate_soup`] against `bvh` and over every triangle: the same
    /// closest distance, a triangle at it, and the same triangles crossed.
    fn hits_as_brute_force_does(bvh: &SceneBvh) {
        let mut rng = crate::Rng::new(7);
        let mut hits = 0;
        for k in 0..300 {
            // From above, the fan is hit first; from below, the stack of quads.
            let above = if k % 2 == 0 { 3.0 } else { -2.0 };
            let from = DVec3::new(0.0, above, 0.0)
                + DVec3::new(
                    rng.next_f64() - 0.5,
                    rng.next_f64() - 0.5,
                    rng.next_f64() - 0.5,
                );
            let target = DVec3::new(
                3.2 * rng.next_f64() - 1.6,
                rng.next_f64(),
                3.2 * rng.next_f64() - 1.6,
            );
            let dir = (target - from).normalize();
            let (tmin, tmax) = (0.0f32, 10.0f32);
            // Brute force over the same f32 triangles, with the same test.
            let wt = WatertightRay::new(bvh.local(from), dir.as_vec3().into());
            let ts: Vec<f32> = bvh
                .tris
                .iter()
                .map(|t| wt.intersect(t, tmin, tmax))
                .collect();
            let closest = ts.iter().copied().fold(f32::INFINITY, f32::min);
            let mut crossed: Vec<u32> = (0..ts.len())
                .filter(|&k| ts[k] < tmax)
                .map(|k| bvh.ids[k])
                .collect();
            crossed.sort_unstable();
            match bvh.closest_hit(from, dir, tmax as f64) {
                Some(hit) => {
                    hits += 1;
                    assert_eq!(hit.t as f32, closest);
                    let k = bvh.ids.iter().position(|&i| i == hit.triangle).unwrap();
                    assert_eq!(ts[k], closest);
                }
                None => assert_eq!(closest, f32::INFINITY),
            }
            let d: Vec3A = dir.as_vec3().into();
            assert_eq!(
                bvh.occluded(from, d, tmin, tmax, u32::MAX),
                !crossed.is_empty()
            );
            let mut found = Vec::new();
            bvh.for_each_hit(from, d, tmin, tmax, u32::MAX, |t| found.push(t));
            found.sort_unstable();
            assert_eq!(found, crossed);
        }
        assert!(hits > 100, "only {hits} of 300 rays hit");
    }

    #[test]
    fn empty_scene_hits_nothing() {
        let bvh = SceneBvh::build(&[]);
        assert!(bvh.closest_hit(DVec3::ZERO, DVec3::Y, 1.0).is_none());
        assert!(!bvh.occluded(DVec3::ZERO, Vec3A::Y, 0.0, 1.0, 0));
    }
}
