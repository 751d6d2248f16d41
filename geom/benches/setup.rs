//! Set-up time of the ray-casting BVH (`SceneBvh::build`) on the inputs that made obvhs' PLOC
//! builder quadratic: N coincident quads (as N `[[mesh]]` entries naming one quad give them, 2N
//! triangles, not deduplicated across meshes) and one convex N-gon (N - 2 slivers sharing its
//! first vertex, as tobj fan-triangulates it).
//!
//! Run with `cargo bench -p penumbra-geom --bench setup`; each line's "time" is one build, and
//! doubling N should a little more than double it (O(N log N)).

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::DVec3;
use penumbra_geom::SceneBvh;

fn coincident_quads(n: usize) -> Vec<[DVec3; 3]> {
    let p = [
        DVec3::new(-1., 1., -1.),
        DVec3::new(1., 1., -1.),
        DVec3::new(1., 1., 1.),
        DVec3::new(-1., 1., 1.),
    ];
    (0..n)
        .flat_map(|_| [[p[0], p[1], p[2]], [p[0], p[2], p[3]]])
        .collect()
}

fn fan(n: usize) -> Vec<[DVec3; 3]> {
    let ring: Vec<DVec3> = (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            DVec3::new(a.cos(), 1.0, a.sin())
        })
        .collect();
    (1..n - 1)
        .map(|i| [ring[0], ring[i], ring[i + 1]])
        .collect()
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("bvh set-up");
    g.sample_size(10);
    for n in [1000, 2000, 4000, 8000, 16000] {
        let tris = coincident_quads(n);
        g.bench_with_input(BenchmarkId::new("coincident quads", n), &tris, |b, t| {
            b.iter(|| SceneBvh::build(t))
        });
    }
    for n in [6250, 12500, 25000, 50000] {
        let tris = fan(n);
        g.bench_with_input(BenchmarkId::new("n-gon fan", n), &tris, |b, t| {
            b.iter(|| SceneBvh::build(t))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
