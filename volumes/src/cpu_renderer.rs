//! The CPU renderer of the volume techniques ([`CpuRenderer`]): the oracle for the GPU back end
//! and the fallback without one.

use std::sync::OnceLock;

use glam::{DVec2, DVec3};
use penumbra_geom::{
    Camera, Interruption, LitScene, Rays, SurfacePoint, Technique, Tracer, TracerGeometry,
    VisibilityImage,
};
use rayon::prelude::*;

use crate::blend::{Part, VBuffer};
use crate::clip::{PART_AREA, RADIAL_PARTS, Rect};
use crate::volumes::{Volumes, along_outlines};
use crate::wedge_grid::{ReceiverCells, WedgeGrid};
use crate::wedge_integral::EdgeIntegral;
use crate::wedge_reach::receiver_box;

/// Everything the CPU needs to render the volume techniques of one scene, and their renderer.
///
/// Per pixel: the surface point P by ray casting; the hard shadow from the light's centre per
/// occluder; the wedges containing P, found through a uniform grid over the wedges' bounding
/// boxes; then
///
/// - `hard`: `V = 0` where the centre is hidden (the stencil answer), else 1;
/// - `wedges` (Akenine-Möller & Assarsson): every edge's integral added into one sum on top of
///   the stencil count `n` (the volumes' winding number at P, `N(P, c)` of [`Wedge`]),
///   `V = 1 - clamp(4·n + Σ_e s_e m_e |R_e|, 0, 4) / 4`. Counting rather than clamping the
///   stencil keeps each occluder's inner half-wedges subtracting from its own hard shadow;
///   overlapping occluders are still counted twice, which is what blending corrects;
/// - `wedges-blend` (Forest, Barthe & Paulin): one visibility buffer per blending unit, its hard
///   shadow plus its own edges' integrals per radial part, blended into the final buffer in
///   unit order with Forest et al.'s function (`volumes/src/blend.rs`).
///
/// The hard shadow is the shadow volumes' winding number. Counted along the ray from P towards
/// the light's centre, no side quad is crossed (each lies in a plane through the centre) and the
/// dark caps behind the light cancel the light caps there, so the count is the number of caster
/// triangles crossed between P and the centre: one BVH query. The tests check this number against
/// the z-fail count of the actual volume geometry along the view ray
/// ([`ShadowVolume::winding_number`]).
///
/// The blending unit is Forest et al.'s "silhouette": a caster patch, the light-facing (for an
/// open mesh, every) triangles joined across edges that are not silhouette edges
/// ([`Silhouette::patch`]). Its boundary is an outer loop with the hole loops inside it, signed
/// parts of one region that share one buffer; patches of one mesh that overlap as seen from the
/// light (a folded sheet, the near and far sides of an open body) each get their own and are
/// blended, where a buffer per mesh would add them. Each unit's stencil count is its casters
/// between P and the light's centre.
///
/// ```
/// use penumbra::geom::{Scene, Technique};
/// use penumbra::volumes::CpuRenderer;
///
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures/scenes/nonmanifold.toml");
/// let scene = Scene::load(std::path::Path::new(path))?;
/// let renderer = CpuRenderer::new(&scene.lit(0));
/// let v = renderer.render(Technique::WedgesBlend, &|_| {});
/// assert_eq!((v.width, v.height), (scene.camera.width, scene.camera.height));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// [`Wedge`]: crate::Wedge
/// [`Wedge::unit`]: crate::Wedge::unit
/// [`ShadowVolume::winding_number`]: crate::ShadowVolume::winding_number
/// [`Silhouette::patch`]: crate::Silhouette::patch
pub struct CpuRenderer {
    /// Ray casting and references.
    pub tracer: Tracer,
    /// Silhouettes, volumes, wedges; each unit's wedges numbered along its outline, unlike
    /// [`Volumes::build`]'s.
    pub volumes: Volumes,
    /// Wedge lookup for queries at any point, built on the first ([`CpuRenderer::grid`]).
    grid: OnceLock<WedgeGrid>,
    /// The light-space box holding every receiver, which the grid covers.
    receivers: (DVec3, DVec3),
    /// Occluder of each scene triangle, with the top bit set for casters.
    triangle_occluder: Vec<u32>,
    /// Per occluder, whether it is a closed mesh around the light and the eye (a room lit
    /// from inside, [`crate::Enclosure::Room`]): its surfaces are seen from their inner side.
    rooms: Vec<bool>,
    /// Blending unit of each caster triangle (`Wedge::unit`).
    triangle_unit: Vec<u32>,
    /// The camera whose pixels [`CpuRenderer::render`] renders.
    camera: Camera,
    /// The number of blending units, numbered from 0 across the scene ([`Wedge::unit`]).
    ///
    /// [`Wedge::unit`]: crate::Wedge::unit
    units: u32,
}

/// Hard-shadow parts: each radial part fully occluded, bounded by its own triangle.
fn full_parts() -> [Part; 4] {
    RADIAL_PARTS.map(|t| Part {
        area: PART_AREA,
        rect: Rect::of(&t),
    })
}

/// [`CpuRenderer::render`] fills the whole grid ([`CpuRenderer::grid`]) when it holds fewer
/// (wedge, cell) entries than this many per pixel and fewer than [`WHOLE_ENTRIES`], and
/// otherwise bins the wedges only into the cells holding its pixels' points (found by a second
/// camera ray per pixel, which costs about as much as filling some 75 entries).
const WHOLE_ENTRIES_PER_PIXEL: u64 = 32;

/// The most (wedge, cell) entries of a whole grid that [`CpuRenderer::render`] fills: 64 MiB.
const WHOLE_ENTRIES: u64 = 1 << 24;

/// [`CpuRenderer::render`] glances at `GLANCE x GLANCE` pixels, evenly spread, to tell whether
/// the camera sees a far smaller part of the receivers' box than the whole.
const GLANCE: u32 = 16;

/// Marks caster triangles in `CpuRenderer::triangle_occluder`.
const CASTER_BIT: u32 = 1 << 31;

/// The wedges [`CpuRenderer::candidates`] lists: a grid cell's, or all of them. An enum rather
/// than a boxed iterator, so the loop over them, run for every pixel, inlines.
enum Candidates<'a> {
    Cell(std::slice::Iter<'a, u32>),
    All(std::ops::Range<u32>),
}

impl Iterator for Candidates<'_> {
    type Item = u32;

    #[inline]
    fn next(&mut self) -> Option<u32> {
        match self {
            Candidates::Cell(c) => c.next().copied(),
            Candidates::All(r) => r.next(),
        }
    }
}

/// What [`CpuRenderer::visibility_in`] keeps from one point to the next on a thread: the
/// accumulators of the blending units that touch the point, and where each unit's lies among
/// them. A search of the accumulators for each wedge's unit took about a tenth of the time under
/// a light larger than the scene, where a point lies in the wedges of hundreds of units.
struct Scratch {
    /// The accumulators, those of a point first; the rest are kept, reset in place when taken
    /// again, as pushing each anew copied it (328 bytes) through `memmove`.
    all: Vec<Accum>,
    /// Index in `all` of each unit's accumulator; `u32::MAX` for units with none, as every
    /// entry is again once a point is done.
    slot: Vec<u32>,
    /// The accumulators' indices in their units' order, for blending.
    order: Vec<u32>,
}

impl Scratch {
    fn new(units: u32) -> Self {
        Scratch {
            all: Vec::new(),
            slot: vec![u32::MAX; units as usize],
            order: Vec::new(),
        }
    }
}

#[derive(Clone, Copy)]
struct Accum {
    occluder: u32,
    /// The occluder's stencil count at P: caster triangles between P and the centre.
    hard: u32,
    area: [f64; 4],
    rect: [Rect; 4],
    inner_rect: [Rect; 4],
    inner_cover: [f64; 4],
}

impl Accum {
    /// Takes the accumulator `all[*used]` for `unit`, reset in place, or a new one; returns
    /// its index and counts it in `used`. The reset sets each field as [`Accum::new`] does:
    /// assigning a whole new value copied its 328 bytes through `memmove` again (1.01 to 1.015
    /// times the time).
    fn open(all: &mut Vec<Accum>, used: &mut usize, unit: u32) -> u32 {
        match all.get_mut(*used) {
            Some(a) => {
                a.occluder = unit;
                a.hard = 0;
                a.area = [0.0; 4];
                a.rect = [Rect::EMPTY; 4];
                a.inner_rect = [Rect::EMPTY; 4];
                a.inner_cover = [0.0; 4];
            }
            None => all.push(Accum::new(unit)),
        }
        *used += 1;
        (*used - 1) as u32
    }

    fn new(occluder: u32) -> Self {
        Accum {
            occluder,
            hard: 0,
            area: [0.0; 4],
            rect: [Rect::EMPTY; 4],
            inner_rect: [Rect::EMPTY; 4],
            inner_cover: [0.0; 4],
        }
    }

    /// The occluder's silhouette visibility buffer.
    fn buffer(&self) -> VBuffer {
        let full = full_parts();
        let mut b = VBuffer::default();
        for (k, full) in full.iter().enumerate() {
            let area = (self.hard as f64 * PART_AREA + self.area[k]).clamp(0.0, PART_AREA);
            if area <= 0.0 {
                continue;
            }
            // Forest et al. 2006, Figure 10: in hard shadow the occluded region reaches the part's border
            // unless the inner half-wedges cover the whole border, in which case it ends at them.
            let hard_rect = if self.hard == 0 {
                Rect::EMPTY
            } else if self.inner_cover[k] >= 2.0 * (1.0 - 1e-9) {
                self.inner_rect[k]
            } else {
                full.rect
            };
            b.parts[k] = Part {
                area,
                rect: self.rect[k].union(&hard_rect).intersection(&full.rect),
            };
        }
        b
    }
}

impl CpuRenderer {
    /// Builds the BVH, the volumes and the wedge grid of `scene`, and keeps its camera.
    pub fn new(scene: &LitScene) -> Self {
        Self::new_reusing(scene, &mut None)
    }

    /// [`CpuRenderer::new`], taking the BVH from `kept` where it serves the scene, and keeping
    /// the one built in `kept` otherwise ([`Tracer::new_reusing`]).
    pub fn new_reusing(scene: &LitScene, kept: &mut Option<TracerGeometry>) -> Self {
        // Its rays: two per pixel from the camera, one to the light's centre.
        let tracer = Tracer::new_reusing(scene, Rays::Few, kept);
        let mut volumes = Volumes::build(scene);
        volumes.wedges = along_outlines(std::mem::take(&mut volumes.wedges));
        let light = scene.light;
        let receivers = receiver_box(&light, &tracer.triangles);
        let mut triangle_occluder = Vec::with_capacity(tracer.triangles.len());
        let mut triangle_unit = Vec::with_capacity(tracer.triangles.len());
        let mut first_unit = 0;
        for (oi, o) in volumes.occluders.iter().enumerate() {
            triangle_occluder.extend(
                o.silhouette
                    .is_caster
                    .iter()
                    .map(|&c| oi as u32 | if c { CASTER_BIT } else { 0 }),
            );
            triangle_unit.extend(o.silhouette.patch.iter().map(|&p| {
                if p == u32::MAX {
                    u32::MAX
                } else {
                    first_unit + p
                }
            }));
            first_unit += o.silhouette.patches;
        }
        let closed: Vec<bool> = volumes.occluders.iter().map(|o| o.outward != 0.0).collect();
        let rooms = crate::light_centre::rooms(
            &tracer,
            &triangle_occluder,
            &closed,
            CASTER_BIT,
            scene.camera.eye,
        );
        CpuRenderer {
            tracer,
            volumes,
            grid: OnceLock::new(),
            receivers,
            rooms,
            triangle_occluder,
            triangle_unit,
            camera: scene.camera,
            units: first_unit,
        }
    }

    /// The stencil count of each blending unit (caster patch, [`Wedge::unit`]) at `p`, for
    /// those where it is not zero, sorted by unit: the number of its caster triangles (light
    /// caps) between `p` and the light's centre, which is its volume's winding number around
    /// `p`.
    ///
    /// [`Wedge::unit`]: crate::Wedge::unit
    pub fn stencil_counts(&self, p: &SurfacePoint) -> Vec<(u32, u32)> {
        let c = self.tracer.light.center;
        let eps = self.tracer.epsilon;
        // The casters within the segment's `f32` start offset of `p`, tested in `f64` over the
        // whole segment as the reference does: that offset grows with the scene's extent, and a
        // caster inside it (a small occluder over a huge ground) still casts its shadow.
        let mut out = Vec::new();
        self.tracer.near_triangles(p, &mut out);
        out.retain(|&t| {
            self.triangle_occluder[t as usize] & CASTER_BIT != 0
                && self.tracer.crosses(p.position, c, t)
        });
        self.tracer
            .for_each_hit_towards(p.position, c, eps, p.triangle, |t| {
                // A caster whose plane holds the segment grazes it (the reference's rule).
                if self.triangle_occluder[t as usize] & CASTER_BIT != 0
                    && !self.tracer.holds_segment(t, p.position, c)
                {
                    out.push(t);
                }
            });
        // A triangle split over several leaves is reported once per leaf, a near one perhaps
        // twice.
        out.sort_unstable();
        out.dedup();
        let mut counts: Vec<(u32, u32)> = Vec::new();
        for t in out {
            let o = self.triangle_unit[t as usize];
            match counts.iter_mut().find(|c| c.0 == o) {
                Some(c) => c.1 += 1,
                None => counts.push((o, 1)),
            }
        }
        counts.sort_unstable();
        counts
    }

    /// The grid of the wedges over the whole receivers' box, for queries at any point
    /// ([`CpuRenderer::visibility`], [`CpuRenderer::wedges_containing`]), built on the first
    /// call, in coarser cells where the finest would hold more than 2^24 entries (64 MiB;
    /// thousands of wedges under a light larger than the scene would fill 1 GB).
    /// [`CpuRenderer::render`] uses it where it holds few entries for the pixels, makes its own
    /// filled only where its pixels' points lie otherwise ([`WedgeGrid::build_for`]), and uses
    /// none for the hard shadow.
    pub fn grid(&self) -> &WedgeGrid {
        self.grid.get_or_init(|| {
            let (lo, hi) = self.receivers;
            WedgeGrid::build_within(&self.volumes.wedges, lo, hi, WHOLE_ENTRIES)
        })
    }

    /// Indices of the wedges that may contain the light-space point `pl`: `grid`'s cell, or
    /// every wedge for points outside it.
    fn candidates<'a>(&'a self, grid: &'a WedgeGrid, pl: DVec3) -> Candidates<'a> {
        match grid.candidates(pl) {
            Some(c) => Candidates::Cell(c.iter()),
            None => Candidates::All(0..self.volumes.wedges.len() as u32),
        }
    }

    /// The wedges containing the world point `p`.
    pub fn wedges_containing(&self, p: DVec3) -> Vec<u32> {
        let l = self.volumes.light.to_light_space(p);
        self.candidates(self.grid(), l)
            .filter(|&w| self.volumes.wedges[w as usize].contains(l))
            .collect()
    }

    /// Visibility of the surface point `p` by `technique`.
    ///
    /// # Panics
    ///
    /// If `technique` is not a volume technique (`hard`, `wedges`, `wedges-blend`).
    pub fn visibility(&self, p: &SurfacePoint, technique: Technique) -> f64 {
        self.visibility_in(p, technique, None, &mut Scratch::new(self.units))
    }

    /// [`CpuRenderer::visibility`] with the wedges looked up in `grid`, or in
    /// [`CpuRenderer::grid`] when it is `None`.
    fn visibility_in(
        &self,
        p: &SurfacePoint,
        technique: Technique,
        grid: Option<&WedgeGrid>,
        scratch: &mut Scratch,
    ) -> f64 {
        assert!(
            technique.is_volume(),
            "{technique} is not a volume technique"
        );
        let light = &self.volumes.light;
        if !light.is_lit_side(p.position) {
            return 0.0;
        }
        let hard = self.stencil_counts(p);
        if technique == Technique::Hard {
            // On a closed mesh, facing away from the centre: the segment to it enters the solid
            // (or, in a room, leaves it) at once, and must cross the mesh again to reach it.
            let away = self
                .outer_normal(p)
                .is_some_and(|n| n.dot(light.center - p.position) < 0.0);
            return if hard.is_empty() && !away { 1.0 } else { 0.0 };
        }
        let pl = light.to_light_space(p.position);
        let Scratch { all, slot, order } = scratch;
        let mut used = 0;
        for &(o, n) in &hard {
            slot[o as usize] = Accum::open(all, &mut used, o);
            all[used - 1].hard = n;
        }
        let mut int = EdgeIntegral::NONE;
        let grid = grid.unwrap_or_else(|| self.grid());
        for wi in self.candidates(grid, pl) {
            let w = &self.volumes.wedges[wi as usize];
            let parts = w.integral_parts(pl, &mut int, true);
            if !parts.any() {
                continue;
            }
            let at = &mut slot[w.unit as usize];
            if *at == u32::MAX {
                *at = Accum::open(all, &mut used, w.unit);
            }
            let a = &mut all[*at as usize];
            // The parts not written add nothing but, to an inner half-wedge whose centre lies
            // on the near side, the centre to their near rectangles.
            if int.sign < 0.0 && parts.centre_near {
                for k in (0..4).filter(|&k| !parts.has(k)) {
                    a.inner_rect[k] = a.inner_rect[k].union(&Rect::of(&[DVec2::ZERO]));
                }
            }
            for k in (0..4).filter(|&k| parts.has(k)) {
                a.area[k] += int.sign * int.area[k];
                if int.sign > 0.0 {
                    if int.area[k] > 0.0 {
                        a.rect[k] = a.rect[k].union(&int.beyond[k]);
                    }
                } else {
                    a.inner_rect[k] = a.inner_rect[k].union(&int.near[k]);
                    a.inner_cover[k] += int.cover[k];
                }
            }
        }
        let acc = &all[..used];
        for a in acc {
            slot[a.occluder as usize] = u32::MAX;
        }
        let occlusion = match technique {
            Technique::Wedges => {
                // The stencil count: one full light per caster between P and the centre.
                let base = 4.0 * PART_AREA * hard.iter().map(|h| h.1 as f64).sum::<f64>();
                let sum: f64 = acc.iter().flat_map(|a| a.area).sum();
                ((base + sum) / (4.0 * PART_AREA)).clamp(0.0, 1.0)
            }
            Technique::WedgesBlend => {
                // In the units' order, each unit once; sorted as indices, as moving the
                // accumulators themselves cost as much as blending them.
                order.clear();
                order.extend(0..acc.len() as u32);
                order.sort_unstable_by_key(|&i| acc[i as usize].occluder);
                let mut fin = VBuffer::default();
                for &i in order.iter() {
                    fin.blend(&acc[i as usize].buffer());
                }
                fin.occlusion()
            }
            _ => unreachable!("hard is handled above, the rest refused"),
        };
        (1.0 - occlusion).min(self.front_share(p))
    }

    /// The share of the light in front of `p`'s tangent plane when `p` lies on a closed mesh
    /// ([`crate::terminator::front_share`]; the plane's side that faces out of the solid, or
    /// into it for a mesh around the light), else 1 (on an open mesh, or on no triangle).
    pub fn front_share(&self, p: &SurfacePoint) -> f64 {
        self.outer_normal(p).map_or(1.0, |n| {
            crate::terminator::front_share(&self.volumes.light, p.position, n)
        })
    }

    /// The normal (not unit) of `p`'s triangle on the side that faces out of its closed mesh,
    /// or into it for a mesh around the light (a room); `None` on an open mesh or on no
    /// triangle.
    fn outer_normal(&self, p: &SurfacePoint) -> Option<DVec3> {
        let o = self.triangle_occluder.get(p.triangle as usize)? & !CASTER_BIT;
        let mut sign = self.volumes.occluders[o as usize].outward;
        if sign == 0.0 {
            return None;
        }
        if self.rooms[o as usize] {
            // The light inside the solid: its surfaces face the light from within.
            sign = -sign;
        }
        let [a, b, c] = self.tracer.triangles[p.triangle as usize];
        Some((b - a).cross(c - a) * sign)
    }

    /// Renders the whole image; `progress` gets the number of finished rows. An interruption
    /// ([`penumbra_geom::Interrupter`]) leaves the rows not yet begun at 1.
    ///
    /// # Panics
    ///
    /// If `technique` is not a volume technique (`hard`, `wedges`, `wedges-blend`).
    pub fn render(&self, technique: Technique, progress: &(dyn Fn(u64) + Sync)) -> VisibilityImage {
        let cam = &self.camera;
        let w = cam.width as usize;
        let mut img = VisibilityImage::filled(cam.width, cam.height, 1.0);
        let done = std::sync::atomic::AtomicU64::new(0);
        let surface = |i: u32, j: u32| self.tracer.surface_point(cam.eye, cam.ray_dir(i, j));
        let light = &self.volumes.light;
        // The cells holding a pixel's surface point first, so that the wedges are binned only
        // into those ([`WedgeGrid::build_for`]), over the box of those points where it is far
        // smaller than the receivers' ([`ReceiverCells::tighter`]); the points are cast again
        // below rather than kept, which would cost memory in proportion to the image. A whole
        // grid with few entries for the pixels ([`WHOLE_ENTRIES_PER_PIXEL`]) costs less than
        // that extra ray, unless a glance at a sparse grid of pixels finds that the camera sees
        // a far smaller box than the receivers' (a ground reaching far beyond the view), whose
        // cells then hold far fewer wedges.
        let pixels = u64::from(cam.width) * u64::from(cam.height);
        let sees_little = || {
            let mut cells = ReceiverCells::new(self.receivers.0, self.receivers.1);
            // The middle of the `k`-th of `GLANCE` spans of `n` pixels; in `u64`, as the product
            // overflows `u32` for images over 138 M pixels wide.
            let at = |k: u32, n: u32| {
                let i = u64::from(2 * k + 1) * u64::from(n) / u64::from(2 * GLANCE);
                i.min(u64::from(n) - 1) as u32
            };
            for j in 0..GLANCE {
                for i in 0..GLANCE {
                    if let Some(p) = surface(at(i, cam.width), at(j, cam.height)) {
                        cells.add(light.to_light_space(p.position));
                    }
                }
            }
            cells.tighter().is_some()
        };
        let whole = technique != Technique::Hard && {
            let (lo, hi) = self.receivers;
            let limit = WHOLE_ENTRIES_PER_PIXEL
                .saturating_mul(pixels)
                .min(WHOLE_ENTRIES);
            WedgeGrid::entries_up_to(&self.volumes.wedges, lo, hi, limit) < limit && !sees_little()
        };
        if whole {
            // Built here rather than by the first row while the others wait.
            self.grid();
        }
        let grid = (technique != Technique::Hard && !whole).then(|| {
            let cells_over = |(lo, hi): (DVec3, DVec3)| {
                (0..cam.height)
                    .into_par_iter()
                    .fold(
                        || ReceiverCells::new(lo, hi),
                        |mut cells, j| {
                            for i in 0..cam.width {
                                if let Some(p) = surface(i, j) {
                                    cells.add(light.to_light_space(p.position));
                                }
                            }
                            cells
                        },
                    )
                    .reduce(|| ReceiverCells::new(lo, hi), ReceiverCells::merge)
            };
            let mut cells = cells_over(self.receivers);
            // Where the pixels' points fill a far smaller box than the receivers' (a ground
            // reaching far beyond the view), a grid over theirs, cast once more.
            if let Some(tighter) = cells.tighter() {
                cells = cells_over(tighter);
            }
            WedgeGrid::build_for(&self.volumes.wedges, cells)
        });
        let scratch = || Scratch::new(self.units);
        let stop = Interruption::since();
        img.data
            .par_chunks_mut(w)
            .enumerate()
            .for_each_init(scratch, |scratch, (j, row)| {
                if stop.happened() {
                    return;
                }
                for (i, out) in row.iter_mut().enumerate() {
                    if let Some(p) = surface(i as u32, j as u32) {
                        *out = self.visibility_in(&p, technique, grid.as_ref(), scratch) as f32;
                    }
                }
                progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
            });
        img
    }
}
