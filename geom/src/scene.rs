//! A scene: the camera, the light (or several named lights), the world-space meshes and the
//! shadow-map techniques' parameters, made in code here (read from a scene file in `scene_file.rs`, held to the
//! supported range in `range.rs`).

use std::path::PathBuf;

use glam::{DMat4, DVec3};
use penumbra_params::TechniqueParams;

use crate::camera::Camera;
use crate::light::RectLight;
use crate::lights::{LightNameError, NamedLight, check_light_names};
use crate::mesh::TriangleMesh;

/// One mesh of a scene, in world space.
#[derive(Clone, Debug)]
pub struct SceneMesh {
    /// The OBJ file it came from.
    pub source: PathBuf,
    /// `translate * rotate * scale`.
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
    pub fn with_lights(mut self, lights: Vec<NamedLight>) -> Result<Scene, LightNameError> {
        check_light_names(&lights)?;
        self.light = lights[0].light;
        self.lights = lights;
        Ok(self)
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
        let mut one = self.clone();
        if let Some(l) = self.lights.get(k) {
            one.light = l.light;
        }
        one.lights = Vec::new();
        one
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
    /// and light included (for invariance tests).
    pub fn transformed(&self, m: &DMat4) -> Scene {
        let dir = |v: DVec3| m.transform_vector3(v).normalize();
        let c = &self.camera;
        let camera = Camera::look_at(
            m.transform_point3(c.eye),
            m.transform_point3(c.eye + c.forward),
            dir(c.true_up),
            c.fov_y_deg,
            c.width,
            c.height,
        )
        .expect("a similarity transform keeps the camera frame valid");
        let moved = |l: &RectLight| {
            let scale = m.transform_vector3(l.tangent).length();
            RectLight::new(
                m.transform_point3(l.center),
                dir(l.normal),
                dir(l.tangent),
                l.size * scale,
            )
        };
        Scene {
            path: self.path.clone(),
            camera,
            light: moved(&self.light),
            lights: self
                .lights
                .iter()
                .map(|l| NamedLight {
                    name: l.name.clone(),
                    light: moved(&l.light),
                })
                .collect(),
            meshes: self
                .meshes
                .iter()
                .map(|s| SceneMesh {
                    source: s.source.clone(),
                    transform: *m * s.transform,
                    mesh: s.mesh.transformed(m),
                })
                .collect(),
            params: self.params,
        }
    }
}
