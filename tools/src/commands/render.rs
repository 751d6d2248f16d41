//! `penumbra render`: one technique's visibility image of a scene, to EXR (and PNG).

use std::path::Path;

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use penumbra::{RenderOptions, Renderer, Technique};

use crate::cli::{Backend, ParamArgs};
use crate::{Sampling, check_outputs, load_scene, samples_per_axis};

pub(crate) fn render(
    scene_path: &Path,
    technique: Technique,
    out: &Path,
    sampling: Sampling,
    png: Option<&Path>,
    backend: Backend,
    params: &ParamArgs,
) -> Result<()> {
    samples_per_axis(sampling.samples)?;
    if sampling.jitter && !technique.takes_samples() {
        bail!(
            "--jitter: {technique:?} takes no light samples (depth-complexity does; the reference always jitters)"
        );
    }
    // `--out` is always an OpenEXR file: one named as another format would mislead its readers.
    let ext = out
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    if let Some(e) =
        ext.filter(|e| ["png", "jpg", "jpeg", "tif", "tiff", "bmp", "hdr"].contains(&e.as_str()))
    {
        bail!(
            "--out {} names a .{e} file, but --out writes an OpenEXR image (channel V): name it .exr, and use --png for an 8-bit PNG",
            out.display()
        );
    }
    let mut outputs = vec![out];
    outputs.extend(png);
    // Checked before and after loading: the scene names the meshes.
    check_outputs(&[scene_path.to_path_buf()], &outputs)?;
    let mut scene = load_scene(scene_path)?;
    params.apply(&mut scene)?;
    check_outputs(&scene.input_files(), &outputs)?;
    for o in &outputs {
        if let Some(dir) = o.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("creating the folder of {}", o.display()))?;
        }
    }
    let bar = ProgressBar::new(scene.camera.height as u64);
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} rows, {elapsed} (eta {eta})")
            .expect("static template")
            .progress_chars("=> "),
    );
    bar.set_message(format!("{technique:?}"));
    let start = std::time::Instant::now();
    let progress = |rows| bar.set_position(rows);
    let options = RenderOptions {
        samples: sampling.samples,
        jitter: sampling.jitter,
    };
    let frame =
        Renderer::new(backend.into()).render_frame(&scene, technique, &options, None, &progress)?;
    let (img, triangles, detail) = (
        frame.image,
        scene.triangle_count(),
        format!(" ({})", frame.detail),
    );
    bar.finish_and_clear();
    img.check_finite()
        .with_context(|| format!("{technique:?} produced a non-finite pixel"))?;
    img.write_exr(out)
        .with_context(|| format!("writing {}", out.display()))?;
    if let Some(png) = png {
        if let Err(e) = img.write_png(png) {
            let _ = std::fs::remove_file(out);
            return Err(e).with_context(|| format!("writing {}", png.display()));
        }
    }
    eprintln!(
        "{}: {}x{} px, {} triangles, {:?}{}, {:.2} s -> {}",
        scene_path.display(),
        img.width,
        img.height,
        triangles,
        technique,
        detail,
        start.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(())
}
