//! The terminator of closed meshes: a point on a closed surface sees none of the light behind
//! its own tangent plane (rays there enter the solid at once), which the silhouette from the
//! light's centre does not account for where the surface turns away from part of the light.
//! The share of the light in front of the plane is a polygon clip of the light rectangle; the
//! wedge techniques cap V by it.

use glam::{DVec2, DVec3};
use penumbra_geom::{HalfEdgeMesh, RectLight, TriangleMesh};

/// +1 when `mesh` is closed and wound with its normals outwards, -1 when closed and wound
/// inwards, 0 when open, inconsistently wound or enclosing no volume (`half_edges` is its
/// half-edge structure). A closed mesh that encloses nothing, such as a sheet listed once per
/// side with its two sides split along different diagonals, has no inside: a point on it sees
/// the light on both sides, as on an open mesh.
pub fn outward_sign(mesh: &TriangleMesh, half_edges: &HalfEdgeMesh) -> f64 {
    if !half_edges.is_closed() || half_edges.has_inconsistent_orientation() {
        return 0.0;
    }
    let p = &mesh.positions;
    let Some(&o) = p.first() else {
        return 0.0;
    };
    let (mut volume, mut area) = (0.0, 0.0);
    for &[a, b, c] in &mesh.triangles {
        let (a, b, c) = (p[a as usize] - o, p[b as usize] - o, p[c as usize] - o);
        volume += a.dot(b.cross(c));
        area += (b - a).cross(c - a).length();
    }
    // Six times the volume against twice the area to the power 3/2: a sphere gives about 0.3,
    // a 1 x 1 x 1e-6 box 1e-6, a sheet with two sides the rounding of its corners.
    if volume.abs() <= 1e-9 * area.powf(1.5) {
        0.0
    } else if volume < 0.0 {
        -1.0
    } else {
        1.0
    }
}

/// The share of `light`'s area strictly in front of the plane through `p` with normal `n`
/// (`n · (X - p) > 0`), in [0, 1].
pub fn front_share(light: &RectLight, p: DVec3, n: DVec3) -> f64 {
    // Over the light's square [-1, 1]^2 in units of its half sides: f(u, v) = c + a u + b v.
    let h = light.half_size();
    let c = n.dot(light.center - p);
    let (a, b) = (n.dot(light.tangent) * h.x, n.dot(light.bitangent) * h.y);
    let corners = [
        DVec2::new(-1.0, -1.0),
        DVec2::new(1.0, -1.0),
        DVec2::new(1.0, 1.0),
        DVec2::new(-1.0, 1.0),
    ];
    let f = |q: DVec2| c + a * q.x + b * q.y;
    let mut poly: Vec<DVec2> = Vec::with_capacity(5);
    for i in 0..4 {
        let (p0, p1) = (corners[i], corners[(i + 1) % 4]);
        let (f0, f1) = (f(p0), f(p1));
        if f0 > 0.0 {
            poly.push(p0);
        }
        if (f0 > 0.0) != (f1 > 0.0) {
            poly.push(p0 + (p1 - p0) * (f0 / (f0 - f1)));
        }
    }
    let n = poly.len();
    if n < 3 {
        return 0.0;
    }
    let twice: f64 = (0..n).map(|i| poly[i].perp_dot(poly[(i + 1) % n])).sum();
    (0.5 * twice / 4.0).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn front_share_is_the_clipped_rectangle() {
        let light =
            RectLight::new(DVec3::ZERO, DVec3::NEG_Z, DVec3::X, DVec2::new(2.0, 4.0)).unwrap();
        let p = DVec3::new(0.0, 0.0, -3.0);
        // Facing the light: all of it; facing away: none.
        assert_eq!(front_share(&light, p, DVec3::Z), 1.0);
        assert_eq!(front_share(&light, p, DVec3::NEG_Z), 0.0);
        // A plane through the light's centre line x = 0: half.
        assert!((front_share(&light, p, DVec3::X) - 0.5).abs() < 1e-12);
        // Through the points with x = 0.5 of the light (half side 1): a quarter.
        let n = DVec3::new(3.0, 0.0, -0.5).normalize();
        assert!(
            (front_share(&light, p, n) - 0.25).abs() < 1e-12,
            "{}",
            front_share(&light, p, n)
        );
    }
}
