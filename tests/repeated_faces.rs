//! A face listed twice, or a sheet listed once per winding: both copies cast one shadow, and the
//! wedge techniques draw it once (each copy's silhouette once blended as a second occluder).

use glam::{DMat4, DVec2, DVec3};
use penumbra::Technique;
use penumbra::geom::Camera;
use penumbra::geom::compare;
use penumbra::geom::{LightSamples, Reference};
use penumbra::geom::{RectLight, Scene, TriangleMesh};
use penumbra::volumes::CpuRenderer;

#[test]
fn repeated_faces_cast_one_shadow() {
    let c = DVec3::new;
    let ground = penumbra_testkit::square(0.0, 2.0);
    let corners = [
        c(-0.5, 1., -0.5),
        c(-0.5, 1., 0.5),
        c(0.5, 1., 0.5),
        c(0.5, 1., -0.5),
    ];
    let once = [[0, 1, 2], [0, 2, 3]];
    let twice = [[0, 1, 2], [0, 2, 3], [0, 1, 2], [0, 2, 3]];
    let both_sides = [[0, 1, 2], [0, 2, 3], [2, 1, 0], [3, 2, 0]];
    // The back split along the other diagonal: no face repeats, and the sheet's two sides meet
    // only at its outline, where each edge folds by half a turn.
    let other_diagonal = [[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]];
    let camera = Camera::look_at(c(0., 3., 4.), DVec3::ZERO, DVec3::Y, 45.0, 48, 32).unwrap();
    let light = RectLight::new(c(0., 4., 0.), -DVec3::Y, DVec3::X, DVec2::ONE).unwrap();
    let scene = |faces: &[[u32; 3]]| {
        let quad = TriangleMesh::from_raw("quad", &corners, faces).unwrap();
        Scene::new(camera)
            .with_light(light)
            .with_mesh("ground", &ground, DMat4::IDENTITY)
            .with_mesh("quad", &quad, DMat4::IDENTITY)
    };
    let single = scene(&once);
    let want: Vec<_> = [Technique::Wedges, Technique::WedgesBlend]
        .map(|t| CpuRenderer::new(&single.lit(0)).render(t, &|_| {}))
        .into();
    for (what, faces, dropped) in [
        ("twice", &twice[..], 2),
        ("both windings", &both_sides[..], 2),
        ("both windings, other diagonal", &other_diagonal[..], 0),
    ] {
        let s = scene(faces);
        assert_eq!(s.meshes[1].mesh.dropped_duplicate, dropped, "{what}");
        assert_eq!(s.meshes[1].mesh.triangles.len(), 4 - dropped, "{what}");
        let truth =
            Reference::new(&s.lit(0)).render(LightSamples::Stratified { per_axis: 16 }, &|_| {});
        for (i, t) in [Technique::Wedges, Technique::WedgesBlend]
            .into_iter()
            .enumerate()
        {
            let img = CpuRenderer::new(&s.lit(0)).render(t, &|_| {});
            if dropped > 0 {
                assert_eq!(
                    img, want[i],
                    "{what} {t}: not the image of the quad listed once"
                );
            } else {
                let d = compare(&img, &want[i]).unwrap();
                assert!(
                    d.all.max < 1e-6,
                    "{what} {t}: {} from the image of the quad listed once",
                    d.all.max
                );
            }
            let m = compare(&img, &truth).unwrap();
            assert!(m.all.max < 0.05, "{what} {t}: max error {}", m.all.max);
        }
    }
}
