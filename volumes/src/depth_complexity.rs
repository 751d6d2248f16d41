//! Exact soft shadows by depth-complexity sampling (Laine, Aila, Assarsson, Lehtinen &
//! Akenine-Möller, "Soft Shadow Volumes for Ray Tracing", 2005; Forest, Barthe & Paulin,
//! "Accurate Shadows by Depth Complexity Sampling", 2008).
//!
//! The depth complexity of a light sample `s` seen from a receiver point `P` is the number of
//! scene triangles the open segment `P s` crosses (the receiver's own triangle never counts);
//! `s` is visible where it is zero, and
//!
//! ```text
//! V(P) = (1 / N²) · #{ s : D(P, s) = 0 }
//! ```
//!
//! over `N x N` light samples. Rather than one ray per sample, one ray counts the crossings
//! towards the light's centre `c`, `D(P, c)`, and every other count follows from the edges the
//! segment crosses as its end slides from `c` to `s` on the light: the segment `P s` sweeps the
//! triangle `P c s`, and an edge `a b` that crosses that triangle moves `s` into the projections
//! of the faces on its far side and out of those on its near side, so
//!
//! ```text
//! D(P, s) = D(P, c) + Σ_{edges e crossing triangle P c s} (far_e − near_e)
//! ```
//!
//! where `far_e` and `near_e` count the edge's faces (other than the receiver's triangle) whose
//! third vertex lies on the far and on the near side of the plane through `P` and the edge,
//! relative to `c`. A face in that plane (seen edge-on from `P`) covers no sample and counts on
//! neither side. An edge whose faces straddle the plane changes nothing (`far = near = 1`): only
//! silhouettes as seen from `P` matter, and those are among the light's potential silhouette
//! edges ([`crate::potential`]). This holds for any topology: open sheets, folds, edges of three
//! or more faces, intersecting meshes.
//!
//! The edge `a b` crosses the open triangle `P c s` when `a` and `b` lie strictly on opposite
//! sides of its plane, and the lines through `a b` and through each side of the triangle turn
//! the same way (the signed-volume segment-triangle test):
//!
//! ```text
//! [a, c, s] and [b, c, s] of opposite signs,   [a b P c], [a b c s], [a b s P] of one sign
//! ```
//!
//! (`[x y z w]` the orientation of the tetrahedron, `[x, c, s]` that of `P c s x`). With `P`, `a`,
//! `b` and `c` fixed, each is an affine function of `s` on the light's plane: four lines cut
//! the light into the samples the edge changes, evaluated per sample with no trigonometry. Two
//! of them pass through the centre and bound the cone from `c` over the edge's projection: only
//! the samples of the angular sectors that cone spans are evaluated (`volumes/src/sectors.rs`).
//!
//! Numbers are `f64` in light space; the reference casts `f32` rays, so the two differ only for
//! samples within rounding of a projected edge, and where the reference's start and end offset
//! [`Tracer::epsilon`] hides a triangle crossed within that distance of `P` or of the light.
//!
//! Counting costs, per point, the potential silhouette edges near it; a ray per sample costs the
//! samples. Where the first outnumber the second many times over (a tile of pixels under a
//! light as large as a group of detailed meshes, see [`DepthComplexity::render`]), the samples
//! of that tile are cast by the reference's rule instead: the same samples, the same answer up
//! to the rounding above. So are a point's samples where its count at the centre would hang on
//! rounding: the segment to the centre through an edge or a vertex, a silhouette in one plane
//! with the point and the centre, the centre on a triangle's crossing of the light's plane (a
//! face in the light's plane, the centre on its edge).

use glam::{DVec2, DVec3};
use penumbra_geom::{
    Camera, Interruption, LitScene, Rays, SurfacePoint, Tracer, TracerGeometry, VisibilityImage,
    segment_meets_plane,
};
use rayon::prelude::*;

use crate::candidates::Candidates;
use crate::potential::{PotentialEdges, pyramid_planes};
use crate::pyramid_grid::PyramidGrid;
use crate::region::{Region, crossing_region, edge_region};
pub use crate::samples::SamplePattern;
use crate::sectors::Sectors;

/// What depth-complexity sampling found at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointVisibility {
    /// Share of the samples with depth complexity zero.
    pub visibility: f64,
    /// Triangles between the point and the light's centre, `D(P, c)`.
    pub centre_count: u32,
    /// Potential silhouette edges that changed the count of at least one sample.
    pub edges: usize,
}

/// Per-thread working memory of [`DepthComplexity::visibility`].
#[derive(Default)]
pub struct Scratch {
    /// The samples of a pixel that casts them.
    points: Vec<DVec2>,
    /// Those of a pixel that counts them, in `f32`, in the pattern's order.
    xs: Vec<f32>,
    ys: Vec<f32>,
    /// The same, sorted by their angle around the light's centre, for points with many regions.
    samples: Sectors,
    /// Their depth complexities less the centre's, in the order of `xs` or of `samples`.
    counts: Vec<i32>,
    /// The regions of the point's edges, before any sample is placed.
    regions: Vec<Region>,
    /// Each region's runs of sorted samples.
    runs: Vec<Option<[std::ops::Range<u32>; 2]>>,
    hits: Vec<u32>,
    near: Vec<u32>,
    candidates: Candidates,
}

/// When a tile of pixels has each sample tested by a ray instead of counted from the edges
/// ([`DepthComplexity::render`]): where its candidate edges outnumber its points' samples
/// `candidates` times, or its middle point keeps (after the silhouette pre-test) `kept` times
/// as many edges as samples.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CastFrom {
    pub candidates: f64,
    pub kept: f64,
}

/// Measured on the scale scene, its 10k- to 840k-triangle versions and under lights of a
/// quarter to four times its size (`docs/benchmarks.md`): a lower `candidates` casts tiles
/// that a small light's points count faster, a higher one spends long on queries under a large
/// light.
const CAST_FROM: CastFrom = CastFrom {
    candidates: 24.0,
    kept: 4.0,
};

/// Up to this many regions a point's samples are tested against every region in the pattern's
/// order; beyond it they are first sorted by angle ([`Sectors`]), so that each region reads
/// only the samples of its cone. Sorting costs about as much as testing every sample against
/// this many regions.
const SORT_FROM: usize = 24;

impl Scratch {
    /// Places the samples of `pixel` and adds every region in `regions` to their counts;
    /// returns how many regions held a sample. Where there is no region the counts are one
    /// zero: the visibility is that of the centre alone.
    fn apply_regions(&mut self, pattern: SamplePattern, pixel: u64) -> usize {
        self.counts.clear();
        if self.regions.is_empty() {
            self.counts.push(0);
            return 0;
        }
        pattern.points_f32(pixel, &mut self.xs, &mut self.ys);
        self.counts.resize(self.xs.len(), 0);
        let counts = &mut self.counts;
        if self.regions.len() < SORT_FROM {
            self.regions
                .iter()
                .filter(|r| r.apply_to_all(&self.xs, &self.ys, counts))
                .count()
        } else {
            self.samples.fill(&self.xs, &self.ys);
            // Every cone's runs first, then the samples: the runs' divisions overlap.
            self.runs.clear();
            self.runs.extend(self.regions.iter().map(|r| {
                let (k0, k1) = r.cone();
                self.samples.cone_runs(k0, k1)
            }));
            self.regions
                .iter()
                .zip(&self.runs)
                .filter(|(r, runs)| r.apply(&self.samples, runs, counts))
                .count()
        }
    }
}

/// The depth-complexity renderer of one scene: its ray tracer (for the surface points and the
/// centre's count) and its potential silhouette edges.
pub struct DepthComplexity {
    /// Ray casting.
    pub tracer: Tracer,
    /// The light's potential silhouette edges.
    pub edges: PotentialEdges,
    /// `R^2` of the pre-test ([`Candidates::pretest`]): the square of the largest light-space coordinate of
    /// an edge or a receiver.
    reach2: f32,
    /// The camera whose pixels [`DepthComplexity::render`] renders.
    camera: Camera,
    /// Under a distant light, the camera in the world, whose rays find the surface points
    /// ([`Tracer::world_surface_point`]).
    world_camera: Option<Camera>,
    /// [`CAST_FROM`], which the tests vary.
    pub(crate) cast_from: CastFrom,
    /// Pixels of the last [`DepthComplexity::render`] whose samples were cast.
    cast_pixels: std::sync::atomic::AtomicU64,
    /// Whether the light is thinner than [`THIN_LIGHT`]: every sample is cast.
    thin: bool,
    /// Whether [`DepthComplexity::render`] gives each point its edges from a [`PyramidGrid`]:
    /// under a distant light, with [`GRID_FROM_EDGES`] edges or more.
    pub(crate) by_grid: bool,
    /// Whether the last [`DepthComplexity::render`] read its points' edges from a grid.
    pub(crate) gridded: std::sync::atomic::AtomicBool,
}

/// A light whose long side exceeds its short one this many times is too thin for counts: its
/// samples lie within rounding of one line in light space, and the edges' crossings between
/// them hang on rounding (a distant light of 90 x 1e-9 degrees differed from the reference on
/// 0.8% of pixels, by up to 0.5). Its samples are cast, as the reference casts them.
pub const THIN_LIGHT: f64 = 1e6;

impl DepthComplexity {
    /// Builds the BVH and the potential silhouette edges of `scene`, and keeps its camera.
    pub fn new(scene: &LitScene) -> Self {
        Self::new_reusing(scene, &mut None)
    }

    /// [`DepthComplexity::new`], taking the BVH from `kept` where it serves the scene, and
    /// keeping the one built in `kept` otherwise ([`Tracer::new_reusing`]).
    pub fn new_reusing(scene: &LitScene, kept: &mut Option<TracerGeometry>) -> Self {
        let tracer = Tracer::new_reusing(scene, Rays::Many, kept);
        Self::from_parts(scene, tracer, PotentialEdges::build(scene))
    }

    /// The renderer of `scene` from its tracer and its potential silhouette edges, built by
    /// the caller ([`crate::SunSeries`] keeps what they share from one light to the next).
    pub fn from_parts(scene: &LitScene, tracer: Tracer, edges: PotentialEdges) -> Self {
        let light = &tracer.light;
        let reach = edges.reach;
        let thin = !(light.size.max_element() <= THIN_LIGHT * light.size.min_element());
        let by_grid = scene.distant.is_some() && !thin && edges.edges.len() >= GRID_FROM_EDGES;
        DepthComplexity {
            reach2: (reach * reach) as f32,
            thin,
            by_grid,
            gridded: Default::default(),
            tracer,
            edges,
            camera: scene.camera,
            world_camera: scene.distant.as_ref().map(|d| d.camera),
            cast_from: CAST_FROM,
            cast_pixels: Default::default(),
        }
    }

    /// `D(P, c)`: the triangles other than `p`'s that the segment from `p` to the light's centre
    /// crosses, by the reference's rule ([`Tracer::sees`]): in `f32` from the start offset on,
    /// and in `f64` from `p` itself for the triangles `near` it.
    pub fn centre_count(&self, p: &SurfacePoint, near: &[u32], hits: &mut Vec<u32>) -> u32 {
        let t = &self.tracer;
        let c = t.light.center;
        hits.clear();
        hits.extend(near.iter().filter(|&&n| t.crosses(p.position, c, n)));
        t.for_each_hit_towards(p.position, c, t.touch, p.triangle, |tri| {
            if t.in_front(tri) && !t.holds_segment(tri, p.position, c) {
                hits.push(tri);
            }
        });
        // A triangle split over several leaves is reported once per leaf, a near one perhaps
        // twice.
        hits.sort_unstable();
        hits.dedup();
        hits.len() as u32
    }

    /// Whether the segment from `p` to the light's centre meets one of the triangles `hits`
    /// (those [`DepthComplexity::centre_count`] counted) within rounding of its boundary: on
    /// an edge two triangles share, or at a vertex, where the count at the centre, from which
    /// every sample's count follows, hangs on rounding.
    fn centre_on_an_edge(&self, p: &SurfacePoint, hits: &[u32]) -> bool {
        let t = &self.tracer;
        hits.iter().any(|&k| {
            // Parallel to the triangle's plane: as ambiguous.
            segment_meets_plane(p.position, t.light.center, t.triangles[k as usize])
                .is_none_or(|(u, v, _)| u.min(v).min(1.0 - u - v) < CENTRE_ON_EDGE)
        })
    }

    /// Visibility of the surface point `p` seen through camera pixel `pixel` (`y * width + x`,
    /// which seeds the jittered pattern).
    pub fn visibility(
        &self,
        p: &SurfacePoint,
        pattern: SamplePattern,
        pixel: u64,
        scratch: &mut Scratch,
    ) -> PointVisibility {
        // Light space's `z` is the signed distance that `RectLight::is_lit_side` tests.
        let pl = self.tracer.light.to_light_space(p.position);
        if !(pl.z > 0.0) {
            return PointVisibility {
                visibility: 0.0,
                centre_count: 0,
                edges: 0,
            };
        }
        let mut candidates = std::mem::take(&mut scratch.candidates);
        candidates.clear();
        self.edges
            .for_each_near(pl, |ei| candidates.push(&self.edges, ei));
        candidates.pretest(pl, self.reach2, true);
        let v = self.visibility_among(p, pl, &candidates, pattern, pixel, scratch);
        scratch.candidates = candidates;
        v
    }

    /// [`DepthComplexity::visibility`] of `p` (light space `pl`, lit side) with its edges taken
    /// from `candidates`, a superset of those near it, pre-tested at `pl`.
    fn visibility_among(
        &self,
        p: &SurfacePoint,
        pl: DVec3,
        candidates: &Candidates,
        pattern: SamplePattern,
        pixel: u64,
        scratch: &mut Scratch,
    ) -> PointVisibility {
        self.tracer.near_triangles(p, &mut scratch.near);
        let centre_count = self.centre_count(p, &scratch.near, &mut scratch.hits);
        let pyramid = pyramid_planes(pl);
        let regions = &mut scratch.regions;
        regions.clear();
        let mut degenerate = false;
        for &k in &candidates.kept {
            let (e, two) = &candidates.edges[k as usize];
            let faces = match e.face_count {
                2 => &two[..],
                _ => self.edges.faces_of(e),
            };
            regions.extend(edge_region(
                e,
                faces,
                pl,
                &pyramid,
                p.triangle,
                &mut degenerate,
            ));
        }
        regions.extend(
            self.edges
                .crossings
                .iter()
                .filter_map(|x| crossing_region(x, pl, p.triangle, &mut degenerate)),
        );
        if self.thin || degenerate || self.centre_on_an_edge(p, &scratch.hits) {
            // A silhouette in one plane with P and the light's centre, the centre on a
            // triangle's crossing of the light's plane, or the centre seen through an edge: its
            // samples are cast, by the reference's rule (`scratch.near`
            // holds P's near triangles).
            let visibility = self.cast(p, pattern, pixel, scratch);
            return PointVisibility {
                visibility,
                centre_count,
                edges: 0,
            };
        }
        let edges = scratch.apply_regions(pattern, pixel);
        let base = centre_count as i32;
        let counts = &scratch.counts;
        let seen = counts.iter().filter(|&&c| base + c <= 0).count();
        PointVisibility {
            visibility: seen as f64 / counts.len() as f64,
            centre_count,
            edges,
        }
    }

    /// Gathers into `candidates` the edges that the light-space points `at` (a tile's lit
    /// receivers, the middle one halfway along) may see fold, and returns whether the tile
    /// should cast its `samples` instead ([`CAST_FROM`]); the gathering stops there. `pyramid`:
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
    /// ([`CAST_FROM`], as [`DepthComplexity::tile_candidates`] decides for a point).
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

    /// The share of `pixel`'s samples that `p` sees, each tested by a ray by the reference's rule
    /// ([`Tracer::share_seen`]; `scratch.near` holds `p`'s near triangles).
    fn cast(
        &self,
        p: &SurfacePoint,
        pattern: SamplePattern,
        pixel: u64,
        scratch: &mut Scratch,
    ) -> f64 {
        pattern.points(pixel, &mut scratch.points);
        self.tracer.share_seen(p, &scratch.near, &scratch.points)
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

/// The barycentric coordinate under which the segment to the light's centre meets a triangle
/// on its boundary ([`DepthComplexity::centre_on_an_edge`]).
const CENTRE_ON_EDGE: f64 = 1e-9;

/// The fewest potential silhouette edges for which a render under a distant light reads each
/// point's edges from a grid (`volumes/src/pyramid_grid.rs`): below it a tile's query of the
/// edge hierarchy finds its few edges in less time than the grid takes to build (a sun over
/// `fixtures/scenes/sun.toml`, about 450 edges: a step 10% slower with the grid; over the scale
/// scene, about 12,000: 25% faster).
pub const GRID_FROM_EDGES: usize = 2048;

/// Side of the square tiles of pixels that share one query of the edge hierarchy.
pub const TILE: usize = 8;
