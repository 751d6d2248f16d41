//! The wedge integral's shortcuts (parts the cone keeps whole or misses, each line's values
//! shared between its two sides) against the plain clipping of every radial part, bit for bit.

use glam::{DVec2, DVec3};
use penumbra_geom::Rng;

use super::*;
use crate::clip::clip_halfplane;

/// The integral as the plain clipping computes it: every part clipped by the cone's two sides,
/// then by the edge's line once for each side (for an edge in front of the light).
fn plain_integral(w: &Wedge, p: DVec3) -> Option<EdgeIntegral> {
    let (a, b) = w.project(p)?;
    if !segment_meets_square(a, b) || cross(a, b) == 0.0 {
        return None;
    }
    let s0 = cross(a, b).signum();
    let side = orient3d(w.from, w.to, DVec3::ZERO, p);
    if side == 0.0 {
        return None;
    }
    let m = w.multiplicity as f64;
    let mut out = EdgeIntegral {
        sign: side.signum(),
        area: [0.0; 4],
        beyond: [Rect::EMPTY; 4],
        near: [Rect::EMPTY; 4],
        cover: [0.0; 4],
    };
    let mut any = false;
    for (k, part) in RADIAL_PARTS.iter().enumerate() {
        let cone = clip_halfplane(part, |x| s0 * cross(a, x));
        let cone = clip_halfplane(&cone, |x| s0 * cross(x, b));
        if cone.len() < 3 {
            continue;
        }
        if let Some((p0, p1)) = clip_segment(part[1], part[2], |x| s0 * cross(a, x))
            .and_then(|(p0, p1)| clip_segment(p0, p1, |x| s0 * cross(x, b)))
        {
            out.cover[k] = (p1 - p0).length();
        }
        let beyond = clip_halfplane(&cone, |x| -s0 * cross(b - a, x - a));
        let near = clip_halfplane(&cone, |x| s0 * cross(b - a, x - a));
        let r = area(&beyond).abs();
        if r > 0.0 {
            out.area[k] = m * r;
            out.beyond[k] = Rect::of(&beyond);
            any = true;
        }
        if near.len() >= 3 {
            out.near[k] = Rect::of(&near);
            any = true;
        }
    }
    any.then_some(out)
}

#[test]
fn integral_matches_the_plain_clipping_bit_for_bit() {
    let mut rng = Rng::new(0x05ee_d0fe_d6e5);
    let mut compared = 0;
    for i in 0..20_000 {
        // Receivers and edges anywhere, and edges whose projections pass through the light's
        // corners and its centre's diagonals, where the shortcuts' conditions tie.
        let p = DVec3::new(
            rng.range(-3.0, 3.0),
            rng.range(-3.0, 3.0),
            rng.range(0.5, 4.0),
        );
        let end = |rng: &mut Rng| {
            let z = rng.range(0.05, 0.95) * p.z;
            let on = match i % 4 {
                0 => DVec2::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0)),
                1 => RADIAL_PARTS[rng.below(4)][1] * rng.range(0.1, 3.0),
                2 => RADIAL_PARTS[rng.below(4)][1],
                _ => DVec2::new(rng.range(-1.0, 1.0), 0.0),
            };
            // The point that projects from p onto `on` in the light's plane.
            let k = p.z / (p.z - z);
            DVec3::new(p.x + (on.x - p.x) / k, p.y + (on.y - p.y) / k, z)
        };
        let w = Wedge {
            from: end(&mut rng),
            to: end(&mut rng),
            multiplicity: 1 + (i % 3) as u32,
            occluder: 0,
            silhouette_loop: 0,
            unit: 0,
            caster: None,
        };
        let (fast, plain) = (w.integral(p), plain_integral(&w, p));
        assert_eq!(fast, plain, "edge {w:?} at {p}");
        compared += usize::from(fast.is_some());
    }
    assert!(compared > 5_000, "only {compared} integrals compared");
}
