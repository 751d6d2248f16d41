//! The wedge integral's shortcuts (parts the cone keeps whole or misses, each line's values
//! shared between its two sides) against the plain clipping of every radial part, bit for bit,
//! and its closed forms for an edge inside one radial part or two against the same, to
//! rounding.

use glam::{DVec2, DVec3};
use penumbra_geom::Rng;

use crate::clip::{RADIAL_PARTS, Rect, area, clip_halfplane, clip_segment, cross};
use crate::silhouette::orient3d;
use crate::wedge::*;
use crate::wedge_integral::*;

/// A receiver point anywhere in front of the light, in light space.
fn random_receiver(rng: &mut Rng) -> DVec3 {
    DVec3::new(
        rng.range(-3.0, 3.0),
        rng.range(-3.0, 3.0),
        rng.range(0.5, 4.0),
    )
}

/// The point at depth `z` (below `p`'s) that projects from `p` onto `on` in the light's plane.
fn projecting_onto(p: DVec3, on: DVec2, z: f64) -> DVec3 {
    let k = p.z / (p.z - z);
    DVec3::new(p.x + (on.x - p.x) / k, p.y + (on.y - p.y) / k, z)
}

/// The wedge of the edge `from -> to` of a mesh in front of the light, `multiplicity` times.
fn front_wedge(from: DVec3, to: DVec3, multiplicity: u32) -> Wedge {
    Wedge {
        from,
        to,
        multiplicity,
        occluder: 0,
        silhouette_loop: 0,
        unit: 0,
        caster: None,
    }
}

/// The integral as the plain clipping computes it: every part clipped by the cone's two sides,
/// then by the edge's line once for each side (for an edge in front of the light).
fn plain_integral(w: &Wedge, p: DVec3) -> Option<EdgeIntegral> {
    // Whether p lies in the wedge is the renderer's own test: this compares what follows it.
    let (a, b) = w.project_onto_light(p)?;
    if cross(a, b) == 0.0 {
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
        let p = random_receiver(&mut rng);
        let end = |rng: &mut Rng| {
            let z = rng.range(0.05, 0.95) * p.z;
            let on = match i % 4 {
                0 => DVec2::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0)),
                1 => RADIAL_PARTS[rng.below(4)][1] * rng.range(0.1, 3.0),
                2 => RADIAL_PARTS[rng.below(4)][1],
                _ => DVec2::new(rng.range(-1.0, 1.0), 0.0),
            };
            // The point that projects from p onto `on` in the light's plane.
            projecting_onto(p, on, z)
        };
        let w = front_wedge(end(&mut rng), end(&mut rng), 1 + (i % 3) as u32);
        let mut out = EdgeIntegral::NONE;
        let fast = w.integral_by(p, &mut out, false).then_some(out);
        let plain = plain_integral(&w, p);
        assert_eq!(fast, plain, "edge {w:?} at {p}");
        compared += usize::from(fast.is_some());
    }
    assert!(compared > 5_000, "only {compared} integrals compared");
}

#[test]
fn closed_forms_inside_the_light_match_the_plain_clipping() {
    let mut rng = Rng::new(0x00c1_05ed);
    // Integrals compared, and those in closed form within one part and across two.
    let (mut compared, mut one, mut two) = (0, 0, 0);
    for i in 0..20_000 {
        let p = random_receiver(&mut rng);
        // Short edges whose projections lie in the light, long ones, and ends on the part
        // boundaries (the diagonals) and near the light's sides.
        let first = DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        let spot = |rng: &mut Rng| match i % 4 {
            0 => first + DVec2::new(rng.range(-0.1, 0.1), rng.range(-0.1, 0.1)),
            1 => DVec2::new(rng.range(-1.2, 1.2), rng.range(-1.2, 1.2)),
            2 => DVec2::splat(rng.range(-1.0, 1.0)) * DVec2::new(1.0, [1.0, -1.0][rng.below(2)]),
            _ => {
                DVec2::new(rng.range(0.999, 1.0), rng.range(-1.0, 1.0)) * [1.0, -1.0][rng.below(2)]
            }
        };
        let end = |rng: &mut Rng, on: DVec2| {
            let z = rng.range(0.05, 0.95) * p.z;
            projecting_onto(p, on, z)
        };
        let (s, t) = (spot(&mut rng), spot(&mut rng));
        let w = front_wedge(end(&mut rng, s), end(&mut rng, t), 1 + (i % 3) as u32);
        let plain = plain_integral(&w, p);
        let got = w.integral(p);
        assert_eq!(got.is_some(), plain.is_some(), "edge {w:?} at {p}");
        let (Some(got), Some(plain)) = (got, plain) else {
            continue;
        };
        compared += 1;
        let (a, b) = w.project(p).expect("it has an integral");
        match (part_within(a), part_within(b)) {
            (Some(ka), Some(kb)) if ka == kb => one += 1,
            (Some(ka), Some(kb)) if (ka + 2) % 4 != kb => two += 1,
            _ => {}
        }
        let close = |x: f64, y: f64| (x - y).abs() <= 1e-9 * (1.0 + x.abs().max(y.abs()));
        let rect_close = |r: Rect, q: Rect| {
            r.is_empty() && q.is_empty()
                || [r.min.x, r.min.y, r.max.x, r.max.y]
                    .iter()
                    .zip([q.min.x, q.min.y, q.max.x, q.max.y])
                    .all(|(&x, y)| close(x, y))
        };
        assert_eq!(got.sign, plain.sign);
        for k in 0..4 {
            assert!(
                close(got.area[k], plain.area[k])
                    && close(got.cover[k], plain.cover[k])
                    && rect_close(got.near[k], plain.near[k])
                    && (plain.area[k] == 0.0 || rect_close(got.beyond[k], plain.beyond[k])),
                "part {k} of edge {w:?} at {p}: {got:?} against {plain:?}"
            );
        }
    }
    assert!(
        compared > 10_000 && one > 5_000 && two > 1_000,
        "{one} closed forms in one part and {two} across two of {compared} integrals"
    );
}

/// Liang & Barsky's loop as the textbook writes it.
fn plain_meets_square(a: DVec2, b: DVec2) -> bool {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-d.x, a.x + 1.0),
        (d.x, 1.0 - a.x),
        (-d.y, a.y + 1.0),
        (d.y, 1.0 - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return false;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    t0 <= t1
}

#[test]
fn a_point_is_in_a_wedge_where_the_projected_edge_meets_the_light_but_for_ties() {
    let mut rng = Rng::new(0x0b5e55ed);
    let (mut inside, mut outside, mut ties) = (0, 0, 0);
    for i in 0..100_000 {
        let p = random_receiver(&mut rng);
        // Ends anywhere in front of p, and ends that project onto the light's corners and
        // sides, where the answer ties. (An end beyond p is clipped to its near plane, a
        // billionth of its depth before it, and projects with a billion times the rounding of
        // the clipped point: its ties are that wide, whichever test decides them.)
        let end = |rng: &mut Rng| {
            let z = rng.range(0.05, 0.95) * p.z;
            let on = match i % 3 {
                0 => DVec2::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0)),
                1 => RADIAL_PARTS[rng.below(4)][1],
                _ => DVec2::new([-1.0, 1.0][rng.below(2)], rng.range(-2.0, 2.0)),
            };
            projecting_onto(p, on, z)
        };
        let w = front_wedge(end(&mut rng), end(&mut rng), 1);
        let ours = w.project_onto_light(p);
        // The projection is the same wherever the edge meets the light.
        if let Some(ends) = ours {
            assert_eq!(Some(ends), w.project(p));
        }
        let Some((a, b)) = w.project(p) else {
            assert!(ours.is_none());
            continue;
        };
        // As in the segment test below: the square grown and shrunk far beyond rounding.
        let m = 1e-9;
        let scaled = |s: f64| segment_meets_square(a / s, b / s);
        if scaled(1.0 - m) {
            assert!(ours.is_some(), "{w:?} at {p} meets the smaller square");
            inside += 1;
        } else if !scaled(1.0 + m) {
            assert!(ours.is_none(), "{w:?} at {p} misses the larger square");
            outside += 1;
        } else {
            ties += 1;
        }
    }
    assert!(
        inside > 10_000 && outside > 10_000 && ties > 1_000,
        "{inside} inside, {outside} outside, {ties} ties"
    );
}

#[test]
fn segment_meets_square_as_the_textbook_loop_does_but_for_ties() {
    let mut rng = Rng::new(0x51de);
    // Coordinates on the square's lines and corners, just off them, and anywhere.
    let coord = |rng: &mut Rng| match rng.below(5) {
        0 => [-1.0, 1.0, 0.0][rng.below(3)],
        1 => [-1.0f64, 1.0][rng.below(2)] * (1.0 + f64::EPSILON * rng.range(-4.0, 4.0)),
        2 => rng.range(-1.0, 1.0),
        _ => rng.range(-4.0, 4.0),
    };
    // The textbook loop on the square grown or shrunk by a relative `1e-12`, far beyond
    // rounding: a segment that meets the smaller square meets this one, one that misses the
    // larger misses it; between the two lie the ties, which either answer may decide.
    let scaled = |a: DVec2, b: DVec2, s: f64| plain_meets_square(a / s, b / s);
    let (mut met, mut missed, mut ties, mut differ) = (0, 0, 0, 0);
    for _ in 0..200_000 {
        let a = DVec2::new(coord(&mut rng), coord(&mut rng));
        let b = DVec2::new(coord(&mut rng), coord(&mut rng));
        let ours = segment_meets_square(a, b);
        differ += usize::from(ours != plain_meets_square(a, b));
        if scaled(a, b, 1.0 - 1e-12) {
            assert!(ours, "{a} {b} meets the smaller square");
            met += 1;
        } else if !scaled(a, b, 1.0 + 1e-12) {
            assert!(!ours, "{a} {b} misses the larger square");
            missed += 1;
        } else {
            ties += 1;
        }
    }
    assert!(
        met > 50_000 && missed > 10_000,
        "{met} met, {missed} missed"
    );
    // The ties are exercised, and they are all the two tests disagree on.
    assert!(
        ties > 1_000 && differ < ties,
        "{ties} ties, {differ} differ"
    );
    // Touching counts as meeting: the square is closed.
    for (a, b) in [
        ((2.0, 3.0), (1.0, 1.0)),
        ((2.0, 0.0), (0.0, 2.0)),
        ((1.0, -5.0), (1.0, 5.0)),
        ((-1.0, -1.0), (-1.0, -1.0)),
    ] {
        assert!(segment_meets_square(a.into(), b.into()), "{a:?} {b:?}");
    }
    for (a, b) in [((1.0, 2.0), (1.0, 3.0)), ((2.5, 0.0), (0.0, 2.5))] {
        assert!(!segment_meets_square(a.into(), b.into()), "{a:?} {b:?}");
    }
}

#[test]
fn the_parts_written_and_what_the_others_stand_for_are_the_whole_integral() {
    let mut rng = Rng::new(0x9a27);
    // An integral whose every field is NaN: a part left as it was shows.
    let stale = EdgeIntegral {
        sign: f64::NAN,
        area: [f64::NAN; 4],
        beyond: [Rect {
            min: DVec2::NAN,
            max: DVec2::NAN,
        }; 4],
        near: [Rect {
            min: DVec2::NAN,
            max: DVec2::NAN,
        }; 4],
        cover: [f64::NAN; 4],
    };
    let (mut some, mut few, mut centre_near) = (0, 0, 0);
    for i in 0..20_000 {
        let p = random_receiver(&mut rng);
        // Short edges inside the light (one part or two written) and edges anywhere (all four).
        let first = DVec2::new(rng.range(-1.2, 1.2), rng.range(-1.2, 1.2));
        let spot = |rng: &mut Rng| match i % 2 {
            0 => first + DVec2::new(rng.range(-0.2, 0.2), rng.range(-0.2, 0.2)),
            _ => DVec2::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0)),
        };
        let end = |rng: &mut Rng| projecting_onto(p, spot(rng), rng.range(0.05, 0.95) * p.z);
        let w = front_wedge(end(&mut rng), end(&mut rng), 1 + (i % 2) as u32);
        let whole = w.integral(p);
        // The parts not written as clipping every part gives them.
        let mut clipped = EdgeIntegral::NONE;
        let clipped = w.integral_by(p, &mut clipped, false).then_some(clipped);
        assert_eq!(clipped.is_some(), whole.is_some(), "edge {w:?} at {p}");
        let mut out = stale;
        let parts = w.integral_parts(p, &mut out, true);
        assert_eq!(parts.any(), whole.is_some(), "edge {w:?} at {p}");
        let (Some(whole), Some(clipped)) = (whole, clipped) else {
            continue;
        };
        some += 1;
        few += usize::from(parts.written != 0b1111);
        centre_near += usize::from(parts.centre_near);
        assert_eq!(out.sign, whole.sign);
        for k in 0..4 {
            if parts.has(k) {
                assert!(
                    out.area[k] == whole.area[k]
                        && out.beyond[k] == whole.beyond[k]
                        && out.near[k] == whole.near[k]
                        && out.cover[k] == whole.cover[k],
                    "part {k} of edge {w:?} at {p}: {out:?} against {whole:?}"
                );
            } else {
                let near = if parts.centre_near {
                    Rect::of(&[DVec2::ZERO])
                } else {
                    Rect::EMPTY
                };
                for got in [whole, clipped] {
                    assert!(
                        got.area[k] == 0.0
                            && got.beyond[k] == Rect::EMPTY
                            && got.near[k] == near
                            && got.cover[k] == 0.0,
                        "part {k} of edge {w:?} at {p} not written: {got:?}"
                    );
                }
            }
        }
    }
    assert!(
        some > 5_000 && few > 2_000 && centre_near > 500 && some - few > 1_000,
        "{some} integrals, {few} with parts not written, {centre_near} with the centre near"
    );
}
