//! What the GPU test files share: the adapter and the fixtures.

use std::path::PathBuf;

use penumbra_geom::Scene;
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
