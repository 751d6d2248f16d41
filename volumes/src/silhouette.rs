//! Silhouette edges with respect to the light's centre, with multiplicities, grouped into loops.
//!
//! Every triangle is first oriented to face the light's centre `c`: a shadow volume is the union
//! of the semi-infinite frusta cast from `c` through each caster triangle, and the boundary of
//! that union, counted with multiplicity, is made of the triangles' edges where the directed
//! edges of the oriented triangles do not cancel (Bergeron 1986, "A general version of Crow's
//! shadow volumes"; Kim, Kim & Turk 2008, "Robust shadow volumes for arbitrary models").
//!
//! For an edge `(u, v)`, `u < v`, its multiplicity is
//!
//! ```text
//! m = Σ_f  (+1 if the light-facing orientation of f runs u -> v, -1 if it runs v -> u)
//! ```
//!
//! over the triangles `f` on the edge. Which triangles count depends on the mesh:
//!
//! - closed meshes (every edge manifold and consistently oriented) use their light-facing
//!   triangles only (Carmack's z-fail volumes): a ray from `P` to `c` crosses the front and the
//!   back surface of a solid, and one layer is enough. Silhouette edges then have `|m| = 1`.
//! - open and non-manifold meshes use every triangle, flipped to face the light where needed,
//!   because a single-sided quad casts a shadow from both sides. Boundary edges have `|m| = 1`,
//!   silhouettes of folded open surfaces `|m| = 2`, and an edge shared by three triangles may have
//!   `|m| = 1` or `3`.
//!
//! An edge with `m != 0` is a silhouette edge; its side quad is extruded `|m|` times with the
//! sign of `m`. A triangle seen edge-on from `c` (`c` in its plane) casts no volume and is skipped.

use glam::DVec3;
use penumbra_geom::HalfEdgeMesh;

/// One silhouette edge: the edge `from -> to` (mesh vertex indices), oriented so that `m > 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SilhouetteEdge {
    /// Start vertex (index into the mesh's positions).
    pub from: u32,
    /// End vertex.
    pub to: u32,
    /// Multiplicity, at least 1.
    pub multiplicity: u32,
    /// Index of the undirected edge in [`HalfEdgeMesh::edges`].
    pub edge: u32,
}

/// The silhouette of one mesh with respect to one light centre.
#[derive(Clone, Debug)]
pub struct Silhouette {
    /// Whether the mesh is closed (light-facing triangles only).
    pub closed: bool,
    /// Which triangles cast a volume: their vertex triples oriented to face the light.
    pub casters: Vec<[u32; 3]>,
    /// Per mesh face, whether it is a caster (a light cap of the volume).
    pub is_caster: Vec<bool>,
    /// Silhouette edges.
    pub edges: Vec<SilhouetteEdge>,
    /// Silhouette loops: connected sets of silhouette edges (indices into `edges`), connected
    /// through shared vertices. A vertex may join more than two edges.
    pub loops: Vec<Vec<u32>>,
    /// Per mesh face, its caster patch (`u32::MAX` for a face that casts nothing): casters
    /// joined across edges that are not silhouette edges. A patch's boundary is its silhouette:
    /// an outer loop with the hole loops inside it, the unit Forest et al. blend.
    pub patch: Vec<u32>,
    /// Number of patches.
    pub patches: u32,
    /// Per silhouette edge (as `edges`), each adjacent patch with its own signed multiplicity
    /// (positive when the patch runs the edge `from -> to`); they sum to the edge's.
    pub edge_patches: Vec<Vec<(u32, i32)>>,
}

/// `(b - a) x (c - a) . (d - a)`: positive when `d` is on the side the triangle `a b c` faces.
#[inline]
pub fn orient3d(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> f64 {
    (b - a).cross(c - a).dot(d - a)
}

impl Silhouette {
    /// Each face that casts: its index in the mesh, its vertices as they face the light (its
    /// light cap) and its patch, in face order.
    pub fn caster_faces(&self) -> impl Iterator<Item = (usize, [u32; 3], u32)> + '_ {
        let faces = self.is_caster.iter().enumerate().filter(|(_, c)| **c);
        faces
            .zip(&self.casters)
            .map(|((f, _), &caster)| (f, caster, self.patch[f]))
    }

    /// The side quads of each patch's shadow volume, in the silhouette edges' order: for each
    /// patch an edge bounds, the patch, the edge `from -> to` as that patch's casters run it,
    /// and how many times its side counts (the patch's own multiplicity there).
    pub fn patch_sides(&self) -> impl Iterator<Item = (u32, u32, u32, u32)> + '_ {
        self.edges
            .iter()
            .zip(&self.edge_patches)
            .flat_map(|(e, patches)| {
                patches.iter().map(move |&(patch, m)| {
                    let (from, to) = if m > 0 {
                        (e.from, e.to)
                    } else {
                        (e.to, e.from)
                    };
                    (patch, from, to, m.unsigned_abs())
                })
            })
    }

    /// Finds the silhouette of `mesh` as seen from the light centre `c`.
    pub fn build(mesh: &HalfEdgeMesh, c: DVec3) -> Self {
        Self::build_as(mesh, c, mesh.is_closed())
    }

    /// [`Silhouette::build`] with the rule for closed meshes (light-facing triangles only) or
    /// for open ones (every triangle) chosen by `closed`: a closed mesh that the light's plane
    /// cuts is open where it can occlude.
    pub fn build_as(mesh: &HalfEdgeMesh, c: DVec3, closed: bool) -> Self {
        let p = &mesh.positions;
        // Orientation of each face as seen from c: +1 facing, -1 away, 0 edge-on (its plane
        // within rounding of c, `PLANE_HOLDS`: a sun on the horizon over a tessellated ground
        // sees the ground edge-on, whichever way the warp rounds it).
        let facing: Vec<i8> = mesh
            .faces
            .iter()
            .map(|f| {
                let [a, b, d] = f.map(|v| p[v as usize]);
                let o = orient3d(a, b, d, c);
                let edge_on = penumbra_geom::PLANE_HOLDS
                    * (b - a).cross(d - a).length()
                    * (c - a).length().max((c - b).length()).max((c - d).length());
                if o.abs() <= edge_on {
                    0
                } else if o > 0.0 {
                    1
                } else if o < 0.0 {
                    -1
                } else {
                    0
                }
            })
            .collect();
        let counts = |fi: usize| -> i8 {
            match (closed, facing[fi]) {
                (_, 0) => 0,
                (true, s) if s < 0 => 0,
                (_, s) => s,
            }
        };
        let casters = mesh
            .faces
            .iter()
            .enumerate()
            .filter_map(|(fi, f)| match counts(fi) {
                0 => None,
                1 => Some(*f),
                _ => Some([f[0], f[2], f[1]]),
            })
            .collect();
        let is_caster: Vec<bool> = (0..mesh.faces.len()).map(|fi| counts(fi) != 0).collect();
        let mut parent: Vec<u32> = (0..mesh.faces.len() as u32).collect();
        let mut edges = Vec::new();
        for (ei, e) in mesh.edges.iter().enumerate() {
            let [u, v] = e.vertices;
            let mut m: i32 = 0;
            for &h in &e.half_edges {
                let he = mesh.half_edges[h as usize];
                let s = counts(HalfEdgeMesh::face(h) as usize) as i32;
                // The face's light-facing orientation runs origin -> dest when s = +1.
                m += if he.origin == u { s } else { -s };
            }
            if m == 0 {
                // Not a silhouette: its casters belong to one patch.
                let mut first = None;
                for &h in &e.half_edges {
                    let f = HalfEdgeMesh::face(h);
                    if !is_caster[f as usize] {
                        continue;
                    }
                    match first {
                        None => first = Some(f),
                        Some(g) => union(&mut parent, f, g),
                    }
                }
            }
            if m != 0 {
                let (from, to) = if m > 0 { (u, v) } else { (v, u) };
                edges.push(SilhouetteEdge {
                    from,
                    to,
                    multiplicity: m.unsigned_abs(),
                    edge: ei as u32,
                });
            }
        }
        let loops = group_loops(&edges, p.len());
        let mut patch = vec![u32::MAX; mesh.faces.len()];
        let mut label = std::collections::HashMap::new();
        for f in 0..mesh.faces.len() {
            if is_caster[f] {
                let r = find(&mut parent, f as u32);
                let n = label.len() as u32;
                patch[f] = *label.entry(r).or_insert(n);
            }
        }
        let edge_patches = edges
            .iter()
            .map(|se| {
                let e = &mesh.edges[se.edge as usize];
                let mut out: Vec<(u32, i32)> = Vec::new();
                for &h in &e.half_edges {
                    let f = HalfEdgeMesh::face(h) as usize;
                    let s = counts(f) as i32;
                    if s == 0 {
                        continue;
                    }
                    let he = mesh.half_edges[h as usize];
                    let d = if he.origin == se.from { s } else { -s };
                    match out.iter_mut().find(|(q, _)| *q == patch[f]) {
                        Some((_, m)) => *m += d,
                        None => out.push((patch[f], d)),
                    }
                }
                out.retain(|&(_, m)| m != 0);
                out
            })
            .collect();
        Silhouette {
            closed,
            casters,
            is_caster,
            edges,
            loops,
            patches: label.len() as u32,
            patch,
            edge_patches,
        }
    }
}

fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        parent[x as usize] = parent[parent[x as usize] as usize];
        x = parent[x as usize];
    }
    x
}

fn union(parent: &mut [u32], a: u32, b: u32) {
    let (a, b) = (find(parent, a), find(parent, b));
    if a != b {
        parent[a.max(b) as usize] = a.min(b);
    }
}

/// Connected components of the silhouette edge graph (union-find over vertices).
fn group_loops(edges: &[SilhouetteEdge], vertex_count: usize) -> Vec<Vec<u32>> {
    let mut parent: Vec<u32> = (0..vertex_count as u32).collect();
    for e in edges {
        let (a, b) = (find(&mut parent, e.from), find(&mut parent, e.to));
        if a != b {
            parent[a.max(b) as usize] = a.min(b);
        }
    }
    let mut loop_of_root = std::collections::HashMap::new();
    let mut loops: Vec<Vec<u32>> = Vec::new();
    for (i, e) in edges.iter().enumerate() {
        let r = find(&mut parent, e.from);
        let k = *loop_of_root.entry(r).or_insert_with(|| {
            loops.push(Vec::new());
            loops.len() - 1
        });
        loops[k].push(i as u32);
    }
    loops
}
