//! `penumbra probe`: the surface point seen through one pixel and its visibility by the exact evaluator, the reference and depth-complexity sampling; of each light in turn in a scene of several.

use std::path::Path;

use anyhow::{Context, Result, bail};
use penumbra::geom::{REFERENCE_SEED, Rays, Rng, Tracer};
use penumbra::volumes::{DepthComplexity, SamplePattern};
use penumbra::{RenderOptions, Scene};

use crate::words::InCommandWords;

pub(crate) fn parse_pixel(s: &str, scene: &Scene) -> Result<(u32, u32)> {
    let (x, y) = s
        .split_once(',')
        .with_context(|| format!("--pixel {s:?}: expected X,Y"))?;
    let x: u32 = x
        .trim()
        .parse()
        .with_context(|| format!("--pixel {s:?}: bad X"))?;
    let y: u32 = y
        .trim()
        .parse()
        .with_context(|| format!("--pixel {s:?}: bad Y"))?;
    let c = &scene.camera;
    if x >= c.width || y >= c.height {
        bail!(
            "--pixel {x},{y} is outside the {}x{} image",
            c.width,
            c.height
        );
    }
    Ok((x, y))
}

pub(crate) fn probe(scene_path: &Path, pixel: &str, samples: usize) -> Result<()> {
    let per_axis = RenderOptions {
        samples,
        jitter: false,
    }
    .pattern()
    .in_command_words()?
    .per_axis;
    let scene = Scene::load(scene_path)?;
    let (x, y) = parse_pixel(pixel, &scene)?;
    if scene.single_channel() {
        return probe_light(&scene, (x, y), samples, per_axis, None);
    }
    // Each light alone, in the scene's order.
    for (k, l) in scene.lights.iter().enumerate() {
        let header = format!("light {} (channel {})", l.name, l.channel());
        probe_light(
            &scene.for_light(k),
            (x, y),
            samples,
            per_axis,
            Some(&header),
        )?;
    }
    Ok(())
}

/// Prints what `penumbra probe` says of pixel `(x, y)` of a scene of one light; `header`, where
/// given, names the light of a scene of several (printed first, its lines indented).
fn probe_light(
    scene: &Scene,
    (x, y): (u32, u32),
    samples: usize,
    per_axis: usize,
    header: Option<&str>,
) -> Result<()> {
    let indent = if header.is_some() { "  " } else { "" };
    if let Some(h) = header {
        println!("{h}");
    }
    let lit = scene.lit(0);
    let tracer = Tracer::new_for(&lit, Rays::Few);
    let dir = lit.camera.ray_dir(x, y);
    match tracer.surface_point(lit.camera.eye, dir) {
        None => println!("{indent}pixel {x},{y}: the ray hits nothing; V = 1"),
        Some(p) => {
            let exact = tracer.exact_visibility(&p);
            let mut rng = Rng::stream(
                REFERENCE_SEED,
                y as u64 * lit.camera.width as u64 + x as u64,
            );
            let sampled = tracer.sampled_visibility(&p, per_axis, &mut rng);
            // In the world's coordinates: a distant light's scene is rendered warped.
            let q = lit.warp().map_or(p.position, |w| w.unwarp(p.position));
            println!("{indent}pixel {x},{y}");
            println!(
                "{indent}P          = [{:.9}, {:.9}, {:.9}] (triangle {})",
                q.x, q.y, q.z, p.triangle
            );
            println!("{indent}V exact    = {exact:.9}");
            println!(
                "{indent}V ref      = {sampled:.9} ({samples} samples, 1-sigma bound {:.4})",
                (sampled * (1.0 - sampled) / samples as f64).sqrt()
            );
            println!("{indent}V hard     = {}", tracer.hard_visibility(&p));
            let dc = DepthComplexity::new(&lit);
            let pattern = SamplePattern {
                per_axis,
                jitter: true,
            };
            let pixel = y as u64 * lit.camera.width as u64 + x as u64;
            let v = dc.visibility(&p, pattern, pixel, &mut Default::default());
            println!(
                "{indent}V depth    = {:.9} (depth complexity, the reference's {samples} samples; {} edges touched it, {} triangles towards the centre)",
                v.visibility, v.edges, v.centre_count
            );
        }
    }
    Ok(())
}
