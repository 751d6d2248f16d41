//! A scene: the camera, the light (or several named lights), the world-space meshes and the
//! shadow-map techniques' parameters, made in code here (read from a scene file in `scene_file.rs`, held to the
//! supported range in `range.rs`).

use std::path::PathBuf;
use std::sync::Arc;

use glam::{DMat4, DVec3};
use penumbra_params::TechniqueParams;

use crate::camera::Camera;
use crate::distant::{DistantLight, Light, Warp};
use crate::light::RectLight;
use crate::lights::{LightNameError, NamedLight, check_light_names};
use crate::mesh::TriangleMesh;

/// One mesh of a scene, in world space.
#[derive(Clone, Debug)]
pub struct SceneMesh {
    /// The OBJ file it came from.
    pub source: PathBuf,
    /// `translate * rotate * scale`: from the OBJ into the world (also in a scene under a
    /// distant light, whose positions are the warped world's).
    pub transform: DMat4,
    /// The welded mesh with world-space positions.
    pub mesh: TriangleMesh,
}

/// A loaded scene: camera, light (or several named lights) and world-space meshes.
///
/// Every renderer renders [`Scene::light`]. A scene of several lights (`[[light]]` in a scene
/// file, [`Scene::with_lights`] in code) lists them in [`Scene::lights`]; its images have one
/// channel per light, each the image of [`Scene::for_light`], the same scene under that light
/// alone.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The scene file.
    pub path: PathBuf,
    /// The camera.
    pub camera: Camera,
    /// The light the renderers render: the scene's one light (`[light]`), or the first of
    /// [`Scene::lights`].
    pub light: RectLight,
    /// The named lights of a scene of several (`[[light]]`, even of one entry), in file order,
    /// each rendered into its own channel `<name>.V`; empty for a scene of one `[light]`, whose
    /// image is the one channel `V`.
    pub lights: Vec<NamedLight>,
    /// The meshes, in file order.
    pub meshes: Vec<SceneMesh>,
    /// Parameters of the shadow-map techniques (defaults where the file has no table).
    pub params: TechniqueParams,
    /// Where [`Scene::light`] stands for a distant light: that light, and the world scene whose
    /// [`Warp`] this scene is ([`Scene::with_distant_light`]). `None` for a rectangle light.
    pub distant: Option<Arc<DistantView>>,
}

/// A scene under a distant light, as the renderers see it: the light, the warp that took the
/// world to the scene they render, and the world scene.
#[derive(Clone, Debug)]
pub struct DistantView {
    /// The distant light, in the world.
    pub light: DistantLight,
    /// The map from the world to the rendered scene.
    pub warp: Warp,
    /// The scene in world coordinates, with its lights; its [`Scene::light`] is the rendered
    /// one's (the world has no rectangle for a distant light).
    pub world: Scene,
}

impl Scene {
    /// A scene made in code: `camera` and `light`, no meshes yet (add them with
    /// [`Scene::with_mesh`]) and the shadow-map techniques' default parameters. Nothing is read
    /// from disk; its path reads `<in memory>`.
    ///
    /// ```
    /// use penumbra::glam::{DMat4, DVec2, DVec3};
    /// use penumbra::geom::{Camera, RectLight, Scene, TriangleMesh};
    ///
    /// let camera = Camera::look_at(DVec3::new(0.0, 4.0, 5.0), DVec3::ZERO, DVec3::Y, 45.0, 64, 48)?;
    /// let light = RectLight::new(DVec3::new(0.0, 5.0, 0.0), DVec3::NEG_Y, DVec3::X, DVec2::splat(2.0));
    /// let ground = TriangleMesh::from_raw(
    ///     "ground",
    ///     &[DVec3::new(-5.0, 0.0, -5.0), DVec3::new(-5.0, 0.0, 5.0), DVec3::new(5.0, 0.0, 5.0), DVec3::new(5.0, 0.0, -5.0)],
    ///     &[[0, 1, 2], [0, 2, 3]],
    /// )?;
    /// let scene = Scene::new(camera, light)
    ///     .with_mesh("ground", &ground, DMat4::IDENTITY)
    ///     .with_mesh("ball", &TriangleMesh::uv_sphere(12, 16), DMat4::from_translation(DVec3::Y));
    /// assert_eq!(scene.meshes.len(), 2);
    /// assert_eq!(scene.triangle_count(), 2 + 2 * 16 * 11);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(camera: Camera, light: RectLight) -> Scene {
        Scene {
            path: PathBuf::from("<in memory>"),
            camera,
            light,
            lights: Vec::new(),
            meshes: Vec::new(),
            params: TechniqueParams::default(),
            distant: None,
        }
    }

    /// The scene with `mesh` added, its positions moved by `transform` into the world; `name`
    /// stands for its file in messages.
    pub fn with_mesh(mut self, name: &str, mesh: &TriangleMesh, transform: DMat4) -> Scene {
        self.meshes.push(SceneMesh {
            source: PathBuf::from(name),
            transform,
            mesh: mesh.transformed(&transform),
        });
        self
    }

    /// The scene with several named lights in place of its one: `lights` in order, checked by
    /// [`crate::check_light_names`] (one at least, names valid and unique); [`Scene::light`]
    /// becomes the first.
    ///
    /// ```
    /// use penumbra::glam::{DVec2, DVec3};
    /// use penumbra::geom::{Camera, NamedLight, RectLight, Scene};
    ///
    /// let camera = Camera::look_at(DVec3::new(0.0, 4.0, 5.0), DVec3::ZERO, DVec3::Y, 45.0, 64, 48)?;
    /// let light = |x: f64| RectLight::new(DVec3::new(x, 5.0, 0.0), DVec3::NEG_Y, DVec3::X, DVec2::ONE);
    /// let scene = Scene::new(camera, light(0.0))
    ///     .with_lights(vec![NamedLight::new("key", light(-2.0))?, NamedLight::new("fill", light(2.0))?])?;
    /// assert_eq!(scene.light_count(), 2);
    /// assert_eq!(scene.channel_names(), ["key.V", "fill.V"]);
    /// assert_eq!(scene.for_light(1).light, light(2.0));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_lights(self, lights: Vec<NamedLight>) -> Result<Scene, LightNameError> {
        check_light_names(&lights)?;
        let first = lights[0].light;
        Ok(self.world_under(lights, first))
    }

    /// The same scene under the distant light `light` alone, in the form every renderer renders:
    /// the scene's [`Warp`] for that light applied to its meshes and camera, and [`Scene::light`]
    /// the rectangle that is the image of the light's directions. Its images are those of the
    /// world scene under `light` (see `docs/scene-format.md`, "Distant lights");
    /// [`Scene::world`] gives the world scene back.
    ///
    /// ```
    /// use penumbra::glam::{DMat4, DVec2, DVec3};
    /// use penumbra::geom::{Camera, DistantLight, RectLight, Scene, TriangleMesh};
    ///
    /// let camera = Camera::look_at(DVec3::new(0.0, 4.0, 5.0), DVec3::ZERO, DVec3::Y, 45.0, 64, 48)?;
    /// let lamp = RectLight::new(DVec3::new(0.0, 5.0, 0.0), DVec3::NEG_Y, DVec3::X, DVec2::ONE);
    /// let sun = DistantLight::new(DVec3::Y, DVec3::X, DVec2::splat(0.53));
    /// let ball = TriangleMesh::uv_sphere(12, 16);
    /// let scene = Scene::new(camera, lamp)
    ///     .with_mesh("ball", &ball, DMat4::IDENTITY)
    ///     .with_distant_light(sun);
    /// assert_eq!(scene.distant.as_ref().map(|d| d.light), Some(sun));
    /// // The renderers see the ball warped; the world keeps it as it was.
    /// assert_ne!(scene.meshes[0].mesh.positions, ball.positions);
    /// assert_eq!(scene.world().meshes[0].mesh.positions, ball.positions);
    /// // The sun shines down: its rectangle faces down.
    /// assert_eq!(scene.light.normal, DVec3::NEG_Y);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_distant_light(self, light: DistantLight) -> Scene {
        self.world_under(Vec::new(), Light::Distant(light))
    }

    /// The world scene with `lights` as its list of lights, in the form the renderers render
    /// under `light`: warped for a distant light, with `light` as [`Scene::light`] for a
    /// rectangle.
    fn world_under(&self, lights: Vec<NamedLight>, light: Light) -> Scene {
        let mut world = self.world().clone();
        world.distant = None;
        world.lights = lights;
        match light {
            Light::Rect(l) => {
                world.light = l;
                world
            }
            Light::Distant(l) => world.warped(l),
        }
    }

    /// The scene in world coordinates: this one, or the world scene of a scene under a distant
    /// light ([`Scene::distant`]).
    pub fn world(&self) -> &Scene {
        self.distant.as_ref().map_or(self, |d| &d.world)
    }

    /// The world scene `self` (not warped) in the form the renderers render under `light`,
    /// keeping its list of lights.
    fn warped(self, light: DistantLight) -> Scene {
        let points = self
            .meshes
            .iter()
            .flat_map(|m| m.mesh.positions.iter().copied())
            .chain(std::iter::once(self.camera.eye));
        let warp = Warp::around(points, light.direction);
        let rendered_light = warp.light(&light);
        let mut world = self;
        world.light = rendered_light;
        Scene {
            path: world.path.clone(),
            camera: warp.camera(&world.camera),
            light: rendered_light,
            lights: world.lights.clone(),
            meshes: world
                .meshes
                .iter()
                .map(|m| {
                    let mut mesh = m.mesh.clone();
                    for p in &mut mesh.positions {
                        *p = warp.point(*p);
                    }
                    SceneMesh {
                        source: m.source.clone(),
                        transform: m.transform,
                        mesh,
                    }
                })
                .collect(),
            params: world.params,
            distant: Some(Arc::new(DistantView { light, warp, world })),
        }
    }

    /// The scene's lights in the world, in order: [`Scene::lights`]' for a scene of several,
    /// else its one light.
    pub fn world_lights(&self) -> Vec<Light> {
        let world = self.world();
        if !world.lights.is_empty() {
            return world.lights.iter().map(|l| l.light).collect();
        }
        vec![match &self.distant {
            Some(d) => Light::Distant(d.light),
            None => Light::Rect(self.light),
        }]
    }

    /// How many lights the scene has, so many channels its images: 1 for a scene of one
    /// `[light]`, the length of [`Scene::lights`] otherwise.
    pub fn light_count(&self) -> usize {
        self.lights.len().max(1)
    }

    /// The names of the channels of the scene's images, one per light in order: `V` for a scene
    /// of one `[light]`, `<name>.V` for each of [`Scene::lights`].
    pub fn channel_names(&self) -> Vec<String> {
        if self.lights.is_empty() {
            vec![crate::image_files::CHANNEL.to_string()]
        } else {
            self.lights.iter().map(NamedLight::channel).collect()
        }
    }

    /// The names of the scene's lights, in order; empty for a scene of one `[light]`.
    pub fn light_names(&self) -> Vec<&str> {
        self.lights.iter().map(|l| l.name.as_str()).collect()
    }

    /// The same scene under its light `k` alone (0-based, of [`Scene::light_count`]): a scene of
    /// one light, [`Scene::light`], whose image is channel `k` of this scene's. The meshes are
    /// copied: 36 bytes per triangle, 5 MB and half a millisecond for the 209,388 triangles of
    /// `fixtures/scale/scale.toml`, next to the seconds and the hundreds of megabytes of its
    /// render (its silhouettes, volumes and wedges alone take about 2.4 KB per triangle).
    ///
    /// # Panics
    ///
    /// If `k` is not below [`Scene::light_count`].
    pub fn for_light(&self, k: usize) -> Scene {
        assert!(
            k < self.light_count(),
            "light {k} of a scene of {} lights",
            self.light_count()
        );
        match self.world().lights.get(k) {
            Some(named) => self.world_under(Vec::new(), named.light),
            None => self.clone(),
        }
    }

    /// Every world-space triangle of every mesh, meshes in order.
    pub fn triangles(&self) -> Vec<[DVec3; 3]> {
        self.meshes
            .iter()
            .flat_map(|m| (0..m.mesh.triangles.len()).map(|t| m.mesh.triangle(t)))
            .collect()
    }

    /// Total number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.mesh.triangles.len()).sum()
    }

    /// The files this scene was read from: the scene file and every OBJ.
    pub fn input_files(&self) -> Vec<PathBuf> {
        std::iter::once(self.path.clone())
            .chain(self.meshes.iter().map(|m| m.source.clone()))
            .collect()
    }

    /// The scene with every position moved by the rigid or similarity transform `m`, camera
    /// and lights included (for invariance tests); a scene under a distant light is moved in
    /// the world and warped again.
    pub fn transformed(&self, m: &DMat4) -> Scene {
        let dir = |v: DVec3| m.transform_vector3(v).normalize();
        let world = self.world();
        let c = &world.camera;
        let camera = Camera::look_at(
            m.transform_point3(c.eye),
            m.transform_point3(c.eye + c.forward),
            dir(c.true_up),
            c.fov_y_deg,
            c.width,
            c.height,
        )
        .expect("a similarity transform keeps the camera frame valid");
        let moved_rect = |l: &RectLight| {
            let scale = m.transform_vector3(l.tangent).length();
            RectLight::new(
                m.transform_point3(l.center),
                dir(l.normal),
                dir(l.tangent),
                l.size * scale,
            )
        };
        // A similarity keeps angles; a mirror turns `(-D) x T` around, which the light's frame
        // recomputes.
        let moved_distant = |l: &DistantLight| {
            DistantLight::new(dir(l.direction), dir(l.tangent), l.angular_size_deg)
        };
        let moved = Scene {
            path: world.path.clone(),
            camera,
            light: moved_rect(&world.light),
            lights: world
                .lights
                .iter()
                .map(|l| NamedLight {
                    name: l.name.clone(),
                    light: match &l.light {
                        Light::Rect(r) => Light::Rect(moved_rect(r)),
                        Light::Distant(d) => Light::Distant(moved_distant(d)),
                    },
                })
                .collect(),
            meshes: world
                .meshes
                .iter()
                .map(|s| SceneMesh {
                    source: s.source.clone(),
                    transform: *m * s.transform,
                    mesh: s.mesh.transformed(m),
                })
                .collect(),
            params: world.params,
            distant: None,
        };
        match &self.distant {
            Some(d) => moved.warped(moved_distant(&d.light)),
            None => moved,
        }
    }
}
