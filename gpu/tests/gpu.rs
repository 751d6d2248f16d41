//! GPU tests. They need an adapter: in CI that is Mesa's lavapipe, and a missing adapter fails
//! the run when `CI` is set; on a developer's machine without one they print a skip.

mod common;
use common::{context, fixtures, l_shaped_room};

use penumbra_geom::{LightSamples, Reference, Scene, Technique, compare};
use penumbra_gpu::{
    GpuRenderer, LightFrustum, ShadowMapRenderer, ShadowUniforms, WedgePass, multi_pass_kernel,
};
use penumbra_params::{MdsmExtra, fractional_disk_samples};
use penumbra_volumes::{CpuRenderer, Volumes};

/// Whether every mesh of `scene` is one of the generated fixture meshes (spheres, quads, the
/// three-page book), not a real mesh.
fn generated(scene: &Scene) -> bool {
    scene.meshes.iter().all(|m| {
        ["sphere.obj", "quad.obj", "book.obj"]
            .iter()
            .any(|g| m.source.ends_with(g))
    })
}

#[test]
fn gpu_hard_matches_the_hard_reference() {
    let Some(ctx) = context() else { return };
    let r = GpuRenderer::with_context(&ctx);
    for (name, scene) in fixtures() {
        let volumes = Volumes::build(&scene.lit(0));
        let img = r.render(&scene.lit(0), &volumes, Technique::Hard).unwrap();
        let want = Reference::new(&scene.lit(0)).render(LightSamples::Centre, &|_| {});
        let differ = img
            .data
            .iter()
            .zip(&want.data)
            .filter(|(a, b)| a != b)
            .count();
        let share = differ as f64 / img.data.len() as f64;
        println!(
            "{name:>18}: GPU hard differs from the hard reference on {differ} pixels ({:.3}%)",
            100.0 * share
        );
        if share > 0.005 {
            let dir = std::env::temp_dir();
            let _ = img.write_exr(&dir.join(format!("{name}-gpu-hard-actual.exr")));
        }
        assert!(share <= 0.005, "{name}: {differ} pixels differ");
    }
}

#[test]
fn gpu_wedges_match_the_cpu_oracle() {
    gpu_matches_cpu(Technique::Wedges);
}

#[test]
fn gpu_wedges_blend_matches_the_cpu_oracle() {
    gpu_matches_cpu(Technique::WedgesBlend);
}

#[test]
fn tiled_wedges_equal_the_rasterised_ones_and_the_cpu_oracle() {
    let Some(ctx) = context() else { return };
    let mut r = GpuRenderer::with_context(&ctx);
    for (name, scene) in fixtures() {
        let [tiled, rasterised] = tiled_and_rasterised(&mut r, &scene, Technique::Wedges);
        let c = compare(&tiled, &rasterised).unwrap();
        let cpu = CpuRenderer::new(&scene.lit(0)).render(Technique::Wedges, &|_| {});
        let (t, r) = (
            compare(&tiled, &cpu).unwrap(),
            compare(&rasterised, &cpu).unwrap(),
        );
        println!(
            "{name:>18}: tiled against rasterised: {:.4}% of pixels differ, max {:.2e}; \
             against the CPU: MAE {:.3e} tiled, {:.3e} rasterised",
            100.0 * (1.0 - c.all.equal),
            c.all.max,
            t.all.mae,
            r.all.mae
        );
        // The same integrals added in the same order (the wedges'): the same bits, but where a
        // receiver within rounding of a solid's face is in one pass's solid and not the
        // other's (2 pixels of `fence`, by 7e-4).
        assert!(c.all.equal >= 0.9999 && c.all.max <= 1e-3, "{name}: {c:?}");
        assert!(
            t.all.mae <= r.all.mae * 1.001 + 1e-9,
            "{name}: {t:?} against {r:?}"
        );
        assert!(t.all.mae <= 1e-3 && t.all.p99 <= 0.02, "{name}: {t:?}");
    }
}

/// `scene` rendered with `technique` by the tiled pass and by the rasterised one.
fn tiled_and_rasterised(
    r: &mut GpuRenderer,
    scene: &Scene,
    technique: Technique,
) -> [penumbra_geom::VisibilityImage; 2] {
    let volumes = Volumes::build(&scene.lit(0));
    [WedgePass::Tiled, WedgePass::Rasterised].map(|pass| {
        r.set_wedge_pass(Some(pass));
        r.render(&scene.lit(0), &volumes, technique).unwrap()
    })
}

fn gpu_matches_cpu(t: Technique) {
    let Some(ctx) = context() else { return };
    let r = GpuRenderer::with_context(&ctx);
    for (name, scene) in fixtures() {
        let volumes = Volumes::build(&scene.lit(0));
        let gpu = r.render(&scene.lit(0), &volumes, t).unwrap();
        let cpu = CpuRenderer::new(&scene.lit(0)).render(t, &|_| {});
        let c = compare(&gpu, &cpu).unwrap();
        println!(
            "{name:>18}: GPU {t:?} vs CPU: MAE {:.2e}, p99 {:.2e}, max {:.2e}; penumbra MAE {:.2e}",
            c.all.mae, c.all.p99, c.all.max, c.penumbra.mae
        );
        if c.all.mae > 1e-3 || c.all.p99 > 0.02 {
            let dir = std::env::temp_dir();
            let _ = gpu.write_exr(&dir.join(format!("{name}-gpu-{t:?}-actual.exr")));
        }
        assert!(c.all.mae <= 1e-3, "{name}: MAE {}", c.all.mae);
        assert!(c.all.p99 <= 0.02, "{name}: p99 {}", c.all.p99);
    }
}

const SHADOW_MAP_TECHNIQUES: [Technique; 5] = [
    Technique::Pcf,
    Technique::Pcss,
    Technique::FractionalDisk,
    Technique::Mdsm,
    Technique::Gaussian,
];

/// Pixels whose whole `radius`-pixel square neighbourhood has reference value `v`.
fn settled(reference: &penumbra_geom::VisibilityImage, v: f32, radius: i64) -> Vec<usize> {
    let (w, h) = (reference.width as i64, reference.height as i64);
    let at = |x: i64, y: i64| reference.data[(y.clamp(0, h - 1) * w + x.clamp(0, w - 1)) as usize];
    (0..w * h)
        .filter(|&i| {
            let (x, y) = (i % w, i / w);
            (-radius..=radius).all(|dy| (-radius..=radius).all(|dx| at(x + dx, y + dy) == v))
        })
        .map(|i| i as usize)
        .collect()
}

/// How far, in pixels, a technique's screen-space filter reaches: `gaussian` blurs the hard
/// shadow in screen space, by its passes' half kernels together; the others filter in the light
/// map and reach no other pixel.
fn screen_reach(t: Technique, p: &penumbra_params::TechniqueParams) -> i64 {
    use penumbra_params::GaussianVariant;
    let g = &p.gaussian;
    match (t, g.variant) {
        (Technique::Gaussian, GaussianVariant::Multi) => (0..g.passes)
            .map(|k| (multi_pass_kernel(k, g.max_kernel) as i64 - 1) / 2)
            .sum(),
        (Technique::Gaussian, _) => (g.max_kernel as i64 - 1) / 2,
        _ => 0,
    }
}

/// How deep in an umbra, in pixels, V must be exactly 0.
const DEEP: i64 = 12;

/// Issue 5: every shadow-map technique renders every fixture (a 512² light map keeps CI short),
/// every pixel in [0, 1]; V = 1 on receivers far from every occluder and V = 0 deep in an umbra:
/// pixels whose neighbourhood the 64-sample reference sees wholly lit (within 4 pixels; at most
/// 0.5% may differ, see below), resp. wholly dark (within `DEEP` pixels plus the technique's
/// screen-space reach: `gaussian` blurs the inside of the hard shadow by up to that many pixels).
#[test]
fn shadow_map_techniques_render_every_fixture_lit_far_away_and_dark_in_umbrae() {
    let Some(ctx) = context() else { return };
    let renderers: Vec<_> = SHADOW_MAP_TECHNIQUES
        .iter()
        .map(|&t| ShadowMapRenderer::new(&ctx, t))
        .collect();
    let mut umbra_pixels = std::collections::BTreeMap::new();
    let mut failures = Vec::new();
    // The real-mesh fixtures are measured in docs/accuracy.md, not bounded here: on them the
    // shadow maps do not hold these bounds yet (`mdsm` and `pcf` shadow far-lit ground, `pcss`
    // and `fractional-disk` light umbra pixels on beetle).
    for (name, mut scene) in fixtures().into_iter().filter(|(_, s)| generated(s)) {
        scene.params.shadow_map.resolution = 512;
        let truth =
            Reference::new(&scene.lit(0)).render(LightSamples::Stratified { per_axis: 8 }, &|_| {});
        let lit = settled(&truth, 1.0, 4);
        assert!(lit.len() > 1000, "{name}: {} lit test pixels", lit.len());
        for r in &renderers {
            let t = r.technique();
            let dark = settled(&truth, 0.0, DEEP + screen_reach(t, &scene.params));
            *umbra_pixels.entry(format!("{t:?}")).or_insert(0) += dark.len();
            let img = r
                .render(&scene.lit(0))
                .unwrap_or_else(|e| panic!("{name}: {t:?}: {e}"));
            check_settled(
                &format!("{name}: {t:?}"),
                &img,
                &truth,
                &lit,
                &dark,
                &mut failures,
            );
        }
    }
    for (t, n) in umbra_pixels {
        assert!(n > 1000, "{t}: only {n} umbra test pixels in all fixtures");
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The checks of one shadow-map render: every value in [0, 1] (a panic otherwise); V = 1 on the
/// far-lit pixels `lit` and V = 0 on the umbra pixels `dark`, failures pushed to `failures`.
fn check_settled(
    label: &str,
    img: &penumbra_geom::VisibilityImage,
    truth: &penumbra_geom::VisibilityImage,
    lit: &[usize],
    dark: &[usize],
    failures: &mut Vec<String>,
) {
    assert_eq!(img.data.len(), truth.data.len());
    assert!(
        img.data.iter().all(|v| (0.0..=1.0).contains(v)),
        "{label} has a value outside [0, 1]"
    );
    let wrong_lit = lit.iter().filter(|&&i| img.data[i] != 1.0).count();
    let wrong_dark = dark.iter().filter(|&&i| img.data[i] != 0.0).count();
    let c = compare(img, truth).unwrap();
    println!(
        "{label:>36}: MAE {:.4}, penumbra MAE {:.4}; V != 1 on {wrong_lit} of {} far-lit px, V != 0 on {wrong_dark} of {} umbra px",
        c.all.mae,
        c.penumbra.mae,
        lit.len(),
        dark.len()
    );
    if wrong_lit > 0 || wrong_dark > 0 {
        let file = label.replace([':', ' ', ',', '='], "_");
        let _ = img.write_exr(&std::env::temp_dir().join(format!("{file}-actual.exr")));
    }
    // A reference-lit neighbourhood is not always far from occluders: at a crease (the
    // non-manifold book's spine) the other face is a texel away in the light map, and a shadow
    // map filter takes it in. So up to 0.5% of the lit pixels may differ; every other fixture
    // has none.
    if wrong_lit as f64 > 0.005 * lit.len() as f64 {
        failures.push(format!("{label} shadows {wrong_lit} far-lit pixels"));
    }
    if wrong_dark > 0 {
        failures.push(format!("{label} lights {wrong_dark} umbra pixels"));
    }
}

/// Every option of the shadow-map techniques keeps far-lit pixels lit and umbrae dark, as the
/// defaults do (`shadow_map_techniques_render_every_fixture_lit_far_away_and_dark_in_umbrae`),
/// on three fixtures.
#[test]
fn shadow_map_options_keep_far_lit_pixels_lit_and_umbrae_dark() {
    use Technique::{FractionalDisk, Gaussian, Mdsm, Pcf, Pcss};
    use penumbra_params::{GaussianVariant, TechniqueParams};
    let Some(ctx) = context() else { return };
    type Option = (Technique, &'static str, fn(&mut TechniqueParams));
    let options: [Option; 11] = [
        (Pcf, "kernel 4", |p| p.pcf.kernel = 4),
        (Pcf, "kernel 5", |p| p.pcf.kernel = 5),
        (Pcss, "dithered 4 of 16", |p| p.pcss.dither = true),
        (FractionalDisk, "the re-test", |p| {
            p.fractional_disk.retest = true
        }),
        (Mdsm, "n = 1", |p| p.mdsm.depths = 1),
        (Mdsm, "2-SM max, k = 16", |p| {
            p.mdsm.depths = 2;
            p.mdsm.kernel = 4;
        }),
        (Mdsm, "2-SM min, k = 4", |p| {
            p.mdsm.depths = 2;
            p.mdsm.kernel = 2;
            p.mdsm.extra = MdsmExtra::Min;
        }),
        (Gaussian, "pcf", |p| {
            p.gaussian.variant = GaussianVariant::Pcf
        }),
        (Gaussian, "single", |p| {
            p.gaussian.variant = GaussianVariant::Single
        }),
        (Gaussian, "multi, dilation 9", |p| p.gaussian.dilation = 9),
        (Gaussian, "multi, 3 passes of 7 taps", |p| {
            p.gaussian.passes = 3;
            p.gaussian.taps = 7;
        }),
    ];
    let mut failures = Vec::new();
    let mut umbra_pixels = vec![0; options.len()];
    for (name, scene) in fixtures().into_iter().filter(|(n, _)| {
        ["camera-in-shadow", "overlapping-quads", "sphere-over-plane"].contains(&n.as_str())
    }) {
        let truth =
            Reference::new(&scene.lit(0)).render(LightSamples::Stratified { per_axis: 8 }, &|_| {});
        for (k, (t, label, set)) in options.iter().enumerate() {
            let mut scene = scene.clone();
            scene.params.shadow_map.resolution = 512;
            set(&mut scene.params);
            scene.params.validate().unwrap();
            // Dilation spreads D, and so the blur, onto lit pixels next to the hard shadow.
            let g = &scene.params.gaussian;
            let spread = if *t == Gaussian && g.dilation > 0 {
                (g.dilation as i64 - 1) / 2 + screen_reach(*t, &scene.params)
            } else {
                0
            };
            let lit = settled(&truth, 1.0, 4 + spread);
            let dark = settled(&truth, 0.0, DEEP + screen_reach(*t, &scene.params));
            umbra_pixels[k] += dark.len();
            let img = ShadowMapRenderer::new(&ctx, *t)
                .render(&scene.lit(0))
                .unwrap();
            check_settled(
                &format!("{name}: {t:?} {label}"),
                &img,
                &truth,
                &lit,
                &dark,
                &mut failures,
            );
        }
    }
    for (k, n) in umbra_pixels.iter().enumerate() {
        assert!(
            *n > 100,
            "{:?} {}: only {n} umbra test pixels",
            options[k].0,
            options[k].1
        );
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Uniforms of `r`'s technique for a probe over a `size`-texel square map.
fn probe_uniforms(r: &ShadowMapRenderer, size: u32) -> ShadowUniforms {
    let (_, scene) = fixtures().swap_remove(0);
    let frustum = LightFrustum::fit(&scene.lit(0).light, &scene.triangles()).unwrap();
    let mut u = r.uniforms(&scene.lit(0), &frustum);
    u.map = [size as f32, size as f32, 1.0, 0.0];
    u
}

/// Pagot et al. 2004, Table 1: PCF(k, n) of an n-depth map reaches n k + 1 distinct outcomes, on the
/// synthetic base map ((7x + 13y + 5xy) mod 17) / 17 and receiver depths (j + 0.5) / 17, for every
/// n (2-SM with either extra depth) and k = 4, 9, 16; a plain shadow map (n = 1) only k + 1.
#[test]
fn mdsm_pcf_reaches_n_k_plus_1_distinct_values() {
    let Some(ctx) = context() else { return };
    let r = ShadowMapRenderer::new(&ctx, Technique::Mdsm);
    const SIZE: u32 = 16;
    const LEVELS: u32 = 17;
    let map: Vec<f32> = (0..SIZE * SIZE)
        .map(|i| {
            let (x, y) = (i % SIZE, i / SIZE);
            ((7 * x + 13 * y + 5 * x * y) % LEVELS) as f32 / LEVELS as f32
        })
        .collect();
    for (n, extra) in [
        (1, MdsmExtra::Max),
        (2, MdsmExtra::Max),
        (2, MdsmExtra::Min),
        (3, MdsmExtra::Max),
    ] {
        for ks in [2u32, 3, 4] {
            let radius = 1;
            let mut u = probe_uniforms(&r, SIZE);
            u.iparams = [n, ks, radius, (extra == MdsmExtra::Max) as u32];
            u.params[1] = LEVELS as f32;
            let w = SIZE - ks - 2 * radius + 1;
            let out = r.probe("fs_probe", &u, &map, (w * w, LEVELS)).unwrap();
            let nk = (n * ks * ks) as f32;
            let mut values: Vec<u32> = out
                .iter()
                .map(|v| {
                    let s = v * nk;
                    assert!(
                        (s - s.round()).abs() < 1e-4,
                        "PCF {v} is not a multiple of 1/(nk)"
                    );
                    s.round() as u32
                })
                .collect();
            values.sort();
            values.dedup();
            let k = ks * ks;
            println!("PCF({k}, {n}) {extra:?}: {} distinct values", values.len());
            assert_eq!(
                values,
                (0..=n * k).collect::<Vec<_>>(),
                "PCF({k}, {n}) {extra:?}"
            );
        }
    }
}

/// Valient & de Boer 2004, Eq. 2 in the shader: f(q) = ceil(pi q^2 / a), capped, as the CPU's function.
#[test]
fn fractional_disk_sample_count_follows_eq_2() {
    let Some(ctx) = context() else { return };
    let r = ShadowMapRenderer::new(&ctx, Technique::FractionalDisk);
    let mut u = probe_uniforms(&r, 4);
    let (a, cap) = (2.0, 50);
    u.params[0] = a as f32;
    u.iparams[0] = cap;
    let out = r.probe("fs_probe_count", &u, &[0.0; 16], (80, 1)).unwrap();
    for (i, v) in out.iter().enumerate() {
        let q = i as f64 * 0.25;
        assert_eq!(*v as u32, fractional_disk_samples(q, a, cap), "f({q})");
    }
    // Fig. 2: q = 2 and 5 texels, a = 2.
    assert_eq!(out[8], 7.0);
    assert_eq!(out[20], 40.0);
    assert_eq!(out[79], 50.0);
}

#[test]
fn occluders_through_the_light_plane_match_the_cpu_oracle() {
    let Some(ctx) = context() else { return };
    let r = GpuRenderer::with_context(&ctx);
    let scene = penumbra_testkit::through_the_light();
    volume_techniques_match_the_oracle(&r, &scene, "through the light");
}

/// GPU `hard`, `wedges` and `wedges-blend` of `scene` against the CPU oracle: mean absolute
/// difference at most 1e-3, 99th percentile at most 0.02 (as on the fixtures).
fn volume_techniques_match_the_oracle(r: &GpuRenderer, scene: &penumbra_geom::Scene, name: &str) {
    let volumes = Volumes::build(&scene.lit(0));
    let cpu = CpuRenderer::new(&scene.lit(0));
    for t in [Technique::Hard, Technique::Wedges, Technique::WedgesBlend] {
        let img = r.render(&scene.lit(0), &volumes, t).unwrap();
        let want = cpu.render(t, &|_| {});
        let c = compare(&img, &want).unwrap();
        println!(
            "{name}: GPU {t} vs CPU: MAE {:.2e}, p99 {:.2e}",
            c.all.mae, c.all.p99
        );
        assert!(c.all.mae <= 1e-3 && c.all.p99 <= 0.02, "{name}: {t}: {c:?}");
    }
}

#[test]
fn random_scenes_match_the_cpu_oracle() {
    use glam::{DMat4, DQuat, DVec2, DVec3};
    use penumbra_geom::Camera;
    use penumbra_geom::{RectLight, Rng, TriangleMesh};
    let Some(ctx) = context() else { return };
    let r = GpuRenderer::with_context(&ctx);
    let mut rng = Rng::new(2026);
    let quad = TriangleMesh::quad();
    let sphere = TriangleMesh::uv_sphere(8, 12);
    let ground = quad.transformed(&DMat4::from_scale(DVec3::splat(12.0)));
    for case in 0..6 {
        let tilt = DQuat::from_axis_angle(
            DVec3::new(rng.range(-1., 1.), 0.0, rng.range(-1., 1.)).normalize(),
            rng.range(0.0, 40f64.to_radians()),
        );
        let normal = tilt * DVec3::NEG_Y;
        let light = RectLight::new(
            DVec3::new(rng.range(-1., 1.), rng.range(4., 6.), rng.range(-1., 1.)),
            normal,
            normal.any_orthonormal_vector(),
            DVec2::new(rng.range(0.5, 3.0), rng.range(0.5, 3.0)),
        )
        .unwrap();
        let eye = DVec3::new(rng.range(-4., 4.), rng.range(2., 5.), rng.range(3., 6.));
        let camera = Camera::look_at(eye, DVec3::ZERO, DVec3::Y, 45.0, 48, 36).unwrap();
        let mut scene = penumbra_geom::Scene::new(camera)
            .with_light(light)
            .with_mesh("ground", &ground, DMat4::IDENTITY);
        for k in 0..1 + rng.below(3) {
            let m = DMat4::from_scale_rotation_translation(
                DVec3::splat(rng.range(0.3, 1.2)),
                DQuat::from_axis_angle(
                    DVec3::new(rng.range(-1., 1.), 1.0, rng.range(-1., 1.)).normalize(),
                    rng.range(0.0, std::f64::consts::TAU),
                ),
                DVec3::new(
                    rng.range(-1.5, 1.5),
                    rng.range(0.8, 2.5),
                    rng.range(-1.5, 1.5),
                ),
            );
            let mesh = if rng.below(2) == 0 { &quad } else { &sphere };
            scene = scene.with_mesh(&format!("m{k}"), mesh, m);
        }
        volume_techniques_match_the_oracle(&r, &scene, &format!("random scene {case}"));
    }
}

/// Pixels where `img` and `truth` differ by more than a half while each of the pixel's eight
/// neighbours agrees within 0.05: one-pixel specks, which the image-wide tolerance hides.
fn isolated_specks(
    img: &penumbra_geom::VisibilityImage,
    truth: &penumbra_geom::VisibilityImage,
) -> Vec<(u32, u32)> {
    let (w, h) = (truth.width, truth.height);
    let diff = |x: u32, y: u32| (img.get(x, y) - truth.get(x, y)).abs();
    let mut specks = Vec::new();
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let quiet = (0..9)
                .filter(|k| *k != 4)
                .all(|k| diff(x + k % 3 - 1, y + k / 3 - 1) <= 0.05);
            if diff(x, y) > 0.5 && quiet {
                specks.push((x, y));
            }
        }
    }
    specks
}

/// The original: the example's scene, where pixel (191, 90) was shadowed (V = 0, the CPU 1).
/// The rasteriser snapped it onto two of the box's light caps that fold over at its outline, the
/// one seen from behind nearer: the ray left the box's volume before entering it, a stencil count
/// of -1, which read as 255.
#[test]
fn a_caster_outline_pixel_snapped_onto_folding_caps_is_not_shadowed() {
    let Some(ctx) = context() else { return };
    let r = GpuRenderer::with_context(&ctx);
    let scene = penumbra_testkit::scene_in_code();
    let volumes = Volumes::build(&scene.lit(0));
    let cpu = CpuRenderer::new(&scene.lit(0));
    for t in [Technique::Hard, Technique::Wedges, Technique::WedgesBlend] {
        let img = r.render(&scene.lit(0), &volumes, t).unwrap();
        let want = cpu.render(t, &|_| {});
        let c = compare(&img, &want).unwrap();
        assert!(c.all.mae <= 1e-3 && c.all.p99 <= 0.02, "{t}: {c:?}");
        let (got, exp) = (img.get(191, 90), want.get(191, 90));
        assert!(
            (got - exp).abs() <= 0.02,
            "{t}: V(191, 90) {got}, CPU {exp}"
        );
        assert_eq!(isolated_specks(&img, &want), [], "{t}");
    }
}

#[test]
fn an_edge_ending_at_the_receivers_depth_gives_a_clean_penumbra() {
    let Some(ctx) = context() else { return };
    let r = GpuRenderer::with_context(&ctx);
    // An L-shaped room seen from inside, its lamp flush with the ceiling in one arm: the inner
    // corner's wall shades the other arm, and its vertical edge ends on the floor, at the depth
    // of the floor's receivers, whose projection of it reaches infinity. Kept as a point a
    // million units out, that end's f32 rounding left the penumbra speckled (MAE 4.3e-3 against
    // the CPU, 3% of the pixels off by more than 0.05).
    let p = glam::DVec3::new;
    let camera = penumbra_geom::Camera::look_at(
        p(0.4, 2.6, 0.4),
        p(1.2, 0.0, 3.4),
        glam::DVec3::Y,
        68.75,
        96,
        72,
    )
    .unwrap();
    let lamp = penumbra_geom::RectLight::new(
        p(3.2, 3.0, 0.8),
        glam::DVec3::NEG_Y,
        glam::DVec3::X,
        glam::DVec2::splat(0.6),
    )
    .unwrap();
    let scene = Scene::new(camera).with_light(lamp).with_mesh(
        "room",
        &l_shaped_room(3.0),
        glam::DMat4::IDENTITY,
    );
    let lit = scene.lit(0);
    let volumes = Volumes::build(&lit);
    for t in [Technique::Wedges, Technique::WedgesBlend] {
        let gpu = r.render(&lit, &volumes, t).unwrap();
        let cpu = CpuRenderer::new(&lit).render(t, &|_| {});
        let c = compare(&gpu, &cpu).unwrap();
        let shaded = cpu.data.iter().filter(|&&v| v < 0.5).count();
        assert!(shaded > 300, "{t}: {shaded} shaded pixels");
        assert!(
            c.penumbra.mae <= 1e-4 && c.all.share_over == 0.0,
            "{t}: {c:?}"
        );
    }
}

#[test]
fn tiled_wedges_blend_matches_the_rasterised_passes_and_the_cpu_oracle() {
    let Some(ctx) = context() else { return };
    let mut r = GpuRenderer::with_context(&ctx);
    for (name, scene) in fixtures() {
        let [tiled, rasterised] = tiled_and_rasterised(&mut r, &scene, Technique::WedgesBlend);
        let c = compare(&tiled, &rasterised).unwrap();
        let cpu = CpuRenderer::new(&scene.lit(0)).render(Technique::WedgesBlend, &|_| {});
        let (t, r) = (
            compare(&tiled, &cpu).unwrap(),
            compare(&rasterised, &cpu).unwrap(),
        );
        println!(
            "{name:>18}: tiled against rasterised: {:.4}% of pixels differ, MAE {:.2e}, max {:.2e}; \
             against the CPU: MAE {:.3e} tiled, {:.3e} rasterised",
            100.0 * (1.0 - c.all.equal),
            c.all.mae,
            c.all.max,
            t.all.mae,
            r.all.mae
        );
        if c.all.mae > 1e-4 {
            let dir = std::env::temp_dir();
            let _ = tiled.write_exr(&dir.join(format!("{name}-tiled-blend.exr")));
            let _ = rasterised.write_exr(&dir.join(format!("{name}-rasterised-blend.exr")));
        }
        // The same counts but where rounding puts a receiver on the other side of a volume's
        // face or a wedge's solid (0.6% of the pixels of `spheres-9x9`, by 0.04 at most), and
        // blends in the units' order instead of the groups'.
        assert!(c.all.mae <= 1e-4 && c.all.p99 <= 1e-3, "{name}: {c:?}");
        assert!(t.all.mae <= 1e-3 && t.all.p99 <= 0.02, "{name}: {t:?}");
        assert!(
            t.all.mae <= 2.0 * r.all.mae + 1e-5,
            "{name}: {t:?} against {r:?}"
        );
    }
}
