//! The rectangular area light and its frame.
//!
//! Light space is the frame in which the light rectangle is `[-1, 1]^2` in the plane `z = 0`:
//! `x` runs along the tangent (scaled by half the first side), `y` along the bitangent
//! `cross(normal, tangent)` (scaled by half the second side) and `z` along the normal (unscaled
//! world length). The light emits on the side its normal points to.

use glam::{DVec2, DVec3};

use crate::light_error::{self as checks, LightError};

/// A one-sided rectangular area light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RectLight {
    /// Centre of the rectangle.
    pub center: DVec3,
    /// Unit normal; the light emits on this side.
    pub normal: DVec3,
    /// Unit tangent, orthogonal to the normal: direction of the first side.
    pub tangent: DVec3,
    /// `cross(normal, tangent)`: direction of the second side.
    pub bitangent: DVec3,
    /// Side lengths along the tangent and the bitangent.
    pub size: DVec2,
}

impl RectLight {
    /// The light of centre `center`, unit `normal` (it emits on that side), unit `tangent`
    /// orthogonal to it (the first side's direction) and side lengths `size` (along the tangent,
    /// then along `normal x tangent`).
    ///
    /// A normal or tangent within [`crate::UNIT_TOLERANCE`] of unit length and orthogonality is
    /// made exactly so; beyond it, the error names the field and, where a vector is merely not
    /// unit length, gives the normalised one.
    ///
    /// ```
    /// use penumbra::glam::{DVec2, DVec3};
    /// use penumbra::geom::{LightError, RectLight};
    ///
    /// let lamp = RectLight::new(DVec3::new(0.0, 5.0, 0.0), DVec3::NEG_Y, DVec3::X, DVec2::new(2.0, 1.0))?;
    /// assert_eq!(lamp.bitangent, DVec3::Z);
    /// let err = RectLight::new(DVec3::ZERO, DVec3::new(0.0, -2.0, 0.0), DVec3::X, DVec2::ONE).unwrap_err();
    /// assert!(matches!(err, LightError::NotUnit { field: "normal", .. }));
    /// assert!(err.to_string().contains("normalised it is [0, -1, 0]"));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(
        center: DVec3,
        normal: DVec3,
        tangent: DVec3,
        size: DVec2,
    ) -> Result<RectLight, LightError> {
        let center = checks::point("center", center)?;
        let normal = checks::unit("normal", normal)?;
        let tangent = checks::tangent(tangent, "normal", normal)?;
        Ok(RectLight::from_frame(
            center,
            normal,
            tangent,
            checks::size(size)?,
        ))
    }

    /// The light of centre `center` facing `target` (its normal `normalize(target - center)`),
    /// of sides `size`. Its tangent, the direction of the first side, is horizontal:
    /// `normalize(Y x normal)` with `Y = +y` up, or `+x` where the light faces straight up or
    /// down (a ceiling lamp's first side then runs along `x`).
    ///
    /// ```
    /// use penumbra::glam::{DVec2, DVec3};
    /// use penumbra::geom::RectLight;
    ///
    /// // A ceiling panel facing the floor, and a wall panel facing the origin.
    /// let panel = RectLight::aimed(DVec3::new(0.0, 3.0, 0.0), DVec3::ZERO, DVec2::new(1.2, 0.6))?;
    /// assert_eq!((panel.normal, panel.tangent), (DVec3::NEG_Y, DVec3::X));
    /// let wall = RectLight::aimed(DVec3::new(0.0, 1.0, -4.0), DVec3::new(0.0, 1.0, 0.0), DVec2::ONE)?;
    /// assert_eq!((wall.normal, wall.tangent), (DVec3::Z, DVec3::X));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn aimed(center: DVec3, target: DVec3, size: DVec2) -> Result<RectLight, LightError> {
        let center = checks::point("center", center)?;
        let target = checks::point("target", target)?;
        let normal = (target - center)
            .try_normalize()
            .ok_or(LightError::TargetAtCenter { target })?;
        let tangent = checks::horizontal_tangent(normal, DVec3::Y, DVec3::X);
        Ok(RectLight::from_frame(
            center,
            normal,
            tangent,
            checks::size(size)?,
        ))
    }

    /// The light of an exactly orthonormal frame, unchecked: for the lights the library derives
    /// from checked ones.
    pub(crate) fn from_frame(center: DVec3, normal: DVec3, tangent: DVec3, size: DVec2) -> Self {
        RectLight {
            center,
            normal,
            tangent,
            bitangent: normal.cross(tangent),
            size,
        }
    }

    /// Area of the rectangle, `w * h`.
    pub fn area(&self) -> f64 {
        self.size.x * self.size.y
    }

    /// Half side lengths.
    pub fn half_size(&self) -> DVec2 {
        self.size * 0.5
    }

    /// Signed distance of `p` from the light's plane, positive on the emitting side.
    pub fn signed_distance(&self, p: DVec3) -> f64 {
        (p - self.center).dot(self.normal)
    }

    /// Whether `p` is strictly on the emitting side of the light's plane. Points that are not
    /// see none of the light (`V = 0`).
    pub fn is_lit_side(&self, p: DVec3) -> bool {
        self.signed_distance(p) > 0.0
    }

    /// World position of the light-space point `(u, v)`, `(u, v)` in `[-1, 1]^2` on the light.
    pub fn point(&self, uv: DVec2) -> DVec3 {
        let h = self.half_size();
        self.center + self.tangent * (uv.x * h.x) + self.bitangent * (uv.y * h.y)
    }

    /// The four corners in counter-clockwise order around the normal.
    pub fn corners(&self) -> [DVec3; 4] {
        [
            self.point(DVec2::new(-1.0, -1.0)),
            self.point(DVec2::new(1.0, -1.0)),
            self.point(DVec2::new(1.0, 1.0)),
            self.point(DVec2::new(-1.0, 1.0)),
        ]
    }

    /// World point to light space: `(u, v, z)` with the rectangle at `z = 0`, `[-1, 1]^2`.
    ///
    /// ```
    /// use penumbra::glam::{DVec2, DVec3};
    /// use penumbra::geom::RectLight;
    ///
    /// // A 4 x 2 light at height 5, shining down.
    /// let l = RectLight::new(DVec3::new(0.0, 5.0, 0.0), DVec3::NEG_Y, DVec3::X, DVec2::new(4.0, 2.0)).unwrap();
    /// let corner = l.point(DVec2::new(1.0, 1.0));
    /// assert!((l.to_light_space(corner) - DVec3::new(1.0, 1.0, 0.0)).length() < 1e-12);
    /// assert_eq!(l.to_light_space(DVec3::ZERO).z, 5.0); // 5 below the light
    /// assert!(l.is_lit_side(DVec3::ZERO));
    /// ```
    pub fn to_light_space(&self, p: DVec3) -> DVec3 {
        let d = p - self.center;
        let h = self.half_size();
        DVec3::new(
            d.dot(self.tangent) / h.x,
            d.dot(self.bitangent) / h.y,
            d.dot(self.normal),
        )
    }

    /// Light space back to world; inverse of [`RectLight::to_light_space`].
    pub fn from_light_space(&self, l: DVec3) -> DVec3 {
        let h = self.half_size();
        self.center + self.tangent * (l.x * h.x) + self.bitangent * (l.y * h.y) + self.normal * l.z
    }

    /// Stratified-jittered sample positions on the light in `[-1, 1]^2`: one uniform point in each
    /// cell of an `n x n` grid, drawn from `rng`. Returns `n * n` points, row by row.
    pub fn stratified_samples(n: usize, rng: &mut crate::rng::Rng) -> Vec<DVec2> {
        let mut out = Vec::with_capacity(n * n);
        let cell = 2.0 / n as f64;
        for j in 0..n {
            for i in 0..n {
                let u = -1.0 + (i as f64 + rng.next_f64()) * cell;
                let v = -1.0 + (j as f64 + rng.next_f64()) * cell;
                out.push(DVec2::new(u, v));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tilted() -> RectLight {
        let n = DVec3::new(0.3, -1.0, 0.2).normalize();
        let t = n.cross(DVec3::Z).normalize();
        RectLight::new(DVec3::new(1.0, 4.0, -2.0), n, t, DVec2::new(2.0, 0.5)).unwrap()
    }

    #[test]
    fn light_space_round_trips() {
        let l = tilted();
        let p = DVec3::new(0.25, -3.0, 7.5);
        let q = l.from_light_space(l.to_light_space(p));
        assert!((p - q).length() < 1e-12);
        for c in l.corners() {
            let s = l.to_light_space(c);
            assert!((s.x.abs() - 1.0).abs() < 1e-12 && (s.y.abs() - 1.0).abs() < 1e-12);
            assert!(s.z.abs() < 1e-12);
        }
    }

    #[test]
    fn stratified_samples_cover_each_cell_once() {
        let mut rng = crate::rng::Rng::new(7);
        let s = RectLight::stratified_samples(8, &mut rng);
        assert_eq!(s.len(), 64);
        let mut seen = [false; 64];
        for p in s {
            let i = ((p.x + 1.0) / 0.25) as usize;
            let j = ((p.y + 1.0) / 0.25) as usize;
            assert!(!seen[j * 8 + i]);
            seen[j * 8 + i] = true;
        }
        assert!(seen.iter().all(|&b| b));
    }
}
