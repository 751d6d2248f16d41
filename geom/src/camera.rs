//! The pinhole camera of the scene contract.
//!
//! Right-handed look-at: `forward = normalize(target - eye)`, `right = normalize(cross(forward,
//! up))`, `true_up = cross(right, forward)`. Pixel `(i, j)`, `j = 0` the top row, is sampled
//! through its centre:
//! `x = (2(i + 0.5)/width - 1) · tan(fov_y/2) · width/height`,
//! `y = (1 - 2(j + 0.5)/height) · tan(fov_y/2)`,
//! `dir = normalize(forward + x·right + y·true_up)`.

use glam::DVec3;

/// Why a camera cannot be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CameraError {
    /// `eye == target`: no view direction.
    #[error("eye and target coincide: the view direction is undefined")]
    EyeIsTarget,
    /// `up` is zero.
    #[error("up {0:?} is zero: it gives no direction")]
    UpZero([f64; 3]),
    /// `up` is parallel to the view direction.
    #[error("up {up:?} is parallel to the view direction {forward:?}")]
    UpParallel {
        /// The given up vector.
        up: [f64; 3],
        /// The view direction.
        forward: [f64; 3],
    },
    /// Image width or height is zero.
    #[error("image size {width}x{height} is empty")]
    EmptyImage {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// Field of view outside `(0, 180)` degrees.
    #[error("fov_y_deg = {0} is outside (0, 180)")]
    BadFov(f64),
}

/// A look-at pinhole camera with its image size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub eye: DVec3,
    /// Unit view direction.
    pub forward: DVec3,
    /// Unit right vector.
    pub right: DVec3,
    /// Unit up vector orthogonal to `forward` and `right`.
    pub true_up: DVec3,
    /// Vertical field of view in degrees.
    pub fov_y_deg: f64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

impl Camera {
    /// Builds the camera of the scene contract, rejecting undefined frames.
    ///
    /// ```
    /// use penumbra::glam::DVec3;
    /// use penumbra::geom::Camera;
    ///
    /// let c = Camera::look_at(DVec3::new(0.0, 2.0, 5.0), DVec3::ZERO, DVec3::Y, 45.0, 320, 240)?;
    /// // The centre pixel's ray points at the target.
    /// assert!(c.ray_dir(160, 120).dot(-c.eye.normalize()) > 0.999);
    /// assert!(Camera::look_at(DVec3::ZERO, DVec3::ZERO, DVec3::Y, 45.0, 8, 8).is_err());
    /// # Ok::<(), penumbra::geom::CameraError>(())
    /// ```
    pub fn look_at(
        eye: DVec3,
        target: DVec3,
        up: DVec3,
        fov_y_deg: f64,
        width: u32,
        height: u32,
    ) -> Result<Self, CameraError> {
        if width == 0 || height == 0 {
            return Err(CameraError::EmptyImage { width, height });
        }
        if !(fov_y_deg > 0.0 && fov_y_deg < 180.0) {
            return Err(CameraError::BadFov(fov_y_deg));
        }
        let forward = (target - eye)
            .try_normalize()
            .ok_or(CameraError::EyeIsTarget)?;
        let side = forward.cross(up);
        if up.length() == 0.0 {
            return Err(CameraError::UpZero(up.to_array()));
        }
        if side.length() <= 1e-9 * up.length() {
            return Err(CameraError::UpParallel {
                up: up.to_array(),
                forward: forward.to_array(),
            });
        }
        let right = side.normalize();
        let true_up = right.cross(forward);
        Ok(Camera {
            eye,
            forward,
            right,
            true_up,
            fov_y_deg,
            width,
            height,
        })
    }

    /// Number of pixels.
    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// Unit direction of the ray through the centre of pixel `(i, j)`, `j = 0` the top row.
    pub fn ray_dir(&self, i: u32, j: u32) -> DVec3 {
        let t = (self.fov_y_deg.to_radians() * 0.5).tan();
        let aspect = self.width as f64 / self.height as f64;
        let x = (2.0 * (i as f64 + 0.5) / self.width as f64 - 1.0) * t * aspect;
        let y = (1.0 - 2.0 * (j as f64 + 0.5) / self.height as f64) * t;
        (self.forward + x * self.right + y * self.true_up).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_pixel_looks_forward_and_top_row_looks_up() {
        let c = Camera::look_at(DVec3::new(0., 0., 5.), DVec3::ZERO, DVec3::Y, 90.0, 3, 3).unwrap();
        assert!((c.ray_dir(1, 1) - DVec3::NEG_Z).length() < 1e-12);
        assert!(c.ray_dir(1, 0).y > 0.0);
        assert!(c.ray_dir(2, 1).x > 0.0);
        // 90 degrees, 3 rows: the top row centre is at y = 2/3 * tan(45) = 2/3.
        let d = c.ray_dir(1, 0);
        assert!((d.y / -d.z - 2.0 / 3.0).abs() < 1e-12);
    }

    #[test]
    fn undefined_frames_are_errors() {
        let e = DVec3::new(0., 1., 0.);
        assert_eq!(
            Camera::look_at(e, e, DVec3::Y, 45., 4, 4),
            Err(CameraError::EyeIsTarget)
        );
        assert!(matches!(
            Camera::look_at(e, DVec3::ZERO, DVec3::Y, 45., 4, 4),
            Err(CameraError::UpParallel { .. })
        ));
        assert_eq!(
            Camera::look_at(e, DVec3::ZERO, DVec3::ZERO, 45., 4, 4),
            Err(CameraError::UpZero([0.0; 3]))
        );
        assert!(matches!(
            Camera::look_at(e, DVec3::X, DVec3::Y, 45., 0, 4),
            Err(CameraError::EmptyImage { .. })
        ));
    }
}
