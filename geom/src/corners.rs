//! The welded mesh of loose triangle corners, as the glTF and PLY readers make them: numbered
//! in the order the OBJ reader numbers vertices, so that the same triangles read from any format
//! make the same mesh.

use std::path::Path;

use glam::DVec3;

use crate::mesh::{MeshError, TriangleMesh};

/// The welded mesh of `triangles` over `positions` (finite, every index in range, fewer than
/// `u32::MAX` positions: the readers check all three with their own messages), its vertices
/// numbered in the order the triangles first use them, as the OBJ reader numbers them: the same
/// triangles read from any format make the same mesh, and vertices no triangle uses are left out.
pub(crate) fn from_corners(
    path: &Path,
    positions: &[DVec3],
    triangles: &[[u32; 3]],
) -> Result<TriangleMesh, MeshError> {
    if triangles.is_empty() {
        return Err(MeshError::Empty {
            path: path.to_path_buf(),
        });
    }
    let mut number = vec![u32::MAX; positions.len()];
    let mut used = Vec::new();
    let mut renumbered = Vec::with_capacity(triangles.len());
    for t in triangles {
        renumbered.push(t.map(|i| {
            let n = &mut number[i as usize];
            if *n == u32::MAX {
                *n = used.len() as u32;
                used.push(positions[i as usize]);
            }
            *n
        }));
    }
    TriangleMesh::from_raw_at(path, &used, &renumbered)
}
