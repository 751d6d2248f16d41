//! The supported range of a scene (`docs/scene-format.md`, "Supported range"): its limits, and
//! the check of a scene made in code against them (the scene loader checks each value of a file
//! at its line).

use glam::DVec3;

use crate::scene::Scene;

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
    pub fn out_of_range(&self) -> Option<String> {
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
}
