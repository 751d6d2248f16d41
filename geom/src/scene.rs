//! A scene: the camera, the light, the world-space meshes and the shadow-map techniques'
//! parameters, made in code here (read from a scene file in `scene_file.rs`, held to the
//! supported range in `range.rs`).

use std::path::PathBuf;

use glam::{DMat4, DVec3};
use penumbra_params::TechniqueParams;

use crate::camera::Camera;
use crate::light::RectLight;
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

/// A loaded scene: camera, light and world-space meshes.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The scene file.
    pub path: PathBuf,
    /// The camera.
    pub camera: Camera,
    /// The light.
    pub light: RectLight,
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
        let l = &self.light;
        let scale = m.transform_vector3(l.tangent).length();
        let light = RectLight::new(
            m.transform_point3(l.center),
            dir(l.normal),
            dir(l.tangent),
            l.size * scale,
        );
        Scene {
            path: self.path.clone(),
            camera,
            light,
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
