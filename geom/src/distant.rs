//! The distant light (the sun): a rectangle of directions at infinity, and the projective warp
//! that brings it to a finite rectangle so that every renderer renders it as a [`RectLight`].
//!
//! A distant light of direction `D` (from the scene towards the light's centre), tangent `T` and
//! full angles `(a, b)` emits along the directions `d(u, v) = normalize(D + u tan(a/2) T +
//! v tan(b/2) B)`, `(u, v)` in `[-1, 1]^2`, `B = (-D) x T`. A point's visibility is the share of
//! that rectangle of directions (uniform in `(u, v)`) whose rays to infinity are unblocked.
//!
//! The [`Warp`] of a scene is the projective map `H(x) = o + k (x - o) / ((x - o)·D + k)`, `o`
//! the centre of the scene's bounding box and `k` twice the radius around `o` that holds the
//! scene and the eye. It maps every point of the scene and the eye to a finite point, sends the
//! point at infinity in direction `d` (`d·D = 1`) to `o + k d`, and so the light's directions to
//! the rectangle light of centre `o + k D`, normal `-D`, tangent `T` and sides `2 k tan(a/2)`,
//! `2 k tan(b/2)`, with `(u, v)` kept uniform. A projective map keeps lines, planes, triangles
//! and the order of points along a segment that does not cross the plane it sends to infinity
//! (`(x - o)·D = -k`, behind the whole scene): the ray from a point of the scene in direction
//! `d(u, v)` becomes the segment from the point's image to the light's point `(u, v)`, and a
//! triangle blocks the one exactly where its image blocks the other. The visibility of a
//! distant light is therefore the visibility of its rectangle light in the warped scene, for the
//! exact evaluator and for every technique alike; only the camera changes form (its rays'
//! frame is no longer orthonormal).

use glam::{DMat3, DMat4, DVec2, DVec3, DVec4};

use crate::camera::Camera;
use crate::light::RectLight;
use crate::light_error::{self as checks, LightError};

/// A distant light: a rectangle of directions around `direction`, seen by every point of the
/// scene alike (the sun is `angular_size = [0.53, 0.53]` degrees).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistantLight {
    /// Unit direction from the scene towards the light's centre, `D`.
    pub direction: DVec3,
    /// Unit tangent, orthogonal to `direction`: the direction of the first side, `T`.
    pub tangent: DVec3,
    /// `(-direction) x tangent`: the direction of the second side, `B`.
    pub bitangent: DVec3,
    /// Full angles of the two sides in degrees, each in `(0, 90]`.
    pub angular_size_deg: DVec2,
}

impl DistantLight {
    /// The distant light of unit `direction` (from the scene towards the light's centre), unit
    /// `tangent` orthogonal to it and full angles `angular_size_deg` (degrees, each in
    /// `(0, 90]`). Checked as [`RectLight::new`] checks its frame: the error names the field.
    ///
    /// ```
    /// use penumbra::glam::{DVec2, DVec3};
    /// use penumbra::geom::DistantLight;
    ///
    /// // The sun 30 degrees above the horizon, in the x-y plane.
    /// let up = 30f64.to_radians();
    /// let sun = DistantLight::new(DVec3::new(up.cos(), up.sin(), 0.0), DVec3::Z, DVec2::splat(0.53))?;
    /// // The centre direction and a corner's.
    /// assert!((sun.direction_at(DVec2::ZERO) - sun.direction).length() < 1e-15);
    /// let corner = sun.direction_at(DVec2::ONE);
    /// assert!((corner.angle_between(sun.direction).to_degrees() - 0.53 / 2f64.sqrt()).abs() < 1e-3);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(
        direction: DVec3,
        tangent: DVec3,
        angular_size_deg: DVec2,
    ) -> Result<DistantLight, LightError> {
        let direction = checks::unit("direction", direction)?;
        let tangent = checks::tangent(tangent, "direction", direction)?;
        Ok(DistantLight::from_frame(
            direction,
            tangent,
            checks::angular_size(angular_size_deg)?,
        ))
    }

    /// The sun (or any distant light) at `azimuth_deg` clockwise from north and
    /// `elevation_deg` above the horizon, a square of `angular_size_deg` on a side (the sun is
    /// 0.53), in the scene file's frame: north `-z`, east `+x`, up `+y`
    /// ([`DistantLight::sun_in`] takes another). Its direction is
    /// `cos(e) (cos(a) N + sin(a) E) + sin(e) U` with `E = N x U`; its tangent is horizontal,
    /// `normalize(U x direction)`, or east for a sun at the zenith or the nadir.
    ///
    /// ```
    /// use penumbra::glam::DVec3;
    /// use penumbra::geom::DistantLight;
    ///
    /// // In the south-east, 30 degrees up.
    /// let sun = DistantLight::sun(135.0, 30.0, 0.53)?;
    /// let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    /// let expected = DVec3::new(c * 0.5f64.sqrt(), s, c * 0.5f64.sqrt());
    /// assert!((sun.direction - expected).length() < 1e-12);
    /// assert!(sun.tangent.y.abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn sun(
        azimuth_deg: f64,
        elevation_deg: f64,
        angular_size_deg: f64,
    ) -> Result<DistantLight, LightError> {
        DistantLight::sun_in(
            DVec3::NEG_Z,
            DVec3::Y,
            azimuth_deg,
            elevation_deg,
            DVec2::splat(angular_size_deg),
        )
    }

    /// [`DistantLight::sun`] in the frame of `north` and `up` (two orthogonal directions, of
    /// any length), and with the full angles `angular_size_deg` along the tangent and the
    /// bitangent: for a scene modelled with `+z` up, `sun_in(DVec3::Y, DVec3::Z, ...)`.
    pub fn sun_in(
        north: DVec3,
        up: DVec3,
        azimuth_deg: f64,
        elevation_deg: f64,
        angular_size_deg: DVec2,
    ) -> Result<DistantLight, LightError> {
        let frame = LightError::SunFrame { north, up };
        let (n, u) = match (north.try_normalize(), up.try_normalize()) {
            (Some(n), Some(u)) if n.dot(u).abs() <= crate::limits::UNIT_TOLERANCE => {
                (n, (u - n * n.dot(u)).normalize())
            }
            _ => return Err(frame),
        };
        if !azimuth_deg.is_finite() {
            return Err(LightError::Angle {
                field: "azimuth_deg",
                degrees: azimuth_deg,
                range: "a finite angle in degrees",
            });
        }
        if !(-90.0..=90.0).contains(&elevation_deg) {
            return Err(LightError::Angle {
                field: "elevation_deg",
                degrees: elevation_deg,
                range: "in [-90, 90] degrees",
            });
        }
        let east = n.cross(u);
        let (a, e) = (azimuth_deg.to_radians(), elevation_deg.to_radians());
        let direction = ((n * a.cos() + east * a.sin()) * e.cos() + u * e.sin()).normalize();
        let tangent = checks::horizontal_tangent(direction, u, east);
        Ok(DistantLight::from_frame(
            direction,
            tangent,
            checks::angular_size(angular_size_deg)?,
        ))
    }

    /// The light of an exactly orthonormal frame, unchecked.
    pub(crate) fn from_frame(direction: DVec3, tangent: DVec3, angular_size_deg: DVec2) -> Self {
        DistantLight {
            direction,
            tangent,
            bitangent: (-direction).cross(tangent),
            angular_size_deg,
        }
    }

    /// `(tan(a/2), tan(b/2))`: the half sides of the rectangle of directions at unit distance
    /// along [`DistantLight::direction`].
    pub fn half_tangents(&self) -> DVec2 {
        DVec2::new(
            (self.angular_size_deg.x.to_radians() * 0.5).tan(),
            (self.angular_size_deg.y.to_radians() * 0.5).tan(),
        )
    }

    /// The unit direction of the light's point `(u, v)`, `(u, v)` in `[-1, 1]^2`:
    /// `normalize(D + u tan(a/2) T + v tan(b/2) B)`.
    pub fn direction_at(&self, uv: DVec2) -> DVec3 {
        let h = self.half_tangents();
        (self.direction + self.tangent * (uv.x * h.x) + self.bitangent * (uv.y * h.y)).normalize()
    }
}

/// The projective map that takes a scene lit by a distant light to one lit by a rectangle
/// (see the module's documentation): `H(x) = o + k (x - o) / ((x - o)·D + k)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Warp {
    /// The fixed point `o`, where the map is the identity to first order.
    pub origin: DVec3,
    /// The light's direction `D`.
    pub direction: DVec3,
    /// The distance `k` from `o` to the light's image; every point `x` warped has
    /// `(x - o)·D > -k / 2`.
    pub k: f64,
}

impl Warp {
    /// The warp for a scene of `points` (its vertices and the eye) under a light of unit
    /// `direction`: `o` the centre of their bounding box, `k` twice the largest distance of a
    /// point from it (at least 1e-6 of the box's largest coordinate, and never 0).
    pub fn around(points: impl IntoIterator<Item = DVec3>, direction: DVec3) -> Warp {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        let points: Vec<DVec3> = points.into_iter().collect();
        for &p in &points {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        let origin = if points.is_empty() {
            DVec3::ZERO
        } else {
            (lo + hi) * 0.5
        };
        let radius = points
            .iter()
            .map(|p| (*p - origin).length())
            .fold(0.0, f64::max);
        let floor = 1e-6 * origin.abs().max_element().max(1.0);
        Warp {
            origin,
            direction,
            k: 2.0 * radius.max(floor),
        }
    }

    /// The image of the world point `x`.
    pub fn point(&self, x: DVec3) -> DVec3 {
        let d = x - self.origin;
        self.origin + d * (self.k / (d.dot(self.direction) + self.k))
    }

    /// The world point whose image is `y`: the inverse of [`Warp::point`].
    pub fn unwarp(&self, y: DVec3) -> DVec3 {
        let e = y - self.origin;
        self.origin + e * (self.k / (self.k - e.dot(self.direction)))
    }

    /// [`Warp::point`] as a matrix of homogeneous coordinates: `(x, 1)` goes to `w (H(x), 1)`,
    /// `w = (x - o)·D + k`.
    pub fn matrix(&self) -> DMat4 {
        let (o, d, k) = (self.origin, self.direction, self.k);
        let od = o.dot(d);
        let linear = DMat3::from_cols(o * d.x, o * d.y, o * d.z) + DMat3::IDENTITY * k;
        DMat4::from_cols(
            linear.x_axis.extend(d.x),
            linear.y_axis.extend(d.y),
            linear.z_axis.extend(d.z),
            (-o * od).extend(k - od),
        )
    }

    /// [`Warp::unwarp`] as a matrix of homogeneous coordinates: `(y, 1)` goes to `w (x, 1)`,
    /// `x` the world point whose image is `y`, `w = k - (y - o)·D`.
    pub fn inverse_matrix(&self) -> DMat4 {
        let (o, d, k) = (self.origin, self.direction, self.k);
        let od = o.dot(d);
        let linear = DMat3::IDENTITY * k - DMat3::from_cols(o * d.x, o * d.y, o * d.z);
        DMat4::from_cols(
            linear.x_axis.extend(-d.x),
            linear.y_axis.extend(-d.y),
            linear.z_axis.extend(-d.z),
            DVec4::from((o * od, k + od)),
        )
    }

    /// The derivative of [`Warp::point`] at `x`, which carries directions at `x` to directions
    /// at its image: `s (I - (x - o) D^T / ((x - o)·D + k))`, `s = k / ((x - o)·D + k)`.
    pub fn jacobian(&self, x: DVec3) -> DMat3 {
        let d = x - self.origin;
        let w = d.dot(self.direction) + self.k;
        let s = self.k / w;
        let outer = DMat3::from_cols(
            d * self.direction.x,
            d * self.direction.y,
            d * self.direction.z,
        );
        (DMat3::IDENTITY - outer * (1.0 / w)) * s
    }

    /// The rectangle light that is the image of `light`'s directions: centre `o + k D`, normal
    /// `-D`, tangent `T`, sides `2 k tan(a/2)` and `2 k tan(b/2)`.
    pub fn light(&self, light: &DistantLight) -> RectLight {
        RectLight::from_frame(
            self.origin + self.direction * self.k,
            -light.direction,
            light.tangent,
            light.half_tangents() * (2.0 * self.k),
        )
    }

    /// The camera that sees the warped scene as `camera` sees the world: the eye's image, and
    /// the frame's vectors carried by the derivative at the eye (no longer orthonormal), so that
    /// the ray through each pixel is the image of the world's.
    pub fn camera(&self, camera: &Camera) -> Camera {
        let j = self.jacobian(camera.eye);
        Camera {
            eye: self.point(camera.eye),
            forward: j * camera.forward,
            right: j * camera.right,
            true_up: j * camera.true_up,
            ..*camera
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sun() -> DistantLight {
        let d = DVec3::new(0.6, 0.7, -0.3).normalize();
        let t = d.cross(DVec3::Y).normalize();
        DistantLight::new(d, t, DVec2::new(4.0, 2.5)).unwrap()
    }

    fn warp() -> Warp {
        Warp::around(
            [DVec3::new(-3.0, 0.0, -2.0), DVec3::new(2.0, 1.5, 4.0)],
            sun().direction,
        )
    }

    #[test]
    fn the_warp_round_trips_and_keeps_lines() {
        let w = warp();
        let a = DVec3::new(0.3, -1.0, 2.0);
        let b = DVec3::new(-2.0, 1.0, 0.5);
        assert!((w.unwarp(w.point(a)) - a).length() < 1e-12);
        // The image of the midpoint lies on the segment between the images.
        let (ia, ib, im) = (w.point(a), w.point(b), w.point((a + b) * 0.5));
        let along = (ib - ia).normalize();
        let off = (im - ia) - along * (im - ia).dot(along);
        assert!(off.length() < 1e-12);
        assert!((im - ia).dot(along) > 0.0 && (im - ia).dot(along) < (ib - ia).length());
    }

    #[test]
    fn a_ray_along_a_light_direction_goes_to_the_light_point() {
        let (l, w) = (sun(), warp());
        let rect = w.light(&l);
        let p = DVec3::new(0.5, 0.2, -1.0);
        for uv in [DVec2::ZERO, DVec2::new(1.0, -1.0), DVec2::new(-0.3, 0.7)] {
            let d = l.direction_at(uv);
            // Points ever farther along the ray approach the rectangle's point (u, v), along a
            // line from the point's image.
            let target = rect.point(uv);
            let far = w.point(p + d * 1e9);
            assert!((far - target).length() < 1e-6 * w.k, "{uv}");
            let mid = w.point(p + d * 3.0);
            let line = (target - w.point(p)).normalize();
            let off = mid - w.point(p);
            assert!((off - line * off.dot(line)).length() < 1e-12);
            assert!(rect.is_lit_side(w.point(p)));
        }
        assert!((rect.bitangent - l.bitangent).length() < 1e-15);
    }

    #[test]
    fn the_matrices_are_the_warp_and_its_inverse() {
        let w = warp();
        for x in [DVec3::new(0.3, -1.0, 2.0), DVec3::new(-2.5, 1.2, -0.4)] {
            let h = w.matrix() * x.extend(1.0);
            assert!((h.truncate() / h.w - w.point(x)).length() < 1e-12);
            let y = w.point(x);
            let g = w.inverse_matrix() * y.extend(1.0);
            assert!((g.truncate() / g.w - x).length() < 1e-12);
            assert!(h.w > 0.0 && g.w > 0.0);
        }
    }

    #[test]
    fn the_warped_camera_casts_the_images_of_the_world_rays() {
        let w = warp();
        let c =
            Camera::look_at(DVec3::new(1.0, 2.0, 5.0), DVec3::ZERO, DVec3::Y, 50.0, 8, 6).unwrap();
        let cw = w.camera(&c);
        for (i, j) in [(0, 0), (7, 5), (3, 2)] {
            let x = c.eye + c.ray_dir(i, j) * 4.0;
            let to = (w.point(x) - cw.eye).normalize();
            assert!((to - cw.ray_dir(i, j)).length() < 1e-12, "{i} {j}");
        }
    }
}
