//! Occluders around the light's centre: a mesh whose cut by the light's plane holds the centre
//! (the centre inside a closed mesh, or inside the outline an open one leaves on the plane).
//! Everything the light-centre techniques build (hard shadow volumes, penumbra wedges, the shadow
//! maps) starts from that centre, and for such a mesh none of it can be right; the front door
//! warns of them.

use glam::DVec3;
use penumbra_geom::RectLight;

use crate::volumes::Volumes;

/// Whether the light's centre lies inside the cut of a mesh (`positions`, `triangles`, world
/// space) by the light's plane: inside the mesh, for a closed one. Its outline seen from the
/// centre then surrounds the whole view, and what the light-centre techniques build from it
/// (hard shadow volumes, penumbra wedges, the shadow maps) cannot be right.
///
/// The test sums the angles that the cut's segments (oriented by their triangles) subtend
/// at the centre: a closed cut around it winds once, one beside it not at all; an open cut
/// counts when it winds more than half way round.
///
/// ```
/// use penumbra::glam::{DMat4, DVec2, DVec3};
/// use penumbra::geom::{RectLight, TriangleMesh};
/// use penumbra::volumes::encloses_light_centre;
///
/// let light = RectLight::new(DVec3::new(0.0, 3.0, 0.0), DVec3::NEG_Y, DVec3::X, DVec2::ONE).unwrap();
/// let sphere = |x: f64| TriangleMesh::uv_sphere(12, 16).transformed(
///     &(DMat4::from_translation(DVec3::new(x, 3.0, 0.0)) * DMat4::from_scale(DVec3::splat(0.6))),
/// );
/// let (beside, around) = (sphere(0.9), sphere(0.3));
/// assert!(!encloses_light_centre(&beside.positions, &beside.triangles, &light));
/// assert!(encloses_light_centre(&around.positions, &around.triangles, &light));
/// ```
pub fn encloses_light_centre(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    light: &RectLight,
) -> bool {
    let ls = |v: u32| light.to_light_space(positions[v as usize]);
    let mut angle = 0.0;
    for t in triangles {
        let p = t.map(ls);
        let above = p.map(|q| q.z >= 0.0);
        if above[0] == above[1] && above[1] == above[2] {
            continue;
        }
        // Where the triangle's boundary goes up through the plane, and where it comes down.
        let (mut up, mut down) = (None, None);
        for i in 0..3 {
            let (a, b) = (p[i], p[(i + 1) % 3]);
            if above[i] != above[(i + 1) % 3] {
                let x = a + (b - a) * (a.z / (a.z - b.z));
                let x = glam::DVec2::new(x.x, x.y);
                if above[i] {
                    down = Some(x);
                } else {
                    up = Some(x);
                }
            }
        }
        if let (Some(u), Some(d)) = (up, down) {
            angle += u.perp_dot(d).atan2(u.dot(d));
        }
    }
    angle.abs() > std::f64::consts::PI
}

impl Volumes {
    /// The occluders whose cut by the light's plane holds the light's centre
    /// ([`encloses_light_centre`]): for them the hard, wedge and shadow-map techniques cannot
    /// be right.
    pub fn enclosing_light_centre(&self) -> Vec<u32> {
        (0..self.occluders.len() as u32)
            .filter(|&i| {
                let m = &self.occluders[i as usize].mesh;
                encloses_light_centre(&m.positions, &m.faces, &self.light)
            })
            .collect()
    }
}
