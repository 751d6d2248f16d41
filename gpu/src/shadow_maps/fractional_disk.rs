//! `fractional-disk`: Valient & de Boer 2004's fractional-disk soft shadows: a back-face map, an
//! edge-distance map built on a grid of the paper's scale and propagated, then a disk of
//! `q = d2/d1 · r` around the receiver sampled `f(q) = ceil(pi q²/a)` times from a Poisson
//! noise map (`shaders/fractional_disk.wgsl`).

use glam::DVec2;
use penumbra_geom::Rng;
use penumbra_params::TechniqueParams;
use wgpu::util::DeviceExt;

use super::inputs::{TechniqueLanes, best_candidates};
use super::pipelines::TechniquePasses;
use super::resources::{RGBA, ShadowFrame};
use crate::constants::NOISE_SIZE;
use crate::counters::Pass;
use crate::passes::fullscreen::LIGHT_MAP_FORMAT;
use crate::passes::{VISIBILITY_FORMAT, texture_descriptor, view};

/// Its shader and its passes: the edges, the propagation, the filter, and the probe of the
/// tests ([`super::ShadowMapRenderer::probe`]).
pub(super) const PASSES: TechniquePasses = TechniquePasses {
    source: include_str!("../shaders/fractional_disk.wgsl"),
    passes: &[
        ("fs_edges", RGBA),
        ("fs_propagate", RGBA),
        ("fs_fractional_disk", VISIBILITY_FORMAT),
        ("fs_probe_count", VISIBILITY_FORMAT),
    ],
};

/// Cells per side of `fractional-disk`'s preprocessing grid: the paper's 256² light maps
/// (Valient & de Boer 2004). Its texel parameters (the largest disk radius, the propagation
/// passes, Eq. 2's q) count cells of this grid, so they keep the paper's scale on a finer map.
const FD_GRID: u32 = 256;

/// Light-map texels per side of one preprocessing cell on a `resolution`² map: 1 up to
/// [`FD_GRID`]², then `ceil(resolution / FD_GRID)`.
fn fd_block(resolution: u32) -> u32 {
    resolution.div_ceil(FD_GRID).max(1)
}

/// Its lanes of the uniforms: `a`, the largest radius, the edge threshold and the re-test; the
/// most samples and the propagation passes; and the preprocessing cell's side.
pub(super) fn lanes(params: &TechniqueParams) -> TechniqueLanes {
    let p = &params.fractional_disk;
    TechniqueLanes {
        params: [
            p.a as f32,
            p.max_radius as f32,
            p.edge_threshold as f32,
            p.retest as u32 as f32,
        ],
        iparams: [p.max_samples, p.passes, 0, 0],
        cell: Some(fd_block(params.shadow_map.resolution)),
    }
}

/// Records the light map of every surface (the hard test's), the edge pass and the
/// propagation passes on the preprocessing grid, then the filter pass. The frame's own light
/// map holds the back faces.
pub(super) fn record(f: &ShadowFrame<'_>, encoder: &mut wgpu::CommandEncoder) {
    let full = f.image("full light map", f.map_size, LIGHT_MAP_FORMAT);
    f.record_light_map(
        encoder,
        (&f.triangle_buffer, f.triangles.len() as u32),
        &full,
    );
    let res = f.params.shadow_map.resolution;
    let cells = res.div_ceil(fd_block(res));
    let grid = (cells, cells);
    let ping = [
        f.image("fd ping", grid, RGBA),
        f.image("fd pong", grid, RGBA),
    ];
    f.run(
        encoder,
        "fs_edges",
        (&f.base_buf, &[&f.map]),
        &ping[0],
        Pass::Preprocess,
    );
    let n = f.params.fractional_disk.passes as usize;
    for p in 0..n {
        f.run(
            encoder,
            "fs_propagate",
            (&f.base_buf, &[&f.map, &ping[p % 2]]),
            &ping[(p + 1) % 2],
            Pass::Preprocess,
        );
    }
    let noise = f.ctx.device.create_texture_with_data(
        &f.ctx.queue,
        &texture_descriptor(
            "noise",
            (NOISE_SIZE as u32, NOISE_SIZE as u32),
            RGBA,
            wgpu::TextureUsages::TEXTURE_BINDING,
        ),
        Default::default(),
        bytemuck::cast_slice(&noise_map()),
    );
    f.run(
        encoder,
        "fs_fractional_disk",
        (&f.base_buf, &[&f.map, &ping[n % 2], &view(&noise), &full]),
        &f.visibility_view,
        Pass::Filter,
    );
}

/// The noise map ("Noise map generation"), `NOISE_SIZE`² texels, row-major: each row's RG a
/// Poisson disk set in the unit disk (best candidate of 30, so every prefix is spread), stored
/// as `0.5 o + 0.5`; BA uniform in [0, 1), the per-pixel start. Deterministic.
fn noise_map() -> Vec<[f32; 4]> {
    let mut rng = Rng::new(0x5eed_0000);
    let mut out = Vec::with_capacity(NOISE_SIZE * NOISE_SIZE);
    for _ in 0..NOISE_SIZE {
        let row = best_candidates(&mut rng, NOISE_SIZE, false, |r| {
            let a = r.range(0.0, std::f64::consts::TAU);
            DVec2::new(a.cos(), a.sin()) * r.next_f64().sqrt()
        });
        for o in row {
            let o = o * 0.5 + 0.5;
            out.push([
                o.x as f32,
                o.y as f32,
                rng.next_f64() as f32,
                rng.next_f64() as f32,
            ]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_rows_are_spread_disk_sets_with_uniform_starts() {
        let n = noise_map();
        assert_eq!(n.len(), NOISE_SIZE * NOISE_SIZE);
        for row in n.chunks(NOISE_SIZE) {
            let pts: Vec<DVec2> = row
                .iter()
                .map(|t| DVec2::new(t[0] as f64, t[1] as f64) * 2.0 - 1.0)
                .collect();
            assert!(pts.iter().all(|p| p.length() <= 1.0 + 1e-6));
            let min = pts
                .iter()
                .enumerate()
                .flat_map(|(i, a)| pts[i + 1..].iter().map(move |b| a.distance(*b)))
                .fold(f64::INFINITY, f64::min);
            assert!(min >= 0.12, "row's closest pair {min}");
            assert!(
                row.iter()
                    .all(|t| (0.0..1.0).contains(&t[2]) && (0.0..1.0).contains(&t[3]))
            );
        }
        assert_eq!(n, noise_map(), "deterministic");
    }

    #[test]
    fn fractional_disk_cells_keep_the_paper_s_256_squared_grid() {
        for (resolution, block, cells) in [
            (16, 1, 16),
            (256, 1, 256),
            (257, 2, 129),
            (1000, 4, 250),
            (2048, 8, 256),
            (8192, 32, 256),
        ] {
            assert_eq!(fd_block(resolution), block, "{resolution}");
            assert_eq!(
                resolution.div_ceil(fd_block(resolution)),
                cells,
                "{resolution}"
            );
        }
    }
}
