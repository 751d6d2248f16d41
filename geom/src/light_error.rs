//! What is wrong with a light's values, and the checks the lights' constructors share: a unit
//! vector within [`UNIT_TOLERANCE`] (then normalised exactly), a tangent orthogonal to the
//! light's axis, coordinates and sizes within the supported range.

use glam::{DVec2, DVec3};

use crate::limits::{MAX_COORDINATE, UNIT_TOLERANCE, within_coordinates};

/// What is wrong with a value given to a light's constructor ([`crate::RectLight::new`],
/// [`crate::RectLight::aimed`], [`crate::DistantLight::new`], [`crate::DistantLight::sun`]):
/// each names the field the caller set.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LightError {
    /// A vector or point with a NaN or infinite coordinate.
    #[error("{field} {value} is not finite")]
    NotFinite {
        /// The field: `center`, `normal`, `tangent`, `direction`, `target`.
        field: &'static str,
        /// Its value.
        value: DVec3,
    },
    /// A point beyond [`MAX_COORDINATE`].
    #[error(
        "{field} {value} lies outside the supported range (coordinates up to {MAX_COORDINATE:e})"
    )]
    OutOfRange {
        /// The field.
        field: &'static str,
        /// Its value.
        value: DVec3,
    },
    /// A direction of zero length.
    #[error("{field} {value} has zero length: it gives no direction")]
    ZeroLength {
        /// The field.
        field: &'static str,
        /// Its value.
        value: DVec3,
    },
    /// A direction that is not unit length (beyond [`UNIT_TOLERANCE`]); `normalized` is the unit
    /// vector it points along.
    #[error(
        "{field} {value} is not unit length (|{field}| = {length}); normalised it is {normalized}"
    )]
    NotUnit {
        /// The field.
        field: &'static str,
        /// Its value.
        value: DVec3,
        /// Its length.
        length: f64,
        /// The unit vector along it.
        normalized: DVec3,
    },
    /// A tangent not orthogonal to the light's axis (its normal, or a distant light's
    /// direction).
    #[error("tangent {tangent} is not orthogonal to {axis_field} {axis}")]
    NotOrthogonal {
        /// The tangent.
        tangent: DVec3,
        /// `normal` or `direction`.
        axis_field: &'static str,
        /// The axis.
        axis: DVec3,
    },
    /// A rectangle's sides that are not two positive finite lengths.
    #[error("size {size} must be two positive finite lengths")]
    Size {
        /// The sides.
        size: DVec2,
    },
    /// A rectangle's side beyond [`MAX_COORDINATE`].
    #[error("size {size} lies outside the supported range (sides up to {MAX_COORDINATE:e})")]
    SizeOutOfRange {
        /// The sides.
        size: DVec2,
    },
    /// A distant light's angles outside `(0, 90]` degrees.
    #[error("angular_size {angular_size} must be two full angles in degrees, each in (0, 90]")]
    AngularSize {
        /// The full angles in degrees.
        angular_size: DVec2,
    },
    /// A light aimed at its own centre.
    #[error("target {target} is the light's center: it gives no direction to face")]
    TargetAtCenter {
        /// The target.
        target: DVec3,
    },
    /// A sun's azimuth that is not finite, or an elevation outside `[-90, 90]` degrees.
    #[error("{field} {degrees} must be {range}")]
    Angle {
        /// `azimuth_deg` or `elevation_deg`.
        field: &'static str,
        /// The value, in degrees.
        degrees: f64,
        /// The values it may take.
        range: &'static str,
    },
    /// A frame for the sun's angles whose north and up are not two orthogonal directions.
    #[error("north {north} and up {up} must be two orthogonal non-zero directions")]
    SunFrame {
        /// North.
        north: DVec3,
        /// Up.
        up: DVec3,
    },
}

/// `value` as a finite point within the supported range.
pub(crate) fn point(field: &'static str, value: DVec3) -> Result<DVec3, LightError> {
    if !value.is_finite() {
        return Err(LightError::NotFinite { field, value });
    }
    if !within_coordinates(value) {
        return Err(LightError::OutOfRange { field, value });
    }
    Ok(value)
}

/// `value` as an exactly unit vector, where it is one within [`UNIT_TOLERANCE`].
pub(crate) fn unit(field: &'static str, value: DVec3) -> Result<DVec3, LightError> {
    let d = direction(field, value)?;
    let length = value.length();
    if (length - 1.0).abs() > UNIT_TOLERANCE {
        return Err(LightError::NotUnit {
            field,
            value,
            length,
            normalized: d,
        });
    }
    Ok(d)
}

/// `value` normalised: any finite non-zero vector.
pub(crate) fn direction(field: &'static str, value: DVec3) -> Result<DVec3, LightError> {
    if !value.is_finite() {
        return Err(LightError::NotFinite { field, value });
    }
    value
        .try_normalize()
        .ok_or(LightError::ZeroLength { field, value })
}

/// The unit `tangent` made exactly orthogonal to the unit `axis`, where it is orthogonal
/// within [`UNIT_TOLERANCE`].
pub(crate) fn tangent(
    tangent: DVec3,
    axis_field: &'static str,
    axis: DVec3,
) -> Result<DVec3, LightError> {
    let t = unit("tangent", tangent)?;
    if axis.dot(t).abs() > UNIT_TOLERANCE {
        return Err(LightError::NotOrthogonal {
            tangent,
            axis_field,
            axis,
        });
    }
    Ok((t - axis * axis.dot(t)).normalize())
}

/// The tangent a light chooses where none is given: the horizontal direction `up x axis`
/// (normalised), or `fallback` where `axis` is vertical (within 1e-9).
pub(crate) fn horizontal_tangent(axis: DVec3, up: DVec3, fallback: DVec3) -> DVec3 {
    let t = up.cross(axis);
    if t.length() > 1e-9 {
        t.normalize()
    } else {
        (fallback - axis * axis.dot(fallback)).normalize()
    }
}

/// `size` as two positive finite sides within the supported range.
pub(crate) fn size(size: DVec2) -> Result<DVec2, LightError> {
    if !(size.x > 0.0 && size.y > 0.0 && size.is_finite()) {
        Err(LightError::Size { size })
    } else if size.max_element() > MAX_COORDINATE {
        Err(LightError::SizeOutOfRange { size })
    } else {
        Ok(size)
    }
}

/// `angular_size` as two full angles in `(0, 90]` degrees.
pub(crate) fn angular_size(angular_size: DVec2) -> Result<DVec2, LightError> {
    let a = angular_size;
    if a.x > 0.0 && a.x <= 90.0 && a.y > 0.0 && a.y <= 90.0 {
        Ok(a)
    } else {
        Err(LightError::AngularSize { angular_size })
    }
}
