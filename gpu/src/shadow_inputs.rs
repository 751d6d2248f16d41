//! What a shadow-map frame uploads, computed on the CPU: the passes' uniforms, the light map's
//! frustum (`light_frustum`), the casters (closed meshes first, and the back faces
//! `fractional-disk` draws), the noise map and the Poisson taps.

use bytemuck::{Pod, Zeroable};
use glam::{DVec2, DVec3};
use penumbra_geom::{HalfEdgeMesh, Rng, Scene, Technique};
use penumbra_params::{MdsmExtra, TechniqueParams, equal_area_radius};
use penumbra_volumes::outward_sign;

pub use crate::constants::{MAX_TAPS, NOISE_SIZE};
pub use crate::light_frustum::{LightFrustum, MAX_SLOPE};

/// The uniforms of every shadow-map pass (`struct Shadow` in `shadow.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ShadowUniforms {
    /// The light frustum in slopes: min x/z, min y/z, max x/z, max y/z.
    pub frustum: [f32; 4],
    /// Map width and height in texels; texels per side of a `fractional-disk` preprocessing cell
    /// ([`fd_block`]).
    pub map: [f32; 4],
    /// Projection near depth, nearest and farthest light depth of the scene, constant bias.
    pub depth: [f32; 4],
    /// Light half sides, equal-area disk radius, slope bias in texels.
    pub light: [f32; 4],
    /// Technique parameters (see each shader).
    pub params: [f32; 4],
    /// Technique integer parameters (see each shader).
    pub iparams: [u32; 4],
    /// `gaussian` multi taps: offset in pixels, weight.
    pub taps: [[f32; 4]; MAX_TAPS],
}

const _: () = assert!(std::mem::size_of::<ShadowUniforms>() == 96 + 16 * MAX_TAPS);

/// The triangles of `scene`, those of closed and consistently oriented meshes first and wound
/// outwards (counter-clockwise seen from outside; the signed volume says which way is out), then
/// the others; and how many are closed.
pub fn closed_first(scene: &Scene) -> (Vec<[DVec3; 3]>, usize) {
    let (mut closed, mut open) = (Vec::new(), Vec::new());
    for m in &scene.meshes {
        let mesh = &m.mesh;
        let tris = (0..mesh.triangles.len()).map(|t| mesh.triangle(t));
        let sign = outward_sign(mesh, &HalfEdgeMesh::build(mesh));
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
pub fn back_faces(c: DVec3, triangles: &[[DVec3; 3]], closed: usize) -> Vec<[DVec3; 3]> {
    triangles
        .iter()
        .enumerate()
        .filter(|(i, t)| *i >= closed || (t[1] - t[0]).cross(t[2] - t[0]).dot(t[0] - c) > 0.0)
        .map(|(_, t)| *t)
        .collect()
}

/// The noise map of `fractional-disk` ("Noise map generation"), `NOISE_SIZE`² texels, row-major:
/// each row's RG a Poisson disk set in the unit disk (best candidate of 30, so every prefix is
/// spread), stored as `0.5 o + 0.5`; BA uniform in [0, 1), the per-pixel start. Deterministic.
pub fn noise_map() -> Vec<[f32; 4]> {
    let mut rng = Rng::new(0x5eed_0000);
    let mut out = Vec::with_capacity(NOISE_SIZE * NOISE_SIZE);
    for _ in 0..NOISE_SIZE {
        let row = best_candidates(&mut rng, NOISE_SIZE, false, |r| {
            let a = r.range(0.0, std::f64::consts::TAU);
            DVec2::new(a.cos(), a.sin()) * r.next_f64().sqrt()
        });
        for o in row {
            let o = o * 0.5 + 0.5;
            out.push([
                o.x as f32,
                o.y as f32,
                rng.next_f64() as f32,
                rng.next_f64() as f32,
            ]);
        }
    }
    out
}

/// `n` points by Mitchell's best candidate: each the farthest, of 30 drawn by `draw`, from
/// those before; the first at the origin when `origin_first`.
fn best_candidates(
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

/// Cherry & Kooima's table of Poisson points in [-1, 1]² ("The first point is fixed at the origin so
/// the center texel is always examined"), deterministic.
pub fn poisson_taps() -> Vec<DVec2> {
    let mut rng = Rng::new(0x9a55_0003);
    best_candidates(&mut rng, MAX_TAPS, true, |r| {
        DVec2::new(r.range(-1.0, 1.0), r.range(-1.0, 1.0))
    })
}

/// The kernel side of `gaussian` multi pass `pass` (0-based): 3, growing by 2 per pass up to
/// `max_kernel` ("starting from 3x3 and going up to 19x19", Fig. 5G).
pub fn multi_pass_kernel(pass: u32, max_kernel: u32) -> u32 {
    (3 + 2 * pass).min(max_kernel)
}

/// The taps of `gaussian` multi pass `pass`: the first `taps` Poisson points scaled to the
/// pass's kernel and rounded to whole pixels, with Gaussian weights (sigma = size / 3) of the
/// rounded offsets, normalised to sum 1.
pub fn multi_pass_taps(pass: u32, max_kernel: u32, taps: usize) -> Vec<[f32; 4]> {
    let ks = multi_pass_kernel(pass, max_kernel) as f64;
    let sigma = ks / 3.0;
    let half = (ks - 1.0) / 2.0;
    let pts: Vec<(DVec2, f64)> = poisson_taps()
        .into_iter()
        .take(taps)
        .map(|p| {
            let o = (p * half).round();
            (o, (-o.length_squared() / (2.0 * sigma * sigma)).exp())
        })
        .collect();
    let sum: f64 = pts.iter().map(|p| p.1).sum();
    pts.iter()
        .map(|(o, w)| [o.x as f32, o.y as f32, (w / sum) as f32, 0.0])
        .collect()
}

/// Cells per side of `fractional-disk`'s preprocessing grid: the paper's 256² light maps
/// (Valient & de Boer 2004). Its texel parameters (the largest disk radius, the propagation
/// passes, Eq. 2's q) count cells of this grid, so they keep the paper's scale on a finer map.
pub const FD_GRID: u32 = 256;

/// Light-map texels per side of one `fractional-disk` preprocessing cell on a `resolution`²
/// map: 1 up to [`FD_GRID`]², then `ceil(resolution / FD_GRID)`.
pub fn fd_block(resolution: u32) -> u32 {
    resolution.div_ceil(FD_GRID).max(1)
}

/// The uniforms of `technique` for `scene` (before per-pass taps).
pub fn uniforms(
    scene: &Scene,
    frustum: &LightFrustum,
    technique: Technique,
    params: &TechniqueParams,
) -> ShadowUniforms {
    let h = scene.light.half_size();
    let res = params.shadow_map.resolution as f32;
    let mut u = ShadowUniforms {
        frustum: [
            frustum.lo.x as f32,
            frustum.lo.y as f32,
            frustum.hi.x as f32,
            frustum.hi.y as f32,
        ],
        // The third lane: texels per side of a fractional-disk preprocessing cell.
        map: [res, res, 1.0, 0.0],
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
        params: [0.0; 4],
        iparams: [0; 4],
        taps: [[0.0; 4]; MAX_TAPS],
    };
    match technique {
        Technique::Pcf => u.iparams[0] = params.pcf.kernel,
        Technique::Pcss => {
            let p = &params.pcss;
            u.iparams = [p.search, p.filter_max, p.dither as u32, 0];
        }
        Technique::FractionalDisk => {
            let p = &params.fractional_disk;
            u.params = [
                p.a as f32,
                p.max_radius as f32,
                p.edge_threshold as f32,
                p.retest as u32 as f32,
            ];
            u.iparams = [p.max_samples, p.passes, 0, 0];
            u.map[2] = fd_block(params.shadow_map.resolution) as f32;
        }
        Technique::Mdsm => {
            let p = &params.mdsm;
            u.iparams = [
                p.depths,
                p.kernel,
                p.radius,
                (p.extra == MdsmExtra::Max) as u32,
            ];
        }
        Technique::Gaussian => {
            let p = &params.gaussian;
            u.params = [
                p.distance_power() as f32,
                p.dm as f32,
                (frustum.z_max - frustum.z_min).max(1e-9) as f32,
                0.0,
            ];
            u.iparams = [p.max_kernel, p.taps, p.dilation, 0];
        }
        _ => unreachable!("a shadow-map technique, checked in new"),
    }
    u
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_rows_are_spread_disk_sets_with_uniform_starts() {
        let n = noise_map();
        assert_eq!(n.len(), NOISE_SIZE * NOISE_SIZE);
        for row in n.chunks(NOISE_SIZE) {
            let pts: Vec<DVec2> = row
                .iter()
                .map(|t| DVec2::new(t[0] as f64, t[1] as f64) * 2.0 - 1.0)
                .collect();
            assert!(pts.iter().all(|p| p.length() <= 1.0 + 1e-6));
            let min = pts
                .iter()
                .enumerate()
                .flat_map(|(i, a)| pts[i + 1..].iter().map(move |b| a.distance(*b)))
                .fold(f64::INFINITY, f64::min);
            assert!(min >= 0.12, "row's closest pair {min}");
            assert!(
                row.iter()
                    .all(|t| (0.0..1.0).contains(&t[2]) && (0.0..1.0).contains(&t[3]))
            );
        }
        assert_eq!(n, noise_map(), "deterministic");
    }

    #[test]
    fn poisson_taps_start_at_the_origin_and_spread() {
        let p = poisson_taps();
        assert_eq!(p.len(), MAX_TAPS);
        assert_eq!(p[0], DVec2::ZERO);
        assert!(p.iter().all(|q| q.abs().max_element() <= 1.0));
        let first: Vec<_> = p[..20].to_vec();
        let min = first
            .iter()
            .enumerate()
            .flat_map(|(i, a)| first[i + 1..].iter().map(move |b| a.distance(*b)))
            .fold(f64::INFINITY, f64::min);
        assert!(min >= 0.25, "first 20 taps' closest pair {min}");
    }

    #[test]
    fn multi_pass_weights_are_normalised_gaussians_on_growing_kernels() {
        assert_eq!(multi_pass_kernel(0, 19), 3);
        assert_eq!(multi_pass_kernel(3, 19), 9);
        assert_eq!(multi_pass_kernel(20, 19), 19);
        for pass in 0..10 {
            let t = multi_pass_taps(pass, 19, 20);
            let sum: f32 = t.iter().map(|w| w[2]).sum();
            assert!((sum - 1.0).abs() < 1e-6);
            // The origin's weight is the largest, and weights fall with distance.
            assert_eq!([t[0][0], t[0][1]], [0.0, 0.0]);
            let half = (multi_pass_kernel(pass, 19) as f32 - 1.0) / 2.0;
            for a in &t {
                assert!(a[0].abs() <= half && a[1].abs() <= half);
                for b in &t {
                    if a[0].hypot(a[1]) < b[0].hypot(b[1]) {
                        assert!(a[2] >= b[2]);
                    }
                }
            }
        }
    }

    #[test]
    fn fractional_disk_cells_keep_the_paper_s_256_squared_grid() {
        for (resolution, block, cells) in [
            (16, 1, 16),
            (256, 1, 256),
            (257, 2, 129),
            (1000, 4, 250),
            (2048, 8, 256),
            (8192, 32, 256),
        ] {
            assert_eq!(fd_block(resolution), block, "{resolution}");
            assert_eq!(
                resolution.div_ceil(fd_block(resolution)),
                cells,
                "{resolution}"
            );
        }
    }

    #[test]
    fn back_faces_keep_a_closed_mesh_s_far_side_and_all_of_an_open_one() {
        let scene = Scene::load(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../fixtures/scenes/sphere-over-plane.toml"
        )))
        .unwrap();
        let (tris, closed) = closed_first(&scene);
        let back = back_faces(scene.light.center, &tris, closed);
        let ground = scene.meshes[0].mesh.triangles.len();
        let sphere = scene.meshes[1].mesh.triangles.len();
        // The whole ground, and about half of the sphere: the half away from the light.
        assert!(back.len() > ground + sphere / 3 && back.len() < ground + 2 * sphere / 3);
        let c = scene.light.center;
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
