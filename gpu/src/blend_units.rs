//! What the tiled `wedges-blend` pass reads of the blending units, computed on the CPU from the
//! volumes: one list of items in the blend's order (each unit's count at the eye, then the side
//! quads of its shadow volume, then its wedges), the side quads, the unit each triangle casts
//! for, and each unit's casters, which give its count at the eye for each frame
//! (`shaders/blend_tiles.wgsl`).

use std::ops::Range;

use glam::DVec3;
use penumbra_volumes::Volumes;

/// A side quad of a unit's shadow volume, as the shader reads it: the silhouette edge `from ->
/// to` as its mesh's vertex buffer stores its ends (placed by the mesh's model matrix), running
/// the way the volume's side `to, from, from∞, to∞` faces outwards, and how many times the quad
/// counts.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct BlendQuad {
    /// `from` (xyz) and the mesh, as an `f32` (exact below 2^24).
    pub from: [f32; 4],
    /// `to` (xyz) and the multiplicity `|m|`.
    pub to: [f32; 4],
}

/// An item's kind, in its word's top two bits: the unit's count at the eye.
pub const EYE_ITEM: u32 = 0;
/// A side quad (the low 30 bits index [`BlendUnits::quads`]).
pub const QUAD_ITEM: u32 = 1 << 30;
/// A wedge (the low 30 bits index the wedge instances).
pub const WEDGE_ITEM: u32 = 2 << 30;

/// What [`BlendUnits::triangle_units`] holds for a triangle that casts for no unit.
pub const NO_UNIT: u32 = u32::MAX;

/// The units' items, quads and casters.
pub struct BlendUnits {
    /// `[unit, kind | index]` in the blend's order: units in order, and for each its count at
    /// the eye, its quads and its wedges.
    pub items: Vec<[u32; 2]>,
    /// The side quads.
    pub quads: Vec<BlendQuad>,
    /// For each scene triangle, the unit it casts for, or [`NO_UNIT`].
    pub triangle_units: Vec<u32>,
    /// Each unit's casters (the light space the volumes were built in) and their box.
    casters: Vec<UnitCasters>,
}

/// One unit's casters and their bounding box.
struct UnitCasters {
    lo: DVec3,
    hi: DVec3,
    triangles: Vec<[DVec3; 3]>,
}

impl BlendUnits {
    /// The items of `volumes`, whose meshes' vertex buffers hold `stored`, with each unit's
    /// range of the wedge instances (`instance_ranges`, [`crate::scene_data::wedge_instances`]).
    pub fn new(volumes: &Volumes, stored: &[&[[f32; 3]]], instance_ranges: &[Range<u32>]) -> Self {
        let units = volumes.unit_count();
        let mut quads_of: Vec<Vec<BlendQuad>> = vec![Vec::new(); units];
        let mut casters: Vec<UnitCasters> = (0..units)
            .map(|_| UnitCasters {
                lo: DVec3::INFINITY,
                hi: DVec3::NEG_INFINITY,
                triangles: Vec::new(),
            })
            .collect();
        let triangles: usize = volumes.occluders.iter().map(|o| o.mesh.faces.len()).sum();
        let mut triangle_units = vec![NO_UNIT; triangles];
        let mut first_unit = 0usize;
        for (oi, (o, stored)) in volumes.occluders.iter().zip(stored).enumerate() {
            let sil = &o.silhouette;
            let p = &o.mesh.positions;
            for (f, caster, patch) in sil.caster_faces() {
                let u = first_unit + patch as usize;
                triangle_units[o.first_triangle as usize + f] = u as u32;
                let unit = &mut casters[u];
                let t = caster.map(|v| p[v as usize]);
                for v in t {
                    unit.lo = unit.lo.min(v);
                    unit.hi = unit.hi.max(v);
                }
                unit.triangles.push(t);
            }
            let at = |v: u32, w: f32| {
                let [x, y, z] = stored[v as usize];
                [x, y, z, w]
            };
            for (patch, from, to, count) in sil.patch_sides() {
                quads_of[first_unit + patch as usize].push(BlendQuad {
                    from: at(from, oi as f32),
                    to: at(to, count as f32),
                });
            }
            first_unit += sil.patches as usize;
        }
        let mut items = Vec::new();
        let mut quads = Vec::new();
        for (u, unit_quads) in quads_of.into_iter().enumerate() {
            let unit = u as u32;
            items.push([unit, EYE_ITEM]);
            for q in unit_quads {
                items.push([unit, QUAD_ITEM | quads.len() as u32]);
                quads.push(q);
            }
            if let Some(r) = instance_ranges.get(u) {
                items.extend(r.clone().map(|i| [unit, WEDGE_ITEM | i]));
            }
        }
        BlendUnits {
            items,
            quads,
            triangle_units,
            casters,
        }
    }

    /// Each unit's z-fail count at the eye `eye`: its casters that the open segment from the
    /// eye to the light's centre `c` crosses (the count every pixel's starts from).
    pub fn eye_counts(&self, eye: DVec3, c: DVec3) -> Vec<i32> {
        let (lo, hi) = (eye.min(c), eye.max(c));
        self.casters
            .iter()
            .map(|u| {
                if !(u.lo.cmple(hi).all() && lo.cmple(u.hi).all()) {
                    return 0;
                }
                u.triangles.iter().filter(|&&t| crosses(eye, c, t)).count() as i32
            })
            .collect()
    }
}

/// Whether the open segment `p l` crosses the triangle `t`, its edges included.
fn crosses(p: DVec3, l: DVec3, t: [DVec3; 3]) -> bool {
    penumbra_geom::segment_meets_plane(p, l, t).is_some_and(|(u, v, along)| {
        u >= 0.0 && v >= 0.0 && u + v <= 1.0 && along > 0.0 && along < 1.0
    })
}
