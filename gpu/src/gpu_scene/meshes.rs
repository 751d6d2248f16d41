//! A [`super::GpuScene`]'s meshes as stored: each in its own space, its vertices relative to an
//! origin in `f32`, and where it is in the world.

use glam::{DMat4, DVec3};
use penumbra_geom::{TriangleMesh, Warp};

/// One mesh as stored: its own-space mesh, its vertices relative to `origin` in `f32`, and where
/// it is.
pub(super) struct StoredMesh {
    pub(super) mesh: TriangleMesh,
    /// `penumbra_volumes::outward_sign` of the mesh in its own space.
    pub(super) outward: f64,
    pub(super) origin: DVec3,
    /// The bounding box of the mesh in its own space (`lo > hi` for a mesh of no vertices).
    pub(super) bounds: (DVec3, DVec3),
    pub(super) transform: DMat4,
    pub(super) stored: Vec<[f32; 3]>,
    /// For the last transform and point in front of the light, and for the last transform and
    /// eye: whether the mesh (closed) winds around that point. Around both, it is a room
    /// around its light, seen from inside.
    pub(super) around: [Option<(DMat4, DVec3, bool)>; 2],
}

impl StoredMesh {
    /// `mesh` with its vertices stored relative to `origin`, placed by `transform`.
    pub(super) fn new(mesh: &TriangleMesh, transform: DMat4, origin: DVec3, outward: f64) -> Self {
        StoredMesh {
            stored: mesh
                .positions
                .iter()
                .map(|&p| (p - origin).as_vec3().to_array())
                .collect(),
            mesh: mesh.clone(),
            outward,
            origin,
            bounds: bounds(&mesh.positions),
            transform,
            around: [None; 2],
        }
    }

    /// Moves its vertices to `positions` (its own space, as many as it has).
    pub(super) fn move_vertices(&mut self, positions: &[DVec3]) {
        self.mesh.positions.copy_from_slice(positions);
        self.stored = positions
            .iter()
            .map(|&p| (p - self.origin).as_vec3().to_array())
            .collect();
        self.bounds = bounds(positions);
        self.around = [None; 2];
    }

    /// Whether this closed mesh, where it is, is a room around the light seen from inside: it
    /// winds around `lamp` (a point just in front of the light's centre) and `eye`, each
    /// remembered for the same transform and point (the eye is asked only of a mesh around
    /// the lamp, so that a moving camera costs nothing in scenes without rooms).
    pub(super) fn is_room(&mut self, lamp: DVec3, eye: DVec3) -> bool {
        self.winds_around(0, lamp) && self.winds_around(1, eye)
    }

    /// Whether the mesh winds around `point`, remembered in slot `slot`.
    fn winds_around(&mut self, slot: usize, point: DVec3) -> bool {
        if let Some((t, p, around)) = self.around[slot]
            && t == self.transform
            && p == point
        {
            return around;
        }
        let world = self.mesh.transformed(&self.transform);
        let around = penumbra_volumes::winds_around(
            world
                .triangles
                .iter()
                .map(|t| t.map(|i| world.positions[i as usize])),
            point,
        );
        self.around[slot] = Some((self.transform, point, around));
        around
    }
}

/// The world-space meshes of `meshes` and their triangles; under a distant light, carried by
/// its `warp` to the scene the passes render.
pub(super) fn world(
    meshes: &[StoredMesh],
    warp: Option<&Warp>,
) -> (Vec<TriangleMesh>, Vec<[DVec3; 3]>) {
    let meshes: Vec<TriangleMesh> = meshes
        .iter()
        .map(|m| {
            let mut world = m.mesh.transformed(&m.transform);
            if let Some(w) = warp {
                for p in &mut world.positions {
                    *p = w.point(*p);
                }
            }
            world
        })
        .collect();
    let triangles = meshes
        .iter()
        .flat_map(|m| {
            m.triangles
                .iter()
                .map(|t| t.map(|i| m.positions[i as usize]))
        })
        .collect();
    (meshes, triangles)
}

/// The bounding box `(lo, hi)` of `positions` (`lo > hi` when there are none).
fn bounds(positions: &[DVec3]) -> (DVec3, DVec3) {
    positions
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        })
}

/// Centre of the bounding box of `positions` (the origin when there are none).
pub(super) fn centre(positions: &[DVec3]) -> DVec3 {
    let (lo, hi) = bounds(positions);
    if lo.x <= hi.x {
        (lo + hi) * 0.5
    } else {
        DVec3::ZERO
    }
}

/// The corners of every mesh's bounding box (kept from its upload), in the world: what a
/// distant light's warp must hold.
pub(super) fn world_corners(meshes: &[StoredMesh]) -> Vec<DVec3> {
    meshes
        .iter()
        .flat_map(|m| {
            let (lo, hi) = m.bounds;
            let corners: Vec<DVec3> = if lo.x <= hi.x {
                (0..8)
                    .map(|c| {
                        let pick = |bit: u32, a: f64, b: f64| if c & bit == 0 { a } else { b };
                        DVec3::new(
                            pick(1, lo.x, hi.x),
                            pick(2, lo.y, hi.y),
                            pick(4, lo.z, hi.z),
                        )
                    })
                    .collect()
            } else {
                Vec::new()
            };
            corners
                .into_iter()
                .map(|c| m.transform.transform_point3(c))
                .collect::<Vec<_>>()
        })
        .collect()
}
