//! Silhouette + shadow volume + wedge construction on closed meshes of about 10k, 100k and 1M
//! triangles, against the memory-bandwidth floor: copying the same input bytes (positions,
//! faces, half-edges and edge lists) once.
//!
//! `cargo bench -p penumbra-volumes --bench construction`; the ratio is printed after each size.

use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::{DVec2, DVec3};
use penumbra_geom::{HalfEdgeMesh, RectLight, TriangleMesh};
use penumbra_volumes::ShadowVolume;
use penumbra_volumes::Silhouette;
use penumbra_volumes::Wedge;

/// A closed UV sphere with `2 * slices * (stacks - 1)` triangles, bumped so that its
/// silhouette is long and ragged like a real model's.
fn sphere(stacks: u32, slices: u32) -> TriangleMesh {
    let mut m = TriangleMesh::uv_sphere(stacks, slices);
    for p in &mut m.positions {
        let (th, ph) = (p.y.clamp(-1.0, 1.0).acos(), (-p.z).atan2(p.x));
        *p *= 1.0 + 0.05 * ((7.0 * ph).sin() * (5.0 * th).cos());
    }
    m
}

/// Builds what a frame needs when the light moves: silhouette, volume and wedges.
fn construct(mesh: &HalfEdgeMesh, light: &RectLight) -> (usize, usize) {
    let sil = Silhouette::build(mesh, light.center);
    let vol = ShadowVolume::build(mesh, &sil, light.center);
    let wedges: Vec<Wedge> = sil
        .edges
        .iter()
        .map(|e| Wedge {
            from: light.to_light_space(mesh.positions[e.from as usize]),
            to: light.to_light_space(mesh.positions[e.to as usize]),
            multiplicity: e.multiplicity,
            occluder: 0,
            silhouette_loop: 0,
            unit: 0,
            caster: None,
        })
        .collect();
    (vol.triangles.len(), wedges.len())
}

/// Bytes of the structure the construction reads.
fn input_bytes(m: &HalfEdgeMesh) -> usize {
    m.positions.len() * 24
        + m.faces.len() * 12
        + m.half_edges.len() * std::mem::size_of::<penumbra_geom::HalfEdge>()
        + m.edges
            .iter()
            .map(|e| 12 + 4 * e.half_edges.len())
            .sum::<usize>()
}

fn bench(c: &mut Criterion) {
    let light = RectLight::new(
        DVec3::new(0.3, 6.0, 0.2),
        DVec3::NEG_Y,
        DVec3::X,
        DVec2::new(2.0, 2.0),
    )
    .unwrap();
    let mut g = c.benchmark_group("construction");
    g.sample_size(10);
    for (label, stacks, slices) in [("10k", 50u32, 100u32), ("100k", 224, 224), ("1M", 708, 708)] {
        let mesh = HalfEdgeMesh::build(&sphere(stacks, slices));
        let bytes = input_bytes(&mesh);
        let input = vec![1u8; bytes];
        let mut copy = vec![0u8; bytes];
        let (vt, w) = construct(&mesh, &light);
        println!(
            "{label}: {} triangles, {} silhouette edges, {vt} volume triangles, {:.1} MB of input",
            mesh.faces.len(),
            w,
            bytes as f64 / 1e6
        );
        g.bench_function(
            format!("{label} triangles: silhouette + volume + wedges"),
            |b| b.iter(|| construct(black_box(&mesh), black_box(&light))),
        );
        g.bench_function(format!("{label} triangles: copy of the input bytes"), |b| {
            b.iter(|| {
                copy.copy_from_slice(black_box(&input));
                black_box(&copy);
            })
        });
        // The ratio from a quick direct measurement (criterion prints the careful numbers).
        let time = |f: &mut dyn FnMut()| {
            let t = Instant::now();
            for _ in 0..5 {
                f();
            }
            t.elapsed().as_secs_f64() / 5.0
        };
        let tc = time(&mut || {
            black_box(construct(&mesh, &light));
        });
        let tf = time(&mut || {
            copy.copy_from_slice(&input);
            black_box(&copy);
        });
        println!(
            "{label}: construction {:.2} ms, copy {:.2} ms, ratio {:.1}x",
            tc * 1e3,
            tf * 1e3,
            tc / tf
        );
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
