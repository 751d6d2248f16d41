//! The light maps of one render: a light that lights a room sees its walls at every slope up to
//! the horizon of its plane, beyond what one perspective map can hold at a useful resolution.
//! The slopes (x/z, y/z of light space) are split into a core, within [`CORE_SLOPE`] of the
//! normal (83 degrees), and four side windows beyond it up to [`MAX_SLOPE`] (89.1 degrees),
//! as a cube map around the light's centre splits directions into faces (Gerasimov 2004,
//! "Omnidirectional Shadow Mapping", GPU Gems): each window is a perspective map of its own
//! from the light's centre, in the same light space and depth, so that every technique runs
//! unchanged in each. A receiver takes the window whose core holds its slopes; each map reaches
//! [`OVERLAP`] past its core, so that a filter or a blocker search near a core's border still
//! finds the map's texels across it.

use glam::DVec2;

use super::light_frustum::{LightFrustum, MAX_SLOPE};

/// Slope of the core's border (about 83 degrees off the light's normal).
pub const CORE_SLOPE: f64 = 8.0;

/// How far, in slope, each window's map reaches past its core.
pub const OVERLAP: f64 = 1.0;

/// A window: its map's frustum, and the slopes whose receivers it renders (its core: min x/z,
/// min y/z, max x/z, max y/z; unbounded sides as `f32::MAX`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Window {
    /// The map's frustum.
    pub frustum: LightFrustum,
    /// The slopes of the receivers it renders.
    pub core: [f32; 4],
}

/// The windows of `fit` (a frustum fitted to the scene, slopes within [`MAX_SLOPE`]): `fit`
/// alone with an unbounded core where it lies within the core's slopes, the render of every
/// scene lit from outside; else the core and each side window that `fit` reaches into, each
/// frustum `fit` cut to the window and its overlap.
pub fn windows(fit: &LightFrustum) -> Vec<Window> {
    const ALL: [f32; 4] = [-f32::MAX, -f32::MAX, f32::MAX, f32::MAX];
    let c = CORE_SLOPE;
    if fit.lo.cmpge(DVec2::splat(-c)).all() && fit.hi.cmple(DVec2::splat(c)).all() {
        return vec![Window {
            frustum: *fit,
            core: ALL,
        }];
    }
    let (o, m, inf) = (OVERLAP, MAX_SLOPE, f32::MAX);
    let cf = c as f32;
    // (core lo, core hi, map lo, map hi) of the core and the right, left, top and bottom sides.
    let all = [
        (
            [-cf, -cf],
            [cf, cf],
            DVec2::splat(-c - o),
            DVec2::splat(c + o),
        ),
        (
            [cf, -inf],
            [inf, inf],
            DVec2::new(c - o, -m),
            DVec2::new(m, m),
        ),
        (
            [-inf, -inf],
            [-cf, inf],
            DVec2::new(-m, -m),
            DVec2::new(-c + o, m),
        ),
        (
            [-cf, cf],
            [cf, inf],
            DVec2::new(-c - o, c - o),
            DVec2::new(c + o, m),
        ),
        (
            [-cf, -inf],
            [cf, -cf],
            DVec2::new(-c - o, -m),
            DVec2::new(c + o, -c + o),
        ),
    ];
    all.into_iter()
        .filter_map(|(core_lo, core_hi, lo, hi)| {
            // Receivers of this core within the fit, else nothing to render.
            let seen_lo = fit.lo.as_vec2().max(core_lo.into());
            let seen_hi = fit.hi.as_vec2().min(core_hi.into());
            if !seen_lo.cmplt(seen_hi).all() {
                return None;
            }
            let (lo, hi) = (fit.lo.max(lo), fit.hi.min(hi));
            Some(Window {
                frustum: LightFrustum { lo, hi, ..*fit },
                core: [core_lo[0], core_lo[1], core_hi[0], core_hi[1]],
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fit(lo: [f64; 2], hi: [f64; 2]) -> LightFrustum {
        LightFrustum {
            lo: lo.into(),
            hi: hi.into(),
            near: 0.01,
            z_min: 0.01,
            z_max: 10.0,
        }
    }

    #[test]
    fn a_fit_within_the_core_is_one_window_as_it_is() {
        let f = fit([-3.0, -1.0], [8.0, 2.0]);
        let w = windows(&f);
        assert_eq!(w.len(), 1);
        assert_eq!(w[0].frustum, f);
    }

    #[test]
    fn a_room_s_fit_takes_the_core_and_the_sides_it_reaches() {
        // A ceiling light in a room: every slope to 30 one way, 20 up, 12 down; 5 the other way.
        let f = fit([-5.0, -12.0], [30.0, 20.0]);
        let w = windows(&f);
        // The core, the right side, the top and the bottom; not the left.
        assert_eq!(w.len(), 4, "{w:?}");
        // Every slope of the fit lies in exactly one core, and in that window's map with the
        // overlap around it (within the fit).
        for i in 0..=70 {
            for j in 0..=64 {
                let s = DVec2::new(
                    -5.0 + 35.0 * i as f64 / 70.0,
                    -12.0 + 32.0 * j as f64 / 64.0,
                );
                let holds = |w: &&Window| {
                    let p = s.as_vec2();
                    p.x >= w.core[0] && p.y >= w.core[1] && p.x < w.core[2] && p.y < w.core[3]
                };
                let cores: Vec<&Window> = w.iter().filter(holds).collect();
                assert!(cores.len() <= 1, "{s}: {cores:?}");
                if s.x < 30.0 && s.y < 20.0 {
                    assert_eq!(cores.len(), 1, "{s}");
                    let m = &cores[0].frustum;
                    let (below, above) = (
                        (s - DVec2::splat(OVERLAP)).max(f.lo),
                        (s + DVec2::splat(OVERLAP)).min(f.hi),
                    );
                    assert!(
                        m.lo.cmple(below).all() && m.hi.cmpge(above).all(),
                        "{s}: {m:?}"
                    );
                }
            }
        }
    }
}
