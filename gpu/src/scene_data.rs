//! What the volume techniques upload for a frame, computed on the CPU: the wedge instances and
//! the solids that bound them, the receivers' clusters and screen tiles that group the
//! occluders, and the vertex data of the triangles and the shadow volumes.

use glam::{DVec2, DVec3, Vec4};
use penumbra_geom::RectLight;
use penumbra_volumes::Volumes;
use penumbra_volumes::{VolumeVertex, caps, side};
use penumbra_volumes::{WedgeFrustum, receiver_box, wedge_frustum};

use crate::frame_uniforms::FrameCamera;
use crate::passes::blend::TileMask;
use crate::passes::wedge::WedgeInstance;

/// The wedges of `volumes` with their light-space bounding boxes clipped to the receivers' box
/// of `triangles` (world space); wedges wholly outside are dropped. Also each blending unit's
/// range of the instances (the wedges come grouped by unit, [`Wedge::unit`]).
///
/// [`Wedge::unit`]: penumbra_volumes::Wedge::unit
pub fn wedge_instances(
    light: &RectLight,
    triangles: &[[DVec3; 3]],
    volumes: &Volumes,
) -> (Vec<WedgeInstance>, Vec<std::ops::Range<u32>>) {
    let (lo, hi) = receiver_box(light, triangles);
    let f = |v: DVec3, w: f32| {
        let v = v.as_vec3();
        [v.x, v.y, v.z, w]
    };
    let mut ranges = vec![0..0; volumes.unit_count()];
    let mut out = Vec::with_capacity(volumes.wedges.len());
    for w in &volumes.wedges {
        let inst = wedge_frustum(w, lo, hi).map(|solid| {
            let rect = |r: (DVec2, DVec2)| {
                let (a, b) = (r.0.as_vec2(), r.1.as_vec2());
                [a.x, a.y, b.x, b.y]
            };
            let (blo, bhi) = solid.bounds();
            WedgeInstance {
                lo: f(blo, 0.0),
                hi: f(bhi, 0.0),
                from: f(w.from, w.multiplicity as f32),
                to: f(w.to, 0.0),
                near: rect(solid.near),
                far: rect(solid.far),
                caster: w.caster.map_or([0.0; 4], |c| f(c, 1.0)),
            }
        });
        if let Some(i) = inst {
            let r = &mut ranges[w.unit as usize];
            if r.start == r.end {
                *r = out.len() as u32..out.len() as u32;
            }
            out.push(i);
            r.end = out.len() as u32;
        }
    }
    (out, ranges)
}

/// Triangles per receiver cluster of [`ReceiverClusters`].
pub const CLUSTER_TRIANGLES: usize = 16;

/// Clusters per block of [`ReceiverClusters`].
const BLOCK_CLUSTERS: usize = 64;

/// A light-space box as its (min, max) corners.
pub type LightBox = (DVec3, DVec3);

fn bounds(boxes: impl Iterator<Item = LightBox>) -> LightBox {
    boxes.fold(
        (DVec3::INFINITY, DVec3::NEG_INFINITY),
        |(lo, hi), (a, b)| (lo.min(a), hi.max(b)),
    )
}

/// The receivers, coarsely, for [`screen_tiles`]: light-space bounding boxes of runs of
/// [`CLUSTER_TRIANGLES`] consecutive scene triangles (a mesh's triangles are stored together, so
/// a run is mostly one patch of one surface), and of blocks of 64 runs, so that a query skips
/// whole blocks (a million triangles make about a thousand blocks).
pub struct ReceiverClusters {
    clusters: Vec<LightBox>,
    blocks: Vec<LightBox>,
}

impl ReceiverClusters {
    /// The clusters of the scene's `triangles` (world space).
    pub fn new(light: &RectLight, triangles: &[[DVec3; 3]]) -> Self {
        let clusters: Vec<LightBox> = triangles
            .chunks(CLUSTER_TRIANGLES)
            .map(|run| {
                bounds(run.iter().flatten().map(|v| {
                    let l = light.to_light_space(*v);
                    (l, l)
                }))
            })
            .collect();
        let blocks = clusters
            .chunks(BLOCK_CLUSTERS)
            .map(|b| bounds(b.iter().copied()))
            .collect();
        ReceiverClusters { clusters, blocks }
    }

    /// The clusters' boxes cut to `[lo, hi]`, where not empty.
    pub fn within(&self, lo: DVec3, hi: DVec3) -> impl Iterator<Item = LightBox> + '_ {
        let cut = move |(clo, chi): LightBox| {
            let (a, b) = (lo.max(clo), hi.min(chi));
            (a.x <= b.x && a.y <= b.y && a.z <= b.z).then_some((a, b))
        };
        self.blocks
            .iter()
            .enumerate()
            .filter(move |&(_, &b)| cut(b).is_some())
            .flat_map(move |(i, _)| {
                let end = ((i + 1) * BLOCK_CLUSTERS).min(self.clusters.len());
                self.clusters[i * BLOCK_CLUSTERS..end].iter().copied()
            })
            .filter_map(cut)
    }
}

/// The screen tiles of `camera` that hold every pixel whose receiver lies in the light-space
/// solid `solid` of `light`: those of the projections of the receiver `clusters`
/// ([`ReceiverClusters`]; a receiver point in the solid lies in one of them) cut to the solid
/// (to its bounding box, then each to the solid's rectangles at the cluster's depths), none when
/// none meets it, and every tile when a corner to project is not in front of the camera. Only
/// receivers deeper than `deeper_than` (light space) count: clusters no deeper are skipped.
pub fn screen_tiles(
    camera: &FrameCamera,
    light: &RectLight,
    clusters: &ReceiverClusters,
    solid: &WedgeFrustum,
    deeper_than: f64,
) -> TileMask {
    let (lo, hi) = solid.bounds();
    let (w, h) = camera.size;
    let view_proj = &camera.view_proj;
    let mut mask = TileMask::new(w, h);
    for (lo, hi) in clusters.within(lo, hi) {
        if hi.z <= deeper_than {
            continue;
        }
        // The solid's sections are linear in depth: over the cluster's depths they lie within
        // the rectangle holding the two at its ends.
        let (a, b) = (solid.section(lo.z), solid.section(hi.z));
        let (lo, hi) = (
            lo.truncate().max(a.0.min(b.0)).extend(lo.z),
            hi.truncate().min(a.1.max(b.1)).extend(hi.z),
        );
        if !(lo.x <= hi.x && lo.y <= hi.y) {
            continue;
        }
        let (mut min, mut max) = (DVec2::INFINITY, DVec2::NEG_INFINITY);
        for i in 0..8 {
            let l = DVec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            );
            let v = light.from_light_space(l) - camera.eye;
            let clip = *view_proj * v.extend(1.0);
            if !(clip.w > 1e-9 * v.length()) {
                mask.fill();
                return mask;
            }
            let ndc = clip.truncate().truncate() / clip.w;
            // Pixels, y down.
            let p = DVec2::new(
                (ndc.x + 1.0) * 0.5 * w as f64,
                (1.0 - ndc.y) * 0.5 * h as f64,
            );
            min = min.min(p);
            max = max.max(p);
        }
        // One pixel of margin for rasterisation at the box's border.
        let x0 = (min.x - 1.0).floor().clamp(0.0, w as f64) as u32;
        let y0 = (min.y - 1.0).floor().clamp(0.0, h as f64) as u32;
        let x1 = (max.x + 1.0).ceil().clamp(0.0, w as f64) as u32;
        let y1 = (max.y + 1.0).ceil().clamp(0.0, h as f64) as u32;
        mask.insert_pixels(x0, y0, x1, y1);
    }
    mask
}

/// A frustum holding the solids of `instances` ([`WedgeInstance::near`] to
/// [`WedgeInstance::far`] over each one's depths), `None` when there are none: from the nearest
/// depth to the farthest, the far rectangle holding all of theirs, the near one grown until each
/// instance's rectangles lie in the sections at their depths (sections are linear in depth, so
/// each instance's solid then lies in it).
pub fn merged_solid(instances: &[WedgeInstance]) -> Option<WedgeFrustum> {
    let solids: Vec<WedgeFrustum> = instances.iter().map(WedgeInstance::solid).collect();
    let rects = |s: &WedgeFrustum| [(s.z.0, s.near), (s.z.1, s.far)];
    let z0 = solids.iter().map(|s| s.z.0).reduce(f64::min)?;
    let z1 = solids.iter().map(|s| s.z.1).reduce(f64::max)?;
    let mut far = (DVec2::INFINITY, DVec2::NEG_INFINITY);
    for (_, r) in solids.iter().flat_map(rects) {
        far = (far.0.min(r.0), far.1.max(r.1));
    }
    // The smallest near rectangle meeting every instance's constraint; `far` when none binds.
    let mut near = (DVec2::INFINITY, DVec2::NEG_INFINITY);
    for (z, r) in solids.iter().flat_map(rects) {
        let t = if z1 > z0 { (z - z0) / (z1 - z0) } else { 1.0 };
        // lerp(near, far, t) must hold r; at t = 1 `far` already does.
        if t < 1.0 {
            near.0 = near.0.min((r.0 - far.0 * t) / (1.0 - t));
            near.1 = near.1.max((r.1 - far.1 * t) / (1.0 - t));
        }
    }
    if !(near.0.is_finite() && near.1.is_finite()) {
        near = far;
    }
    Some(WedgeFrustum {
        z: (z0, z1),
        near,
        far,
    })
}

/// Each occluder's screen tiles ([`screen_tiles`]): where the receivers in the merged solid of
/// its wedges `instances[ranges[o]]` ([`wedge_instances`], [`merged_solid`]) project, counting
/// only receivers deeper than its nearest silhouette edge (`nearest[o]`, [`nearest_edges`]).
///
/// Its hard shadow lies in that solid too: the solid is convex and holds the shadow volume's
/// sides (each in its edge's wedge), hence every cross-section of the volume between them. A
/// receiver is beyond an edge only if it is deeper than the edge, and in the occluder's hard
/// shadow only if a light-facing part of it lies between the receiver and the light's centre,
/// beyond that part's bounding silhouette. Receivers at the nearest edge's depth are thus left
/// out, which drops an occluder that can shadow nothing: a ground plane facing the light, whose
/// only silhouette is its own border at its own depth.
pub fn occluder_tiles(
    camera: &FrameCamera,
    light: &RectLight,
    clusters: &ReceiverClusters,
    nearest: &[f64],
    instances: &[WedgeInstance],
    ranges: &[std::ops::Range<u32>],
) -> Vec<TileMask> {
    let (w, h) = camera.size;
    ranges
        .iter()
        .zip(nearest)
        .map(
            |(r, &z)| match merged_solid(&instances[r.start as usize..r.end as usize]) {
                Some(solid) => screen_tiles(camera, light, clusters, &solid, z),
                None => TileMask::new(w, h),
            },
        )
        .collect()
}

/// Each blending unit's nearest silhouette edge's light-space depth in `volumes` (infinite for a
/// unit without one), for [`occluder_tiles`].
pub fn nearest_edges(volumes: &Volumes) -> Vec<f64> {
    let mut nearest = vec![f64::INFINITY; volumes.unit_count()];
    for wedge in &volumes.wedges {
        let z = &mut nearest[wedge.unit as usize];
        *z = z.min(wedge.from.z).min(wedge.to.z);
    }
    nearest
}

/// Homogeneous shadow-volume vertices, and each blending unit's mesh and range of them.
pub type UnitVolumes = (Vec<[f32; 4]>, Vec<(u32, std::ops::Range<u32>)>);

/// Each blending unit's shadow volume (the unit is a caster patch, [`Wedge::unit`]: its light
/// caps, its dark caps and the side quads of the silhouette edges it bounds, each `|m|` times
/// with the patch's own multiplicity), closed on its own, so that its z-fail count is the number
/// of its casters between P and the light's centre, as the CPU oracle counts per unit. Vertices
/// are homogeneous: a mesh vertex as `stored[o][i]` (mesh `o`'s vertex `i` as its vertex buffer
/// holds it, placed by the mesh's model matrix) with `w = 1`, a vertex at infinity as its
/// direction from the light's centre with `w = 0`. Also each unit's mesh and range.
///
/// [`Wedge::unit`]: penumbra_volumes::Wedge::unit
pub fn volume_vertices(volumes: &Volumes, stored: &[&[[f32; 3]]]) -> UnitVolumes {
    use VolumeVertex::{Finite as F, Infinite as I};
    let c = volumes.light.center;
    let mut vol = Vec::new();
    let mut ranges = Vec::with_capacity(volumes.unit_count());
    for (oi, (o, stored)) in volumes.occluders.iter().zip(stored).enumerate() {
        let sil = &o.silhouette;
        let p = &o.mesh.positions;
        let vertex = |v: VolumeVertex| match v {
            F(i) => {
                let [x, y, z] = stored[i as usize];
                [x, y, z, 1.0]
            }
            I(i) => Vec4::to_array(&(p[i as usize] - c).as_vec3().extend(0.0)),
        };
        // Each patch's triangles, in patch order.
        let mut per_patch: Vec<Vec<[VolumeVertex; 3]>> = vec![Vec::new(); sil.patches as usize];
        for (_, caster, patch) in sil.caster_faces() {
            per_patch[patch as usize].extend(caps(caster));
        }
        for (patch, from, to, count) in sil.patch_sides() {
            for _ in 0..count {
                per_patch[patch as usize].extend(side(from, to));
            }
        }
        for tris in per_patch {
            let start = vol.len() as u32;
            vol.extend(tris.iter().flatten().map(|&v| vertex(v)));
            ranges.push((oi as u32, start..vol.len() as u32));
        }
    }
    (vol, ranges)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn merged_solid_holds_every_instance_solid() {
        // Instances with their own depths and rectangles, some boxes (near = far), some frusta.
        let mut rng = penumbra_geom::Rng::new(0x2545_f491_4f6c_dd1d);
        let mut r = || rng.next_f64() as f32;
        let instances: Vec<WedgeInstance> = (0..40)
            .map(|i| {
                // As `wedge_instances` makes them, every solid ends at the receivers' far depth.
                let (z0, z1) = (1.0 + 4.0 * r(), 9.0);
                let (cx, cy) = (4.0 * r() - 2.0, 4.0 * r() - 2.0);
                let far = [
                    cx - 1.0 - r(),
                    cy - 1.0 - r(),
                    cx + 1.0 + r(),
                    cy + 1.0 + r(),
                ];
                let near = if i % 3 == 0 {
                    far
                } else {
                    let (a, b) = (0.3 * r(), 0.3 * r());
                    [cx - a, cy - b, cx + a, cy + b]
                };
                WedgeInstance {
                    lo: [far[0], far[1], z0, 0.0],
                    hi: [far[2], far[3], z1, 0.0],
                    from: [0.0; 4],
                    to: [0.0; 4],
                    near,
                    far,
                    caster: [0.0; 4],
                }
            })
            .collect();
        let m = merged_solid(&instances).unwrap();
        assert!(merged_solid(&[]).is_none());
        // Frusta alone narrow it towards their near ends: its near rectangle is smaller than
        // its far one.
        let frusta: Vec<WedgeInstance> = instances.iter().skip(1).step_by(3).copied().collect();
        let f = merged_solid(&frusta).unwrap();
        let size = |r: (DVec2, DVec2)| (r.1 - r.0).element_product();
        assert!(size(f.near) < 0.8 * size(f.far), "{f:?}");
        for b in &instances {
            let solid = b.solid();
            for i in 0..=8 {
                let z = solid.z.0 + (solid.z.1 - solid.z.0) * i as f64 / 8.0;
                let (lo, hi) = solid.section(z);
                for c in [lo, hi, DVec2::new(lo.x, hi.y), DVec2::new(hi.x, lo.y)] {
                    assert!(m.holds(c.extend(z), 1e-9), "{c} at {z} outside {m:?}");
                }
            }
        }
    }

    #[test]
    fn receiver_clusters_return_every_cluster_meeting_the_box_cut_to_it() {
        // Light at the origin facing -z: light space is (x, -y, -z).
        let light =
            RectLight::new(DVec3::ZERO, DVec3::NEG_Z, DVec3::X, DVec2::new(2.0, 2.0)).unwrap();
        // 200 clusters, each one small triangle 16 times over, at x = 0, 1, 2, ... and depth 5:
        // four blocks, the last one partial.
        let triangles: Vec<[DVec3; 3]> = (0..200 * CLUSTER_TRIANGLES)
            .map(|t| {
                let x = (t / CLUSTER_TRIANGLES) as f64;
                [
                    DVec3::new(x, 0.0, -5.0),
                    DVec3::new(x + 0.5, 0.0, -5.0),
                    DVec3::new(x, 0.5, -5.5),
                ]
            })
            .collect();
        let c = ReceiverClusters::new(&light, &triangles);
        assert_eq!((c.clusters.len(), c.blocks.len()), (200, 4));
        // A box over clusters 62 to 66 (across the first two blocks), cut at x = 66.25.
        let got: Vec<LightBox> = c
            .within(DVec3::new(61.75, -1.0, 0.0), DVec3::new(66.25, 1.0, 10.0))
            .collect();
        assert_eq!(got.len(), 5);
        assert_eq!(
            got[0],
            (DVec3::new(62.0, -0.5, 5.0), DVec3::new(62.5, 0.0, 5.5))
        );
        assert_eq!(
            got[4],
            (DVec3::new(66.0, -0.5, 5.0), DVec3::new(66.25, 0.0, 5.5))
        );
        // The last, partial block, and nothing in front of the receivers.
        assert_eq!(c.within(DVec3::splat(-1e9), DVec3::splat(1e9)).count(), 200);
        assert_eq!(
            c.within(DVec3::new(0.0, 0.0, 0.0), DVec3::new(1e9, 1.0, 4.9))
                .count(),
            0
        );
    }

    /// Every fixture scene, by name.
    fn fixtures() -> Vec<(String, penumbra_geom::Scene)> {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scenes");
        let mut v: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "toml"))
            .map(|p| {
                let name = p.file_stem().unwrap().to_string_lossy().into_owned();
                (name, penumbra_geom::Scene::load(&p).unwrap())
            })
            .collect();
        v.sort_by(|a, b| a.0.cmp(&b.0));
        assert!(v.len() >= 13, "fixtures missing");
        v
    }

    /// Every pixel where an occluder's silhouette buffer can be non-zero (its stencil count is,
    /// or one of its wedges holds the receiver) lies in that occluder's screen tiles, which its
    /// blend covers and which no other occluder of its group shares.
    #[test]
    fn occluder_tiles_hold_every_pixel_their_silhouette_reaches() {
        use crate::frame_uniforms::eye_relative;
        use penumbra_volumes::CpuRenderer;
        for (name, scene) in fixtures() {
            let scene = scene.lit(0);
            let cpu = CpuRenderer::new(&scene);
            let world = scene.triangles();
            let camera =
                FrameCamera::for_scene(&scene.camera, &eye_relative(scene.camera.eye, &world));
            let (instances, ranges) = wedge_instances(&scene.light, &world, &cpu.volumes);
            let masks = occluder_tiles(
                &camera,
                &scene.light,
                &ReceiverClusters::new(&scene.light, &world),
                &nearest_edges(&cpu.volumes),
                &instances,
                &ranges,
            );
            let cam = &scene.camera;
            let (mut reached, mut tiles) = (0usize, 0usize);
            for j in 0..cam.height {
                for i in 0..cam.width {
                    let Some(p) = cpu.tracer.surface_point(cam.eye, cam.ray_dir(i, j)) else {
                        continue;
                    };
                    // Blending units (caster patches), as the stencil counts and wedges name
                    // them.
                    let mut units: Vec<u32> = cpu.stencil_counts(&p).iter().map(|c| c.0).collect();
                    units.extend(
                        cpu.wedges_containing(p.position)
                            .iter()
                            .map(|&w| cpu.volumes.wedges[w as usize].unit),
                    );
                    units.sort_unstable();
                    units.dedup();
                    for o in units {
                        assert!(
                            masks[o as usize].holds_pixel(i, j),
                            "{name}: pixel ({i}, {j}) is reached by unit {o} but not in its tiles"
                        );
                        reached += 1;
                    }
                }
            }
            for m in &masks {
                tiles += m.packed_tiles().len();
            }
            println!("{name:>18}: {reached} (pixel, occluder) pairs, {tiles} occluder tiles");
            assert!(reached > 0, "{name}: no shadow to check");
        }
    }
}
