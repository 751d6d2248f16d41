//! Tests of the exact point evaluator: union areas against closed forms, visibility against the
//! closed form of parallel axis-aligned quads, clipping against hand-clipped triangles, and a
//! sphere against brute-force ray casting.

use glam::{DMat3, DVec2, DVec3};

use super::exact_scene_tests::{ray_cast_visibility, uv_sphere};
use super::*;
use crate::rng::Rng;

pub(super) const SEED: u64 = 0x5EED_E8AC;

/// Counter-clockwise axis-aligned rectangle `[x0, x1] x [y0, y1]`.
pub(super) fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<DVec2> {
    vec![
        DVec2::new(x0, y0),
        DVec2::new(x1, y0),
        DVec2::new(x1, y1),
        DVec2::new(x0, y1),
    ]
}

/// Union area of axis-aligned rectangles `[x0, y0, x1, y1]` within `[-1, 1]^2` by coordinate
/// compression: every cell of the grid of all rectangle edges is inside or outside as a whole.
pub(super) fn brute_union_of_rects(rects: &[[f64; 4]]) -> f64 {
    let clamp = |s: f64| s.clamp(-1.0, 1.0);
    let mut xs = vec![-1.0, 1.0];
    let mut ys = vec![-1.0, 1.0];
    for r in rects {
        xs.extend([clamp(r[0]), clamp(r[2])]);
        ys.extend([clamp(r[1]), clamp(r[3])]);
    }
    xs.sort_by(f64::total_cmp);
    ys.sort_by(f64::total_cmp);
    let mut area = 0.0;
    for i in 0..xs.len() - 1 {
        for j in 0..ys.len() - 1 {
            let mx = 0.5 * (xs[i] + xs[i + 1]);
            let my = 0.5 * (ys[j] + ys[j + 1]);
            if rects
                .iter()
                .any(|r| r[0] < mx && mx < r[2] && r[1] < my && my < r[3])
            {
                area += (xs[i + 1] - xs[i]) * (ys[j + 1] - ys[j]);
            }
        }
    }
    area
}

/// Light at height `h_light` facing down (-Y), its sides along X and Z.
pub(super) fn light_facing_down(h_light: f64, center_xz: DVec2, size: DVec2) -> RectLight {
    RectLight::new(
        DVec3::new(center_xz.x, h_light, center_xz.y),
        DVec3::NEG_Y,
        DVec3::X,
        size,
    )
    .unwrap()
}

/// The horizontal quad `[x0, x1] x [z0, z1]` at height `y` as two triangles sharing the
/// diagonal from `(x0, z0)` to `(x1, z1)`.
pub(super) fn quad(x0: f64, x1: f64, z0: f64, z1: f64, y: f64) -> [[DVec3; 3]; 2] {
    let (a, b, c, d) = (
        DVec3::new(x0, y, z0),
        DVec3::new(x1, y, z0),
        DVec3::new(x1, y, z1),
        DVec3::new(x0, y, z1),
    );
    [[a, b, c], [a, c, d]]
}

/// The same quad as four triangles fanned around its centre.
fn quad_fan(x0: f64, x1: f64, z0: f64, z1: f64, y: f64) -> [[DVec3; 3]; 4] {
    let (a, b, c, d) = (
        DVec3::new(x0, y, z0),
        DVec3::new(x1, y, z0),
        DVec3::new(x1, y, z1),
        DVec3::new(x0, y, z1),
    );
    let m = (a + c) * 0.5;
    [[a, b, m], [b, c, m], [c, d, m], [d, a, m]]
}

/// Closed form: occluded fraction of a light facing down at `light` height seen from `p` through
/// horizontal quads `[x0, x1, z0, z1, y]`, by projecting each quad's corners from `p` onto the
/// light plane (`c' = p + (c - p) * (H - p.y) / (y - p.y)`) and measuring the union of the
/// projected rectangles inside the light by coordinate compression.
fn closed_form_visibility(p: DVec3, light: &RectLight, quads: &[[f64; 5]]) -> f64 {
    let h_light = light.center.y;
    let half = light.half_size();
    let rects: Vec<[f64; 4]> = quads
        .iter()
        .filter(|q| q[4] > p.y && q[4] < h_light)
        .map(|q| {
            let s = (h_light - p.y) / (q[4] - p.y);
            // In light space: x along X, y along Z (the bitangent), both scaled to [-1, 1].
            let u = |x: f64| (p.x + (x - p.x) * s - light.center.x) / half.x;
            let v = |z: f64| (p.z + (z - p.z) * s - light.center.z) / half.y;
            [u(q[0]), v(q[2]), u(q[1]), v(q[3])]
        })
        .collect();
    1.0 - brute_union_of_rects(&rects) / 4.0
}

#[test]
fn quad_matches_closed_form_at_random_points() {
    let mut rng = Rng::new(SEED);
    let light = light_facing_down(4.0, DVec2::new(0.3, -0.2), DVec2::new(1.5, 0.8));
    let q = [-0.6, 0.4, -0.3, 0.5, 2.0];
    let two = quad(q[0], q[1], q[2], q[3], q[4]);
    let other_diagonal = [
        [two[0][0], two[0][1], two[1][2]],
        [two[0][1], two[0][2], two[1][2]],
    ];
    let fan = quad_fan(q[0], q[1], q[2], q[3], q[4]);
    let mut partial = 0;
    for i in 0..1000 {
        let p = DVec3::new(rng.range(-3.0, 3.0), 0.0, rng.range(-3.0, 3.0));
        let expected = closed_form_visibility(p, &light, &[q]);
        let got = exact_visibility(p, &light, &two, None);
        assert!(
            (got.visibility - expected).abs() < 1e-9,
            "point {i} {p}: {} vs {expected}",
            got.visibility
        );
        assert!((got.visibility - (1.0 - got.occluded_area / 4.0)).abs() < 1e-15);
        let v2 = exact_visibility(p, &light, &other_diagonal, None).visibility;
        let v4 = exact_visibility(p, &light, &fan, None).visibility;
        assert!((v2 - expected).abs() < 1e-9 && (v4 - expected).abs() < 1e-9);
        if expected > 1e-6 && expected < 1.0 - 1e-6 {
            partial += 1;
        }
    }
    // The sample must actually exercise the penumbra.
    assert!(partial > 100, "only {partial} penumbra points");
}

#[test]
fn several_quads_match_closed_form_union() {
    let mut rng = Rng::new(SEED ^ 1);
    let light = light_facing_down(5.0, DVec2::new(0.0, 0.0), DVec2::new(2.0, 1.0));
    for case in 0..50 {
        let quads: Vec<[f64; 5]> = (0..1 + rng.below(6))
            .map(|_| {
                let (x, z) = (rng.range(-1.5, 1.0), rng.range(-1.5, 1.0));
                let y = rng.range(0.5, 4.5);
                [x, x + rng.range(0.1, 1.0), z, z + rng.range(0.1, 1.0), y]
            })
            .collect();
        let tris: Vec<[DVec3; 3]> = quads
            .iter()
            .flat_map(|q| quad(q[0], q[1], q[2], q[3], q[4]))
            .collect();
        for _ in 0..20 {
            let p = DVec3::new(
                rng.range(-2.0, 2.0),
                rng.range(0.0, 0.4),
                rng.range(-2.0, 2.0),
            );
            let expected = closed_form_visibility(p, &light, &quads);
            let got = exact_visibility(p, &light, &tris, None).visibility;
            assert!(
                (got - expected).abs() < 1e-9,
                "case {case} {p}: {got} vs {expected}"
            );
        }
    }
}

#[test]
fn point_on_the_wrong_side_sees_nothing() {
    let light = light_facing_down(4.0, DVec2::ZERO, DVec2::ONE);
    for p in [
        DVec3::new(0.0, 5.0, 0.0),
        DVec3::new(0.0, 4.0, 0.0),
        DVec3::new(9.0, 4.5, -2.0),
        DVec3::new(f64::NAN, 1.0, 0.0),
    ] {
        let v = exact_visibility(p, &light, &[], None);
        assert_eq!(v.visibility, 0.0, "{p}");
        assert_eq!(v.occluded_area, 4.0);
    }
    assert_eq!(
        exact_visibility(DVec3::ZERO, &light, &[], None).visibility,
        1.0
    );
}

#[test]
fn triangle_beyond_the_light_does_not_occlude() {
    let light = light_facing_down(4.0, DVec2::ZERO, DVec2::ONE);
    let tris = quad(-10.0, 10.0, -10.0, 10.0, 4.5);
    let v = exact_visibility(DVec3::new(0.1, 0.0, -0.2), &light, &tris, None);
    assert_eq!(v.visibility, 1.0);
    assert_eq!(v.polygons, 0);
}

#[test]
fn occluder_covering_the_light_gives_zero() {
    let light = light_facing_down(4.0, DVec2::new(0.5, 0.5), DVec2::new(2.0, 3.0));
    let tris = quad(-10.0, 10.0, -10.0, 10.0, 2.0);
    for p in [
        DVec3::ZERO,
        DVec3::new(1.0, 1.0, -1.0),
        DVec3::new(3.0, 1.9, 2.0),
    ] {
        // Two triangles: the shared diagonal costs a few ulps of the square's area.
        let v = exact_visibility(p, &light, &tris, None);
        assert!(v.visibility < 1e-12, "{p}: {}", v.visibility);
        let one = exact_visibility(
            p,
            &light,
            &[[
                DVec3::new(-20.0, 2.0, -20.0),
                DVec3::new(40.0, 2.0, -20.0),
                DVec3::new(-20.0, 2.0, 40.0),
            ]],
            None,
        );
        assert_eq!(one.visibility, 0.0, "{p}");
    }
    // Many small tiles covering the light's whole image, seen from the origin.
    let mut tiles = Vec::new();
    for i in 0..10 {
        for j in 0..10 {
            let (x, z) = (-2.0 + 0.4 * i as f64, -2.0 + 0.4 * j as f64);
            tiles.extend(quad(x, x + 0.4, z, z + 0.4, 2.0));
        }
    }
    let v = exact_visibility(DVec3::new(0.5, 0.0, 0.5), &light, &tiles, None);
    assert!(v.visibility.abs() < 1e-12, "{}", v.visibility);
}

#[test]
fn receiver_triangle_and_coplanar_neighbours_do_not_occlude() {
    let light = light_facing_down(4.0, DVec2::ZERO, DVec2::ONE);
    // The receiver's own triangle, tilted, containing p: occludes only when not excluded.
    let p = DVec3::new(0.2, 1.0, 0.1);
    let tri = [
        DVec3::new(-3.0, 0.0, -3.0),
        DVec3::new(3.0, 2.0, -3.0),
        DVec3::new(0.0, 1.0, 3.0),
    ];
    let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
    let p = p - n * (n.dot(p - tri[0]) / n.length_squared());
    assert_eq!(exact_visibility(p, &light, &[tri], Some(0)).visibility, 1.0);
    // A ground made of two triangles: p on the first, the second coplanar, a tilted light.
    let n = DVec3::new(0.4, -1.0, 0.3).normalize();
    let tilted = RectLight::new(
        DVec3::new(0.5, 3.0, 0.2),
        n,
        n.cross(DVec3::Z).normalize(),
        DVec2::new(2.0, 1.0),
    )
    .unwrap();
    let ground = quad(-5.0, 5.0, -5.0, 5.0, 0.0);
    let mut rng = Rng::new(SEED);
    for _ in 0..100 {
        let p = DVec3::new(rng.range(-4.0, 4.0), 0.0, rng.range(-4.0, 4.0));
        // quad() splits along the diagonal from (-5, -5) to (5, 5): z <= x is triangle 0.
        let own = if p.z <= p.x { 0 } else { 1 };
        let v = exact_visibility(p, &tilted, &ground, Some(own));
        if tilted.is_lit_side(p) {
            assert_eq!(v.visibility, 1.0, "{p}");
        }
    }
}

/// Triangles crossing the near plane or the light plane equal the same triangles clipped by hand
/// to the slab between them.
#[test]
fn crossing_triangles_equal_hand_clipped_ones() {
    let light = light_facing_down(4.0, DVec2::new(0.2, 0.0), DVec2::new(2.0, 1.5));
    let p = DVec3::new(0.1, 1.0, -0.3);
    // Slanted triangle from below the receiver's height to above the light.
    let tri = [
        DVec3::new(-2.0, -1.0, 1.0),
        DVec3::new(2.5, -1.0, 1.5),
        DVec3::new(0.5, 6.0, -1.5),
    ];
    let clip_y = |poly: Vec<DVec3>, y: f64, keep_above: bool| -> Vec<DVec3> {
        let f = |v: DVec3| if keep_above { v.y - y } else { y - v.y };
        let mut out = Vec::new();
        for i in 0..poly.len() {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            if f(a) >= 0.0 {
                out.push(a);
            }
            if (f(a) >= 0.0) != (f(b) >= 0.0) {
                out.push(a + (b - a) * (f(a) / (f(a) - f(b))));
            }
        }
        out
    };
    let piece = clip_y(clip_y(tri.to_vec(), p.y, true), 4.0, false);
    let fan: Vec<[DVec3; 3]> = (1..piece.len() - 1)
        .map(|i| [piece[0], piece[i], piece[i + 1]])
        .collect();
    let whole = exact_visibility(p, &light, &[tri], None);
    let clipped = exact_visibility(p, &light, &fan, None);
    assert!(
        whole.visibility > 0.01 && whole.visibility < 0.99,
        "{}",
        whole.visibility
    );
    let sampled = ray_cast_visibility(p, &light, &[tri], 128, &mut Rng::new(SEED));
    assert!(
        (whole.visibility - sampled).abs() < 2e-3,
        "{} vs ray cast {sampled}",
        whole.visibility
    );
    assert!(
        (whole.visibility - clipped.visibility).abs() < 1e-9,
        "{} vs {}",
        whole.visibility,
        clipped.visibility
    );
}

#[test]
fn degenerate_triangles_never_give_nan() {
    let light = light_facing_down(4.0, DVec2::ZERO, DVec2::new(2.0, 2.0));
    let a = DVec3::new(-0.5, 2.0, -0.5);
    let b = DVec3::new(0.5, 2.0, -0.5);
    let c = DVec3::new(0.0, 2.0, 0.5);
    let tris = [
        [a, a, a],
        [a, a, b],
        [a, b, (a + b) * 0.5],
        [a, b, a * 2.0 - b],
        [DVec3::new(0.0, -1.0, 0.0), DVec3::new(0.0, 8.0, 0.0), c],
        [
            DVec3::new(-5.0, 0.0, 0.0),
            DVec3::new(5.0, 0.0, 0.0),
            DVec3::new(0.0, 0.0, 3.0),
        ],
        [
            DVec3::new(-5.0, -1.0, 1.0),
            DVec3::new(5.0, 1.0, 1.0),
            DVec3::new(0.0, 9.0, 1.0),
        ],
        [DVec3::new(f64::NAN, 2.0, 0.0), b, c],
        [DVec3::new(f64::INFINITY, 2.0, 0.0), b, c],
        [
            DVec3::new(1e300, 2.0, 0.0),
            DVec3::new(-1e300, 2.0, 1e-300),
            c,
        ],
    ];
    let mut rng = Rng::new(SEED);
    for _ in 0..200 {
        let p = DVec3::new(
            rng.range(-2.0, 2.0),
            rng.range(-0.5, 3.0),
            rng.range(-2.0, 2.0),
        );
        for t in &tris {
            let v = exact_visibility(p, &light, std::slice::from_ref(t), None);
            assert!((0.0..=1.0).contains(&v.visibility), "{p} {t:?}: {v:?}");
            assert!(v.occluded_area.is_finite());
        }
        let v = exact_visibility(p, &light, &tris, None);
        assert!((0.0..=1.0).contains(&v.visibility), "{p}: {v:?}");
        // P at a vertex of a triangle, and P on its edge.
        for q in [a, (a + b) * 0.5] {
            let v = exact_visibility(q, &light, &[[a, b, p]], None);
            assert!((0.0..=1.0).contains(&v.visibility), "{q} {p}: {v:?}");
        }
    }
}

#[test]
fn project_triangle_stays_in_the_square() {
    let mut rng = Rng::new(SEED);
    let mut kept = 0;
    for _ in 0..5000 {
        let p = DVec3::new(
            rng.range(-3.0, 3.0),
            rng.range(-3.0, 3.0),
            rng.range(0.01, 3.0),
        );
        let tri = [0; 3].map(|_| {
            DVec3::new(
                rng.range(-4.0, 4.0),
                rng.range(-4.0, 4.0),
                rng.range(-1.0, 4.0),
            )
        });
        if let Some(poly) = project_triangle(p, tri) {
            kept += 1;
            assert!(poly.len() >= 3 && poly.len() <= 8);
            assert!(poly.iter().all(|v| v.x.abs() <= 1.0 && v.y.abs() <= 1.0));
            assert!(polygon_area(&poly) >= MIN_POLYGON_AREA);
            assert!(poly.windows(2).all(|w| w[0] != w[1]));
        }
    }
    assert!(kept > 500, "{kept}");
}

// ---------------------------------------------------------------------------------------------
// Invariance and a curved occluder.

/// Rotating, translating and scaling the scene together with its light leaves visibility alone.
#[test]
fn visibility_is_invariant_under_similarity() {
    let mut rng = Rng::new(SEED);
    let light = light_facing_down(4.0, DVec2::new(0.3, -0.2), DVec2::new(1.5, 0.8));
    let tris = uv_sphere(DVec3::new(0.2, 2.0, 0.0), 0.7, 8, 10);
    let rot = DMat3::from_axis_angle(DVec3::new(1.0, 2.0, -0.5).normalize(), 0.9);
    let (scale, shift) = (2.5, DVec3::new(-3.0, 7.0, 1.0));
    let f = |v: DVec3| rot * v * scale + shift;
    let moved_light = RectLight::new(
        f(light.center),
        rot * light.normal,
        rot * light.tangent,
        light.size * scale,
    )
    .unwrap();
    let moved: Vec<[DVec3; 3]> = tris.iter().map(|t| t.map(f)).collect();
    for _ in 0..30 {
        let p = DVec3::new(rng.range(-2.0, 2.0), 0.0, rng.range(-2.0, 2.0));
        let v = exact_visibility(p, &light, &tris, None).visibility;
        let w = exact_visibility(f(p), &moved_light, &moved, None).visibility;
        assert!((v - w).abs() < 1e-9, "{p}: {v} vs {w}");
    }
}
