//! Loads a scene file, renders its visibility image (one per light of a scene of several) and
//! writes it as EXR and PNG.
//!
//! `cargo run --release --example render_scene [SCENE] [TECHNIQUE] [OUT_DIR]`, by default
//! `fixtures/scenes/spot.toml`, `wedges-blend` and `out/`.

use std::path::PathBuf;

use penumbra::{Backend, RenderOptions, Renderer, Scene, Technique};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let scene_path = args
        .next()
        .map_or_else(|| root.join("fixtures/scenes/spot.toml"), PathBuf::from);
    let technique: Technique = args.next().as_deref().unwrap_or("wedges-blend").parse()?;
    let out = args.next().map_or_else(|| root.join("out"), PathBuf::from);

    let scene = Scene::load(&scene_path)?;
    // The GPU where there is one (Mesa's lavapipe counts), the CPU otherwise.
    let mut renderer = Renderer::new(Backend::Auto);
    // One image per light: the one channel `V`, or `<name>.V` for each light of `[[light]]`.
    let images = renderer.render_lights(&scene, technique, &RenderOptions::default())?;

    std::fs::create_dir_all(&out)?;
    let stem = scene_path.file_stem().unwrap_or_default().to_string_lossy();
    let exr = out.join(format!("{stem}-{technique}.exr"));
    images.write_exr(&exr)?;
    let device = renderer
        .gpu_description()
        .unwrap_or_else(|| "the CPU".to_string());
    for c in images.channels() {
        // `spot-wedges-blend.png`, or `two-lights-wedges-blend.key.png` per light.
        let light = c
            .name
            .strip_suffix(".V")
            .map(|l| format!(".{l}"))
            .unwrap_or_default();
        let png = out.join(format!("{stem}-{technique}{light}.png"));
        c.image.write_png(&png)?;
        let image = &c.image;
        let lit = image.data.iter().filter(|&&v| v == 1.0).count();
        println!(
            "{technique} on {device}, channel {}: {}x{} px, {:.1}% wholly lit, mean V {:.3} -> {} and {}",
            c.name,
            image.width,
            image.height,
            100.0 * lit as f64 / image.data.len() as f64,
            image.data.iter().map(|&v| v as f64).sum::<f64>() / image.data.len() as f64,
            exr.display(),
            png.display()
        );
    }
    Ok(())
}
