//! Occlusion and closest-hit rays per second on one core, on `spheres-9x9` (61,562 triangles):
//! the shadow rays of the reference, from every camera pixel's surface point to 16 stratified
//! points of the light.
//!
//! Run with `cargo bench -p penumbra-geom --bench rays`; criterion's "thrpt" line is rays per
//! second on one core (the loop is single-threaded; the reference renderer runs one per core).

use std::path::PathBuf;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{DVec2, DVec3, Vec3A};
use penumbra_geom::{Rng, Scene, Tracer};

struct ShadowRay {
    origin: DVec3,
    dir: Vec3A,
    tmax: f32,
    exclude: u32,
}

fn setup() -> (Tracer, Scene, Vec<ShadowRay>) {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scenes/spheres-9x9.toml");
    let scene = Scene::load(&path).expect("fixture scene");
    let tracer = Tracer::new(&scene.lit(0));
    let cam = scene.camera;
    let mut rng = Rng::new(1);
    let mut rays = Vec::new();
    for j in 0..cam.height {
        for i in 0..cam.width {
            let Some(p) = tracer.surface_point(cam.eye, cam.ray_dir(i, j)) else {
                continue;
            };
            if !scene.lit(0).light.is_lit_side(p.position) {
                continue;
            }
            for s in 0..16 {
                let uv = DVec2::new(
                    -1.0 + ((s % 4) as f64 + rng.next_f64()) * 0.5,
                    -1.0 + ((s / 4) as f64 + rng.next_f64()) * 0.5,
                );
                let d = scene.lit(0).light.point(uv) - p.position;
                let len = d.length();
                rays.push(ShadowRay {
                    origin: p.position,
                    dir: (d / len).as_vec3().into(),
                    tmax: (len - tracer.epsilon) as f32,
                    exclude: p.triangle,
                });
            }
        }
    }
    (tracer, scene, rays)
}

fn bench(c: &mut Criterion) {
    let (tracer, scene, rays) = setup();
    let eps = tracer.epsilon as f32;
    // Every k-th ray, so the batch spans the whole image rather than its first rows.
    let stride = rays.len().div_ceil(200_000);
    let batch: Vec<&ShadowRay> = rays.iter().step_by(stride).collect();
    let blocked = batch
        .iter()
        .filter(|r| {
            tracer
                .hierarchy()
                .occluded(r.origin, r.dir, eps, r.tmax, r.exclude)
        })
        .count();
    println!(
        "spheres-9x9: {} triangles, {} shadow rays in the batch (of {}), {:.1}% blocked",
        tracer.triangles.len(),
        batch.len(),
        rays.len(),
        100.0 * blocked as f64 / batch.len() as f64
    );
    let mut g = c.benchmark_group("spheres-9x9");
    g.sample_size(10);
    g.throughput(Throughput::Elements(batch.len() as u64));
    g.bench_function("occlusion rays, one core", |b| {
        b.iter(|| {
            batch
                .iter()
                .filter(|r| {
                    tracer
                        .hierarchy()
                        .occluded(r.origin, r.dir, eps, r.tmax, r.exclude)
                })
                .count()
        })
    });
    let cam = scene.camera;
    let dirs: Vec<_> = (0..cam.height)
        .flat_map(|j| (0..cam.width).map(move |i| (i, j)))
        .map(|(i, j)| cam.ray_dir(i, j))
        .collect();
    g.throughput(Throughput::Elements(dirs.len() as u64));
    g.bench_function("camera rays (closest hit), one core", |b| {
        b.iter(|| {
            dirs.iter()
                .filter(|d| tracer.surface_point(cam.eye, **d).is_some())
                .count()
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
