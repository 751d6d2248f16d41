//! `penumbra render`: one technique's visibility image of a scene, to EXR (and PNG): one
//! channel `V`, or for a scene of several lights a channel `<name>.V` and a PNG
//! `OUT.<name>.png` per light; with `--shaded`, a diffuse picture of the scene lit by them
//! ([`ShadedImage`]).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use penumbra::{Backend, Channel, RenderOptions, Renderer, Scene, Technique, VisibilityChannels};

use crate::cli::ParamArgs;
use crate::outputs::{check_outputs, prepare};
use crate::words::InCommandWords;

/// Where `penumbra render` writes its images: the EXR, and the PNGs asked for.
pub(crate) struct RenderOutputs<'a> {
    /// `--out`: the visibility EXR.
    pub(crate) out: &'a Path,
    /// `--png`: the greyscale PNG of V (one per light of a scene of several).
    pub(crate) png: Option<&'a Path>,
    /// `--shaded`: the shaded preview.
    pub(crate) shaded: Option<&'a Path>,
}

pub(crate) fn render(
    scene_path: &Path,
    technique: Technique,
    outputs: RenderOutputs<'_>,
    options: RenderOptions,
    backend: Backend,
    params: &ParamArgs,
) -> Result<()> {
    let RenderOutputs { out, png, shaded } = outputs;
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
    // `--shaded` is always a PNG.
    if let Some(p) = shaded {
        let ext = p
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        if ext.as_deref() != Some("png") {
            let named = match &ext {
                Some(e) => format!("names a .{e} file"),
                None => "has no extension".to_string(),
            };
            bail!(
                "--shaded {} {named}, but --shaded writes an 8-bit RGB PNG: name it .png",
                p.display()
            );
        }
    }
    let mut outputs = vec![out];
    outputs.extend(png);
    outputs.extend(shaded);
    // Checked before and after loading: the scene names the meshes.
    check_outputs(&[scene_path.to_path_buf()], &outputs)?;
    let mut scene = Scene::load(scene_path)?;
    params.apply(&mut scene)?;
    // A scene of several lights writes a PNG per light.
    let pngs: Vec<PathBuf> = match png {
        Some(p) if !scene.single_channel() => scene
            .light_names()
            .iter()
            .map(|name| light_png(p, name))
            .collect(),
        Some(p) => vec![p.to_path_buf()],
        None => Vec::new(),
    };
    let mut outputs = vec![out];
    outputs.extend(pngs.iter().map(PathBuf::as_path));
    outputs.extend(shaded);
    check_outputs(&scene.input_files(), &outputs)?;
    // Missing folders are made before the render and every output checked writable (so that
    // what cannot be written fails early), the folders said on success and removed again on
    // failure.
    let prepared = prepare(&outputs)?;
    let outputs = DrawOutputs {
        out,
        pngs: &pngs,
        shaded,
    };
    let summary = draw(scene_path, &scene, technique, outputs, options, backend)?;
    for d in prepared.keep() {
        eprintln!("created folder {}", d.display());
    }
    eprintln!("{summary}");
    Ok(())
}

/// The PNG of the light `name` of a scene of several lights, for `--png png`: `OUT.<name>.png`
/// for `OUT.png` (the extension kept, whatever it is), `png.<name>.png` for a name without one.
pub(crate) fn light_png(png: &Path, name: &str) -> PathBuf {
    match (png.file_stem(), png.extension()) {
        (Some(stem), Some(ext)) => {
            let mut file = stem.to_os_string();
            file.push(format!(".{name}."));
            file.push(ext);
            png.with_file_name(file)
        }
        _ => {
            let mut file = png.as_os_str().to_os_string();
            file.push(format!(".{name}.png"));
            PathBuf::from(file)
        }
    }
}

/// The files [`draw`] writes.
struct DrawOutputs<'a> {
    out: &'a Path,
    /// One per light, or none.
    pngs: &'a [PathBuf],
    shaded: Option<&'a Path>,
}

/// Renders `scene` into `out` (and `pngs`, one per light, and the `shaded` preview); returns the
/// summary line. On failure, none of them is left.
fn draw(
    scene_path: &Path,
    scene: &Scene,
    technique: Technique,
    outputs: DrawOutputs<'_>,
    options: RenderOptions,
    backend: Backend,
) -> Result<String> {
    let DrawOutputs { out, pngs, shaded } = outputs;
    let lights = scene.light_count();
    let rows = scene.camera.height as u64;
    let bar = ProgressBar::new(rows * lights as u64);
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} rows, {elapsed} (eta {eta})")
            .expect("static template")
            .progress_chars("=> "),
    );
    bar.set_message(format!("{technique:?}"));
    let start = std::time::Instant::now();
    let mut renderer = Renderer::new(backend);
    let mut channels = Vec::with_capacity(lights);
    let mut details = Vec::with_capacity(lights);
    // The lights' names, where the image names its channels by them.
    let names = if scene.single_channel() {
        Vec::new()
    } else {
        scene.light_names()
    };
    for (k, channel) in scene.channel_names().into_iter().enumerate() {
        let done = k as u64 * rows;
        let progress = |r| bar.set_position(done + r);
        let frame = renderer
            .render_frame(&scene.lit(k), technique, &options, None, &progress)
            .in_command_words()?;
        let light = names
            .get(k)
            .map(|n| format!("light {n}: "))
            .unwrap_or_default();
        for w in &frame.warnings {
            bar.suspend(|| eprintln!("warning: {light}{w}"));
        }
        // Of a scene of several lights, the light's channel is named.
        let of = if names.is_empty() {
            String::new()
        } else {
            format!(" ({light}{channel})")
        };
        frame
            .image
            .check_finite()
            .with_context(|| format!("{technique:?} produced a non-finite pixel{of}"))?;
        details.push(frame.detail);
        channels.push(Channel {
            name: channel,
            image: frame.image,
        });
    }
    bar.finish_and_clear();
    let triangles = scene.triangle_count();
    let images = VisibilityChannels::new(channels)?;
    images
        .write_exr(out)
        .with_context(|| format!("writing {}", out.display()))?;
    for (k, (png, c)) in pngs.iter().zip(images.channels()).enumerate() {
        if let Err(e) = c.image.write_png(png) {
            let _ = std::fs::remove_file(out);
            for written in &pngs[..k] {
                let _ = std::fs::remove_file(written);
            }
            return Err(e).with_context(|| format!("writing {}", png.display()));
        }
    }
    if let Some(path) = shaded {
        let written = renderer
            .shaded(scene, &images)
            .and_then(|img| img.write_png(path));
        if let Err(e) = written {
            let _ = std::fs::remove_file(out);
            for written in pngs {
                let _ = std::fs::remove_file(written);
            }
            return Err(e).with_context(|| format!("writing {}", path.display()));
        }
    }
    let (width, height) = images.size();
    // The lights' details, once where they are all the same.
    let detail = if details.windows(2).all(|w| w[0] == w[1]) {
        details.swap_remove(0)
    } else {
        names
            .iter()
            .zip(&details)
            .map(|(n, d)| format!("{n}: {d}"))
            .collect::<Vec<_>>()
            .join("; ")
    };
    let lights = if names.is_empty() {
        String::new()
    } else {
        format!(", {} lights", names.len())
    };
    Ok(format!(
        "{}: {}x{} px, {} triangles{lights}, {:?} ({}), {:.2} s -> {}",
        scene_path.display(),
        width,
        height,
        triangles,
        technique,
        detail,
        start.elapsed().as_secs_f64(),
        out.display()
    ))
}
