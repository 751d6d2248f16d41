//! `gaussian`: Cherry & Kooima 2015's contact-hardening soft shadows: a screen-space distance
//! map `D = Δ^Dp · Dm` of the hard shadow, an optional dilation, then one of three Gaussian
//! filters (`pcf`, `single`, `multi`) and the read-out (`shaders/gaussian.wgsl`).

use glam::DVec2;
use penumbra_geom::Rng;
use penumbra_params::{GaussianVariant, TechniqueParams};

use super::inputs::{TechniqueLanes, best_candidates};
use super::light_frustum::LightFrustum;
use super::pipelines::TechniquePasses;
use super::resources::{RGBA, ShadowFrame, uniform_buffer};
use crate::constants::MAX_TAPS;
use crate::counters::Pass;
use crate::passes::VISIBILITY_FORMAT;

/// Its shader and its passes: the distance map, the dilation, the three filters and the
/// read-out.
pub(super) const PASSES: TechniquePasses = TechniquePasses {
    source: include_str!("../shaders/gaussian.wgsl"),
    passes: &[
        ("fs_distance", RGBA),
        ("fs_dilate_h", RGBA),
        ("fs_dilate_v", RGBA),
        ("fs_pcf", RGBA),
        ("fs_single_h", RGBA),
        ("fs_single_v", RGBA),
        ("fs_multi", RGBA),
        ("fs_readout", VISIBILITY_FORMAT),
    ],
};

/// Its lanes of the uniforms: `Dp`, `Dm` and the scene's light-depth range (`frustum`'s);
/// the largest kernel, the taps and the dilation.
pub(super) fn lanes(params: &TechniqueParams, frustum: &LightFrustum) -> TechniqueLanes {
    let p = &params.gaussian;
    TechniqueLanes {
        params: [
            p.distance_power() as f32,
            p.dm as f32,
            (frustum.z_max - frustum.z_min).max(1e-9) as f32,
            0.0,
        ],
        iparams: [p.max_kernel, p.taps, p.dilation, 0],
        cell: None,
    }
}

/// The screen-space images the passes write in turn: `cur` is the last one written.
struct PingPong<'f, 'a> {
    f: &'f ShadowFrame<'a>,
    images: [wgpu::TextureView; 2],
    cur: usize,
}

impl PingPong<'_, '_> {
    /// Records pass `entry` with uniforms `buffer` from the last image into the other one.
    fn run(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        entry: &str,
        buffer: &wgpu::Buffer,
        kind: Pass,
    ) {
        let f = self.f;
        f.run(
            encoder,
            entry,
            (buffer, &[&f.map, &self.images[self.cur]]),
            &self.images[1 - self.cur],
            kind,
        );
        self.cur = 1 - self.cur;
    }
}

/// Records the distance map, the dilation (when on), the variant's filter passes and the
/// read-out into V. Returns the uniform buffers of the multi passes, to be kept until the
/// commands are submitted.
pub(super) fn record(f: &ShadowFrame<'_>, encoder: &mut wgpu::CommandEncoder) -> Vec<wgpu::Buffer> {
    let mut ping = PingPong {
        f,
        images: [
            f.image("gaussian ping", f.screen, RGBA),
            f.image("gaussian pong", f.screen, RGBA),
        ],
        cur: 0,
    };
    f.run(
        encoder,
        "fs_distance",
        (&f.base_buf, &[&f.map]),
        &ping.images[0],
        Pass::Preprocess,
    );
    let g = &f.params.gaussian;
    let base = &f.base_buf;
    if g.dilation > 0 {
        ping.run(encoder, "fs_dilate_h", base, Pass::Preprocess);
        ping.run(encoder, "fs_dilate_v", base, Pass::Preprocess);
    }
    let mut keep = Vec::new();
    match g.variant {
        GaussianVariant::Pcf => ping.run(encoder, "fs_pcf", base, Pass::Filter),
        GaussianVariant::Single => {
            ping.run(encoder, "fs_single_h", base, Pass::Filter);
            ping.run(encoder, "fs_single_v", base, Pass::Filter);
        }
        GaussianVariant::Multi => {
            for p in 0..g.passes {
                let mut u = f.base;
                for (slot, t) in
                    u.taps
                        .iter_mut()
                        .zip(multi_pass_taps(p, g.max_kernel, g.taps as usize))
                {
                    *slot = t;
                }
                let buf = uniform_buffer(&f.ctx.device, &u);
                ping.run(encoder, "fs_multi", &buf, Pass::Filter);
                keep.push(buf);
            }
        }
    }
    f.run(
        encoder,
        "fs_readout",
        (&f.base_buf, &[&f.map, &ping.images[ping.cur]]),
        &f.visibility_view,
        Pass::Resolve,
    );
    keep
}

/// Cherry & Kooima's table of Poisson points in [-1, 1]² ("The first point is fixed at the origin so
/// the center texel is always examined"), deterministic.
fn poisson_taps() -> Vec<DVec2> {
    let mut rng = Rng::new(0x9a55_0003);
    best_candidates(&mut rng, MAX_TAPS, true, |r| {
        DVec2::new(r.range(-1.0, 1.0), r.range(-1.0, 1.0))
    })
}

/// The kernel side of `gaussian` multi pass `pass` (0-based): 3, growing by 2 per pass up to
/// `max_kernel` ("starting from 3x3 and going up to 19x19", Fig. 5G).
pub fn multi_pass_kernel(pass: u32, max_kernel: u32) -> u32 {
    (3 + 2 * pass).min(max_kernel)
}

/// The taps of `gaussian` multi pass `pass`: the first `taps` Poisson points scaled to the
/// pass's kernel and rounded to whole pixels, with Gaussian weights (sigma = size / 3) of the
/// rounded offsets, normalised to sum 1.
fn multi_pass_taps(pass: u32, max_kernel: u32, taps: usize) -> Vec<[f32; 4]> {
    let ks = multi_pass_kernel(pass, max_kernel) as f64;
    let sigma = ks / 3.0;
    let half = (ks - 1.0) / 2.0;
    let pts: Vec<(DVec2, f64)> = poisson_taps()
        .into_iter()
        .take(taps)
        .map(|p| {
            let o = (p * half).round();
            (o, (-o.length_squared() / (2.0 * sigma * sigma)).exp())
        })
        .collect();
    let sum: f64 = pts.iter().map(|p| p.1).sum();
    pts.iter()
        .map(|(o, w)| [o.x as f32, o.y as f32, (w / sum) as f32, 0.0])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn poisson_taps_start_at_the_origin_and_spread() {
        let p = poisson_taps();
        assert_eq!(p.len(), MAX_TAPS);
        assert_eq!(p[0], DVec2::ZERO);
        assert!(p.iter().all(|q| q.abs().max_element() <= 1.0));
        let first: Vec<_> = p[..20].to_vec();
        let min = first
            .iter()
            .enumerate()
            .flat_map(|(i, a)| first[i + 1..].iter().map(move |b| a.distance(*b)))
            .fold(f64::INFINITY, f64::min);
        assert!(min >= 0.25, "first 20 taps' closest pair {min}");
    }

    #[test]
    fn multi_pass_weights_are_normalised_gaussians_on_growing_kernels() {
        assert_eq!(multi_pass_kernel(0, 19), 3);
        assert_eq!(multi_pass_kernel(3, 19), 9);
        assert_eq!(multi_pass_kernel(20, 19), 19);
        for pass in 0..10 {
            let t = multi_pass_taps(pass, 19, 20);
            let sum: f32 = t.iter().map(|w| w[2]).sum();
            assert!((sum - 1.0).abs() < 1e-6);
            // The origin's weight is the largest, and weights fall with distance.
            assert_eq!([t[0][0], t[0][1]], [0.0, 0.0]);
            let half = (multi_pass_kernel(pass, 19) as f32 - 1.0) / 2.0;
            for a in &t {
                assert!(a[0].abs() <= half && a[1].abs() <= half);
                for b in &t {
                    if a[0].hypot(a[1]) < b[0].hypot(b[1]) {
                        assert!(a[2] >= b[2]);
                    }
                }
            }
        }
    }
}
