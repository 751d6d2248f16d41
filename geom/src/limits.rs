//! The limits of the supported range of a scene (`docs/scene-format.md`, "Supported range"):
//! the scene loader, the lights' constructors and the renderers' check (`range.rs`) hold every
//! value to them.

use glam::DVec3;

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
    v.is_finite() && v.abs().max_element() <= MAX_COORDINATE
}
