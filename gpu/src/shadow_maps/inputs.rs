//! What every shadow-map technique uploads, computed on the CPU: the passes' uniforms (each
//! technique fills its own lanes), the casters (closed meshes first, and the back faces
//! `fractional-disk` draws), and the point sets that `fractional-disk`'s noise map and
//! `gaussian`'s taps draw from.

use bytemuck::{Pod, Zeroable};
use glam::{DVec2, DVec3};
use penumbra_geom::{HalfEdgeMesh, LitScene, Rng};
use penumbra_params::{TechniqueParams, equal_area_radius};
use penumbra_volumes::{Enclosure, enclosure, outward_sign};

use super::light_frustum::LightFrustum;
use crate::constants::MAX_TAPS;

/// The uniforms of every shadow-map pass (`struct Shadow` in `shadow.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ShadowUniforms {
    /// The light frustum in slopes: min x/z, min y/z, max x/z, max y/z.
    pub frustum: [f32; 4],
    /// Map width and height in texels; texels per side of a `fractional-disk` preprocessing cell
    /// (1 for the other techniques).
    pub map: [f32; 4],
    /// Projection near depth, nearest and farthest light depth of the scene, constant bias.
    pub depth: [f32; 4],
    /// Light half sides, equal-area disk radius, slope bias in texels.
    pub light: [f32; 4],
    /// Technique parameters (see each shader).
    pub params: [f32; 4],
    /// Technique integer parameters (see each shader).
    pub iparams: [u32; 4],
    /// The slopes whose receivers this render decides (min x/z, min y/z, max x/z, max y/z;
    /// [`super::windows::Window::core`]); the others read 2.
    pub core: [f32; 4],
    /// `gaussian` multi taps: offset in pixels, weight.
    pub taps: [[f32; 4]; MAX_TAPS],
}

const _: () = assert!(std::mem::size_of::<ShadowUniforms>() == 112 + 16 * MAX_TAPS);

/// The triangles of `scene`, those of closed and consistently oriented meshes first and wound
/// outwards (counter-clockwise seen from outside; the signed volume says which way is out), then
/// the others; and how many are closed. A closed mesh around a lamp and the eye (a room lit from
/// its ceiling, [`penumbra_volumes::Enclosure::Room`]) is seen from inside, as the complement of
/// a solid: it is wound inwards, so that its faces' outer side is the room's.
pub(super) fn closed_first(scene: &LitScene) -> (Vec<[DVec3; 3]>, usize) {
    let (mut closed, mut open) = (Vec::new(), Vec::new());
    // A distant light is in no room.
    let (room, eye) = (scene.distant.is_none(), scene.camera.eye);
    for m in scene.meshes.iter() {
        let mesh = &m.mesh;
        let tris = (0..mesh.triangles.len()).map(|t| mesh.triangle(t));
        let mut sign = outward_sign(mesh, &HalfEdgeMesh::build(mesh));
        if sign != 0.0 && room && enclosure(tris.clone(), &scene.light, eye) == Enclosure::Room {
            sign = -sign;
        }
        if sign == 0.0 {
            open.extend(tris);
        } else {
            closed.extend(tris.map(|[a, b, c]| if sign < 0.0 { [a, c, b] } else { [a, b, c] }));
        }
    }
    let n = closed.len();
    closed.extend(open);
    (closed, n)
}

/// The triangles that the back-face ("second-depth") map of `fractional-disk` draws (Valient & de Boer 2004,
/// "Shadow map generation": "we render only polygons facing away from the light"), of
/// `triangles` and `closed` as [`closed_first`] gives them: those of closed meshes whose outward
/// normal points away from the light's centre `c`, and every triangle of the other meshes, which
/// occlude from both sides.
pub(super) fn back_faces(c: DVec3, triangles: &[[DVec3; 3]], closed: usize) -> Vec<[DVec3; 3]> {
    triangles
        .iter()
        .enumerate()
        .filter(|(i, t)| *i >= closed || (t[1] - t[0]).cross(t[2] - t[0]).dot(t[0] - c) > 0.0)
        .map(|(_, t)| *t)
        .collect()
}

/// `n` points by Mitchell's best candidate: each the farthest, of 30 drawn by `draw`, from
/// those before; the first at the origin when `origin_first`.
pub(super) fn best_candidates(
    rng: &mut Rng,
    n: usize,
    origin_first: bool,
    draw: impl Fn(&mut Rng) -> DVec2,
) -> Vec<DVec2> {
    let mut pts: Vec<DVec2> = Vec::with_capacity(n);
    if origin_first {
        pts.push(DVec2::ZERO);
    }
    while pts.len() < n {
        let best = (0..30)
            .map(|_| draw(rng))
            .map(|c| {
                let d = pts
                    .iter()
                    .map(|p| p.distance(c))
                    .fold(f64::INFINITY, f64::min);
                (c, d)
            })
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .expect("30 candidates")
            .0;
        pts.push(best);
    }
    pts
}

/// A technique's own lanes of [`ShadowUniforms`] (each shader says what they mean).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct TechniqueLanes {
    /// [`ShadowUniforms::params`].
    pub(super) params: [f32; 4],
    /// [`ShadowUniforms::iparams`].
    pub(super) iparams: [u32; 4],
    /// Texels per side of a `fractional-disk` preprocessing cell (1 for the others): the third
    /// lane of [`ShadowUniforms::map`].
    pub(super) cell: Option<u32>,
}

impl ShadowUniforms {
    /// The uniforms of a technique whose own lanes are `lanes`, for `scene` with its light map
    /// fitted to `frustum` (before per-pass taps).
    pub(super) fn new(
        scene: &LitScene,
        frustum: &LightFrustum,
        params: &TechniqueParams,
        lanes: TechniqueLanes,
    ) -> ShadowUniforms {
        let h = scene.light.half_size();
        let res = params.shadow_map.resolution as f32;
        ShadowUniforms {
            frustum: [
                frustum.lo.x as f32,
                frustum.lo.y as f32,
                frustum.hi.x as f32,
                frustum.hi.y as f32,
            ],
            map: [res, res, lanes.cell.map_or(1.0, |c| c as f32), 0.0],
            depth: [
                frustum.near as f32,
                frustum.z_min as f32,
                frustum.z_max as f32,
                params.shadow_map.depth_bias as f32,
            ],
            light: [
                h.x as f32,
                h.y as f32,
                equal_area_radius(h.x, h.y) as f32,
                params.shadow_map.slope_bias as f32,
            ],
            params: lanes.params,
            iparams: lanes.iparams,
            core: [-f32::MAX, -f32::MAX, f32::MAX, f32::MAX],
            taps: [[0.0; 4]; MAX_TAPS],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn back_faces_keep_a_closed_mesh_s_far_side_and_all_of_an_open_one() {
        let scene = penumbra_geom::Scene::load(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../fixtures/scenes/sphere-over-plane.toml"
        )))
        .unwrap();
        let (tris, closed) = closed_first(&scene.lit(0));
        let back = back_faces(scene.lit(0).light.center, &tris, closed);
        let ground = scene.meshes[0].mesh.triangles.len();
        let sphere = scene.meshes[1].mesh.triangles.len();
        // The whole ground, and about half of the sphere: the half away from the light.
        assert!(back.len() > ground + sphere / 3 && back.len() < ground + 2 * sphere / 3);
        let c = scene.lit(0).light.center;
        let centre = DVec3::new(0.0, 1.6, 0.0);
        // The sphere's own normal, not the mesh's winding, says which faces look away. (Closed
        // meshes come first.)
        for t in &back[..back.len() - ground] {
            let m = (t[0] + t[1] + t[2]) / 3.0;
            let n = (m - centre).normalize();
            assert!(
                n.dot((m - c).normalize()) > -0.05,
                "a back face faces the light: {m}"
            );
        }
    }
}
