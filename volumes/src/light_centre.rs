//! Closed meshes around a lamp: a room lit from its ceiling, or a lamp shut in a box seen from
//! outside. A closed mesh whose generalised winding number about a point just in front of the
//! lamp's centre is not zero encloses the lamp. With the eye inside it too, it is a room: the
//! renderers built from the light's centre (hard shadow volumes, penumbra wedges, the shadow
//! maps) take it as the complement of a solid, its surfaces seen from inside, and are right.
//! With the eye outside, every point in view is outside a solid the lamp shines into; the front
//! door takes `hard` from the hard reference there and warns of the soft approximations.

use glam::DVec3;
use penumbra_geom::RectLight;

/// Where a closed mesh stands to a lamp and the eye.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Enclosure {
    /// The mesh does not wind around the lamp.
    Apart,
    /// The mesh winds around the lamp and the eye: a room lit from inside, seen from inside.
    Room,
    /// The mesh winds around the lamp but not the eye: a lamp shut in a solid, seen from
    /// outside it.
    Sealed,
}

/// How closed mesh `triangles` (world space) stands to `light` and `eye` (see [`Enclosure`]),
/// by [`winds_around`] the point [`in_front_of`] the light and the eye.
///
/// ```
/// use penumbra::glam::{DMat4, DVec2, DVec3};
/// use penumbra::geom::{RectLight, TriangleMesh};
/// use penumbra::volumes::{Enclosure, enclosure};
///
/// let light = RectLight::new(DVec3::new(0.0, 3.0, 0.0), DVec3::NEG_Y, DVec3::X, DVec2::ONE).unwrap();
/// // A room 6 x 3 x 5 whose ceiling holds the light, and a box whose top face does.
/// let room = TriangleMesh::cube().transformed(
///     &(DMat4::from_translation(DVec3::new(0.0, 1.5, 0.0)) * DMat4::from_scale(DVec3::new(6.0, 3.0, 5.0))),
/// );
/// let tris = |m: &TriangleMesh| m.triangles.iter().map(|t| t.map(|i| m.positions[i as usize])).collect::<Vec<_>>();
/// let eye = DVec3::new(2.0, 1.6, 2.0);
/// assert_eq!(enclosure(tris(&room), &light, eye), Enclosure::Room);
/// assert_eq!(enclosure(tris(&room), &light, DVec3::new(9.0, 1.6, 2.0)), Enclosure::Sealed);
/// let beside = room.transformed(&DMat4::from_translation(DVec3::new(7.0, 0.0, 0.0)));
/// assert_eq!(enclosure(tris(&beside), &light, eye), Enclosure::Apart);
/// ```
pub fn enclosure<T>(triangles: T, light: &RectLight, eye: DVec3) -> Enclosure
where
    T: IntoIterator<Item = [DVec3; 3]>,
    T::IntoIter: Clone,
{
    let triangles = triangles.into_iter();
    if !winds_around(triangles.clone(), in_front_of(light)) {
        Enclosure::Apart
    } else if winds_around(triangles, eye) {
        Enclosure::Room
    } else {
        Enclosure::Sealed
    }
}

/// Whether `triangles` (a closed mesh) wind around `point`: their generalised winding number
/// about it (the triangles' signed solid angles over 4 pi, Van Oosterom & Strackee, "The Solid
/// Angle of a Plane Triangle", 1983) is about +-1 inside and 0 outside, whichever way the mesh
/// is wound.
pub fn winds_around(triangles: impl IntoIterator<Item = [DVec3; 3]>, point: DVec3) -> bool {
    around(triangles.into_iter().map(|t| solid_angle(t, point)).sum())
}

/// Whether a closed mesh's solid angles summed about a point, `w`, wind around it: its
/// winding number `w / 4 pi` is about +-1 inside and 0 outside.
fn around(w: f64) -> bool {
    (w / (4.0 * std::f64::consts::PI)).abs() > 0.5
}

/// The point just in front of a lamp's centre about which [`winds_around`] asks whether a
/// closed mesh encloses the lamp: 1e-4 of the lamp's distance from the origin and its size
/// along its normal, so that a lamp flush with a ceiling is inside the room it lights.
pub fn in_front_of(light: &RectLight) -> DVec3 {
    light.center + light.normal * (1e-4 * (light.center.length() + light.size.max_element()))
}

/// The signed solid angle of triangle `t` seen from `p`.
fn solid_angle(t: [DVec3; 3], p: DVec3) -> f64 {
    let [a, b, c] = t.map(|v| v - p);
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let num = a.dot(b.cross(c));
    let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * num.atan2(den)
}

/// Per occluder (`closed` says which are closed meshes; each triangle's occluder in
/// `triangle_occluder`, `caster_bit` masked off), whether it is a room around the light seen
/// from `eye` ([`Enclosure::Room`]). Open meshes have no inside, and their triangles are not
/// visited.
pub(crate) fn rooms(
    tracer: &penumbra_geom::Tracer,
    triangle_occluder: &[u32],
    closed: &[bool],
    caster_bit: u32,
    eye: DVec3,
) -> Vec<bool> {
    let at = in_front_of(&tracer.light);
    let mut winding = vec![(0.0f64, 0.0f64); closed.len()];
    for (t, tri) in tracer.triangles.iter().enumerate() {
        let o = (triangle_occluder[t] & !caster_bit) as usize;
        if closed.get(o) == Some(&true) {
            winding[o].0 += solid_angle(*tri, at);
            winding[o].1 += solid_angle(*tri, eye);
        }
    }
    winding
        .into_iter()
        .map(|(lamp, eye)| around(lamp) && around(eye))
        .collect()
}

/// Whether a mesh (`triangles`, world space) passes through `light`'s own rectangle: one of its
/// triangles crosses the light's plane (corners strictly on both sides), or meets it along a
/// side, along a segment that meets the rectangle's interior. The silhouette from the light's centre, which the wedges
/// and the shadow maps build from, is then far from the silhouette seen from the rest of the
/// light. Faces lying in the light's plane (a ceiling flush with its lamp) hide nothing and do
/// not count.
pub fn passes_through_light(
    triangles: impl IntoIterator<Item = [DVec3; 3]>,
    light: &RectLight,
) -> bool {
    triangles.into_iter().any(|t| {
        let l = t.map(|p| light.to_light_space(p));
        let on = l.iter().filter(|p| p.z == 0.0).count();
        let both = l.iter().any(|p| p.z > 0.0) && l.iter().any(|p| p.z < 0.0);
        // Across the plane, or meeting it along a side (a ring of vertices on the plane).
        if on == 3 || !(both || on == 2) {
            return false;
        }
        // The cut: the corners on the plane, and where sides cross it.
        let mut cut = Vec::with_capacity(3);
        for i in 0..3 {
            let (a, b) = (l[i], l[(i + 1) % 3]);
            if a.z == 0.0 {
                cut.push(a.truncate());
            } else if b.z != 0.0 && (a.z > 0.0) != (b.z > 0.0) {
                cut.push((a + (b - a) * (a.z / (a.z - b.z))).truncate());
            }
        }
        cut.len() >= 2 && segment_meets_square(cut[0], cut[1])
    })
}

/// Whether the segment from `a` to `b` meets the open square (-1, 1)^2 (Liang and Barsky's
/// clip). Open, unlike `wedge::segment_meets_square`'s closed square: a surface that meets the
/// light's plane only along the light's border (a panel filling its recess) does not pass
/// through it.
fn segment_meets_square(a: glam::DVec2, b: glam::DVec2) -> bool {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-d.x, a.x + 1.0),
        (d.x, 1.0 - a.x),
        (-d.y, a.y + 1.0),
        (d.y, 1.0 - a.y),
    ] {
        if p == 0.0 {
            if q <= 0.0 {
                return false;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    t0 < t1
}

/// Whether a mesh (`triangles`, world space) has a part in front of `light` within [`NEAR_LIGHT`]
/// of the light's larger side `s`: in the box that reaches `s / 4` beyond each side of the
/// rectangle and `s / 4` in front of its plane (a lamp in a recess, a shade, a fitting around
/// it). Such a blocker casts penumbrae more than three times the light's width at every receiver
/// farther than the light's size, and far wider across a room; the shadow maps, whose filters
/// take the penumbra's width from one blocker depth per texel, cannot reach them. Faces lying
/// in the light's plane (a ceiling flush with its lamp) do not count.
///
/// ```
/// use penumbra::glam::{DVec2, DVec3};
/// use penumbra::geom::RectLight;
/// use penumbra::volumes::near_light;
///
/// // A 1.2 x 0.8 lamp at height 3.15, facing down, 0.15 into a recess 1.4 wide.
/// let lamp = RectLight::new(DVec3::new(0.0, 3.15, 0.0), DVec3::NEG_Y, DVec3::X, DVec2::new(1.2, 0.8)).unwrap();
/// let quad = |a: DVec3, b: DVec3, c: DVec3, d: DVec3| vec![[a, b, c], [a, c, d]];
/// let v = DVec3::new;
/// // The recess's wall, 0.1 beside the lamp and down to 0.15 in front of it.
/// let wall = quad(v(0.7, 3.0, -0.5), v(0.7, 3.3, -0.5), v(0.7, 3.3, 0.5), v(0.7, 3.0, 0.5));
/// assert!(near_light(wall, &lamp));
/// // A ceiling flush with the lamp, the room's wall 2.4 beside it, a table 2.4 below it, a
/// // block 0.5 below it.
/// let flush = quad(v(-3.0, 3.15, -3.0), v(3.0, 3.15, -3.0), v(3.0, 3.15, 3.0), v(-3.0, 3.15, 3.0));
/// assert!(!near_light(flush, &lamp));
/// let room_wall = quad(v(3.0, 0.0, -3.0), v(3.0, 3.3, -3.0), v(3.0, 3.3, 3.0), v(3.0, 0.0, 3.0));
/// assert!(!near_light(room_wall, &lamp));
/// let table = quad(v(-1.0, 0.75, -1.0), v(1.0, 0.75, -1.0), v(1.0, 0.75, 1.0), v(-1.0, 0.75, 1.0));
/// assert!(!near_light(table, &lamp));
/// let block = quad(v(-0.2, 2.65, -0.2), v(0.2, 2.65, -0.2), v(0.2, 2.65, 0.2), v(-0.2, 2.65, 0.2));
/// assert!(!near_light(block, &lamp));
/// ```
pub fn near_light(triangles: impl IntoIterator<Item = [DVec3; 3]>, light: &RectLight) -> bool {
    let s = NEAR_LIGHT * light.size.max_element();
    let h = light.half_size();
    // The box in light space, where the rectangle is [-1, 1]^2 and z the distance in front:
    // its faces as half-spaces `n . p <= c`, the plane's own side last.
    let (x, y) = (1.0 + s / h.x, 1.0 + s / h.y);
    let bounds = [
        (DVec3::X, x),
        (DVec3::NEG_X, x),
        (DVec3::Y, y),
        (DVec3::NEG_Y, y),
        (DVec3::Z, s),
        (DVec3::NEG_Z, 0.0),
    ];
    let (mut poly, mut clipped) = (Vec::with_capacity(9), Vec::with_capacity(9));
    triangles.into_iter().any(|t| {
        poly.clear();
        poly.extend(t.map(|p| light.to_light_space(p)));
        for &(n, c) in &bounds {
            penumbra_geom::clip_step(
                &poly,
                |p| c - n.dot(p),
                |a, b, t| a + (b - a) * t,
                &mut clipped,
            );
            std::mem::swap(&mut poly, &mut clipped);
            if poly.is_empty() {
                return false;
            }
        }
        poly.iter().any(|p| p.z > 1e-9 * s)
    })
}

/// How near the light, as a share of its larger side, [`near_light`] finds a blocker.
pub const NEAR_LIGHT: f64 = 0.25;
