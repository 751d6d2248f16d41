//! A half-edge structure over a triangle mesh that represents, rather than rejects, what real
//! meshes contain: boundary edges (open meshes), non-manifold edges (three or more faces), and
//! inconsistently oriented neighbours.
//!
//! Half-edge `3 f + k` runs from corner `k` to corner `k + 1 (mod 3)` of face `f`, so `next`,
//! `prev` and `face` are implicit. Every undirected edge lists the half-edges lying on it; an edge
//! with exactly two half-edges is manifold and those two are each other's `twin`.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use glam::DVec3;

use crate::mesh::TriangleMesh;

/// Sentinel for "no twin".
pub const NO_TWIN: u32 = u32::MAX;

/// One directed edge of a face.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HalfEdge {
    /// Start vertex.
    pub origin: u32,
    /// End vertex.
    pub dest: u32,
    /// The undirected edge this half-edge lies on.
    pub edge: u32,
    /// The other half-edge of a manifold edge, or [`NO_TWIN`].
    pub twin: u32,
}

/// How many faces meet at an edge, and whether they agree on orientation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeKind {
    /// One face: the edge of an open mesh.
    Boundary,
    /// Two faces whose half-edges run opposite ways (a consistently oriented manifold edge).
    Manifold,
    /// Two faces whose half-edges run the same way: their orientations disagree.
    Inconsistent,
    /// Three or more faces.
    NonManifold,
}

/// An undirected edge and the half-edges on it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Edge {
    /// Its two vertices, smaller index first.
    pub vertices: [u32; 2],
    /// The half-edges lying on it, in face order.
    pub half_edges: HalfEdgeList,
    /// Classification by the faces meeting there.
    pub kind: EdgeKind,
}

/// The half-edges on one edge, read as a slice: up to two kept inline (every edge of a manifold
/// mesh), more in a list of their own, so that building a mesh's edges allocates nothing for
/// most of them.
#[derive(Clone, Debug, Default)]
pub struct HalfEdgeList {
    inline: [u32; 2],
    len: u32,
    more: Vec<u32>,
}

impl HalfEdgeList {
    /// Appends half-edge `h`.
    pub fn push(&mut self, h: u32) {
        match self.len {
            0 | 1 => self.inline[self.len as usize] = h,
            2 => {
                self.more.extend_from_slice(&self.inline);
                self.more.push(h);
            }
            _ => self.more.push(h),
        }
        self.len += 1;
    }
}

impl std::ops::Deref for HalfEdgeList {
    type Target = [u32];

    fn deref(&self) -> &[u32] {
        if self.len <= 2 {
            &self.inline[..self.len as usize]
        } else {
            &self.more
        }
    }
}

impl<'a> IntoIterator for &'a HalfEdgeList {
    type Item = &'a u32;
    type IntoIter = std::slice::Iter<'a, u32>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl PartialEq for HalfEdgeList {
    fn eq(&self, other: &Self) -> bool {
        **self == **other
    }
}

impl Eq for HalfEdgeList {}

/// The map key of the undirected edge `(lo, hi)`.
fn edge_key((lo, hi): (u32, u32)) -> u64 {
    (u64::from(lo) << 32) | u64::from(hi)
}

/// Hashes an edge key in a few instructions (the finaliser of MurmurHash3's 64-bit variant,
/// which mixes every bit into the high and the low ones the table reads). The map's keys are a
/// mesh's own vertex indices, not input an attacker chooses to collide, and the edges are
/// numbered in the order they are met, whatever the hash: the standard hasher's cost bought
/// nothing here.
#[derive(Default)]
struct EdgeKeyHasher(u64);

impl Hasher for EdgeKeyHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = self.0.rotate_left(8) ^ u64::from(b);
        }
    }

    fn write_u64(&mut self, k: u64) {
        self.0 ^= k;
    }

    fn finish(&self) -> u64 {
        let mut h = self.0;
        h ^= h >> 33;
        h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
        h ^= h >> 33;
        h = h.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
        h ^ (h >> 33)
    }
}

/// Half-edge mesh over welded positions.
#[derive(Clone, Debug)]
pub struct HalfEdgeMesh {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Faces as vertex triples.
    pub faces: Vec<[u32; 3]>,
    /// `3 * faces.len()` half-edges.
    pub half_edges: Vec<HalfEdge>,
    /// Undirected edges.
    pub edges: Vec<Edge>,
}

/// A broken invariant found by [`HalfEdgeMesh::validate`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("half-edge invariant broken at half-edge {half_edge}: {what}")]
pub struct InvariantError {
    /// The half-edge where the check failed.
    pub half_edge: usize,
    /// Which invariant.
    pub what: &'static str,
}

impl HalfEdgeMesh {
    /// Builds the structure from a welded triangle mesh.
    pub fn build(mesh: &TriangleMesh) -> Self {
        let mut half_edges = Vec::with_capacity(mesh.triangles.len() * 3);
        // A closed mesh has 3/2 edges per face, an open one a few more: reserved ahead, the list
        // is copied once at most as it grows.
        let mut edges: Vec<Edge> = Vec::with_capacity(mesh.triangles.len() * 3 / 2 + 16);
        let mut edge_of: HashMap<u64, u32, BuildHasherDefault<EdgeKeyHasher>> =
            HashMap::with_capacity_and_hasher(mesh.triangles.len() * 2, Default::default());
        for (f, tri) in mesh.triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                let key = (a.min(b), a.max(b));
                let e = *edge_of.entry(edge_key(key)).or_insert_with(|| {
                    edges.push(Edge {
                        vertices: [key.0, key.1],
                        half_edges: HalfEdgeList::default(),
                        kind: EdgeKind::Boundary,
                    });
                    (edges.len() - 1) as u32
                });
                let h = (3 * f + k) as u32;
                edges[e as usize].half_edges.push(h);
                half_edges.push(HalfEdge {
                    origin: a,
                    dest: b,
                    edge: e,
                    twin: NO_TWIN,
                });
            }
        }
        for edge in &mut edges {
            edge.kind = match edge.half_edges.len() {
                1 => EdgeKind::Boundary,
                2 => {
                    let (h0, h1) = (edge.half_edges[0] as usize, edge.half_edges[1] as usize);
                    half_edges[h0].twin = h1 as u32;
                    half_edges[h1].twin = h0 as u32;
                    if half_edges[h0].origin == half_edges[h1].dest {
                        EdgeKind::Manifold
                    } else {
                        EdgeKind::Inconsistent
                    }
                }
                _ => EdgeKind::NonManifold,
            };
        }
        HalfEdgeMesh {
            positions: mesh.positions.clone(),
            faces: mesh.triangles.clone(),
            half_edges,
            edges,
        }
    }

    /// Face of half-edge `h`.
    pub fn face(h: u32) -> u32 {
        h / 3
    }

    /// Next half-edge around the same face.
    pub fn next(h: u32) -> u32 {
        h - h % 3 + (h % 3 + 1) % 3
    }

    /// Previous half-edge around the same face.
    pub fn prev(h: u32) -> u32 {
        h - h % 3 + (h % 3 + 2) % 3
    }

    /// Number of edges of each kind: `[boundary, manifold, inconsistent, non-manifold]`.
    pub fn edge_counts(&self) -> [usize; 4] {
        let mut c = [0; 4];
        for e in &self.edges {
            c[match e.kind {
                EdgeKind::Boundary => 0,
                EdgeKind::Manifold => 1,
                EdgeKind::Inconsistent => 2,
                EdgeKind::NonManifold => 3,
            }] += 1;
        }
        c
    }

    /// Whether every edge is manifold and consistently oriented: the mesh bounds a volume.
    pub fn is_closed(&self) -> bool {
        self.edges.iter().all(|e| e.kind == EdgeKind::Manifold)
    }

    /// Whether some neighbouring faces disagree on orientation.
    pub fn has_inconsistent_orientation(&self) -> bool {
        self.edges.iter().any(|e| e.kind == EdgeKind::Inconsistent)
    }

    /// Checks every invariant of the structure; tests call it after every build.
    ///
    /// - there are three half-edges per face, each joining consecutive corners of its face, and
    ///   `next`/`prev` cycle through them;
    /// - every half-edge lies on exactly one edge, which joins the same two vertices and lists it;
    /// - twins are mutual, join the same vertices, belong to different faces and exist exactly on
    ///   edges with two half-edges;
    /// - each edge's kind matches its half-edges;
    /// - no vertex index is out of range, and no face repeats a vertex.
    pub fn validate(&self) -> Result<(), InvariantError> {
        let fail = |h: usize, what| Err(InvariantError { half_edge: h, what });
        if self.half_edges.len() != 3 * self.faces.len() {
            return fail(0, "half-edge count is not three per face");
        }
        let mut listed = vec![0u8; self.half_edges.len()];
        for e in &self.edges {
            for &h in &e.half_edges {
                if (h as usize) < listed.len() {
                    listed[h as usize] += 1;
                }
            }
        }
        for (h, he) in self.half_edges.iter().enumerate() {
            let hu = h as u32;
            let f = &self.faces[h / 3];
            let k = h % 3;
            if he.origin != f[k] || he.dest != f[(k + 1) % 3] {
                return fail(h, "half-edge does not join consecutive corners of its face");
            }
            if Self::next(Self::prev(hu)) != hu || Self::next(Self::next(Self::next(hu))) != hu {
                return fail(h, "next/prev do not cycle in three");
            }
            if f.iter().any(|&v| v as usize >= self.positions.len()) {
                return fail(h, "vertex index out of range");
            }
            if f[0] == f[1] || f[1] == f[2] || f[0] == f[2] {
                return fail(h, "face repeats a vertex");
            }
            if listed[h] != 1 {
                return fail(h, "half-edge not listed by exactly one edge");
            }
            let Some(edge) = self.edges.get(he.edge as usize) else {
                return fail(h, "edge index out of range");
            };
            if !edge.half_edges.contains(&hu) {
                return fail(h, "edge does not list its half-edge");
            }
            let key = [he.origin.min(he.dest), he.origin.max(he.dest)];
            if edge.vertices != key {
                return fail(h, "edge joins other vertices than its half-edge");
            }
            let two = edge.half_edges.len() == 2;
            if two != (he.twin != NO_TWIN) {
                return fail(h, "twin present iff the edge has two half-edges");
            }
            if he.twin != NO_TWIN {
                let t = &self.half_edges[he.twin as usize];
                if t.twin != hu || t.edge != he.edge || he.twin / 3 == hu / 3 {
                    return fail(h, "twin is not mutual, on the same edge, in another face");
                }
            }
            let kind = match edge.half_edges.len() {
                1 => EdgeKind::Boundary,
                2 if self.half_edges[edge.half_edges[0] as usize].origin
                    == self.half_edges[edge.half_edges[1] as usize].dest =>
                {
                    EdgeKind::Manifold
                }
                2 => EdgeKind::Inconsistent,
                _ => EdgeKind::NonManifold,
            };
            if kind != edge.kind {
                return fail(h, "edge kind does not match its half-edges");
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh(p: &[[f64; 3]], t: &[[u32; 3]]) -> TriangleMesh {
        let p: Vec<DVec3> = p.iter().map(|&a| DVec3::from(a)).collect();
        TriangleMesh::from_raw("test", &p, t).unwrap()
    }

    fn tetra() -> TriangleMesh {
        mesh(
            &[[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]],
            &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
        )
    }

    #[test]
    fn closed_tetrahedron() {
        let h = HalfEdgeMesh::build(&tetra());
        h.validate().unwrap();
        assert_eq!(h.edges.len(), 6);
        assert!(h.is_closed());
        assert_eq!(h.edge_counts(), [0, 6, 0, 0]);
    }

    #[test]
    fn open_quad_has_boundary() {
        let m = mesh(
            &[[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]],
            &[[0, 1, 2], [0, 2, 3]],
        );
        let h = HalfEdgeMesh::build(&m);
        h.validate().unwrap();
        assert_eq!(h.edge_counts(), [4, 1, 0, 0]);
        assert!(!h.is_closed());
    }

    #[test]
    fn three_faces_on_one_edge_are_non_manifold() {
        let m = mesh(
            &[
                [0., 0., 0.],
                [1., 0., 0.],
                [0., 1., 0.],
                [0., -1., 0.],
                [0., 0., 1.],
            ],
            &[[0, 1, 2], [1, 0, 3], [0, 1, 4]],
        );
        let h = HalfEdgeMesh::build(&m);
        h.validate().unwrap();
        assert_eq!(h.edge_counts()[3], 1);
        let e = h
            .edges
            .iter()
            .find(|e| e.kind == EdgeKind::NonManifold)
            .unwrap();
        assert_eq!(e.vertices, [0, 1]);
        assert_eq!(e.half_edges.len(), 3);
    }

    #[test]
    fn flipped_face_is_detected() {
        let mut m = tetra();
        m.triangles[2] = [1, 3, 2];
        let h = HalfEdgeMesh::build(&m);
        h.validate().unwrap();
        assert!(h.has_inconsistent_orientation());
        assert_eq!(h.edge_counts()[2], 3);
    }

    #[test]
    fn validate_catches_a_broken_twin() {
        let mut h = HalfEdgeMesh::build(&tetra());
        let t = h.half_edges[0].twin;
        h.half_edges[t as usize].twin = 5;
        assert!(h.validate().is_err());
    }
}
