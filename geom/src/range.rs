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

impl Scene {
    /// The first value of the scene outside the supported range of `docs/scene-format.md`
    /// ("Supported range"), described, or `None` when all are inside: the scene loader refuses
    /// such scenes with their line, and a renderer refuses a scene made in code the same way.
    ///
    /// It also holds a scene made in code to what the loader checks of a file: a light whose
    /// normal and tangent are unit and orthogonal (and its bitangent their cross product) with
    /// two positive sides, a camera frame of unit orthogonal vectors and a non-empty image, and
    /// shadow-map parameters within their ranges.
    pub fn out_of_range(&self) -> Option<String> {
        if let Some(why) = self.invalid_frames() {
            return Some(why);
        }
        if let Err(e) = self.params.validate() {
            return Some(format!("shadow-map parameter {e}"));
        }
        let coordinate = |v: DVec3| !within_coordinates(v);
        if coordinate(self.camera.eye) {
            return Some(format!(
                "the eye at {} lies outside the supported range (coordinates up to {MAX_COORDINATE:e})",
                self.camera.eye
            ));
        }
        if coordinate(self.light.center) || !(self.light.size.max_element() <= MAX_COORDINATE) {
            return Some(format!(
                "the light at {} of size {} lies outside the supported range (coordinates and sides up to {MAX_COORDINATE:e})",
                self.light.center, self.light.size
            ));
        }
        if !(MIN_FOV_DEG..=MAX_FOV_DEG).contains(&self.camera.fov_y_deg) {
            return Some(format!(
                "a field of view of {} degrees lies outside the supported range [{MIN_FOV_DEG}, {MAX_FOV_DEG}]",
                self.camera.fov_y_deg
            ));
        }
        for (index, m) in self.meshes.iter().enumerate() {
            if let Some(v) = m.mesh.positions.iter().find(|v| coordinate(**v)) {
                return Some(format!(
                    "mesh {index} ({}) has a vertex at {v}, outside the supported range (coordinates up to {MAX_COORDINATE:e})",
                    m.source.display()
                ));
            }
        }
        None
    }

    /// What the scene loader would refuse in the light's and the camera's frames.
    fn invalid_frames(&self) -> Option<String> {
        let unit = |v: DVec3| (v.length() - 1.0).abs() <= UNIT_TOLERANCE;
        let orthogonal = |a: DVec3, b: DVec3| a.dot(b).abs() <= UNIT_TOLERANCE;
        let l = &self.light;
        if !unit(l.normal) {
            return Some(format!(
                "the light's normal {} is not unit length (|n| = {})",
                l.normal,
                l.normal.length()
            ));
        }
        if !unit(l.tangent) {
            return Some(format!(
                "the light's tangent {} is not unit length (|t| = {})",
                l.tangent,
                l.tangent.length()
            ));
        }
        if !orthogonal(l.normal, l.tangent) {
            return Some(format!(
                "the light's tangent {} is not orthogonal to its normal {}",
                l.tangent, l.normal
            ));
        }
        if !((l.bitangent - l.normal.cross(l.tangent)).length() <= UNIT_TOLERANCE) {
            return Some(format!(
                "the light's bitangent {} is not normal x tangent {}",
                l.bitangent,
                l.normal.cross(l.tangent)
            ));
        }
        if !(l.size.x > 0.0 && l.size.y > 0.0 && l.size.is_finite()) {
            return Some(format!(
                "the light's size {} must be two positive finite lengths",
                l.size
            ));
        }
        let c = &self.camera;
        if c.width == 0 || c.height == 0 {
            return Some(format!("the image size {}x{} is empty", c.width, c.height));
        }
        let frame = [c.forward, c.right, c.true_up];
        if !frame.iter().all(|&v| unit(v))
            || !orthogonal(c.forward, c.right)
            || !orthogonal(c.forward, c.true_up)
            || !orthogonal(c.right, c.true_up)
        {
            return Some(format!(
                "the camera's frame (forward {}, right {}, up {}) is not three orthogonal unit vectors: build it with Camera::look_at",
                c.forward, c.right, c.true_up
            ));
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
                .unwrap_or_else(|| panic!("{want}: accepted"));
            assert!(why.contains(want), "{want}: {why}");
        }
    }
}
