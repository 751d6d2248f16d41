//! What the GPU test files share: the adapter, the fixtures and scenes made in code.

use std::path::PathBuf;

use glam::DVec3;
use penumbra_geom::{Scene, TriangleMesh};
use penumbra_gpu::GpuContext;

/// The adapter: in CI Mesa's lavapipe, and a missing one fails the run when `CI` is set; on a
/// developer's machine without one the tests print a skip.
pub fn context() -> Option<GpuContext> {
    match GpuContext::new() {
        Ok(c) => {
            println!("adapter: {}", c.describe());
            Some(c)
        }
        Err(e) if std::env::var_os("CI").is_some() => panic!("CI needs a GPU adapter: {e}"),
        Err(e) => {
            println!("SKIPPED (no adapter): {e}");
            None
        }
    }
}

/// Every fixture scene, by name.
#[allow(dead_code)] // Not every test file that shares this module uses it.
pub fn fixtures() -> Vec<(String, Scene)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scenes");
    let mut v: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| {
            let name = p.file_stem().unwrap().to_string_lossy().into_owned();
            (name, Scene::load(&p).unwrap())
        })
        .collect();
    v.sort_by(|a, b| a.0.cmp(&b.0));
    assert!(v.len() >= 13, "fixtures missing");
    v
}

/// The view of all of `texture`.
#[allow(dead_code)] // Not every test file that shares this module uses it.
pub fn view(texture: &penumbra_gpu::wgpu::Texture) -> penumbra_gpu::wgpu::TextureView {
    texture.create_view(&Default::default())
}

/// A 2D texture of `size` texels, one mip level, one sample.
#[allow(dead_code)] // Not every test file that shares this module uses it.
pub fn texture(
    device: &penumbra_gpu::wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
    format: penumbra_gpu::wgpu::TextureFormat,
    usage: penumbra_gpu::wgpu::TextureUsages,
) -> penumbra_gpu::wgpu::Texture {
    use penumbra_gpu::wgpu;
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// How far the GPU's depth-complexity image `gpu` is from the oracle's `cpu` at light samples
/// of weight `step`: the share of equal pixels, and the pixels more than one sample apart.
#[allow(dead_code)] // Not every test file that shares this module uses it.
pub fn agreement(
    cpu: &penumbra_geom::VisibilityImage,
    gpu: &penumbra_geom::VisibilityImage,
    step: f32,
) -> (f64, usize) {
    let pairs = || cpu.data.iter().zip(&gpu.data);
    let equal = pairs().filter(|(a, b)| a == b).count();
    let beyond = pairs()
        .filter(|(a, b)| (*a - *b).abs() > 1.5 * step)
        .count();
    (equal as f64 / cpu.data.len() as f64, beyond)
}

/// One scene rendered by depth complexity on the GPU and by the CPU oracle, at 64 and at 256
/// multi-jittered samples: `(samples, oracle, GPU render)` for each.
#[allow(dead_code)] // Not every test file that shares this module uses it.
pub fn against_the_oracle(
    r: &penumbra_gpu::GpuRenderer,
    name: &str,
    scene: &penumbra_geom::LitScene,
) -> Vec<(
    usize,
    penumbra_geom::VisibilityImage,
    penumbra_gpu::ComplexityImage,
)> {
    let oracle = penumbra_volumes::DepthComplexity::new(scene);
    [8usize, 16]
        .into_iter()
        .map(|per_axis| {
            let samples = per_axis * per_axis;
            let pattern = penumbra_volumes::SamplePattern {
                per_axis,
                jitter: false,
            };
            let cpu = oracle.render(pattern, &|_| {});
            let gpu = r
                .render_depth_complexity(scene, samples as u32)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(gpu.potential_edges, oracle.edges.edges.len(), "{name}");
            (samples, cpu, gpu)
        })
        .collect()
}

/// A closed L-shaped room of height `h`, wound outwards: the outline (0, 0) (4, 0) (4, 2)
/// (2, 2) (2, 4) (0, 4) of its floor (x, z) extruded along y.
#[allow(dead_code)] // Not every test file that shares this module uses it.
pub fn l_shaped_room(h: f64) -> TriangleMesh {
    let outline = [
        (0.0, 0.0),
        (4.0, 0.0),
        (4.0, 2.0),
        (2.0, 2.0),
        (2.0, 4.0),
        (0.0, 4.0),
    ];
    let n = outline.len() as u32;
    let mut positions: Vec<DVec3> = outline
        .iter()
        .map(|&(x, z)| DVec3::new(x, 0.0, z))
        .collect();
    positions.extend(outline.iter().map(|&(x, z)| DVec3::new(x, h, z)));
    // Floor and ceiling fanned from the inner corner (vertex 3), then the walls.
    let mut triangles = Vec::new();
    for k in [4u32, 5, 0, 1] {
        let next = (k + 1) % n;
        triangles.push([3, k, next]);
        triangles.push([n + 3, n + next, n + k]);
    }
    for k in 0..n {
        let next = (k + 1) % n;
        triangles.push([k, next + n, next]);
        triangles.push([k, k + n, next + n]);
    }
    TriangleMesh::from_raw("room", &positions, &triangles).unwrap()
}
