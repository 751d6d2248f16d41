//! A scene made in code, no files: a ground, a sphere and a tilted box under a square light.
//! Renders it exactly (`depth-complexity`) and with the penumbra wedges (`wedges-blend`), and
//! prints how far the wedges are from the exact image.
//!
//! `cargo run --release --example scene_in_code [OUT_DIR]` (default `out/`).

use std::path::PathBuf;

use penumbra::glam::{DMat4, DQuat, DVec2, DVec3};
use penumbra::{
    Backend, Camera, RectLight, RenderOptions, Renderer, Scene, Technique, TriangleMesh, compare,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args().nth(1).map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("out"),
        PathBuf::from,
    );
    let p = |x, y, z| DVec3::new(x, y, z);
    // The unit quad and the unit cube, placed by matrices: a 12 x 12 ground and a tilted box.
    let ground = TriangleMesh::quad().transformed(&DMat4::from_scale(DVec3::splat(12.0)));
    let cube = TriangleMesh::cube();
    let camera = Camera::look_at(p(0.0, 5.0, 7.0), p(0.0, 0.5, 0.0), DVec3::Y, 45.0, 320, 240)?;
    // A 2.5 x 2.5 lamp 6 above the ground, facing straight down.
    let light = RectLight::aimed(p(-1.0, 6.0, 0.5), p(-1.0, 0.0, 0.5), DVec2::splat(2.5))?;
    let scene = Scene::new(camera)
        .with_light(light)
        .with_mesh("ground", &ground, DMat4::IDENTITY)
        .with_mesh(
            "sphere",
            &TriangleMesh::uv_sphere(20, 24),
            DMat4::from_scale_rotation_translation(
                DVec3::splat(0.8),
                DQuat::IDENTITY,
                p(-0.8, 1.2, 0.0),
            ),
        )
        .with_mesh(
            "box",
            &cube,
            DMat4::from_rotation_translation(
                DQuat::from_axis_angle(DVec3::new(1.0, 1.0, 0.0).normalize(), 0.6),
                p(1.0, 1.0, 0.6),
            ),
        );

    let mut renderer = Renderer::new(Backend::Auto);
    let exact = renderer.render(
        &scene,
        Technique::DepthComplexity,
        &RenderOptions::default(),
    )?;
    let wedges = renderer.render(&scene, Technique::WedgesBlend, &RenderOptions::default())?;
    std::fs::create_dir_all(&out)?;
    exact.write_png(&out.join("scene_in_code-depth-complexity.png"))?;
    wedges.write_png(&out.join("scene_in_code-wedges-blend.png"))?;
    let c = compare(&wedges, &exact)?;
    println!(
        "{} triangles; wedges-blend against depth-complexity: mean absolute error {:.4} over all pixels, {:.4} over the {} penumbra pixels; images in {}",
        scene.triangle_count(),
        c.all.mae,
        c.penumbra.mae,
        c.penumbra.pixels,
        out.display()
    );
    Ok(())
}
