//! Helpers shared by the workspace tests.

use std::path::PathBuf;

use penumbra::geom::{LitScene, Scene};
use penumbra::{Backend, Renderer, Technique};

/// Path of a fixture scene by name.
pub fn scene_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures/scenes")
        .join(format!("{name}.toml"))
}

/// Loads a fixture scene, panicking with the loader's message.
pub fn load(name: &str) -> Scene {
    Scene::load(&scene_path(name)).unwrap_or_else(|e| panic!("{e}"))
}

/// A fixture scene under its first light, as the renderers render it ([`Scene::lit`]).
pub fn load_lit(name: &str) -> LitScene {
    load(name).lit(0)
}

/// Every fixture scene's name, from the folder (so a new fixture is tested without a list to
/// keep up to date). Fails if the folder is empty. A scene of several lights (`two-lights`) is
/// rendered under its first, [`Scene::lit`], by the tests that take every fixture;
/// `several_lights.rs` checks that each light's channel is the scene under that light alone.
pub fn fixture_names() -> Vec<String> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/scenes");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "toml")
                .then(|| p.file_stem().unwrap().to_string_lossy().into_owned())
        })
        .collect();
    names.sort();
    assert!(
        names.len() >= 7,
        "expected the seven fixtures, found {names:?}"
    );
    names
}

/// How many pixels of two images of one size differ, bit for bit.
pub fn differing_pixels(a: &[f32], b: &[f32]) -> usize {
    assert_eq!(a.len(), b.len(), "images of different sizes");
    a.iter()
        .zip(b)
        .filter(|(x, y)| x.to_bits() != y.to_bits())
        .count()
}

/// A renderer on the GPU, or none where there is no adapter outside CI (said on the test's
/// output, for the test to skip its GPU part); CI must have one (Mesa's lavapipe).
pub fn gpu_renderer() -> Option<Renderer> {
    let mut gpu = Renderer::new(Backend::Gpu);
    match gpu.uses_gpu(Technique::Hard) {
        Ok(_) => Some(gpu),
        Err(e) => {
            assert!(std::env::var_os("CI").is_none(), "CI needs a GPU: {e}");
            println!("SKIPPED (no GPU): {e}");
            None
        }
    }
}
