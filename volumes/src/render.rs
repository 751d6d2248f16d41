//! The CPU renderer of the volume techniques: the oracle for the GPU back end and the fallback
//! without one.
//!
//! Per pixel: the surface point P by ray casting; the hard shadow from the light's centre per
//! occluder; the wedges containing P, found through a uniform grid over the wedges' bounding
//! boxes; then
//!
//! - `hard`: `V = 0` where the centre is hidden (the stencil answer), else 1;
//! - `wedges` (Akenine-Möller & Assarsson): every edge's integral added into one sum on top of
//!   the stencil count `n` (the volumes' winding number at P, `N(P, c)` of [`crate::wedge`]),
//!   `V = 1 - clamp(4·n + Σ_e s_e m_e |R_e|, 0, 4) / 4`. Counting rather than clamping the
//!   stencil keeps each occluder's inner half-wedges subtracting from its own hard shadow;
//!   overlapping occluders are still counted twice, which is what blending corrects;
//! - `wedges-blend` (Forest, Barthe & Paulin): one visibility buffer per blending unit, its hard
//!   shadow plus its own edges' integrals per radial part, blended into the final buffer in
//!   unit order with Forest et al.'s function ([`crate::blend`]).
//!
//! The hard shadow is the shadow volumes' winding number. Counted along the ray from P towards
//! the light's centre, no side quad is crossed (each lies in a plane through the centre) and the
//! dark caps behind the light cancel the light caps there, so the count is the number of caster
//! triangles crossed between P and the centre: one BVH query. The tests check this number against
//! the z-fail count of the actual volume geometry along the view ray
//! ([`ShadowVolume::winding_number`]).
//!
//! The blending unit is Forest et al.'s "silhouette": a caster patch, the light-facing (for an
//! open mesh, every) triangles joined across edges that are not silhouette edges
//! ([`Silhouette::patch`]). Its boundary is an outer loop with the hole loops inside it, signed
//! parts of one region that share one buffer; patches of one mesh that overlap as seen from the
//! light (a folded sheet, the near and far sides of an open body) each get their own and are
//! blended, where a buffer per mesh would add them. Each unit's stencil count is its casters
//! between P and the light's centre.

use glam::DVec3;
use penumbra_geom::image::VisibilityImage;
use penumbra_geom::{
    HalfEdgeMesh, RectLight, Scene, SurfacePoint, Technique, Tracer, TriangleMesh,
};
use rayon::prelude::*;

use crate::blend::{Part, VBuffer};
use crate::clip::{PART_AREA, RADIAL_PARTS, Rect};
pub use crate::light_centre::encloses_light_centre;
use crate::shadow_volume::ShadowVolume;
use crate::silhouette::Silhouette;
use crate::wedge::{EdgeIntegral, Wedge};
pub use crate::wedge_grid::{
    WedgeFrustum, WedgeGrid, receiver_box, wedge_bounds, wedge_box, wedge_frustum,
};

/// One scene mesh with its half-edges, silhouette and shadow volume.
pub struct Occluder {
    /// Half-edge structure (world space), wound outwards where the mesh is closed: a closed
    /// scene mesh wound inwards is flipped here ([`Occluder::outward`] keeps its own winding).
    pub mesh: HalfEdgeMesh,
    /// Its silhouette from the light's centre.
    pub silhouette: Silhouette,
    /// Index of its first triangle in [`Scene::triangles`].
    pub first_triangle: u32,
    /// [`crate::terminator::outward_sign`] of the scene's mesh: +1 or -1 for a closed mesh
    /// wound outwards or inwards, 0 for an open one.
    pub outward: f64,
}

impl Occluder {
    /// Its closed shadow volume from the light's centre `c` (built on demand: the renderers
    /// count casters along rays on the CPU and build per-patch volumes on the GPU).
    pub fn shadow_volume(&self, c: DVec3) -> ShadowVolume {
        ShadowVolume::build(&self.mesh, &self.silhouette, c)
    }
}

/// Silhouettes, volumes and wedges of a whole scene.
pub struct Volumes {
    /// The light.
    pub light: RectLight,
    /// One per scene mesh.
    pub occluders: Vec<Occluder>,
    /// One per silhouette edge, in light space.
    pub wedges: Vec<Wedge>,
}

impl Volumes {
    /// Builds every silhouette, volume and wedge of `scene`.
    pub fn build(scene: &Scene) -> Self {
        Self::build_meshes(scene.meshes.iter().map(|m| &m.mesh), &scene.light)
    }

    /// Builds every silhouette, volume and wedge of the world-space `meshes` lit by `light`.
    pub fn build_meshes<'a>(
        meshes: impl IntoIterator<Item = &'a TriangleMesh>,
        light: &RectLight,
    ) -> Self {
        let scene_light = light;
        let c = light.center;
        let mut first = 0u32;
        let mut first_unit = 0u32;
        let mut wedges = Vec::new();
        let occluders: Vec<Occluder> = meshes
            .into_iter()
            .enumerate()
            .map(|(oi, m)| {
                let mesh = HalfEdgeMesh::build(m);
                let outward = crate::terminator::outward_sign(m, &mesh);
                // A closed mesh wound inwards (mirrored by a negative scale, or authored so) is
                // turned outwards for its silhouette and volume. Their rule for closed meshes
                // takes the light-facing triangles as casters; on an inward mesh those are the
                // ones facing away, and a point on its shadowed side found no caster between
                // itself and the light.
                let mesh = if outward < 0.0 {
                    HalfEdgeMesh::build(&m.flipped())
                } else {
                    mesh
                };
                let ls: Vec<DVec3> = mesh
                    .positions
                    .iter()
                    .map(|&v| scene_light.to_light_space(v))
                    .collect();
                // A mesh cut by the light's plane: only its part in front can occlude, an open
                // surface even when the mesh is closed; its silhouette from the centre no longer
                // bounds what it hides, and each wedge is split by its caster's side instead.
                let cut = mesh.faces.iter().any(|t| {
                    t.iter().any(|&v| ls[v as usize].z < 0.0)
                        && t.iter().any(|&v| ls[v as usize].z > 0.0)
                });
                let silhouette = Silhouette::build_as(&mesh, c, mesh.is_closed() && !cut);
                for (li, lp) in silhouette.loops.iter().enumerate() {
                    for &ei in lp {
                        let e = silhouette.edges[ei as usize];
                        // Only the part in front of the light's plane can hide light.
                        let (a, b) = (ls[e.from as usize], ls[e.to as usize]);
                        let Some((from, to)) = Wedge::clipped_to_light(a, b) else {
                            continue;
                        };
                        // One wedge per patch the edge bounds, with that patch's own
                        // multiplicity and direction: each patch blends its own buffer.
                        for &(patch, m) in &silhouette.edge_patches[ei as usize] {
                            let (from, to) = if m > 0 { (from, to) } else { (to, from) };
                            let caster = if cut {
                                caster_next_to(&mesh, &silhouette, e.edge, patch)
                                    .map(|v| ls[v as usize])
                            } else {
                                None
                            };
                            wedges.push(Wedge {
                                from,
                                to,
                                multiplicity: m.unsigned_abs(),
                                occluder: oi as u32,
                                silhouette_loop: li as u32,
                                unit: first_unit + patch,
                                caster,
                            });
                        }
                    }
                }
                // Casters through the light's plane: the cut closes their outline.
                let loops = silhouette.loops.len() as u32;
                for (f, face) in mesh.faces.iter().enumerate() {
                    if !silhouette.is_caster[f] {
                        continue;
                    }
                    if let Some((from, to, top)) = Wedge::cut(face.map(|v| ls[v as usize])) {
                        wedges.push(Wedge {
                            from,
                            to,
                            multiplicity: 1,
                            occluder: oi as u32,
                            silhouette_loop: loops,
                            unit: first_unit + silhouette.patch[f],
                            caster: Some(top),
                        });
                    }
                }
                let o = Occluder {
                    outward,
                    mesh,
                    silhouette,
                    first_triangle: first,
                };
                first += m.triangles.len() as u32;
                first_unit += o.silhouette.patches;
                o
            })
            .collect();
        // Each unit's wedges together (a stable sort keeps the loops' order within a unit).
        wedges.sort_by_key(|w| w.unit);
        Volumes {
            light: *light,
            occluders,
            wedges,
        }
    }
}

/// The vertex opposite mesh edge `edge` in one of its faces of caster patch `patch`.
fn caster_next_to(mesh: &HalfEdgeMesh, sil: &Silhouette, edge: u32, patch: u32) -> Option<u32> {
    let e = &mesh.edges[edge as usize];
    e.half_edges.iter().find_map(|&h| {
        let f = HalfEdgeMesh::face(h) as usize;
        (sil.is_caster[f] && sil.patch[f] == patch)
            .then(|| mesh.faces[f].into_iter().find(|v| !e.vertices.contains(v)))
            .flatten()
    })
}

impl Volumes {
    /// The blending units (caster patches) of all occluders: [`Wedge::unit`] runs below it.
    pub fn unit_count(&self) -> usize {
        self.occluders
            .iter()
            .map(|o| o.silhouette.patches as usize)
            .sum()
    }

    /// The occluder that blending unit `unit` belongs to (units are numbered occluder by
    /// occluder).
    pub fn unit_occluder(&self, unit: u32) -> u32 {
        let mut first = 0;
        for (oi, o) in self.occluders.iter().enumerate() {
            first += o.silhouette.patches;
            if unit < first {
                return oi as u32;
            }
        }
        self.occluders.len() as u32
    }
}

/// The counts that `fixtures/expected/*.json` pins per scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct GeometryCounts {
    /// Silhouette edges (each counted once whatever its multiplicity).
    pub silhouette_edges: usize,
    /// Sum of the silhouette edges' multiplicities.
    pub silhouette_multiplicity: usize,
    /// Silhouette loops over all meshes.
    pub loops: usize,
    /// Penumbra wedges (one per silhouette edge).
    pub wedges: usize,
    /// Triangles of all shadow volumes (light caps, dark caps, sides).
    pub volume_triangles: usize,
}

impl GeometryCounts {
    /// Counts the geometry of `v`.
    pub fn of(v: &Volumes) -> Self {
        let sil = v.occluders.iter().map(|o| &o.silhouette);
        GeometryCounts {
            silhouette_edges: sil.clone().map(|s| s.edges.len()).sum(),
            silhouette_multiplicity: sil
                .clone()
                .flat_map(|s| s.edges.iter().map(|e| e.multiplicity as usize))
                .sum(),
            loops: sil.clone().map(|s| s.loops.len()).sum(),
            // One wedge solid per silhouette edge (split by patch for the blending only).
            wedges: sil.clone().map(|s| s.edges.len()).sum(),
            volume_triangles: v
                .occluders
                .iter()
                .map(|o| o.shadow_volume(v.light.center).triangles.len())
                .sum(),
        }
    }
}

/// Everything the CPU needs to render the volume techniques of one scene.
pub struct CpuRenderer {
    /// Ray casting and references.
    pub tracer: Tracer,
    /// Silhouettes, volumes, wedges.
    pub volumes: Volumes,
    /// Wedge lookup.
    pub grid: WedgeGrid,
    /// Occluder of each scene triangle, with the top bit set for casters.
    triangle_occluder: Vec<u32>,
    /// Blending unit of each caster triangle ([`Wedge::unit`]).
    triangle_unit: Vec<u32>,
}

/// Hard-shadow parts: each radial part fully occluded, bounded by its own triangle.
fn full_parts() -> [Part; 4] {
    RADIAL_PARTS.map(|t| Part {
        area: PART_AREA,
        rect: Rect::of(&t),
    })
}

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
    /// Builds the BVH, the volumes and the wedge grid of `scene`.
    pub fn new(scene: &Scene) -> Self {
        let tracer = Tracer::new(scene);
        let volumes = Volumes::build(scene);
        let light = scene.light;
        let (lo, hi) = receiver_box(&light, &tracer.triangles);
        let grid = WedgeGrid::build(&volumes.wedges, lo, hi);
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
        CpuRenderer {
            tracer,
            volumes,
            grid,
            triangle_occluder,
            triangle_unit,
        }
    }

    /// The stencil count of each blending unit (caster patch, [`Wedge::unit`]) at `p`, for
    /// those where it is not zero, sorted by unit: the number of its caster triangles (light
    /// caps) between `p` and the light's centre, which is its volume's winding number around
    /// `p`.
    pub fn stencil_counts(&self, p: &SurfacePoint) -> Vec<(u32, u32)> {
        let c = self.tracer.light.center;
        let d = c - p.position;
        let dist = d.length();
        let eps = self.tracer.epsilon;
        let mut out = Vec::new();
        if dist > 2.0 * eps {
            let dir = d / dist;
            self.tracer.bvh.for_each_hit(
                p.position,
                dir.as_vec3().into(),
                eps as f32,
                (dist - eps) as f32,
                p.triangle,
                |t| {
                    if self.triangle_occluder[t as usize] & CASTER_BIT != 0 {
                        out.push(t);
                    }
                },
            );
        }
        // The casters within the segment's `f32` start offset of `p`, tested in `f64` over the
        // whole segment as the reference does: that offset grows with the scene's extent, and a
        // caster inside it (a small occluder over a huge ground) still casts its shadow.
        let mut near = Vec::new();
        self.tracer.near_triangles(p, &mut near);
        out.extend(near.into_iter().filter(|&t| {
            self.triangle_occluder[t as usize] & CASTER_BIT != 0
                && self.tracer.crosses(p.position, c, t)
        }));
        // A triangle split over several leaves is reported once per leaf.
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

    /// Indices of the wedges that may contain the light-space point `pl`: the grid's cell, or
    /// every wedge for points outside the scene's box.
    fn candidates(&self, pl: DVec3) -> Candidates<'_> {
        match self.grid.candidates(pl) {
            Some(c) => Candidates::Cell(c.iter()),
            None => Candidates::All(0..self.volumes.wedges.len() as u32),
        }
    }

    /// The wedges containing the world point `p`.
    pub fn wedges_containing(&self, p: DVec3) -> Vec<u32> {
        let l = self.volumes.light.to_light_space(p);
        self.candidates(l)
            .filter(|&w| self.volumes.wedges[w as usize].contains(l))
            .collect()
    }

    /// Visibility of the surface point `p` by `technique`.
    ///
    /// # Panics
    ///
    /// If `technique` is not a volume technique (`hard`, `wedges`, `wedges-blend`).
    pub fn visibility(&self, p: &SurfacePoint, technique: Technique) -> f64 {
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
            return if hard.is_empty() { 1.0 } else { 0.0 };
        }
        let pl = light.to_light_space(p.position);
        let mut acc: Vec<Accum> = hard
            .iter()
            .map(|&(o, n)| Accum {
                hard: n,
                ..Accum::new(o)
            })
            .collect();
        let mut int = EdgeIntegral::NONE;
        for wi in self.candidates(pl) {
            let w = &self.volumes.wedges[wi as usize];
            if !w.integral_into(pl, &mut int) {
                continue;
            }
            let a = match acc.iter().position(|a| a.occluder == w.unit) {
                Some(i) => &mut acc[i],
                None => {
                    acc.push(Accum::new(w.unit));
                    acc.last_mut().expect("just pushed")
                }
            };
            for k in 0..4 {
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
        let occlusion = match technique {
            Technique::Wedges => {
                // The stencil count: one full light per caster between P and the centre.
                let base = 4.0 * PART_AREA * hard.iter().map(|h| h.1 as f64).sum::<f64>();
                let sum: f64 = acc.iter().flat_map(|a| a.area).sum();
                ((base + sum) / (4.0 * PART_AREA)).clamp(0.0, 1.0)
            }
            Technique::WedgesBlend => {
                acc.sort_by_key(|a| a.occluder);
                let mut fin = VBuffer::default();
                for a in &acc {
                    fin.blend(&a.buffer());
                }
                fin.occlusion()
            }
            _ => unreachable!("hard is handled above, the rest refused"),
        };
        (1.0 - occlusion).min(self.front_share(p))
    }

    /// The share of the light in front of `p`'s tangent plane when `p` lies on a closed mesh
    /// ([`crate::terminator::front_share`]), else 1 (on an open mesh, or on no triangle).
    pub fn front_share(&self, p: &SurfacePoint) -> f64 {
        let Some(&o) = self.triangle_occluder.get(p.triangle as usize) else {
            return 1.0;
        };
        let o = o & !CASTER_BIT;
        let sign = self.volumes.occluders[o as usize].outward;
        if sign == 0.0 {
            return 1.0;
        }
        let [a, b, c] = self.tracer.triangles[p.triangle as usize];
        let n = (b - a).cross(c - a) * sign;
        crate::terminator::front_share(&self.volumes.light, p.position, n)
    }

    /// Renders the whole image; `progress` gets the number of finished rows.
    ///
    /// # Panics
    ///
    /// If `technique` is not a volume technique (`hard`, `wedges`, `wedges-blend`).
    pub fn render(
        &self,
        scene: &Scene,
        technique: Technique,
        progress: &(dyn Fn(u64) + Sync),
    ) -> VisibilityImage {
        let cam = &scene.camera;
        let w = cam.width as usize;
        let mut img = VisibilityImage::filled(cam.width, cam.height, 1.0);
        let done = std::sync::atomic::AtomicU64::new(0);
        img.data.par_chunks_mut(w).enumerate().for_each(|(j, row)| {
            for (i, out) in row.iter_mut().enumerate() {
                if let Some(p) = self
                    .tracer
                    .surface_point(cam.eye, cam.ray_dir(i as u32, j as u32))
                {
                    *out = self.visibility(&p, technique) as f32;
                }
            }
            progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
        });
        img
    }
}
