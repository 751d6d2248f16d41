//! `quad-over-plane` has a closed form: from a receiver at height `y` under the 2x2 quad at
//! height `h = 1` and the 2x2 light at `H = 4` (both centred on the y axis, both horizontal), the
//! quad projects onto the light plane as the axis-aligned square
//! `P + (c - P)·(H - y)/(h - y)`, and the occluded fraction is its overlap with the light
//! rectangle divided by the light's area.

use glam::{DVec2, DVec3};
use penumbra::geom::compare;
use penumbra::geom::exact_visibility;
use penumbra::geom::{LightSamples, Reference};
use penumbra::geom::{Rng, Scene, VisibilityImage};

use crate::common::load;

const QUAD_HALF: f64 = 1.0;
const QUAD_Y: f64 = 1.0;

/// Closed-form V at `p` for the `quad-over-plane` fixture (receivers below the quad).
fn closed_form(scene: &Scene, p: DVec3) -> f64 {
    let l = &scene.lit(0).light;
    let big_h = l.center.y;
    let s = (big_h - p.y) / (QUAD_Y - p.y);
    let proj = |c: f64, pc: f64| pc + (c - pc) * s;
    let lo = DVec2::new(proj(-QUAD_HALF, p.x), proj(-QUAD_HALF, p.z));
    let hi = DVec2::new(proj(QUAD_HALF, p.x), proj(QUAD_HALF, p.z));
    let half = l.size * 0.5;
    let lmin = DVec2::new(l.center.x, l.center.z) - half;
    let lmax = DVec2::new(l.center.x, l.center.z) + half;
    let ov = (hi.min(lmax) - lo.max(lmin)).max(DVec2::ZERO);
    1.0 - ov.x * ov.y / l.area()
}

fn check_fixture_is_what_the_closed_form_assumes(scene: &Scene) {
    let l = &scene.lit(0).light;
    assert_eq!(l.normal, DVec3::NEG_Y);
    assert_eq!((l.center.x, l.center.z), (0.0, 0.0));
    let quad = &scene.meshes[1].mesh;
    for p in &quad.positions {
        assert_eq!(p.y, QUAD_Y);
        assert_eq!((p.x.abs(), p.z.abs()), (QUAD_HALF, QUAD_HALF));
    }
}

#[test]
fn exact_evaluator_matches_the_closed_form_at_1000_points() {
    let scene = load("quad-over-plane");
    check_fixture_is_what_the_closed_form_assumes(&scene);
    let tris = scene.triangles();
    let mut rng = Rng::new(20261122);
    let mut worst: f64 = 0.0;
    let mut penumbra = 0;
    for _ in 0..1000 {
        // Receivers on the ground (its two triangles excluded as P's own), and in the air
        // between ground and quad, where nothing is excluded.
        let on_ground = rng.next_f64() < 0.7;
        let y = if on_ground { 0.0 } else { rng.range(0.0, 0.95) };
        let p = DVec3::new(rng.range(-2.2, 2.2), y, rng.range(-2.2, 2.2));
        let exclude = on_ground.then(|| {
            // The ground is the first mesh: triangles 0 and 1; find the one holding p.
            let inside = |t: &[DVec3; 3]| {
                let s = |a: DVec3, b: DVec3| (b.x - a.x) * (p.z - a.z) - (b.z - a.z) * (p.x - a.x);
                let d = [s(t[0], t[1]), s(t[1], t[2]), s(t[2], t[0])];
                d.iter().all(|&x| x >= 0.0) || d.iter().all(|&x| x <= 0.0)
            };
            (0..2).find(|&i| inside(&tris[i])).unwrap()
        });
        let want = closed_form(&scene, p);
        let got = exact_visibility(p, &scene.lit(0).light, &tris, exclude).visibility;
        if want > 0.0 && want < 1.0 {
            penumbra += 1;
        }
        worst = worst.max((got - want).abs());
        assert!(
            (got - want).abs() <= 1e-5,
            "at {p}: exact {got}, closed form {want}"
        );
    }
    println!(
        "exact vs closed form: max |error| {worst:.3e} over 1000 points, {penumbra} in penumbra"
    );
    assert!(
        penumbra > 300,
        "too few penumbra points ({penumbra}) to mean anything"
    );
}

#[test]
fn reference_1024_is_within_2e_3_of_the_closed_form() {
    let scene = load("quad-over-plane");
    check_fixture_is_what_the_closed_form_assumes(&scene);
    let reference = Reference::new(&scene.lit(0));
    let tracer = &reference.tracer;
    let img = reference.render(LightSamples::Stratified { per_axis: 32 }, &|_| {});
    let cam = &scene.camera;
    let mut truth = VisibilityImage::filled(cam.width, cam.height, 1.0);
    for j in 0..cam.height {
        for i in 0..cam.width {
            if let Some(p) = tracer.surface_point(cam.eye, cam.ray_dir(i, j)) {
                // Points on top of the quad see the whole light.
                let v = if p.position.y >= QUAD_Y - 1e-9 {
                    1.0
                } else {
                    closed_form(&scene, p.position)
                };
                truth.data[(j * cam.width + i) as usize] = v as f32;
            }
        }
    }
    let c = compare(&img, &truth).unwrap();
    // Expected penumbra MAE if every pixel erred like plain Monte Carlo with 1024 samples:
    // E|N(0, σ)| = σ·sqrt(2/π), σ = sqrt(V(1 - V)/1024). Stratification must do no worse.
    let (mut plain_mc, mut count) = (0.0, 0);
    for &v in &truth.data {
        if v > 0.02 && v < 0.98 {
            plain_mc +=
                (v as f64 * (1.0 - v as f64) / 1024.0).sqrt() * (2.0 / std::f64::consts::PI).sqrt();
            count += 1;
        }
    }
    let plain_mc = plain_mc / count as f64;
    println!(
        "reference (1024) vs closed form: MAE {:.2e}, p99 {:.2e}; penumbra ({} px): MAE {:.2e} \
         (plain Monte Carlo would give {plain_mc:.2e})",
        c.all.mae, c.all.p99, c.penumbra.pixels, c.penumbra.mae
    );
    assert!(
        c.penumbra.pixels > 2000,
        "the fixture must show a real penumbra"
    );
    assert!(c.all.mae <= 2e-3, "MAE {}", c.all.mae);
    assert!(
        c.penumbra.mae <= plain_mc,
        "penumbra MAE {} above plain Monte Carlo's {plain_mc}",
        c.penumbra.mae
    );
}
