//! Shadow volumes for z-fail stencil counting (Carmack 2000; Everitt & Kilgard 2002, "Practical
//! and robust stenciled shadow volumes"): the casters as light caps, the same triangles pushed to
//! infinity as dark caps, and each silhouette edge extruded away from the light's centre to
//! infinity, `|m|` times, as a side quad. Points at infinity are homogeneous, `w = 0`, with the
//! direction `v - c` from the light's centre `c`.
//!
//! Every face is oriented with its normal pointing out of the volume (light caps face the light),
//! so the winding number of the volume around a point P, the z-fail stencil count, is the sum
//! over the crossings of any ray from P to infinity of `+1` where the ray leaves through a face
//! and `-1` where it enters. P is in hard shadow iff that number is non-zero.

use glam::{DVec3, DVec4};
use penumbra_geom::HalfEdgeMesh;

use crate::silhouette::Silhouette;

/// A vertex of the volume: a mesh vertex, or the same vertex pushed to infinity away from the
/// light's centre.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum VolumeVertex {
    /// Mesh vertex `i`, `w = 1`.
    Finite(u32),
    /// Direction `positions[i] - c`, `w = 0`.
    Infinite(u32),
}

/// Which part of the volume a triangle belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FaceKind {
    /// A caster triangle, facing the light.
    LightCap,
    /// A caster triangle at infinity, facing away.
    DarkCap,
    /// Half of an extruded silhouette quad.
    Side,
}

/// A closed shadow volume in homogeneous coordinates.
#[derive(Clone, Debug)]
pub struct ShadowVolume {
    /// The light's centre.
    pub light_center: DVec3,
    /// The mesh's positions.
    pub positions: Vec<DVec3>,
    /// Outward-oriented triangles.
    pub triangles: Vec<([VolumeVertex; 3], FaceKind)>,
}

/// A directed edge of the volume that no face runs the other way: the volume leaks there.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "shadow volume is open: edge {from:?} -> {to:?} is used {forward} times, its reverse {backward} times"
)]
pub struct OpenVolume {
    /// Edge start.
    pub from: VolumeVertex,
    /// Edge end.
    pub to: VolumeVertex,
    /// How often faces run `from -> to`.
    pub forward: usize,
    /// How often faces run `to -> from`.
    pub backward: usize,
}

/// The light cap and the dark cap of the caster triangle `t` (oriented to face the light).
pub fn caps([a, b, c]: [u32; 3]) -> [[VolumeVertex; 3]; 2] {
    use VolumeVertex::{Finite as F, Infinite as I};
    [[F(a), F(b), F(c)], [I(a), I(c), I(b)]]
}

/// The two triangles of the side quad of the silhouette edge `from -> to` (the casters run it
/// that way; the quad `to, from, from∞, to∞` runs it back), once per unit of multiplicity.
pub fn side(from: u32, to: u32) -> [[VolumeVertex; 3]; 2] {
    use VolumeVertex::{Finite as F, Infinite as I};
    [[F(to), F(from), I(from)], [F(to), I(from), I(to)]]
}

impl ShadowVolume {
    /// Builds the volume of `mesh` for the silhouette `sil` taken from the light's centre `c`.
    pub fn build(mesh: &HalfEdgeMesh, sil: &Silhouette, c: DVec3) -> Self {
        let mut triangles = Vec::with_capacity(2 * sil.casters.len() + 2 * sil.edges.len());
        for &caster in &sil.casters {
            let [light, dark] = caps(caster);
            triangles.push((light, FaceKind::LightCap));
            triangles.push((dark, FaceKind::DarkCap));
        }
        for e in &sil.edges {
            for _ in 0..e.multiplicity {
                triangles.extend(side(e.from, e.to).map(|t| (t, FaceKind::Side)));
            }
        }
        ShadowVolume {
            light_center: c,
            positions: mesh.positions.clone(),
            triangles,
        }
    }

    /// Homogeneous coordinates of a volume vertex (`w = 0` at infinity).
    pub fn homogeneous(&self, v: VolumeVertex) -> DVec4 {
        match v {
            VolumeVertex::Finite(i) => self.positions[i as usize].extend(1.0),
            VolumeVertex::Infinite(i) => {
                (self.positions[i as usize] - self.light_center).extend(0.0)
            }
        }
    }

    /// Number of triangles of each kind: `[light caps, dark caps, sides]`.
    pub fn counts(&self) -> [usize; 3] {
        let mut c = [0; 3];
        for (_, k) in &self.triangles {
            c[*k as usize] += 1;
        }
        c
    }

    /// Proves the volume watertight: every directed edge is met by its reverse as often as it is
    /// used, so the faces bound a closed (possibly multiply covered) region.
    pub fn check_closed(&self) -> Result<(), OpenVolume> {
        let mut count: std::collections::HashMap<(VolumeVertex, VolumeVertex), isize> =
            std::collections::HashMap::new();
        for (t, _) in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if a < b {
                    *count.entry((a, b)).or_default() += 1;
                } else {
                    *count.entry((b, a)).or_default() -= 1;
                }
            }
        }
        let mut bad: Vec<_> = count.into_iter().filter(|&(_, n)| n != 0).collect();
        bad.sort();
        match bad.first() {
            None => Ok(()),
            Some(&((a, b), n)) => {
                let uses = |x, y| {
                    self.triangles
                        .iter()
                        .filter(|(t, _)| (0..3).any(|k| t[k] == x && t[(k + 1) % 3] == y))
                        .count()
                };
                let _ = n;
                Err(OpenVolume {
                    from: a,
                    to: b,
                    forward: uses(a, b),
                    backward: uses(b, a),
                })
            }
        }
    }

    /// Winding number of the volume around `p`: the signed count of crossings of the ray
    /// `p + t·dir`, `t > 0`, with the faces (+1 leaving, -1 entering), the dark caps crossed at
    /// infinity. This is what a z-fail stencil pass counts along the view ray.
    pub fn winding_number(&self, p: DVec3, dir: DVec3) -> i32 {
        self.triangles
            .iter()
            .map(|(t, _)| crossing(t.map(|v| self.homogeneous(v)), p, dir))
            .sum()
    }
}

/// Signed crossing of the ray `p + t·d`, `t > 0` (to infinity included), with the homogeneous
/// triangle `h`: `+1` along the face's normal, `-1` against it, 0 if missed.
pub fn crossing(h: [DVec4; 3], p: DVec3, d: DVec3) -> i32 {
    let finite = h.iter().filter(|v| v.w != 0.0).count();
    if finite == 0 {
        // Dark cap: the ray reaches infinity in direction d; crossed iff d lies in the cone of
        // the three directions. Oriented outward, the cone's determinant is positive.
        let [a, b, c] = h.map(|v| v.truncate());
        let det = a.dot(b.cross(c));
        if det == 0.0 {
            return 0;
        }
        let s = det.signum();
        let inside = s * d.dot(b.cross(c)) >= 0.0
            && s * a.dot(d.cross(c)) >= 0.0
            && s * a.dot(b.cross(d)) >= 0.0;
        return if inside { s as i32 } else { 0 };
    }
    // Rotate so the first vertex is finite, keeping orientation.
    let k = h.iter().position(|v| v.w != 0.0).unwrap_or(0);
    let [a, b, c] = [h[k], h[(k + 1) % 3], h[(k + 2) % 3]];
    let o = a.truncate() / a.w;
    // Edge vectors from `o`: to a finite vertex, its offset; to an infinite one, its direction.
    let e = |v: DVec4| {
        if v.w != 0.0 {
            v.truncate() / v.w - o
        } else {
            v.truncate()
        }
    };
    let (e1, e2) = (e(b), e(c));
    let n = e1.cross(e2);
    let denom = n.dot(d);
    if denom == 0.0 {
        return 0;
    }
    let t = n.dot(o - p) / denom;
    if t <= 0.0 {
        return 0;
    }
    let x = p + d * t - o;
    // x = s·e1 + r·e2 in the plane; solve by cross products.
    let nn = n.dot(n);
    let s = x.cross(e2).dot(n) / nn;
    let r = e1.cross(x).dot(n) / nn;
    let inside = match (b.w != 0.0, c.w != 0.0) {
        (true, true) => s >= 0.0 && r >= 0.0 && s + r <= 1.0,
        // (o, b finite, c infinite): the segment o-b swept along c's direction.
        (true, false) => (0.0..=1.0).contains(&s) && r >= 0.0,
        // (o, b infinite, c finite): the segment o-c swept along b's direction.
        (false, true) => s >= 0.0 && (0.0..=1.0).contains(&r),
        // (o, two directions): a cone at o.
        (false, false) => s >= 0.0 && r >= 0.0,
    };
    if inside { denom.signum() as i32 } else { 0 }
}
