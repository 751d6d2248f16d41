//! The union area of the exact evaluator: against inclusion-exclusion, coordinate compression
//! and slab decomposition, on rectangles, random and lattice triangles, slivers and non-finite
//! input.

use glam::DVec2;

use super::exact_tests::{SEED, brute_union_of_rects, rect};
use super::*;
use crate::rng::Rng;

/// Intersection of two convex counter-clockwise polygons, by clipping `a` against each edge of
/// `b` (written independently of the module's clipper).
fn convex_intersection(a: &[DVec2], b: &[DVec2]) -> Vec<DVec2> {
    let mut cur = a.to_vec();
    for i in 0..b.len() {
        let (e0, e1) = (b[i], b[(i + 1) % b.len()]);
        let side = |q: DVec2| (e1 - e0).perp_dot(q - e0);
        let mut next = Vec::new();
        for k in 0..cur.len() {
            let (p, q) = (cur[k], cur[(k + 1) % cur.len()]);
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                next.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                next.push(p + (q - p) * (sp / (sp - sq)));
            }
        }
        cur = next;
        if cur.is_empty() {
            break;
        }
    }
    cur
}

fn random_ccw_triangle(rng: &mut Rng, lo: f64, hi: f64) -> Vec<DVec2> {
    loop {
        let mut t: Vec<DVec2> = (0..3)
            .map(|_| DVec2::new(rng.range(lo, hi), rng.range(lo, hi)))
            .collect();
        let a = polygon_area(&t);
        if a.abs() > 1e-3 {
            if a < 0.0 {
                t.reverse();
            }
            return t;
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Polygon helpers.

#[test]
fn polygon_area_is_signed_shoelace() {
    let r = rect(-0.5, -0.25, 0.5, 0.75);
    assert_eq!(polygon_area(&r), 1.0);
    let mut rev = r.clone();
    rev.reverse();
    assert_eq!(polygon_area(&rev), -1.0);
    assert_eq!(polygon_area(&r[..2]), 0.0);
}

#[test]
fn clip_to_rect_keeps_inside_and_cuts_outside() {
    let inside = rect(-0.5, -0.5, 0.5, 0.5);
    assert_eq!(clip_polygon_to_rect(&inside), inside);
    let big = rect(-3.0, -2.0, 4.0, 5.0);
    let clipped = clip_polygon_to_rect(&big);
    assert!((polygon_area(&clipped) - 4.0).abs() < 1e-15);
    assert!(clipped.iter().all(|v| v.x.abs() <= 1.0 && v.y.abs() <= 1.0));
    let outside = rect(1.5, 1.5, 2.0, 2.0);
    assert!(clip_polygon_to_rect(&outside).is_empty());
    // A triangle poking out of one edge loses its tip, with the cut exactly on x = 1.
    let tri = [
        DVec2::new(0.0, 0.0),
        DVec2::new(2.0, 0.0),
        DVec2::new(0.0, 2.0),
    ];
    let c = clip_polygon_to_rect(&tri);
    assert!((polygon_area(&c) - (2.0 - 0.5 - 0.5)).abs() < 1e-15);
    assert!(c.iter().any(|v| v.x == 1.0));
}

// ---------------------------------------------------------------------------------------------
// Union area.

#[test]
fn union_of_one_square_is_its_area() {
    assert_eq!(union_area(&[rect(-0.5, -0.5, 0.25, 0.5)]), 0.75);
    assert!((union_area(&[rect(-2.0, -2.0, 2.0, 2.0)]) - 4.0).abs() < 1e-15);
    assert_eq!(union_area(&[]), 0.0);
}

#[test]
fn union_of_two_overlapping_squares_is_inclusion_exclusion() {
    let a = rect(-0.8, -0.6, 0.2, 0.4);
    let b = rect(-0.3, -0.1, 0.6, 0.9);
    // |A| + |B| - |A n B| = 1 + 0.9 - 0.5 * 0.5.
    let expected = 1.0 + 0.9 - 0.5 * 0.5;
    assert!((union_area(&[a.clone(), b.clone()]) - expected).abs() < 1e-12);
    // Orientation does not matter.
    let mut b_cw = b;
    b_cw.reverse();
    assert!((union_area(&[a, b_cw]) - expected).abs() < 1e-12);
}

#[test]
fn union_of_identical_polygons_counts_once() {
    let a = rect(-0.3, -0.2, 0.5, 0.6);
    let t = vec![
        DVec2::new(-0.9, -0.9),
        DVec2::new(0.7, -0.5),
        DVec2::new(0.1, 0.8),
    ];
    let area_t = polygon_area(&t);
    assert!((union_area(&[a.clone(), a.clone()]) - 0.64).abs() < 1e-12);
    let three = [t.clone(), t.clone(), t.clone()];
    assert!((union_area(&three) - area_t).abs() < 1e-12);
}

/// A square tiled by the two triangles of every cell of a grid (random diagonals), shared
/// edges and all, has the square's area.
#[test]
fn union_of_triangulated_grid_is_the_square() {
    let mut rng = Rng::new(SEED);
    for (lo, hi, n) in [(-0.7, 0.55, 7usize), (-1.0, 1.0, 10), (-1.5, 0.5, 13)] {
        let at = |i: usize, j: usize| {
            let s = |k: usize| lo + (hi - lo) * k as f64 / n as f64;
            DVec2::new(s(i), s(j))
        };
        let mut tris = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                if rng.next_f64() < 0.5 {
                    tris.push(vec![a, b, c]);
                    tris.push(vec![a, c, d]);
                } else {
                    tris.push(vec![a, b, d]);
                    tris.push(vec![b, c, d]);
                }
            }
        }
        let side = hi.min(1.0) - lo.max(-1.0);
        let got = union_area(&tris);
        assert!(
            (got - side * side).abs() < 1e-12,
            "grid [{lo}, {hi}]^2 of {n}: {got} vs {}",
            side * side
        );
    }
}

#[test]
fn union_of_random_rectangles_matches_coordinate_compression() {
    let mut rng = Rng::new(SEED);
    for case in 0..200 {
        let count = 1 + rng.below(12);
        let rects: Vec<[f64; 4]> = (0..count)
            .map(|_| {
                let (x, y) = (rng.range(-1.3, 1.1), rng.range(-1.3, 1.1));
                [x, y, x + rng.range(0.01, 1.0), y + rng.range(0.01, 1.0)]
            })
            .collect();
        let polys: Vec<Vec<DVec2>> = rects.iter().map(|r| rect(r[0], r[1], r[2], r[3])).collect();
        let (got, expected) = (union_area(&polys), brute_union_of_rects(&rects));
        assert!(
            (got - expected).abs() < 1e-9,
            "case {case}: {got} vs {expected}"
        );
    }
}

/// Random triangles, two and three at a time, against inclusion-exclusion with convex
/// intersections: exercises crossing constraints at arbitrary angles.
#[test]
fn union_of_random_triangles_matches_inclusion_exclusion() {
    let mut rng = Rng::new(SEED);
    let area = |p: &[DVec2]| polygon_area(p).abs();
    for case in 0..300 {
        let (a, b, c) = (
            random_ccw_triangle(&mut rng, -0.95, 0.95),
            random_ccw_triangle(&mut rng, -0.95, 0.95),
            random_ccw_triangle(&mut rng, -0.95, 0.95),
        );
        let ab = convex_intersection(&a, &b);
        let two = area(&a) + area(&b) - area(&ab);
        let got = union_area(&[a.clone(), b.clone()]);
        assert!((got - two).abs() < 1e-9, "case {case}: {got} vs {two}");

        let (ac, bc) = (convex_intersection(&a, &c), convex_intersection(&b, &c));
        let abc = convex_intersection(&ab, &c);
        let three = area(&a) + area(&b) + area(&c) - area(&ab) - area(&ac) - area(&bc) + area(&abc);
        let got = union_area(&[a, b, c]);
        assert!((got - three).abs() < 1e-9, "case {case}: {got} vs {three}");
    }
}

#[test]
fn union_ignores_slivers_and_non_finite_polygons() {
    let a = rect(-0.5, -0.5, 0.5, 0.5);
    let sliver = vec![
        DVec2::new(-1.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(0.0, 1e-16),
    ];
    let nan = vec![
        DVec2::new(f64::NAN, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(0.0, 1.0),
    ];
    let repeated = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(0.0, 0.0),
        DVec2::new(0.9, 0.0),
        DVec2::new(0.9, 0.0),
        DVec2::new(0.9, 0.9),
        DVec2::new(0.0, 0.0),
    ];
    let got = union_area(&[a, sliver, nan, repeated]);
    let expected = 1.0 + 0.5 * 0.81 - 0.5 * 0.25;
    assert!((got - expected).abs() < 1e-12, "{got} vs {expected}");
}

// ---------------------------------------------------------------------------------------------
// Visibility: parallel axis-aligned quads under a light facing down.

/// Union area within `[-1, 1]^2` by vertical slabs, independent of the triangulation: between
/// consecutive x-coordinates of vertices and edge crossings (the square's edges included) no two
/// edges cross, so the covered
/// length is linear across a slab and the slab's area is its width times the covered length at
/// its middle (even-odd rule per polygon, union over polygons).
fn slab_union_area(polys: &[Vec<DVec2>]) -> f64 {
    // The square's bottom and top are included: where an edge crosses them the clamped length
    // bends.
    let square = rect(-1.0, -1.0, 1.0, 1.0);
    let edges: Vec<(DVec2, DVec2)> = polys
        .iter()
        .chain(std::iter::once(&square))
        .flat_map(|p| (0..p.len()).map(move |i| (p[i], p[(i + 1) % p.len()])))
        .collect();
    let mut xs: Vec<f64> = vec![-1.0, 1.0];
    xs.extend(polys.iter().flatten().map(|v| v.x.clamp(-1.0, 1.0)));
    for (i, &(a, b)) in edges.iter().enumerate() {
        for &(c, d) in &edges[i + 1..] {
            let den = (b - a).perp_dot(d - c);
            if den == 0.0 {
                continue;
            }
            let t = (c - a).perp_dot(d - c) / den;
            let u = (c - a).perp_dot(b - a) / den;
            if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u) {
                xs.push((a.x + (b.x - a.x) * t).clamp(-1.0, 1.0));
            }
        }
    }
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    let mut area = 0.0;
    for w in xs.windows(2) {
        let x = 0.5 * (w[0] + w[1]);
        let mut intervals: Vec<(f64, f64)> = Vec::new();
        for p in polys {
            let mut ys: Vec<f64> = (0..p.len())
                .filter_map(|i| {
                    let (a, b) = (p[i], p[(i + 1) % p.len()]);
                    ((a.x > x) != (b.x > x)).then(|| a.y + (b.y - a.y) * (x - a.x) / (b.x - a.x))
                })
                .collect();
            ys.sort_by(f64::total_cmp);
            intervals.extend(
                ys.chunks(2)
                    .map(|c| (c[0].max(-1.0), c[1].min(1.0)))
                    .filter(|(lo, hi)| lo < hi),
            );
        }
        intervals.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (mut length, mut reach) = (0.0, -1.0f64);
        for (lo, hi) in intervals {
            if hi > reach {
                length += hi - lo.max(reach);
                reach = hi;
            }
        }
        area += (w[1] - w[0]) * length;
    }
    area
}

/// [`union_area`] through the internal entry point, asserting that no fragment needed spade's
/// splitting insertion.
fn union_area_without_splits(polys: &[Vec<DVec2>]) -> f64 {
    let clean: Vec<Vec<DVec2>> = polys
        .iter()
        .filter_map(|p| finish_polygon(clip_polygon_to_rect(p)))
        .collect();
    let u = union_area_of_clean(&clean);
    assert_eq!(u.split_fallbacks, 0, "snap-rounded fragments crossed");
    u.area
}

/// Triangles with vertices on coarse lattices (dyadic and not): shared and collinear edges,
/// edges through vertices, many crossings at one point. Before snap rounding, spade's splitting
/// insertion panicked or looped on about one case in five of these
/// (`assertion failed: !previous_region.is_empty() || from == final_vertex`).
#[test]
fn union_of_lattice_triangles_matches_slab_decomposition() {
    let mut rng = Rng::new(SEED);
    for case in 0..400 {
        let (step, origin) = [(0.25, -1.25), (0.125, -1.25), (0.1, -1.2), (0.25, -1.2)][case % 4];
        let m = (2.5 / step) as usize;
        let count = 2 + rng.below(40);
        let polys: Vec<Vec<DVec2>> = (0..count)
            .map(|_| {
                (0..3)
                    .map(|_| {
                        DVec2::new(
                            origin + step * rng.below(m + 1) as f64,
                            origin + step * rng.below(m + 1) as f64,
                        )
                    })
                    .collect()
            })
            .collect();
        let got = union_area_without_splits(&polys);
        let expected = slab_union_area(&polys);
        assert!(
            (got - expected).abs() < 1e-9,
            "case {case}: {got} vs {expected}"
        );
        // Order and exact quarter turns change nothing.
        let mut reversed = polys.clone();
        reversed.reverse();
        let turned: Vec<Vec<DVec2>> = polys
            .iter()
            .map(|p| p.iter().map(|v| DVec2::new(-v.y, v.x)).collect())
            .collect();
        for other in [reversed, turned] {
            let v = union_area_without_splits(&other);
            assert!((got - v).abs() < 1e-9, "case {case}: {got} vs {v}");
        }
    }
}

#[test]
fn union_of_random_triangles_matches_slab_decomposition() {
    let mut rng = Rng::new(SEED ^ 2);
    for case in 0..100 {
        let polys: Vec<Vec<DVec2>> = (0..2 + rng.below(60))
            .map(|_| {
                let c = DVec2::new(rng.range(-1.3, 1.3), rng.range(-1.3, 1.3));
                let r = rng.range(0.01, 0.8);
                (0..3)
                    .map(|_| c + DVec2::new(rng.range(-r, r), rng.range(-r, r)))
                    .collect()
            })
            .collect();
        let got = union_area_without_splits(&polys);
        let expected = slab_union_area(&polys);
        assert!(
            (got - expected).abs() < 1e-9,
            "case {case}: {got} vs {expected}"
        );
    }
}
