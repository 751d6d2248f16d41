//! A scene: the camera, its lights (rectangles or distant lights, each named), the world-space
//! meshes and the shadow-map techniques' parameters, made in code here (read from a scene file
//! in `scene_file.rs`, held to the supported range in `range.rs`). Every renderer renders one
//! light at a time, through the scene's [`LitScene`](crate::LitScene) for that light (`lit_scene.rs`).

use std::path::PathBuf;
use std::sync::Arc;

use glam::{DMat4, DVec3};
use penumbra_params::TechniqueParams;
use rayon::prelude::*;

use crate::camera::Camera;
use crate::distant::DistantLight;
use crate::light::RectLight;
use crate::lights::{Light, LightNameError, NamedLight, check_light_names, default_light_name};
use crate::mesh::TriangleMesh;

/// One mesh of a scene, in world space.
#[derive(Clone, Debug)]
pub struct SceneMesh {
    /// The mesh file it came from, OBJ, glTF or PLY (or the name it was given in code).
    pub source: PathBuf,
    /// `translate * rotate * scale`: from the mesh file into the world.
    pub transform: DMat4,
    /// The welded mesh with world-space positions (in a [`LitScene`](crate::LitScene) under a distant light,
    /// the warped world's).
    pub mesh: TriangleMesh,
}

/// A scene: camera, lights and world-space meshes.
///
/// Its lights are a list, each a rectangle or a distant light with a name; the renderers render
/// one light at a time, through [`Scene::lit`]. A scene's images have one channel per light:
/// `V` for a scene of one light (`[light]` in a scene file, one [`Scene::with_light`] in code),
/// `<name>.V` for each light otherwise (`[[light]]`, even of one entry, or
/// [`Scene::with_lights`]). The meshes are shared between the scene's copies and its
/// [`LitScene`](crate::LitScene)s: cloning a scene or taking one light's view copies no mesh.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The scene file, or `<in memory>` for a scene made in code.
    pub path: PathBuf,
    /// The camera, in the world.
    pub camera: Camera,
    /// The lights, in order: the file's, or those added in code.
    pub lights: Vec<NamedLight>,
    /// The meshes, in order.
    pub meshes: Arc<Vec<SceneMesh>>,
    /// Parameters of the shadow-map techniques (defaults where the file has no table).
    pub params: TechniqueParams,
    /// Whether each light's channel is `<name>.V` even for a scene of one light (`[[light]]`
    /// in a file, [`Scene::with_lights`] in code).
    pub named_channels: bool,
}

impl Scene {
    /// A scene made in code: `camera`, no lights and no meshes yet (add them with
    /// [`Scene::with_light`] and [`Scene::with_mesh`], in any order) and the shadow-map
    /// techniques' default parameters. Nothing is read from disk; its path reads `<in memory>`.
    ///
    /// ```
    /// use penumbra::glam::{DMat4, DVec2, DVec3};
    /// use penumbra::geom::{Camera, DistantLight, RectLight, Scene, TriangleMesh};
    ///
    /// let camera = Camera::look_at(DVec3::new(0.0, 4.0, 5.0), DVec3::ZERO, DVec3::Y, 45.0, 64, 48)?;
    /// let lamp = RectLight::aimed(DVec3::new(0.0, 5.0, 0.0), DVec3::ZERO, DVec2::splat(2.0))?;
    /// let ground = TriangleMesh::from_raw(
    ///     "ground",
    ///     &[DVec3::new(-5.0, 0.0, -5.0), DVec3::new(-5.0, 0.0, 5.0), DVec3::new(5.0, 0.0, 5.0), DVec3::new(5.0, 0.0, -5.0)],
    ///     &[[0, 1, 2], [0, 2, 3]],
    /// )?;
    /// let scene = Scene::new(camera)
    ///     .with_mesh("ground", &ground, DMat4::IDENTITY)
    ///     .with_light(lamp)
    ///     .with_mesh("ball", &TriangleMesh::uv_sphere(12, 16), DMat4::from_translation(DVec3::Y));
    /// assert_eq!(scene.meshes.len(), 2);
    /// assert_eq!(scene.triangle_count(), 2 + 2 * 16 * 11);
    /// assert_eq!(scene.channel_names(), ["V"]);
    /// // A scene lit by the sun alone needs nothing else.
    /// let sunny = Scene::new(camera).with_light(DistantLight::sun(135.0, 30.0, 0.53)?);
    /// assert_eq!(sunny.light_count(), 1);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(camera: Camera) -> Scene {
        Scene {
            path: PathBuf::from("<in memory>"),
            camera,
            lights: Vec::new(),
            meshes: Arc::new(Vec::new()),
            params: TechniqueParams::default(),
            named_channels: false,
        }
    }

    /// The scene with `mesh` added, its positions moved by `transform` into the world; `name`
    /// stands for its file in messages.
    pub fn with_mesh(mut self, name: &str, mesh: &TriangleMesh, transform: DMat4) -> Scene {
        Arc::make_mut(&mut self.meshes).push(SceneMesh {
            source: PathBuf::from(name),
            transform,
            mesh: mesh.transformed(&transform),
        });
        self
    }

    /// The scene with `light` (a [`RectLight`] or a [`DistantLight`]) added after its others,
    /// named `light<k>` by its 0-based position `k` ([`default_light_name`]).
    pub fn with_light(mut self, light: impl Into<Light>) -> Scene {
        self.lights.push(NamedLight {
            name: default_light_name(self.lights.len()),
            light: light.into(),
        });
        self
    }

    /// The scene with `light` added after its others under `name`, refused where the name is
    /// not valid ([`crate::check_light_name`]) or is already another light's.
    pub fn with_named_light(
        mut self,
        name: &str,
        light: impl Into<Light>,
    ) -> Result<Scene, LightNameError> {
        self.lights.push(NamedLight::new(name, light)?);
        check_light_names(&self.lights)?;
        Ok(self)
    }

    /// The scene with `lights` in place of its lights, in order, checked by
    /// [`crate::check_light_names`] (one at least, names valid and unique); its images have a
    /// channel `<name>.V` for each, even for one light.
    ///
    /// ```
    /// use penumbra::glam::{DVec2, DVec3};
    /// use penumbra::geom::{Camera, NamedLight, RectLight, Scene};
    ///
    /// let camera = Camera::look_at(DVec3::new(0.0, 4.0, 5.0), DVec3::ZERO, DVec3::Y, 45.0, 64, 48)?;
    /// let light = |x: f64| RectLight::aimed(DVec3::new(x, 5.0, 0.0), DVec3::new(x, 0.0, 0.0), DVec2::ONE);
    /// let scene = Scene::new(camera)
    ///     .with_lights(vec![NamedLight::new("key", light(-2.0)?)?, NamedLight::new("fill", light(2.0)?)?])?;
    /// assert_eq!(scene.light_count(), 2);
    /// assert_eq!(scene.channel_names(), ["key.V", "fill.V"]);
    /// assert_eq!(scene.lit(1).light, light(2.0)?);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_lights(mut self, lights: Vec<NamedLight>) -> Result<Scene, LightNameError> {
        check_light_names(&lights)?;
        self.lights = lights;
        self.named_channels = true;
        Ok(self)
    }

    /// The same scene under its light `k` alone (0-based, of [`Scene::light_count`]): a scene
    /// of one light, whose image (its one channel `V`) is channel `k` of this scene's. The
    /// meshes are shared, not copied.
    ///
    /// # Panics
    ///
    /// If `k` is not below [`Scene::light_count`].
    pub fn for_light(&self, k: usize) -> Scene {
        assert!(
            k < self.lights.len(),
            "light {k} of a scene of {} lights",
            self.lights.len()
        );
        Scene {
            lights: vec![self.lights[k].clone()],
            named_channels: false,
            ..self.clone()
        }
    }

    /// How many lights the scene has, so many channels its images.
    pub fn light_count(&self) -> usize {
        self.lights.len()
    }

    /// Whether the scene's images have the one channel `V`: a scene of one light without
    /// [`Scene::named_channels`].
    pub fn single_channel(&self) -> bool {
        self.lights.len() == 1 && !self.named_channels
    }

    /// The names of the channels of the scene's images, one per light in order: `V` for a scene
    /// of one light without [`Scene::named_channels`], `<name>.V` for each light otherwise.
    pub fn channel_names(&self) -> Vec<String> {
        if self.single_channel() {
            vec![crate::image_files::CHANNEL.to_string()]
        } else {
            self.lights.iter().map(NamedLight::channel).collect()
        }
    }

    /// The names of the scene's lights, in order.
    pub fn light_names(&self) -> Vec<&str> {
        self.lights.iter().map(|l| l.name.as_str()).collect()
    }

    /// Every world-space triangle of every mesh, meshes in order.
    pub fn triangles(&self) -> Vec<[DVec3; 3]> {
        triangles(&self.meshes)
    }

    /// Total number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.mesh.triangles.len()).sum()
    }

    /// The files this scene was read from: the scene file and every mesh file.
    pub fn input_files(&self) -> Vec<PathBuf> {
        std::iter::once(self.path.clone())
            .chain(self.meshes.iter().map(|m| m.source.clone()))
            .collect()
    }

    /// The scene with every position moved by the rigid or similarity transform `m`, camera
    /// and lights included (for invariance tests).
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
        // A similarity keeps angles; a mirror turns the bitangent around, which the light's
        // frame recomputes.
        let moved = |l: &Light| match l {
            Light::Rect(r) => Light::Rect(RectLight::from_frame(
                m.transform_point3(r.center),
                dir(r.normal),
                dir(r.tangent),
                r.size * m.transform_vector3(r.tangent).length(),
            )),
            Light::Distant(d) => Light::Distant(DistantLight::from_frame(
                dir(d.direction),
                dir(d.tangent),
                d.angular_size_deg,
            )),
        };
        Scene {
            path: self.path.clone(),
            camera,
            lights: self
                .lights
                .iter()
                .map(|l| NamedLight {
                    name: l.name.clone(),
                    light: moved(&l.light),
                })
                .collect(),
            meshes: Arc::new(
                self.meshes
                    .iter()
                    .map(|s| SceneMesh {
                        source: s.source.clone(),
                        transform: *m * s.transform,
                        mesh: s.mesh.transformed(m),
                    })
                    .collect(),
            ),
            params: self.params,
            named_channels: self.named_channels,
        }
    }
}

/// Every triangle of `meshes`, meshes in order.
pub(crate) fn triangles(meshes: &[SceneMesh]) -> Vec<[DVec3; 3]> {
    let mut all = Vec::with_capacity(meshes.iter().map(|m| m.mesh.triangles.len()).sum());
    for m in meshes {
        let n = m.mesh.triangles.len();
        // A large mesh on every core; a small one on this thread.
        if n > 1 << 14 {
            all.par_extend((0..n).into_par_iter().map(|t| m.mesh.triangle(t)));
        } else {
            all.extend((0..n).map(|t| m.mesh.triangle(t)));
        }
    }
    all
}
