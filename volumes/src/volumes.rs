//! What the scene's volume techniques are made of, on the CPU and the GPU alike: per mesh its
//! half-edges, silhouette from the light's centre and shadow volume ([`Occluder`]), and the
//! penumbra wedges of every silhouette edge ([`Volumes`]).

use std::collections::HashMap;

use glam::DVec3;
use penumbra_geom::{HalfEdgeMesh, LitScene, RectLight, TriangleMesh};

use crate::shadow_volume::ShadowVolume;
use crate::silhouette::Silhouette;
use crate::wedge::Wedge;

/// One scene mesh with its half-edges, silhouette and shadow volume.
pub struct Occluder {
    /// Half-edge structure (world space), wound outwards where the mesh is closed: a closed
    /// scene mesh wound inwards is flipped here ([`Occluder::outward`] keeps its own winding).
    pub mesh: HalfEdgeMesh,
    /// Its silhouette from the light's centre.
    pub silhouette: Silhouette,
    /// Index of its first triangle in [`LitScene::triangles`].
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
    pub fn build(scene: &LitScene) -> Self {
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
                // A closed mesh around the light (a room lit from inside, through whose walls
                // or recess the plane passes) keeps the rule of closed meshes: only its faces
                // whose outer side faces the centre (a ceiling beside a recessed lamp) can hide
                // light from the room, and its walls are not casters over their own receivers.
                let cut = mesh.faces.iter().any(|t| {
                    t.iter().any(|&v| ls[v as usize].z < 0.0)
                        && t.iter().any(|&v| ls[v as usize].z > 0.0)
                }) && !(mesh.is_closed()
                    && crate::light_centre::winds_around(
                        mesh.faces
                            .iter()
                            .map(|f| f.map(|v| mesh.positions[v as usize])),
                        crate::light_centre::in_front_of(scene_light),
                    ));
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

/// `wedges` (each unit's together) with each unit's in runs that follow its outline: after
/// each wedge, the unit's first wedge not yet taken that starts where it ends, else its first
/// not yet taken. A silhouette loop lists its edges as a set; along the outline, the wedges a
/// receiver point meets one after another project next to one another, so that the CPU
/// renderer's tests and closed forms take the same branches in turn (docs/benchmarks.md). The
/// GPU keeps the order of [`Volumes::build`]: in this one its `wedges-blend` image of
/// `spheres-9x9` moved by up to 0.037 in 0.5% of the penumbra's pixels (mean 6e-7).
pub(crate) fn along_outlines(wedges: Vec<Wedge>) -> Vec<Wedge> {
    let key = |unit: u32, p: DVec3| (unit, p.x.to_bits(), p.y.to_bits(), p.z.to_bits());
    // The wedges starting at each (unit, point), in their order, and how many of them are
    // known to be taken (each is taken once: a vertex shared by many edges costs no more).
    let mut starting: HashMap<_, (Vec<u32>, usize)> = HashMap::new();
    for (i, w) in wedges.iter().enumerate() {
        starting
            .entry(key(w.unit, w.from))
            .or_default()
            .0
            .push(i as u32);
    }
    let mut taken = vec![false; wedges.len()];
    let mut out = Vec::with_capacity(wedges.len());
    for first in 0..wedges.len() {
        let mut at = first;
        while !taken[at] {
            taken[at] = true;
            let w = wedges[at];
            out.push(w);
            let Some((run, skip)) = starting.get_mut(&key(w.unit, w.to)) else {
                break;
            };
            while *skip < run.len() && taken[run[*skip] as usize] {
                *skip += 1;
            }
            match run.get(*skip) {
                Some(&next) => at = next as usize,
                None => break,
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wedge(unit: u32, from: [f64; 2], to: [f64; 2]) -> Wedge {
        Wedge {
            from: DVec3::new(from[0], from[1], 1.0),
            to: DVec3::new(to[0], to[1], 1.0),
            multiplicity: 1,
            occluder: 0,
            silhouette_loop: 0,
            unit,
            caster: None,
        }
    }

    #[test]
    fn each_unit_s_wedges_follow_its_outline() {
        // Unit 0: a square listed out of order; unit 1: two triangles sharing the corner
        // (0, 0), one of them listed backwards from the middle.
        let wedges = vec![
            wedge(0, [1., 1.], [0., 1.]),
            wedge(0, [0., 0.], [1., 0.]),
            wedge(0, [0., 1.], [0., 0.]),
            wedge(0, [1., 0.], [1., 1.]),
            wedge(1, [2., 0.], [0., 0.]),
            wedge(1, [0., 0.], [-1., 0.]),
            wedge(1, [0., 0.], [2., 1.]),
            wedge(1, [-1., -1.], [0., 0.]),
            wedge(1, [2., 1.], [2., 0.]),
            wedge(1, [-1., 0.], [-1., -1.]),
        ];
        let ordered = along_outlines(wedges.clone());
        // The same wedges, each unit's together.
        assert_eq!(ordered.len(), wedges.len());
        for w in &wedges {
            let n = |v: &[Wedge]| v.iter().filter(|x| *x == w).count();
            assert_eq!(n(&ordered), n(&wedges), "{w:?}");
        }
        assert!(ordered.windows(2).all(|p| p[0].unit <= p[1].unit));
        // Each wedge but a unit's last starts where the one before it ends.
        for p in ordered.windows(2).filter(|p| p[0].unit == p[1].unit) {
            assert_eq!(p[0].to, p[1].from, "{ordered:?}");
        }
    }
}
