//! Depth-complexity sampling of a whole image ([`DepthComplexity::render`]): pixels in tiles
//! that share one query of the potential edges' hierarchy, or, under a distant light over many
//! edges, each point's edges from a grid (`pyramid_grid.rs`); the counts of each point are
//! `depth_complexity.rs`'s.

use glam::{DVec2, DVec3};
use penumbra_geom::{Interruption, SurfacePoint, VisibilityImage};
use rayon::prelude::*;

use crate::candidates::Candidates;
use crate::depth_complexity::{DepthComplexity, SamplePattern, Scratch};
use crate::pyramid_grid::PyramidGrid;

impl DepthComplexity {
    /// Gathers into `candidates` the edges that the light-space points `at` (a tile's lit
    /// receivers, the middle one halfway along) may see fold, and returns whether the tile
    /// should cast its `samples` instead ([`crate::depth_complexity::CAST_FROM`]); the gathering stops there. `pyramid`:
    /// whether the middle point's pre-test drops the edges outside its pyramid.
    fn tile_candidates(
        &self,
        at: &[DVec3],
        samples: usize,
        candidates: &mut Candidates,
        pyramid: bool,
    ) -> bool {
        candidates.clear();
        if self.thin {
            return true;
        }
        let (lo, hi) = at.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &q| (lo.min(q), hi.max(q)),
        );
        // Saturating: no limit for an infinite factor.
        let limit = (self.cast_from.candidates * samples as f64) as usize;
        let complete = self.edges.for_each_near_any_while(at, |ei| {
            if self.edges.may_fold_within(ei, lo, hi) {
                candidates.push(&self.edges, ei);
            }
            candidates.ids.len() <= limit
        });
        !complete
            || at.get(at.len() / 2).is_some_and(|&m| {
                candidates.pretest(m, self.reach2, pyramid);
                let kept = candidates.kept.len();
                kept as f64 > self.cast_from.kept * samples as f64
            })
    }

    /// Gathers into `candidates` the edges of the light-space point `p`'s cell of `grid`,
    /// pre-tested at `p`, and returns whether the point should cast its `samples` instead
    /// ([`crate::depth_complexity::CAST_FROM`], as [`DepthComplexity::tile_candidates`] decides for a point).
    fn grid_candidates(
        &self,
        grid: &PyramidGrid,
        p: DVec3,
        samples: usize,
        candidates: &mut Candidates,
    ) -> bool {
        candidates.clear();
        if grid.count_near(p) as f64 > self.cast_from.candidates * samples as f64 {
            return true;
        }
        grid.candidates(&self.edges, p, self.reach2, candidates);
        candidates.kept.len() as f64 > self.cast_from.kept * samples as f64
    }

    /// How many pixels of the last [`DepthComplexity::render`] had their samples tested by rays
    /// rather than counted from the edges.
    pub fn cast_pixels(&self) -> u64 {
        self.cast_pixels.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Renders the whole image; `progress` gets the number of finished rows. An interruption
    /// ([`penumbra_geom::Interrupter`]) stops it at the next pixel, the rest left at 1.
    ///
    /// Pixels go in tiles of [`TILE`] x [`TILE`]: one query of the edge hierarchy finds the
    /// candidates of a whole tile (the union of its points' pyramids), and its pixels share them.
    /// A tile whose candidates outnumber its samples 24 times, or whose middle point keeps four
    /// times as many edges as samples (a large light over detailed meshes: thousands of
    /// potential silhouette edges around each point), tests each sample by a ray instead, which
    /// costs less there; the query stops at the first number. A tile whose points spread wider
    /// than the light (a small light, the sun, over a tile of the ground) holds in the union of
    /// their pyramids many times the edges of any one: each point takes its own, by the same
    /// rules. A point none of whose edges passes the pre-test needs only whether its count at
    /// the centre is zero: one ray that stops at its first crossing.
    ///
    /// Under a distant light over many edges ([`GRID_FROM_EDGES`]) every point takes its own
    /// edges, read from a grid laid over the image's points as the light sees them
    /// (`volumes/src/pyramid_grid.rs`): the same edges change the same counts as the
    /// hierarchy's, and a point reads a few instead of its tile's hundreds.
    pub fn render(
        &self,
        pattern: SamplePattern,
        progress: &(dyn Fn(u64) + Sync),
    ) -> VisibilityImage {
        let t = &self.tracer;
        match &self.world_camera {
            None => {
                let cam = &self.camera;
                self.render_at(pattern, progress, &|i, j| {
                    t.surface_point(cam.eye, cam.ray_dir(i, j))
                })
            }
            Some(cam) => self.render_at(pattern, progress, &|i, j| {
                let p = t.world_surface_point(cam.eye, cam.ray_dir(i, j))?;
                Some(t.rendered(p))
            }),
        }
    }

    /// [`DepthComplexity::render`] with the surface point of pixel `(i, j)` given by
    /// `surface` (the one the tracer finds, or one found before).
    pub fn render_at(
        &self,
        pattern: SamplePattern,
        progress: &(dyn Fn(u64) + Sync),
        surface: &(dyn Fn(u32, u32) -> Option<SurfacePoint> + Sync),
    ) -> VisibilityImage {
        self.gridded
            .store(false, std::sync::atomic::Ordering::Relaxed);
        if !self.by_grid {
            return self.render_with(pattern, progress, surface, None);
        }
        // The grid is built for the image's points: found first.
        let (w, h) = (self.camera.width as usize, self.camera.height as usize);
        let points: Vec<Option<SurfacePoint>> = (0..w * h)
            .into_par_iter()
            .map(|k| surface((k % w) as u32, (k / w) as u32))
            .collect();
        let light = &self.tracer.light;
        let receivers: Vec<DVec3> = points
            .iter()
            .flatten()
            .map(|p| light.to_light_space(p.position))
            .filter(|p| p.z > 0.0)
            .collect();
        let grid = PyramidGrid::build(&self.edges, &receivers);
        self.gridded
            .store(grid.is_some(), std::sync::atomic::Ordering::Relaxed);
        let at = |i: u32, j: u32| points[j as usize * w + i as usize];
        self.render_with(pattern, progress, &at, grid.as_ref())
    }

    /// [`DepthComplexity::render_at`], each point's edges from `grid` where there is one.
    fn render_with(
        &self,
        pattern: SamplePattern,
        progress: &(dyn Fn(u64) + Sync),
        surface: &(dyn Fn(u32, u32) -> Option<SurfacePoint> + Sync),
        grid: Option<&PyramidGrid>,
    ) -> VisibilityImage {
        let cam = &self.camera;
        let w = cam.width as usize;
        let light = &self.tracer.light;
        let mut img = VisibilityImage::filled(cam.width, cam.height, 1.0);
        let done = std::sync::atomic::AtomicU64::new(0);
        self.cast_pixels
            .store(0, std::sync::atomic::Ordering::Relaxed);
        let stop = Interruption::since();
        img.data
            .par_chunks_mut(w * TILE)
            .enumerate()
            .for_each(|(tile_row, block)| {
                if stop.happened() {
                    return;
                }
                let mut scratch = Scratch::default();
                let mut lit: Vec<(usize, SurfacePoint, DVec3)> = Vec::new();
                let mut at = Vec::new();
                let rows = block.len() / w;
                for x0 in (0..w).step_by(TILE) {
                    lit.clear();
                    for dy in 0..rows {
                        let j = tile_row * TILE + dy;
                        for i in x0..(x0 + TILE).min(w) {
                            let Some(p) = surface(i as u32, j as u32) else {
                                continue;
                            };
                            let pl = light.to_light_space(p.position);
                            if pl.z > 0.0 {
                                lit.push((dy * w + i, p, pl));
                            } else {
                                block[dy * w + i] = 0.0;
                            }
                        }
                    }
                    let mut candidates = std::mem::take(&mut scratch.candidates);
                    let samples = pattern.per_axis * pattern.per_axis;
                    // Under a small light each point reads its own edges from the grid;
                    // otherwise a tile's points share one query of the edge hierarchy.
                    let (tile_casts, per_point, wide) = match grid {
                        Some(_) => (false, true, true),
                        None => {
                            at.clear();
                            at.extend(lit.iter().map(|l| l.2));
                            // Points far apart under a small light: each point's pyramid holds
                            // a small part of the tile's. Its pre-test drops the edges outside
                            // it, and where the tile has too many, the point takes its own.
                            let wide = wider_than_the_light(&at);
                            let casts = self.tile_candidates(&at, samples, &mut candidates, false);
                            (casts, casts && wide, wide)
                        }
                    };
                    for (k, p, pl) in &lit {
                        if stop.happened() {
                            return;
                        }
                        let pixel = (tile_row * TILE * w + k) as u64;
                        let casts = match (per_point, grid) {
                            (true, Some(grid)) => {
                                self.grid_candidates(grid, *pl, samples, &mut candidates)
                            }
                            (true, None) => {
                                self.tile_candidates(&[*pl], samples, &mut candidates, true)
                            }
                            (false, _) => tile_casts,
                        };
                        if casts {
                            self.cast_pixels
                                .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                            self.tracer.near_triangles(p, &mut scratch.near);
                            block[*k] = self.cast(p, pattern, pixel, &mut scratch) as f32;
                            continue;
                        }
                        if grid.is_none() {
                            candidates.pretest(*pl, self.reach2, wide);
                        }
                        if candidates.kept.is_empty() && self.edges.crossings.is_empty() {
                            // No edge comes between the point and the light: every sample's
                            // count is the centre's, and only whether it is zero matters (the
                            // first crossing found ends the ray).
                            self.tracer.near_triangles(p, &mut scratch.near);
                            let c = self.tracer.light.center;
                            block[*k] = f32::from(u8::from(self.tracer.sees(p, c, &scratch.near)));
                            continue;
                        }
                        let v = self.visibility_among(
                            p,
                            *pl,
                            &candidates,
                            pattern,
                            pixel,
                            &mut scratch,
                        );
                        block[*k] = v.visibility as f32;
                    }
                    scratch.candidates = candidates;
                }
                let n = done.fetch_add(rows as u64, std::sync::atomic::Ordering::Relaxed);
                progress(n + rows as u64);
            });
        img
    }
}

/// Whether the light-space points `at` spread wider, across the light's normal, than the
/// light's side (2): the union of their pyramids to the light is then several times as wide
/// as any one of them.
fn wider_than_the_light(at: &[DVec3]) -> bool {
    let (lo, hi) = at.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), q| (lo.min(q.truncate()), hi.max(q.truncate())),
    );
    (hi - lo).max_element() > 2.0
}

/// The fewest potential silhouette edges for which a render under a distant light reads each
/// point's edges from a grid (`volumes/src/pyramid_grid.rs`): below it a tile's query of the
/// edge hierarchy finds its few edges in less time than the grid takes to build (a sun over
/// `fixtures/scenes/sun.toml`, about 450 edges: a step 10% slower with the grid; over the scale
/// scene, about 12,000: 25% faster).
pub const GRID_FROM_EDGES: usize = 2048;

/// Side of the square tiles of pixels that share one query of the edge hierarchy.
pub const TILE: usize = 8;
