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
//! bit for bit, as a [`DepthComplexity`] built for each direction.

use std::sync::Arc;

use penumbra_geom::{
    Camera, HalfEdgeMesh, LitScene, Rays, SceneMesh, SurfacePoint, Tracer, TracerGeometry,
    VisibilityImage,
};
use rayon::prelude::*;

use crate::depth_complexity::DepthComplexity;
use crate::potential::PotentialEdges;
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
    /// The world's camera the hits are of.
    camera: Option<Camera>,
    /// Per pixel, rows from the top, its surface point in the world.
    hits: Vec<Option<SurfacePoint>>,
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
        let moved = self
            .topology
            .iter()
            .zip(scene.meshes.iter().map(|m| m.mesh.positions.as_slice()));
        let edges = PotentialEdges::build_moved(moved, &scene.light);
        let dc = DepthComplexity::from_parts(scene, tracer, edges);
        let width = view.camera.width as usize;
        dc.render_at(pattern, progress, &|i, j| {
            let p = self.hits[j as usize * width + i as usize]?;
            Some(dc.tracer.rendered(p))
        })
    }
}
