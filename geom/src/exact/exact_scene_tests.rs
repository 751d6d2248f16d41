//! The exact evaluator on whole scenes: a sphere against ray casting, boxes seen from lattice
//! points (the inputs that broke constrained triangulation before snap rounding), spheres over a
//! ground at the fixtures' scale.

use glam::{DVec2, DVec3};

use super::exact_tests::{SEED, light_facing_down, quad};
use super::*;
use crate::rng::Rng;

/// UV sphere with `stacks` rings and `slices` segments: `2 * slices * (stacks - 1)` triangles.
pub(super) fn uv_sphere(
    center: DVec3,
    radius: f64,
    stacks: usize,
    slices: usize,
) -> Vec<[DVec3; 3]> {
    let at = |i: usize, j: usize| {
        let theta = std::f64::consts::PI * i as f64 / stacks as f64;
        let phi = std::f64::consts::TAU * (j % slices) as f64 / slices as f64;
        center
            + radius
                * DVec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                )
    };
    let mut tris = Vec::new();
    for i in 0..stacks {
        for j in 0..slices {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            if i != 0 {
                tris.push([a, b, d]);
            }
            if i != stacks - 1 {
                tris.push([b, c, d]);
            }
        }
    }
    tris
}

/// Whether the segment `p -> q` (open at both ends) crosses the triangle (Möller & Trumbore 1997,
/// two-sided).
fn segment_hits(p: DVec3, q: DVec3, t: &[DVec3; 3]) -> bool {
    let d = q - p;
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let h = d.cross(e2);
    let det = e1.dot(h);
    if det.abs() < 1e-14 {
        return false;
    }
    let s = p - t[0];
    let u = s.dot(h) / det;
    if !(0.0..=1.0).contains(&u) {
        return false;
    }
    let qv = s.cross(e1);
    let v = d.dot(qv) / det;
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    let s = e2.dot(qv) / det;
    s > 1e-9 && s < 1.0 - 1e-9
}

/// Fraction of `n x n` stratified light samples whose segment from `p` hits no triangle.
pub(super) fn ray_cast_visibility(
    p: DVec3,
    light: &RectLight,
    tris: &[[DVec3; 3]],
    n: usize,
    rng: &mut Rng,
) -> f64 {
    let samples = RectLight::stratified_samples(n, rng);
    let visible = samples
        .iter()
        .filter(|&&uv| {
            let y = light.point(uv);
            !tris.iter().any(|t| segment_hits(p, y, t))
        })
        .count();
    visible as f64 / (n * n) as f64
}

/// A 760-triangle sphere (20 x 20) against brute-force stratified ray casting; also prints the
/// evaluation time per point (a rough figure, not asserted: speed belongs in benchmarks).
#[test]
fn sphere_matches_ray_casting() {
    let light = light_facing_down(4.0, DVec2::new(0.0, 0.0), DVec2::new(1.5, 1.0));
    let tris = uv_sphere(DVec3::new(0.1, 2.0, 0.05), 0.6, 20, 20);
    assert_eq!(tris.len(), 760);
    let mut rng = Rng::new(SEED);
    let points = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(0.8, 0.0, 0.3),
        DVec3::new(-1.1, 0.0, -0.4),
        DVec3::new(1.6, 0.0, 1.0),
    ];
    for p in points {
        let start = std::time::Instant::now();
        let exact = exact_visibility(p, &light, &tris, None);
        let elapsed = start.elapsed();
        let sampled = ray_cast_visibility(p, &light, &tris, 128, &mut rng);
        println!(
            "sphere 760 tris, p = {p}: V = {:.6} (ray cast {sampled:.6}), {} polygons, {:?}",
            exact.visibility, exact.polygons, elapsed
        );
        assert!(
            (exact.visibility - sampled).abs() < 2e-3,
            "{p}: {} vs {sampled}",
            exact.visibility
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Degenerate arrangements: snap rounding must leave spade nothing to split.

/// Exact visibility through the internal entry points, asserting no constraint was split.
fn visibility_without_splits(
    p: DVec3,
    light: &RectLight,
    tris: &[[DVec3; 3]],
    exclude: Option<usize>,
) -> f64 {
    let v = exact_visibility(p, light, tris, exclude);
    if light.is_lit_side(p) {
        let pl = light.to_light_space(p);
        let polys: Vec<Vec<DVec2>> = tris
            .iter()
            .enumerate()
            .filter(|&(i, _)| Some(i) != exclude)
            .filter_map(|(_, t)| project_triangle(pl, t.map(|x| light.to_light_space(x))))
            .collect();
        let u = union_area_of_clean(&polys);
        assert_eq!(u.split_fallbacks, 0, "{p}");
        assert_eq!(u.area, v.occluded_area);
    }
    assert!((0.0..=1.0).contains(&v.visibility), "{p}: {v:?}");
    v.visibility
}

/// Two triangles per face of an axis-aligned box.
fn cube(lo: DVec3, side: f64) -> Vec<[DVec3; 3]> {
    let c = |x: f64, y: f64, z: f64| lo + DVec3::new(x, y, z) * side;
    let v = [
        c(0., 0., 0.),
        c(1., 0., 0.),
        c(1., 1., 0.),
        c(0., 1., 0.),
        c(0., 0., 1.),
        c(1., 0., 1.),
        c(1., 1., 1.),
        c(0., 1., 1.),
    ];
    let faces = [
        [0, 1, 2, 3],
        [4, 5, 6, 7],
        [0, 1, 5, 4],
        [3, 2, 6, 7],
        [0, 3, 7, 4],
        [1, 2, 6, 5],
    ];
    faces
        .iter()
        .flat_map(|f| [[v[f[0]], v[f[1]], v[f[2]]], [v[f[0]], v[f[2]], v[f[3]]]])
        .collect()
}

/// Boxes on a lattice under a light facing down, seen from receiver points on the same
/// lattice: projected edges coincide with each other and with the light's edges. Before snap
/// rounding about one point in 200 of this scene panicked inside spade.
#[test]
fn aligned_boxes_seen_from_lattice_points() {
    let mut rng = Rng::new(SEED);
    let light = light_facing_down(4.0, DVec2::ZERO, DVec2::new(2.0, 2.0));
    let mut tris = Vec::new();
    for i in 0..4 {
        for j in 0..4 {
            if rng.next_f64() < 0.6 {
                let lo = DVec3::new(
                    -2.0 + i as f64,
                    0.5 + 0.25 * (i % 2) as f64,
                    -2.0 + j as f64,
                );
                tris.extend(cube(lo, 0.5));
            }
        }
    }
    let mut checked = 0;
    for i in 0..21 {
        for j in 0..21 {
            let p = DVec3::new(-2.0 + 0.2 * i as f64, 0.0, -2.0 + 0.2 * j as f64);
            let v = visibility_without_splits(p, &light, &tris, None);
            if (i * 21 + j) % 97 == 0 {
                let s = ray_cast_visibility(p, &light, &tris, 64, &mut rng);
                assert!((v - s).abs() < 3e-3, "{p}: {v} vs ray cast {s}");
                checked += 1;
            }
        }
    }
    assert!(checked >= 4);
}

/// The scale of the project's largest scenes: 81 spheres of 760 triangles over a ground of two
/// triangles, receivers on the ground and on the spheres (their own triangle excluded), a tilted
/// light. Prints the time per point (rough, not asserted).
#[test]
fn spheres_over_ground_at_scene_scale() {
    let n = DVec3::new(0.2, -1.0, 0.1).normalize();
    let light = RectLight::new(
        DVec3::new(0.3, 7.0, -0.2),
        n,
        n.cross(DVec3::Z).normalize(),
        DVec2::new(4.0, 3.0),
    )
    .unwrap();
    let mut tris: Vec<[DVec3; 3]> = quad(-20.0, 20.0, -20.0, 20.0, 0.0).to_vec();
    for i in 0..9 {
        for j in 0..9 {
            let c = DVec3::new(
                -4.0 + i as f64,
                1.0 + 0.1 * ((i * j) % 5) as f64,
                -4.0 + j as f64,
            );
            tris.extend(uv_sphere(c, 0.45, 20, 20));
        }
    }
    assert_eq!(tris.len(), 2 + 81 * 760);
    let mut rng = Rng::new(SEED);
    let start = std::time::Instant::now();
    let count = 60;
    let mut partial = 0;
    for k in 0..count {
        let (p, own) = if k % 2 == 0 {
            let p = DVec3::new(rng.range(-6.0, 6.0), 0.0, rng.range(-6.0, 6.0));
            // quad() splits along the diagonal from (-20, -20) to (20, 20): z <= x is triangle 0.
            (p, if p.z <= p.x { 0 } else { 1 })
        } else {
            let own = 2 + rng.below(tris.len() - 2);
            let (u, v) = (rng.next_f64(), rng.next_f64());
            let (u, v) = if u + v > 1.0 {
                (1.0 - u, 1.0 - v)
            } else {
                (u, v)
            };
            let t = tris[own];
            (t[0] + (t[1] - t[0]) * u + (t[2] - t[0]) * v, own)
        };
        let v = visibility_without_splits(p, &light, &tris, Some(own));
        if v > 1e-6 && v < 1.0 - 1e-6 {
            partial += 1;
        }
    }
    println!(
        "{} triangles, {count} points: {:?} per point",
        tris.len(),
        start.elapsed() / count
    );
    assert!(partial > 5, "only {partial} penumbra points");
}
