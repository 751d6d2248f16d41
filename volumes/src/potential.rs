//! Potential silhouette edges of a scene with respect to a rectangular light, and a hierarchy
//! over them that finds those a receiver's view of the light can meet.
//!
//! An edge is a silhouette from a point `L` when the faces meeting there lie on the same side of
//! the plane through `L` and the edge (seen from `L`, the surface folds back at the edge). It is
//! a *potential* silhouette edge when that holds for at least one point of the light (Laine,
//! Aila, Assarsson, Lehtinen & Akenine-Möller, "Soft Shadow Volumes for Ray Tracing", 2005):
//!
//! - every boundary edge (one face) and every edge with three or more faces;
//! - a two-face edge unless the light rectangle lies wholly on one side of one face's plane and
//!   wholly on the other side of the other's, in the orientation the edge gives them (then no
//!   light point sees the fold). The face side of the light is linear along the rectangle, so
//!   its four corners decide.
//!
//! Orientation plays no part: a face counts by the side of the edge its third vertex lies on,
//! so inconsistently oriented, open and non-manifold meshes need no special case. Edges wholly
//! behind the light's plane never come between a receiver and the light and are left out.
//!
//! Everything is kept in light space (see [`RectLight::to_light_space`]), an affine image of
//! world space with a positive determinant: sides and orientations are the world's.

use glam::DVec3;
use penumbra_geom::{BoxTree, Plane};
use penumbra_geom::{Edge, HalfEdgeMesh, LitScene, RectLight, TriangleMesh};
use rayon::prelude::*;

/// One face on a potential silhouette edge `a b`, as the plane through the edge and the face's
/// third vertex `w`: `F(x) = n . (x - a)` with `n = (b - a) x (w - a)`, whose sign at a point
/// tells the side of the plane through that point and the edge the face lies on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeFace {
    /// `(b - a) x (w - a)`, light space.
    pub normal: DVec3,
    /// `|normal|^2`, which both silhouette tests scale their margins by.
    pub normal_length2: f64,
    /// Index of the face in [`LitScene::triangles`].
    pub triangle: u32,
}

/// A potential silhouette edge: light-space ends and the faces meeting there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PotentialEdge {
    /// Light-space start.
    pub a: DVec3,
    /// Light-space end.
    pub b: DVec3,
    /// `(b - a) x (c - a)` for the light's centre `c` (the origin): the plane through the edge
    /// and the centre, in the form of [`EdgeFace::normal`].
    pub toward_centre: DVec3,
    /// First of its faces in [`PotentialEdges::faces`].
    pub first_face: u32,
    /// Number of faces (1 for a boundary edge, 3 or more for a non-manifold one).
    pub face_count: u32,
}

/// The light rectangle's corners in light space, counter-clockwise.
pub const LIGHT_CORNERS: [DVec3; 4] = [
    DVec3::new(-1.0, -1.0, 0.0),
    DVec3::new(1.0, -1.0, 0.0),
    DVec3::new(1.0, 1.0, 0.0),
    DVec3::new(-1.0, 1.0, 0.0),
];

/// Every potential silhouette edge of a scene, and their hierarchy.
pub struct PotentialEdges {
    /// The light they were chosen for.
    pub light: RectLight,
    /// The edges.
    pub edges: Vec<PotentialEdge>,
    /// Their faces, `face_count` per edge from `first_face`.
    pub faces: Vec<EdgeFace>,
    /// Edges of the scene's meshes before the selection.
    pub all_edges: usize,
    /// The largest light-space coordinate of a vertex of the meshes, and at least 1.
    pub reach: f64,
    /// Where triangles pass through the light's plane across the light.
    pub crossings: Vec<LightCrossing>,
    bvh: BoxTree,
}

/// A triangle passing through the light's plane where the light is: the segment `a b` (light
/// space, `z = 0`) where it crosses, which bounds its projection on the light as an edge does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightCrossing {
    /// Start, on the light's plane.
    pub a: DVec3,
    /// End, on the light's plane.
    pub b: DVec3,
    /// A point of the triangle just on the emitting side of the segment, whose projection from
    /// a receiver tells which side of the segment the triangle's projection lies on.
    pub inside: DVec3,
    /// Index of the triangle in [`LitScene::triangles`].
    pub triangle: u32,
}

/// The segment where the triangle `t` (light space) crosses the light's plane, if it does
/// with vertices strictly on both sides, or lies on it with a side there and its third vertex in
/// front, and the segment meets the light; with a point of the triangle just on the emitting
/// side of it.
fn light_crossing(t: [DVec3; 3], triangle: u32) -> Option<LightCrossing> {
    // A triangle with a side lying in the plane and its third vertex in front bounds its
    // projection there too (a box whose top face is the light's plane, a sphere with a ring of
    // vertices on it): that side is no potential silhouette edge (those lie strictly in front),
    // and without it the samples beyond it lost the triangle.
    let on_plane = t.iter().filter(|v| v.z == 0.0).count();
    if !(t.iter().any(|v| v.z > 0.0) && (t.iter().any(|v| v.z < 0.0) || on_plane == 2)) {
        return None;
    }
    let mut ends = Vec::with_capacity(3);
    for k in 0..3 {
        let (p, q) = (t[k], t[(k + 1) % 3]);
        if p.z == 0.0 {
            ends.push(DVec3::new(p.x, p.y, 0.0));
        } else if (p.z < 0.0) != (q.z < 0.0) && q.z != 0.0 {
            let x = p + (q - p) * (p.z / (p.z - q.z));
            ends.push(DVec3::new(x.x, x.y, 0.0));
        }
    }
    let (&a, &b) = (ends.first()?, ends.last()?);
    if a == b || !crate::wedge::segment_meets_square(a.truncate(), b.truncate()) {
        return None;
    }
    // The vertices on the emitting side, pulled towards the segment's middle.
    let lit: Vec<DVec3> = t.into_iter().filter(|v| v.z > 0.0).collect();
    let centre = lit.iter().copied().sum::<DVec3>() / lit.len() as f64;
    let mid = 0.5 * (a + b);
    Some(LightCrossing {
        a,
        b,
        inside: mid + (centre - mid) * 1e-3,
        triangle,
    })
}

/// Whether some point of the light sees the two faces with apices `w0`, `w1` on the same side
/// of the edge `a b` (conservatively: only a light wholly on opposite sides says no).
fn may_fold(a: DVec3, b: DVec3, w0: DVec3, w1: DVec3) -> bool {
    // `orient3d(a, b, l, w)` for the four corners `l`, the cross products shared by both apices
    // (the same operations, so the same values).
    let normals = LIGHT_CORNERS.map(|l| (b - a).cross(l - a));
    let side = |w: DVec3| normals.map(|n| n.dot(w - a));
    let (s0, s1) = (side(w0), side(w1));
    let opposite =
        |p: [f64; 4], q: [f64; 4]| p.iter().all(|&x| x > 0.0) && q.iter().all(|&x| x < 0.0);
    !(opposite(s0, s1) || opposite(s1, s0))
}

/// The third vertex of the face of half-edge `h`, which lies on the edge `ends`: the apex of
/// the face's plane through the edge ([`EdgeFace`]); its first vertex for a degenerate face
/// that repeats one of the edge's.
pub(crate) fn apex(mesh: &HalfEdgeMesh, h: u32, [ia, ib]: [u32; 2]) -> u32 {
    let f = mesh.faces[HalfEdgeMesh::face(h) as usize];
    f.into_iter().find(|&v| v != ia && v != ib).unwrap_or(f[0])
}

/// Edges a task of [`PotentialEdges::build_moved`] tests.
const EDGE_RUN: usize = 1 << 14;

/// The potential silhouette edges among `run`, edges of `mesh` whose vertices are at the
/// light-space `pos`, with their faces (numbered from `first_triangle`; `first_face` counted
/// from the run's first).
fn potential_in(
    mesh: &HalfEdgeMesh,
    run: &[Edge],
    folds: Option<&[bool]>,
    pos: &[DVec3],
    first_triangle: u32,
) -> (Vec<PotentialEdge>, Vec<EdgeFace>) {
    let (mut edges, mut faces) = (Vec::new(), Vec::new());
    // One list for every edge's apices: allocating one per edge cost as much as the tests.
    let mut apices: Vec<DVec3> = Vec::new();
    for (k, e) in run.iter().enumerate() {
        if folds.is_some_and(|f| !f[k]) {
            continue;
        }
        let [ia, ib] = e.vertices;
        let (a, b) = (pos[ia as usize], pos[ib as usize]);
        if a.z <= 0.0 && b.z <= 0.0 {
            continue;
        }
        apices.clear();
        apices.extend(
            e.half_edges
                .iter()
                .map(|&h| pos[apex(mesh, h, [ia, ib]) as usize]),
        );
        if apices.len() == 2 && !may_fold(a, b, apices[0], apices[1]) {
            continue;
        }
        edges.push(PotentialEdge {
            a,
            b,
            toward_centre: (b - a).cross(-a),
            first_face: faces.len() as u32,
            face_count: apices.len() as u32,
        });
        faces.extend(e.half_edges.iter().zip(&apices).map(|(&h, &w)| {
            let normal = (b - a).cross(w - a);
            EdgeFace {
                normal,
                normal_length2: normal.length_squared(),
                triangle: first_triangle + HalfEdgeMesh::face(h),
            }
        }));
    }
    (edges, faces)
}

impl PotentialEdges {
    /// Finds the potential silhouette edges of every mesh of `scene` for its light.
    pub fn build(scene: &LitScene) -> Self {
        Self::build_meshes(scene.meshes.iter().map(|m| &m.mesh), &scene.light)
    }

    /// Finds the potential silhouette edges of the world-space `meshes` for `light`; triangles
    /// are numbered through the meshes in order, as [`LitScene::triangles`] numbers them.
    pub fn build_meshes<'a>(
        meshes: impl IntoIterator<Item = &'a TriangleMesh>,
        light: &RectLight,
    ) -> Self {
        Self::build_half_edge(meshes.into_iter().map(HalfEdgeMesh::build), light)
    }

    /// [`PotentialEdges::build_meshes`] of meshes whose half-edge structures the caller has
    /// built already (world space, in the scene's order).
    pub fn build_half_edge(
        meshes: impl IntoIterator<Item = impl std::borrow::Borrow<HalfEdgeMesh>>,
        light: &RectLight,
    ) -> Self {
        let meshes: Vec<_> = meshes.into_iter().collect();
        Self::build_moved(
            meshes
                .iter()
                .map(|m| (m.borrow(), m.borrow().positions.as_slice())),
            light,
        )
    }

    /// [`PotentialEdges::build_half_edge`] of meshes whose vertices have moved (under a distant
    /// light, the warped world's): each mesh's half-edge structure, whose positions are not
    /// read, with its vertices' positions now, as many, in its order.
    ///
    /// # Panics
    ///
    /// If a mesh is given fewer positions than its faces name.
    pub fn build_moved<'a>(
        meshes: impl IntoIterator<Item = (&'a HalfEdgeMesh, &'a [DVec3])>,
        light: &RectLight,
    ) -> Self {
        Self::build_folding(meshes.into_iter().map(|(m, p)| (m, p, None)), light)
    }

    /// [`PotentialEdges::build_moved`] where the caller has ruled out some edges already: with
    /// each mesh, `None` or one flag per edge of it, false where no point of the light can see
    /// the edge fold (the edges of a sun study, [`crate::SunSeries`], ruled out by their faces'
    /// normals in the world). The flags only save the test: an edge flagged false must be one
    /// the test leaves out.
    pub(crate) fn build_folding<'a>(
        meshes: impl IntoIterator<Item = (&'a HalfEdgeMesh, &'a [DVec3], Option<&'a [bool]>)>,
        light: &RectLight,
    ) -> Self {
        let light = *light;
        let mut edges = Vec::new();
        let mut faces = Vec::new();
        let mut all_edges = 0;
        let mut reach = 1.0f64;
        let mut first_triangle = 0u32;
        let mut crossings = Vec::new();
        for (mesh, positions, folds) in meshes {
            all_edges += mesh.edges.len();
            // A large mesh on every core, in runs of edges joined in their order; a small one
            // on this thread (waking the others would cost more).
            let large = mesh.edges.len() > EDGE_RUN;
            let to_light = |p: &DVec3| light.to_light_space(*p);
            let pos: Vec<DVec3> = match large {
                true => positions.par_iter().map(to_light).collect(),
                false => positions.iter().map(to_light).collect(),
            };
            let (mesh_reach, nearest) = pos.iter().fold((reach, f64::INFINITY), |(r, z), p| {
                (r.max(p.abs().max_element()), z.min(p.z))
            });
            reach = mesh_reach;
            let run_folds =
                |k: usize| folds.map(|f| &f[k * EDGE_RUN..(f.len()).min((k + 1) * EDGE_RUN)]);
            let runs: Vec<(Vec<PotentialEdge>, Vec<EdgeFace>)> = match large {
                true => mesh
                    .edges
                    .par_chunks(EDGE_RUN)
                    .enumerate()
                    .map(|(k, run)| potential_in(mesh, run, run_folds(k), &pos, first_triangle))
                    .collect(),
                false => vec![potential_in(mesh, &mesh.edges, folds, &pos, first_triangle)],
            };
            for (run_edges, run_faces) in runs {
                let offset = faces.len() as u32;
                edges.extend(run_edges.into_iter().map(|mut e| {
                    e.first_face += offset;
                    e
                }));
                faces.extend(run_faces);
            }
            let crossing = |(f, tri): (usize, &[u32; 3])| {
                light_crossing(tri.map(|v| pos[v as usize]), first_triangle + f as u32)
            };
            // Only a mesh with a vertex on or behind the light's plane crosses it.
            match (large, nearest > 0.0) {
                (_, true) => {}
                (true, false) => {
                    crossings.par_extend(mesh.faces.par_iter().enumerate().filter_map(crossing))
                }
                (false, false) => {
                    crossings.extend(mesh.faces.iter().enumerate().filter_map(crossing))
                }
            }
            first_triangle += mesh.faces.len() as u32;
        }
        let boxes: Vec<(DVec3, DVec3)> =
            edges.iter().map(|e| (e.a.min(e.b), e.a.max(e.b))).collect();
        let mut bvh = BoxTree::build(&boxes);
        // Edges and faces in the tree's leaf order: a query reads them in runs.
        let mut sorted = Vec::with_capacity(edges.len());
        let mut sorted_faces = Vec::with_capacity(faces.len());
        for &i in bvh.order() {
            let mut e: PotentialEdge = edges[i as usize];
            let from = e.first_face as usize;
            e.first_face = sorted_faces.len() as u32;
            sorted_faces.extend_from_slice(&faces[from..from + e.face_count as usize]);
            sorted.push(e);
        }
        bvh.renumber();
        let (edges, faces) = (sorted, sorted_faces);
        PotentialEdges {
            light,
            edges,
            faces,
            all_edges,
            reach,
            crossings,
            bvh,
        }
    }

    /// The faces of edge `e`.
    pub fn faces_of(&self, e: &PotentialEdge) -> &[EdgeFace] {
        &self.faces[e.first_face as usize..(e.first_face + e.face_count) as usize]
    }

    /// Whether edge `ei` may be a silhouette seen from some point of the light-space box
    /// `[lo, hi]`: false only for a two-face edge whose faces' planes through the edge keep the
    /// box on opposite sides of each, `F0 > 0 > F1` or `F0 < 0 < F1` everywhere in it
    /// ([`EdgeFace`]). Each `F` is linear, so its range over the box is its value at the centre
    /// plus or minus `|n| . half-size`; a margin of 1e-9 of that range's scale covers rounding.
    pub fn may_fold_within(&self, ei: u32, lo: DVec3, hi: DVec3) -> bool {
        let e = &self.edges[ei as usize];
        let [f0, f1] = self.faces_of(e) else {
            return true;
        };
        let (centre, half) = (0.5 * (lo + hi) - e.a, 0.5 * (hi - lo));
        let range = |n: DVec3| {
            let (mid, spread) = (n.dot(centre), n.abs().dot(half));
            (mid - spread, mid + spread, spread)
        };
        let ((lo0, hi0, s0), (lo1, hi1, s1)) = (range(f0.normal), range(f1.normal));
        // Apart with the ranges widened by margins `m0` and `m1`.
        let apart = |m0: f64, m1: f64| {
            (lo0 - m0 > 0.0 && hi1 + m1 < 0.0) || (hi0 + m0 < 0.0 && lo1 - m1 > 0.0)
        };
        // The margins only widen the ranges: a box that straddles a plane without them does
        // with them, so they are computed (square roots) only for the boxes left.
        if !apart(0.0, 0.0) {
            return true;
        }
        let c = centre.length();
        let margin = |n: DVec3, spread: f64| 1e-9 * (n.length() * c + spread);
        !apart(margin(f0.normal, s0), margin(f1.normal, s1))
    }

    /// Calls `f` with every edge that may meet the pyramid from the light-space point `p`
    /// (`p.z > 0`) to the light rectangle: a superset of the edges that come between `p` and
    /// some point of the light.
    pub fn for_each_near(&self, p: DVec3, f: impl FnMut(u32)) {
        self.for_each_near_any(&[p], f);
    }

    /// [`PotentialEdges::for_each_near`] for several points at once (`z > 0` each): every edge
    /// that may meet one of their pyramids, each once, in increasing order.
    ///
    /// The pyramids' union lies in the light's half-space and, for each edge of the light, in
    /// the outermost of the planes through that edge and a point: planes through one line are
    /// ordered by their angle with the light's plane, and a point lies inside those at least as
    /// steep as its own.
    pub fn for_each_near_any(&self, points: &[DVec3], mut f: impl FnMut(u32)) {
        self.for_each_near_any_while(points, |i| {
            f(i);
            true
        });
    }

    /// [`PotentialEdges::for_each_near_any`] until `f` returns `false`; returns whether it never
    /// did (every edge was visited).
    pub fn for_each_near_any_while(
        &self,
        points: &[DVec3],
        mut f: impl FnMut(u32) -> bool,
    ) -> bool {
        let Some((&first, rest)) = points.split_first() else {
            return true;
        };
        let mut planes = pyramid_planes(first);
        for &p in rest {
            let own = pyramid_planes(p);
            for k in 1..5 {
                if planes[k].n.dot(p) + planes[k].d < 0.0 {
                    planes[k] = own[k];
                }
            }
        }
        self.bvh.query_planes_while(&planes, &mut f)
    }
}

/// The five planes bounding the pyramid from `p` to the light rectangle: its four sides through
/// `p` and the light's edges, and the light's plane `z >= 0`.
pub fn pyramid_planes(p: DVec3) -> [Plane; 5] {
    let mut planes = [Plane {
        n: DVec3::Z,
        d: 0.0,
    }; 5];
    for k in 0..4 {
        let (c0, c1) = (LIGHT_CORNERS[k], LIGHT_CORNERS[(k + 1) % 4]);
        let mut n = (c0 - p).cross(c1 - p);
        // The light's centre (the origin) is inside.
        if n.dot(-p) < 0.0 {
            n = -n;
        }
        planes[k + 1] = Plane { n, d: -n.dot(p) };
    }
    planes
}
