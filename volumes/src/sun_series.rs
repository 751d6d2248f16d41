//! One scene rendered by depth-complexity sampling under a distant light in one direction after
//! another (a sun study), building once what does not depend on the direction.
//!
//! Under a distant light a scene is rendered warped for the light's direction (`distant.rs` in
//! `penumbra_geom`), so that each direction is a scene of its own. Three things of it do not
//! change with the direction: the hierarchies of the world's triangles, which the tracer casts
//! its rays in ([`Tracer::new_reusing`]); the half-edge structures of the meshes, whose
//! vertices alone the warp moves ([`PotentialEdges::build_moved`]); and the world's surface
//! point behind each pixel ([`Tracer::world_surface_point`]). A [`SunSeries`] keeps the three
//! from one render to the next while the meshes and the camera stay, and builds per direction
//! only the warped positions, the potential silhouette edges and the counts: the same image,
//! bit for bit, as a [`DepthComplexity`] built for each direction. It also keeps, for each
//! edge, its faces' normals in the world, which rule out most edges for a direction by two dot
//! products before the light-space test (the sun is half a degree wide: an edge whose faces
//! both lean more than that from its direction, one towards and one away, cannot fold).

use std::sync::Arc;

use glam::Vec3;
use penumbra_geom::{
    Camera, DistantLight, HalfEdgeMesh, LitScene, Rays, SceneMesh, SurfacePoint, Tracer,
    TracerGeometry, VisibilityImage,
};
use rayon::prelude::*;

use crate::depth_complexity::DepthComplexity;
use crate::potential::{PotentialEdges, apex};
use crate::samples::SamplePattern;

/// What renders of one scene under a distant light share (see the module's documentation).
///
/// ```
/// use penumbra::geom::{DistantLight, Light, NamedLight, Scene};
/// use penumbra::volumes::{DepthComplexity, SamplePattern, SunSeries};
///
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures/scenes/sun.toml");
/// let mut scene = Scene::load(std::path::Path::new(path))?;
/// (scene.camera.width, scene.camera.height) = (24, 16);
/// let pattern = SamplePattern { per_axis: 4, jitter: false };
/// let mut series = SunSeries::default();
/// for azimuth in [100.0, 140.0, 180.0] {
///     let sun = DistantLight::sun(azimuth, 35.0, 0.53)?;
///     scene.lights = vec![NamedLight { name: "sun".into(), light: Light::Distant(sun) }];
///     let lit = scene.lit(0);
///     let image = series.render(&lit, pattern, &|_| {});
///     assert_eq!(image, DepthComplexity::new(&lit).render(pattern, &|_| {}));
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Default)]
pub struct SunSeries {
    /// The ray-casting hierarchies of the world's triangles.
    kept: Option<TracerGeometry>,
    /// The world's meshes the topology and the hits are of (shared with the scene, and held
    /// here, so that an equal pointer is the same meshes).
    meshes: Option<Arc<Vec<SceneMesh>>>,
    /// Their half-edge structures, in order.
    topology: Vec<HalfEdgeMesh>,
    /// For each of their edges, its faces' normals in the world ([`FaceNormals`]).
    normals: Vec<Vec<FaceNormals>>,
    /// The world's camera the hits are of.
    camera: Option<Camera>,
    /// Per pixel, rows from the top, its surface point in the world.
    hits: Vec<Option<SurfacePoint>>,
}

/// The unit normals in the world of an edge's two faces' planes through it, `(b - a) x (w -
/// a)` normalised for each face's third vertex `w` (the planes of
/// [`crate::potential::EdgeFace`]), or NaN for an edge without two faces or with a degenerate
/// one: one that no direction rules out.
type FaceNormals = [Vec3; 2];

/// [`FaceNormals`] of each edge of `mesh`, whose positions are the world's.
fn face_normals(mesh: &HalfEdgeMesh) -> Vec<FaceNormals> {
    let pos = &mesh.positions;
    mesh.edges
        .iter()
        .map(|e| {
            let [ia, ib] = e.vertices;
            let (a, b) = (pos[ia as usize], pos[ib as usize]);
            let normal = |h: u32| {
                let w = apex(mesh, h, [ia, ib]);
                let n = (b - a).cross(pos[w as usize] - a);
                let len = n.length();
                match len > 0.0 && len.is_finite() {
                    true => (n / len).as_vec3(),
                    false => Vec3::NAN,
                }
            };
            match &e.half_edges[..] {
                &[h0, h1] => [normal(h0), normal(h1)],
                _ => [Vec3::NAN; 2],
            }
        })
        .collect()
}

/// The largest difference between a dot product of unit vectors in `f32` and the exact one
/// that [`may_fold`] allows for, far above the `f32` rounding of normals computed in `f64`.
const FOLD_MARGIN: f32 = 1e-4;

/// For each edge of `normals`, whether some direction of `light` may see its two faces on one
/// side of the plane through the edge and that direction (where it may be a silhouette): false
/// only where every direction within the light's cone keeps the faces' planes on opposite
/// sides, `n0 . d` and `n1 . d` of opposite signs, each farther from zero than the sine of the
/// cone's half angle (out to the rectangle's corners) for the cone's axis. In the warped scene
/// a direction is a point of the rectangle light ([`penumbra_geom::Warp`]), so an edge ruled out
/// here is one the light-space test ([`PotentialEdges::build_moved`]) leaves out too.
fn may_fold(normals: &[FaceNormals], light: &DistantLight) -> Vec<bool> {
    let half = light.half_tangents().length();
    let sine = (half / (1.0 + half * half).sqrt()) as f32 + FOLD_MARGIN;
    let d: Vec3 = light.direction.as_vec3();
    let fold = |[n0, n1]: &FaceNormals| {
        let (s0, s1) = (n0.dot(d), n1.dot(d));
        !(s0 * s1 < 0.0 && s0.abs() > sine && s1.abs() > sine)
    };
    match normals.len() > 1 << 14 {
        true => normals.par_iter().map(fold).collect(),
        false => normals.iter().map(fold).collect(),
    }
}

impl SunSeries {
    /// A series that keeps `kept`'s hierarchies where they serve the first scene.
    pub fn reusing(kept: Option<TracerGeometry>) -> Self {
        SunSeries {
            kept,
            ..SunSeries::default()
        }
    }

    /// The hierarchies it holds, for another renderer.
    pub fn kept(&self) -> Option<&TracerGeometry> {
        self.kept.as_ref()
    }

    /// The depth-complexity image of `scene` with `pattern`, as [`DepthComplexity::render`]
    /// makes it; `progress` gets the number of finished rows. Under a rectangle light nothing
    /// but the hierarchies is shared.
    pub fn render(
        &mut self,
        scene: &LitScene,
        pattern: SamplePattern,
        progress: &(dyn Fn(u64) + Sync),
    ) -> VisibilityImage {
        let Some(view) = &scene.distant else {
            return DepthComplexity::new_reusing(scene, &mut self.kept).render(pattern, progress);
        };
        let same = self
            .meshes
            .as_ref()
            .is_some_and(|m| Arc::ptr_eq(m, &view.meshes));
        if !same {
            self.topology = view
                .meshes
                .par_iter()
                .map(|m| HalfEdgeMesh::build(&m.mesh))
                .collect();
            self.normals = self.topology.par_iter().map(face_normals).collect();
            self.meshes = Some(Arc::clone(&view.meshes));
            self.camera = None;
        }
        let tracer = match (&self.kept, same) {
            (Some(geometry), true) => Tracer::with_geometry(scene, geometry.clone()),
            _ => Tracer::new_reusing(scene, Rays::Many, &mut self.kept),
        };
        if self.camera != Some(view.camera) {
            let cam = view.camera;
            self.hits = (0..cam.width as usize * cam.height as usize)
                .into_par_iter()
                .map(|k| {
                    let (i, j) = (
                        (k % cam.width as usize) as u32,
                        (k / cam.width as usize) as u32,
                    );
                    tracer.world_surface_point(cam.eye, cam.ray_dir(i, j))
                })
                .collect();
            self.camera = Some(cam);
        }
        let folds: Vec<Vec<bool>> = self
            .normals
            .iter()
            .map(|n| may_fold(n, &view.light))
            .collect();
        let moved = self
            .topology
            .iter()
            .zip(scene.meshes.iter().map(|m| m.mesh.positions.as_slice()))
            .zip(&folds)
            .map(|((mesh, positions), folds)| (mesh, positions, Some(folds.as_slice())));
        let edges = PotentialEdges::build_folding(moved, &scene.light);
        let dc = DepthComplexity::from_parts(scene, tracer, edges);
        let width = view.camera.width as usize;
        dc.render_at(pattern, progress, &|i, j| {
            let p = self.hits[j as usize * width + i as usize]?;
            Some(dc.tracer.rendered(p))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_geom::{Light, NamedLight, Scene};

    /// The edges ruled out by their normals in the world are edges the light-space test leaves
    /// out: the same potential edges, for the sun high and low and for wider distant lights.
    #[test]
    fn edges_ruled_out_in_the_world_are_those_the_light_leaves_out() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures/scenes/sun.toml");
        let mut scene = Scene::load(std::path::Path::new(path)).unwrap();
        let topology: Vec<HalfEdgeMesh> = scene
            .meshes
            .iter()
            .map(|m| HalfEdgeMesh::build(&m.mesh))
            .collect();
        let normals: Vec<Vec<FaceNormals>> = topology.iter().map(face_normals).collect();
        let (mut edges, mut ruled_out) = (0, 0);
        for (azimuth, elevation, size) in [
            (100.0, 35.0, 0.53),
            (180.0, 70.0, 0.53),
            (260.0, 2.0, 0.53),
            (300.0, -0.2, 0.53),
            (30.0, 20.0, 8.0),
            (140.0, 50.0, 60.0),
        ] {
            let sun = DistantLight::sun(azimuth, elevation, size).unwrap();
            scene.lights = vec![NamedLight {
                name: "sun".into(),
                light: Light::Distant(sun),
            }];
            let lit = scene.lit(0);
            let positions = lit.meshes.iter().map(|m| m.mesh.positions.as_slice());
            let want =
                PotentialEdges::build_moved(topology.iter().zip(positions.clone()), &lit.light);
            let folds: Vec<Vec<bool>> = normals.iter().map(|n| may_fold(n, &sun)).collect();
            let moved = topology
                .iter()
                .zip(positions)
                .zip(&folds)
                .map(|((m, p), f)| (m, p, Some(f.as_slice())));
            let got = PotentialEdges::build_folding(moved, &lit.light);
            assert_eq!(got.edges, want.edges, "{azimuth}, {elevation}, {size}");
            assert_eq!(got.faces, want.faces);
            edges += want.all_edges;
            ruled_out += folds.iter().flatten().filter(|&&f| !f).count();
        }
        // Most edges are ruled out by two dot products.
        assert!(ruled_out * 10 > edges * 8, "{ruled_out} of {edges}");
    }
}
