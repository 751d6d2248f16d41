//! `penumbra render`: one technique's visibility image of a scene, to EXR (and PNG).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use penumbra::{Backend, RenderOptions, Renderer, Scene, Technique};

use crate::cli::ParamArgs;
use crate::outputs::check_outputs;
use crate::words::InCommandWords;

pub(crate) fn render(
    scene_path: &Path,
    technique: Technique,
    out: &Path,
    options: RenderOptions,
    png: Option<&Path>,
    backend: Backend,
    params: &ParamArgs,
) -> Result<()> {
    // The renderer's own check of the options, asked before the scene is loaded.
    options.pattern_for(technique).in_command_words()?;
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
    let mut scene = Scene::load(scene_path)?;
    params.apply(&mut scene)?;
    check_outputs(&scene.input_files(), &outputs)?;
    // Missing folders are made before the render (so that one that cannot be made fails
    // early), said on success, and removed again on failure.
    let mut created: Vec<PathBuf> = Vec::new();
    let made = make_folders(&outputs, &mut created);
    let result =
        made.and_then(|()| draw(scene_path, &scene, technique, out, options, png, backend));
    match result {
        Ok(summary) => {
            for d in &created {
                eprintln!("created folder {}", d.display());
            }
            eprintln!("{summary}");
            Ok(())
        }
        Err(e) => {
            for d in created.iter().rev() {
                let _ = std::fs::remove_dir(d);
            }
            Err(e)
        }
    }
}

/// Makes the missing folders of `outputs`, recording each in `created` (outermost first).
fn make_folders(outputs: &[&Path], created: &mut Vec<PathBuf>) -> Result<()> {
    for o in outputs {
        let Some(dir) = o.parent().filter(|d| !d.as_os_str().is_empty()) else {
            continue;
        };
        let missing: Vec<&Path> = dir
            .ancestors()
            .filter(|a| !a.as_os_str().is_empty())
            .take_while(|a| std::fs::symlink_metadata(a).is_err())
            .collect();
        for d in missing.into_iter().rev() {
            match std::fs::create_dir(d) {
                Ok(()) => created.push(d.to_path_buf()),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
                Err(e) => {
                    return Err(e).with_context(|| {
                        format!("creating the folder {} of {}", d.display(), o.display())
                    });
                }
            }
        }
    }
    Ok(())
}

/// Renders `scene` into `out` (and `png`); returns the summary line.
fn draw(
    scene_path: &Path,
    scene: &Scene,
    technique: Technique,
    out: &Path,
    options: RenderOptions,
    png: Option<&Path>,
    backend: Backend,
) -> Result<String> {
    let bar = ProgressBar::new(scene.camera.height as u64);
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} rows, {elapsed} (eta {eta})")
            .expect("static template")
            .progress_chars("=> "),
    );
    bar.set_message(format!("{technique:?}"));
    let start = std::time::Instant::now();
    let progress = |rows| bar.set_position(rows);
    let frame = Renderer::new(backend)
        .render_frame(scene, technique, &options, None, &progress)
        .in_command_words()?;
    let (img, triangles, detail) = (
        frame.image,
        scene.triangle_count(),
        format!(" ({})", frame.detail),
    );
    bar.finish_and_clear();
    for w in &frame.warnings {
        eprintln!("warning: {w}");
    }
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
    Ok(format!(
        "{}: {}x{} px, {} triangles, {:?}{}, {:.2} s -> {}",
        scene_path.display(),
        img.width,
        img.height,
        triangles,
        technique,
        detail,
        start.elapsed().as_secs_f64(),
        out.display()
    ))
}
