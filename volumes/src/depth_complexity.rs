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
    Camera, LitScene, Rays, SurfacePoint, Tracer, TracerGeometry, segment_meets_plane,
};

use crate::candidates::Candidates;
use crate::potential::{PotentialEdges, pyramid_planes};
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
    pub(crate) near: Vec<u32>,
    pub(crate) candidates: Candidates,
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
    pub(crate) reach2: f32,
    /// The camera whose pixels [`DepthComplexity::render`] renders.
    pub(crate) camera: Camera,
    /// Under a distant light, the camera in the world, whose rays find the surface points
    /// ([`Tracer::world_surface_point`]).
    pub(crate) world_camera: Option<Camera>,
    /// [`CAST_FROM`], which the tests vary.
    pub(crate) cast_from: CastFrom,
    /// Pixels of the last [`DepthComplexity::render`] whose samples were cast.
    pub(crate) cast_pixels: std::sync::atomic::AtomicU64,
    /// Whether the light is thinner than [`THIN_LIGHT`]: every sample is cast.
    pub(crate) thin: bool,
    /// Whether [`DepthComplexity::render`] gives each point its edges from a [`PyramidGrid`]:
    /// under a distant light, with [`crate::GRID_FROM_EDGES`] edges or more.
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
        let by_grid =
            scene.distant.is_some() && !thin && edges.edges.len() >= crate::GRID_FROM_EDGES;
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
    pub(crate) fn visibility_among(
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

    /// The share of `pixel`'s samples that `p` sees, each tested by a ray by the reference's rule
    /// ([`Tracer::share_seen`]; `scratch.near` holds `p`'s near triangles).
    pub(crate) fn cast(
        &self,
        p: &SurfacePoint,
        pattern: SamplePattern,
        pixel: u64,
        scratch: &mut Scratch,
    ) -> f64 {
        pattern.points(pixel, &mut scratch.points);
        self.tracer.share_seen(p, &scratch.near, &scratch.points)
    }
}

/// The barycentric coordinate under which the segment to the light's centre meets a triangle
/// on its boundary ([`DepthComplexity::centre_on_an_edge`]).
const CENTRE_ON_EDGE: f64 = 1e-9;
