//! The supported range of a scene (`docs/scene-format.md`, "Supported range"): its limits, and
//! the check of a scene made in code against them (the scene loader checks each value of a file
//! at its line).

use glam::DVec3;

use crate::scene::Scene;

/// Tolerance on the unit length and orthogonality of the light's normal and tangent (and of the
/// camera's frame of a scene made in code).
pub const UNIT_TOLERANCE: f64 = 1e-4;

/// Largest magnitude of a world coordinate (eye, target, light centre, every mesh vertex after
/// its transform): the ray caster's hierarchy quantizes boxes relative to the scene's, and
/// scenes reaching 1e20 break it. Within it, every back end renders the same image.
pub const MAX_COORDINATE: f64 = 1e15;

/// Narrowest supported field of view, in degrees: below, a pixel's footprint is beneath `f32`'s
/// resolution of the GPU's projection and the back ends disagree.
pub const MIN_FOV_DEG: f64 = 1e-3;

/// Widest supported field of view, in degrees (the projection diverges at 180).
pub const MAX_FOV_DEG: f64 = 179.0;

/// Whether every coordinate of `v` lies within [`MAX_COORDINATE`] (false for NaN).
pub fn within_coordinates(v: DVec3) -> bool {
    v.abs().max_element() <= MAX_COORDINATE
}

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
}

impl Scene {
    /// The first value of the scene outside the supported range of `docs/scene-format.md`
    /// ("Supported range"), or `None` when all are inside: the scene loader refuses such scenes
    /// with their line, and a renderer refuses a scene made in code the same way.
    ///
    /// It also holds a scene made in code to what the loader checks of a file: a light whose
    /// normal and tangent are unit and orthogonal (and its bitangent their cross product) with
    /// two positive sides, a camera frame of unit orthogonal vectors and a non-empty image, and
    /// shadow-map parameters within their ranges.
    pub fn out_of_range(&self) -> Option<RangeError> {
        if let Some(why) = self.invalid_frames() {
            return Some(why);
        }
        if let Err(error) = self.params.validate() {
            return Some(RangeError::Param { error });
        }
        let coordinate = |v: DVec3| !within_coordinates(v);
        let world = self.world();
        if coordinate(world.camera.eye) {
            return Some(RangeError::Eye {
                eye: world.camera.eye,
            });
        }
        if coordinate(self.light.center) || !(self.light.size.max_element() <= MAX_COORDINATE) {
            return Some(RangeError::Light {
                center: self.light.center,
                size: self.light.size,
            });
        }
        if !(MIN_FOV_DEG..=MAX_FOV_DEG).contains(&self.camera.fov_y_deg) {
            return Some(RangeError::FieldOfView {
                degrees: self.camera.fov_y_deg,
            });
        }
        for (mesh, m) in world.meshes.iter().enumerate() {
            if let Some(&at) = m.mesh.positions.iter().find(|v| coordinate(**v)) {
                return Some(RangeError::Vertex {
                    mesh,
                    name: m.source.display().to_string(),
                    at,
                });
            }
        }
        None
    }

    /// What the scene loader would refuse in the light's and the camera's frames.
    fn invalid_frames(&self) -> Option<RangeError> {
        let unit = |v: DVec3| (v.length() - 1.0).abs() <= UNIT_TOLERANCE;
        let orthogonal = |a: DVec3, b: DVec3| a.dot(b).abs() <= UNIT_TOLERANCE;
        let l = &self.light;
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
        if let Some(d) = &self.distant {
            let l = &d.light;
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
        }
        // The world's camera: a scene under a distant light renders a warped one.
        let c = &self.world().camera;
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
        None
    }
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, DVec3};

    use crate::camera::Camera;
    use crate::light::RectLight;
    use crate::scene::Scene;

    fn good() -> Scene {
        let camera =
            Camera::look_at(DVec3::new(0., 3., 4.), DVec3::ZERO, DVec3::Y, 45.0, 8, 6).unwrap();
        let light = RectLight::new(DVec3::new(0., 4., 0.), -DVec3::Y, DVec3::X, DVec2::ONE);
        Scene::new(camera, light)
    }

    /// Every check the scene file's loader makes of the light and the camera, made of a scene
    /// built in code.
    #[test]
    fn a_scene_made_in_code_gets_the_checks_of_a_scene_file() {
        assert_eq!(good().out_of_range(), None);
        type Break = fn(&mut Scene);
        let cases: [(&str, Break); 10] = [
            ("normal", |s| {
                s.light = RectLight::new(
                    s.light.center,
                    DVec3::new(0., -1., 0.5),
                    DVec3::X,
                    DVec2::ONE,
                )
            }),
            ("tangent", |s| s.light.tangent *= 2.0),
            ("not orthogonal", |s| {
                s.light = RectLight::new(
                    s.light.center,
                    -DVec3::Y,
                    DVec3::new(1., 1., 0.).normalize(),
                    DVec2::ONE,
                )
            }),
            ("bitangent", |s| s.light.bitangent = -s.light.bitangent),
            ("size", |s| s.light.size = DVec2::new(1.0, 0.0)),
            ("size", |s| s.light.size = DVec2::new(f64::NAN, 1.0)),
            ("empty", |s| s.camera.width = 0),
            ("frame", |s| s.camera.forward = DVec3::new(0., 0., -2.)),
            ("frame", |s| s.camera.right = s.camera.true_up),
            ("pcss", |s| s.params.pcss.search = 0),
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
