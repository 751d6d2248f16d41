//! A scene under one of its lights, in the form every renderer renders: the camera, the
//! rectangle light to render, the meshes and, for a distant light, the warp that took the world
//! to what is rendered (see `distant.rs`).

use std::path::PathBuf;
use std::sync::Arc;

use glam::DVec3;
use penumbra_params::TechniqueParams;
use rayon::prelude::*;

use crate::camera::Camera;
use crate::distant::{DistantLight, Warp};
use crate::light::RectLight;
use crate::lights::Light;
use crate::scene::{Scene, SceneMesh, triangles};

/// A scene under one light ([`Scene::lit`]): what a renderer renders.
///
/// Under a rectangle light it is the scene itself, its meshes shared with the [`Scene`]. Under a
/// distant light, the scene's [`Warp`] for that light is applied to the meshes and the camera,
/// and [`LitScene::light`] is the rectangle that is the image of the light's directions: its
/// images are those of the world scene under the distant light; [`LitScene::distant`] keeps the
/// light, the warp and the world's camera and meshes.
#[derive(Clone, Debug)]
pub struct LitScene {
    /// The scene file, or `<in memory>`.
    pub path: PathBuf,
    /// The camera the renderers cast from (the warped world's under a distant light); its
    /// size is set with [`LitScene::set_size`], which keeps the world's camera in step.
    pub camera: Camera,
    /// The rectangle light the renderers render.
    pub light: RectLight,
    /// The meshes the renderers render (the warped world's under a distant light).
    pub meshes: Arc<Vec<SceneMesh>>,
    /// Parameters of the shadow-map techniques.
    pub params: TechniqueParams,
    /// Under a distant light: the light, its warp and the world.
    pub distant: Option<DistantView>,
}

/// A distant light's part of a [`LitScene`]: the light, the warp that took the world to the
/// scene the renderers render, and the world's camera and meshes.
#[derive(Clone, Debug)]
pub struct DistantView {
    /// The distant light, in the world.
    pub light: DistantLight,
    /// The map from the world to the rendered scene.
    pub warp: Warp,
    /// The camera in the world.
    pub camera: Camera,
    /// The meshes in the world (shared with the [`Scene`]).
    pub meshes: Arc<Vec<SceneMesh>>,
}

impl LitScene {
    /// `scene` under `light`.
    pub(crate) fn new(scene: &Scene, light: Light) -> LitScene {
        match light {
            Light::Rect(l) => LitScene {
                path: scene.path.clone(),
                camera: scene.camera,
                light: l,
                meshes: onto_the_light_plane(&scene.meshes, &l),
                params: scene.params,
                distant: None,
            },
            Light::Distant(l) => {
                let points = scene
                    .meshes
                    .iter()
                    .flat_map(|m| m.mesh.positions.iter().copied())
                    .chain(std::iter::once(scene.camera.eye));
                let warp = Warp::around(points, l.direction);
                let meshes = scene
                    .meshes
                    .iter()
                    .map(|m| {
                        let mut mesh = m.mesh.clone();
                        mesh.positions
                            .par_iter_mut()
                            .for_each(|p| *p = warp.point(*p));
                        SceneMesh {
                            source: m.source.clone(),
                            transform: m.transform,
                            mesh,
                        }
                    })
                    .collect();
                LitScene {
                    path: scene.path.clone(),
                    camera: warp.camera(&scene.camera),
                    light: warp.light(&l),
                    meshes: Arc::new(meshes),
                    params: scene.params,
                    distant: Some(DistantView {
                        light: l,
                        warp,
                        camera: scene.camera,
                        meshes: Arc::clone(&scene.meshes),
                    }),
                }
            }
        }
    }

    /// Renders `width x height` pixels with the same view: the rendered camera and, under a
    /// distant light, the world's camera alike.
    pub fn set_size(&mut self, width: u32, height: u32) {
        for camera in
            std::iter::once(&mut self.camera).chain(self.distant.as_mut().map(|d| &mut d.camera))
        {
            camera.width = width;
            camera.height = height;
        }
    }

    /// The light in the world: the rectangle, or the distant light.
    pub fn world_light(&self) -> Light {
        match &self.distant {
            Some(d) => Light::Distant(d.light),
            None => Light::Rect(self.light),
        }
    }

    /// The camera in the world.
    pub fn world_camera(&self) -> &Camera {
        self.distant.as_ref().map_or(&self.camera, |d| &d.camera)
    }

    /// The meshes in the world.
    pub fn world_meshes(&self) -> &[SceneMesh] {
        self.distant.as_ref().map_or(&self.meshes, |d| &d.meshes)
    }

    /// The warp of a distant light, `None` under a rectangle.
    pub fn warp(&self) -> Option<&Warp> {
        self.distant.as_ref().map(|d| &d.warp)
    }

    /// Every triangle the renderers render, meshes in order.
    pub fn triangles(&self) -> Vec<[DVec3; 3]> {
        triangles(&self.meshes)
    }

    /// Every triangle in the world, meshes in order: [`LitScene::triangles`] under a rectangle
    /// light.
    pub fn world_triangles(&self) -> Vec<[DVec3; 3]> {
        triangles(self.world_meshes())
    }

    /// Total number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.mesh.triangles.len()).sum()
    }
}

/// How far, relative to the scene's extent (its bounding box's diagonal), a vertex may lie in
/// front of a light's plane and be taken as in it ([`Scene::lit`]), at most.
pub const PLANE_SNAP: f64 = 1e-6;

/// `meshes` with every vertex that lies strictly in front of `light`'s plane by no more than
/// the rounding of `f32` coordinates (4 ulps of each coordinate and of the light's centre's,
/// along the light's normal; at most [`PLANE_SNAP`] of the scene's extent) moved along the
/// normal onto the plane (or within rounding behind it). Meshes stored in `f32` (OBJ, PLY, glTF)
/// put a ceiling meant to hold its lamp (both at 3.3, say) within rounding of the lamp's plane,
/// on either side; in front, it would hide the whole lamp. The meshes are shared, not copied,
/// where no vertex moves.
fn onto_the_light_plane(meshes: &Arc<Vec<SceneMesh>>, light: &RectLight) -> Arc<Vec<SceneMesh>> {
    let (c, n) = (light.center, light.normal);
    let (lo, hi) = meshes
        .iter()
        .flat_map(|m| m.mesh.positions.iter())
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    let cap = PLANE_SNAP * (hi - lo).length();
    let near = |v: DVec3| {
        let d = light.signed_distance(v);
        let rounding = 4.0 * f64::from(f32::EPSILON) * n.abs().dot(v.abs() + c.abs());
        d > 0.0 && d <= rounding.min(cap)
    };
    if !(cap > 0.0)
        || !meshes
            .iter()
            .any(|m| m.mesh.positions.iter().any(|&v| near(v)))
    {
        return Arc::clone(meshes);
    }
    let snapped = meshes
        .iter()
        .map(|m| {
            let mut m = m.clone();
            for v in m.mesh.positions.iter_mut().filter(|v| near(**v)) {
                // Onto the plane, then past it by the rounding left over, if any.
                for _ in 0..4 {
                    let d = light.signed_distance(*v);
                    if d <= 0.0 {
                        break;
                    }
                    *v -= n * d.max(f64::EPSILON * v.abs().max_element());
                }
            }
            m
        })
        .collect();
    Arc::new(snapped)
}

impl Scene {
    /// The scene under its light `k` (0-based, of [`Scene::light_count`]) in the form every
    /// renderer renders: the camera, the rectangle to render, the meshes (shared, not copied,
    /// under a rectangle light, but for vertices within `f32` rounding in front of its plane,
    /// which move onto it: [`PLANE_SNAP`]) and, for a distant light, its [`crate::Warp`] with the warped
    /// meshes and camera (see `docs/scene-format.md`, "Distant lights").
    ///
    /// # Panics
    ///
    /// If `k` is not below [`Scene::light_count`].
    pub fn lit(&self, k: usize) -> LitScene {
        assert!(
            k < self.lights.len(),
            "light {k} of a scene of {} lights",
            self.lights.len()
        );
        LitScene::new(self, self.lights[k].light)
    }
}
