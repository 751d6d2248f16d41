//! The supported range of a scene (`docs/scene-format.md`, "Supported range"): its limits, and
//! the check of a scene made in code against them (the scene loader checks each value of a file
//! at its line).

use glam::DVec3;
use penumbra_params::TechniqueParams;

use crate::camera::Camera;
use crate::lights::Light;
use crate::limits::{MAX_COORDINATE, MAX_FOV_DEG, MIN_FOV_DEG, UNIT_TOLERANCE, within_coordinates};
use crate::lit_scene::LitScene;
use crate::scene::{Scene, SceneMesh};

/// The first value of a scene outside the supported range, or that the scene loader would refuse
/// of a scene file ([`Scene::out_of_range`]).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RangeError {
    /// The light's normal is not unit length.
    #[error("the light's normal {normal} is not unit length (|n| = {})", .normal.length())]
    LightNormal {
        /// The normal.
        normal: DVec3,
    },
    /// The light's tangent is not unit length.
    #[error("the light's tangent {tangent} is not unit length (|t| = {})", .tangent.length())]
    LightTangent {
        /// The tangent.
        tangent: DVec3,
    },
    /// The light's tangent is not orthogonal to its normal.
    #[error("the light's tangent {tangent} is not orthogonal to its normal {normal}")]
    LightNotOrthogonal {
        /// The tangent.
        tangent: DVec3,
        /// The normal.
        normal: DVec3,
    },
    /// The light's bitangent is not normal x tangent.
    #[error("the light's bitangent {bitangent} is not normal x tangent {expected}")]
    LightBitangent {
        /// The bitangent.
        bitangent: DVec3,
        /// normal x tangent.
        expected: DVec3,
    },
    /// The light's sides are not two positive finite lengths.
    #[error("the light's size {size} must be two positive finite lengths")]
    LightSize {
        /// The sides.
        size: glam::DVec2,
    },
    /// An image of no pixels.
    #[error("the image size {width}x{height} is empty")]
    EmptyImage {
        /// The image's width.
        width: u32,
        /// The image's height.
        height: u32,
    },
    /// A camera frame that is not three orthogonal unit vectors.
    #[error(
        "the camera's frame (forward {forward}, right {right}, up {up}) is not three orthogonal unit vectors: build it with Camera::look_at"
    )]
    CameraFrame {
        /// The forward vector.
        forward: DVec3,
        /// The right vector.
        right: DVec3,
        /// The up vector.
        up: DVec3,
    },
    /// A shadow-map parameter outside its range.
    #[error("shadow-map parameter {error}")]
    Param {
        /// The parameter and why.
        error: penumbra_params::ParamError,
    },
    /// The eye beyond [`MAX_COORDINATE`].
    #[error(
        "the eye at {eye} lies outside the supported range (coordinates up to {MAX_COORDINATE:e})"
    )]
    Eye {
        /// The eye.
        eye: DVec3,
    },
    /// The light's centre or sides beyond [`MAX_COORDINATE`].
    #[error(
        "the light at {center} of size {size} lies outside the supported range (coordinates and sides up to {MAX_COORDINATE:e})"
    )]
    Light {
        /// The light's centre.
        center: DVec3,
        /// Its sides.
        size: glam::DVec2,
    },
    /// A distant light whose direction and tangent are not unit and orthogonal, or whose angles
    /// are not in `(0, 90]` degrees.
    #[error(
        "the distant light of direction {direction}, tangent {tangent} and angular size {angular_size} needs a unit direction and a unit tangent orthogonal to it, and two angles in (0, 90] degrees"
    )]
    DistantLight {
        /// Its direction.
        direction: DVec3,
        /// Its tangent.
        tangent: DVec3,
        /// Its full angles in degrees.
        angular_size: glam::DVec2,
    },
    /// A scene without a light.
    #[error("the scene has no light: add one with Scene::with_light")]
    NoLights,
    /// A field of view outside [[`MIN_FOV_DEG`], [`MAX_FOV_DEG`]].
    #[error(
        "a field of view of {degrees} degrees lies outside the supported range [{MIN_FOV_DEG}, {MAX_FOV_DEG}]"
    )]
    FieldOfView {
        /// The vertical field of view, in degrees.
        degrees: f64,
    },
    /// A mesh vertex beyond [`MAX_COORDINATE`].
    #[error(
        "mesh {mesh} ({name}) has a vertex at {at}, outside the supported range (coordinates up to {MAX_COORDINATE:e})"
    )]
    Vertex {
        /// The mesh's index in the scene.
        mesh: usize,
        /// The mesh's name.
        name: String,
        /// The vertex.
        at: DVec3,
    },
    /// A mesh triangle naming a vertex the mesh does not have.
    #[error(
        "mesh {mesh} ({name}): triangle {triangle} names vertex {index}, but the mesh has {vertices} vertices"
    )]
    Index {
        /// The mesh's index in the scene.
        mesh: usize,
        /// The mesh's name.
        name: String,
        /// The triangle's index in the mesh.
        triangle: usize,
        /// The vertex index it names.
        index: u32,
        /// How many vertices the mesh has.
        vertices: usize,
    },
}

impl Scene {
    /// The first value of the scene outside the supported range of `docs/scene-format.md`
    /// ("Supported range"), or `None` when all are inside: the scene loader refuses such scenes
    /// with their line, and a renderer refuses a scene made in code the same way.
    ///
    /// It also holds a scene made in code to what the loader checks of a file: one light at
    /// least; lights whose frames are unit and orthogonal (a rectangle's bitangent its normal
    /// times its tangent) with positive sides or angles, as the lights' constructors make them;
    /// a camera frame of unit orthogonal vectors and a non-empty image; and shadow-map
    /// parameters within their ranges.
    pub fn out_of_range(&self) -> Option<RangeError> {
        if self.lights.is_empty() {
            return Some(RangeError::NoLights);
        }
        self.lights
            .iter()
            .find_map(|l| invalid_light(&l.light))
            .or_else(|| out_of_range(&self.camera, &self.meshes, &self.params))
    }
}

impl LitScene {
    /// [`Scene::out_of_range`] of the scene of this one light.
    pub fn out_of_range(&self) -> Option<RangeError> {
        invalid_light(&self.world_light())
            .or_else(|| out_of_range(self.world_camera(), self.world_meshes(), &self.params))
    }
}

/// What the scene loader would refuse of `light`.
fn invalid_light(light: &Light) -> Option<RangeError> {
    let unit = |v: DVec3| (v.length() - 1.0).abs() <= UNIT_TOLERANCE;
    let orthogonal = |a: DVec3, b: DVec3| a.dot(b).abs() <= UNIT_TOLERANCE;
    let l = match light {
        Light::Rect(l) => l,
        Light::Distant(l) => {
            let a = l.angular_size_deg;
            if !(unit(l.direction)
                && unit(l.tangent)
                && orthogonal(l.direction, l.tangent)
                && a.x > 0.0
                && a.x <= 90.0
                && a.y > 0.0
                && a.y <= 90.0)
            {
                return Some(RangeError::DistantLight {
                    direction: l.direction,
                    tangent: l.tangent,
                    angular_size: a,
                });
            }
            return None;
        }
    };
    if !unit(l.normal) {
        return Some(RangeError::LightNormal { normal: l.normal });
    }
    if !unit(l.tangent) {
        return Some(RangeError::LightTangent { tangent: l.tangent });
    }
    if !orthogonal(l.normal, l.tangent) {
        return Some(RangeError::LightNotOrthogonal {
            tangent: l.tangent,
            normal: l.normal,
        });
    }
    if !((l.bitangent - l.normal.cross(l.tangent)).length() <= UNIT_TOLERANCE) {
        return Some(RangeError::LightBitangent {
            bitangent: l.bitangent,
            expected: l.normal.cross(l.tangent),
        });
    }
    if !(l.size.x > 0.0 && l.size.y > 0.0 && l.size.is_finite()) {
        return Some(RangeError::LightSize { size: l.size });
    }
    if !within_coordinates(l.center) || !(l.size.max_element() <= MAX_COORDINATE) {
        return Some(RangeError::Light {
            center: l.center,
            size: l.size,
        });
    }
    None
}

/// What the scene loader would refuse of a world's camera, meshes and parameters.
fn out_of_range(
    camera: &Camera,
    meshes: &[SceneMesh],
    params: &TechniqueParams,
) -> Option<RangeError> {
    let unit = |v: DVec3| (v.length() - 1.0).abs() <= UNIT_TOLERANCE;
    let orthogonal = |a: DVec3, b: DVec3| a.dot(b).abs() <= UNIT_TOLERANCE;
    let c = camera;
    if c.width == 0 || c.height == 0 {
        return Some(RangeError::EmptyImage {
            width: c.width,
            height: c.height,
        });
    }
    let frame = [c.forward, c.right, c.true_up];
    if !frame.iter().all(|&v| unit(v))
        || !orthogonal(c.forward, c.right)
        || !orthogonal(c.forward, c.true_up)
        || !orthogonal(c.right, c.true_up)
    {
        return Some(RangeError::CameraFrame {
            forward: c.forward,
            right: c.right,
            up: c.true_up,
        });
    }
    if let Err(error) = params.validate() {
        return Some(RangeError::Param { error });
    }
    if !within_coordinates(c.eye) {
        return Some(RangeError::Eye { eye: c.eye });
    }
    if !(MIN_FOV_DEG..=MAX_FOV_DEG).contains(&c.fov_y_deg) {
        return Some(RangeError::FieldOfView {
            degrees: c.fov_y_deg,
        });
    }
    for (mesh, m) in meshes.iter().enumerate() {
        if let Some(&at) = m.mesh.positions.iter().find(|v| !within_coordinates(**v)) {
            return Some(RangeError::Vertex {
                mesh,
                name: m.source.display().to_string(),
                at,
            });
        }
        let vertices = m.mesh.positions.len();
        for (triangle, t) in m.mesh.triangles.iter().enumerate() {
            if let Some(&index) = t.iter().find(|&&i| i as usize >= vertices) {
                return Some(RangeError::Index {
                    mesh,
                    name: m.source.display().to_string(),
                    triangle,
                    index,
                    vertices,
                });
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, DVec3};

    use crate::camera::Camera;
    use crate::light::RectLight;
    use crate::lights::Light;
    use crate::scene::Scene;

    fn good() -> Scene {
        let camera =
            Camera::look_at(DVec3::new(0., 3., 4.), DVec3::ZERO, DVec3::Y, 45.0, 8, 6).unwrap();
        let light =
            RectLight::new(DVec3::new(0., 4., 0.), -DVec3::Y, DVec3::X, DVec2::ONE).unwrap();
        Scene::new(camera).with_light(light)
    }

    /// Every check the scene file's loader makes of the light and the camera, made of a scene
    /// built in code.
    #[test]
    fn a_scene_made_in_code_gets_the_checks_of_a_scene_file() {
        assert_eq!(good().out_of_range(), None);
        type Break = fn(&mut Scene);
        fn rect(s: &mut Scene) -> &mut RectLight {
            match &mut s.lights[0].light {
                Light::Rect(r) => r,
                Light::Distant(_) => unreachable!("a rectangle light"),
            }
        }
        let cases: [(&str, Break); 15] = [
            ("normal", |s| rect(s).normal = DVec3::new(0., -1., 0.5)),
            ("tangent", |s| rect(s).tangent *= 2.0),
            ("not orthogonal", |s| {
                rect(s).tangent = DVec3::new(1., 1., 0.).normalize()
            }),
            ("bitangent", |s| rect(s).bitangent = -rect(s).bitangent),
            ("size", |s| rect(s).size = DVec2::new(1.0, 0.0)),
            ("size", |s| rect(s).size = DVec2::new(f64::NAN, 1.0)),
            ("no light", |s| s.lights.clear()),
            ("empty", |s| s.camera.width = 0),
            ("frame", |s| s.camera.forward = DVec3::new(0., 0., -2.)),
            ("frame", |s| s.camera.right = s.camera.true_up),
            ("pcss", |s| s.params.pcss.search = 0),
            ("light", |s| rect(s).center.x = f64::NAN),
            ("vertex", |s| {
                *s = s.clone().with_mesh(
                    "nan",
                    &crate::mesh::TriangleMesh::quad(),
                    glam::DMat4::from_translation(DVec3::new(f64::NAN, 0.0, 0.0)),
                )
            }),
            ("eye", |s| s.camera.eye.y = f64::NAN),
            ("names vertex 7", |s| {
                let mut quad = crate::mesh::TriangleMesh::quad();
                quad.triangles[1][2] = 7;
                *s = s.clone().with_mesh("bad", &quad, glam::DMat4::IDENTITY)
            }),
        ];
        for (want, break_it) in cases {
            let mut s = good();
            break_it(&mut s);
            let why = s
                .out_of_range()
                .unwrap_or_else(|| panic!("{want}: accepted"))
                .to_string();
            assert!(why.contains(want), "{want}: {why}");
        }
    }
}
