//! `penumbra compare`: the error metrics of one image against another, channel by channel for
//! images of several lights.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use penumbra::geom::{self, Comparison, VisibilityChannels};

use crate::commands::render::light_png;
use crate::outputs::{check_outputs, prepare};

pub(crate) fn compare(
    a: &Path,
    b: &Path,
    channel: Option<&str>,
    heatmap: Option<&Path>,
    json: bool,
) -> Result<()> {
    if let Some(h) = heatmap {
        check_outputs(&[a.to_path_buf(), b.to_path_buf()], &[h])?;
    }
    // Sizes and channels from the headers first: an image that declares more pixels than the
    // other is refused before either is read.
    let (wa, ha, na) = VisibilityChannels::read_exr_names(a)?;
    let (wb, hb, nb) = VisibilityChannels::read_exr_names(b)?;
    if (wa, ha) != (wb, hb) {
        bail!(
            "image sizes differ: {} is {} x {} pixels, {} is {} x {}",
            a.display(),
            wa,
            ha,
            b.display(),
            wb,
            hb
        );
    }
    let names: Vec<String> = match channel {
        Some(c) => {
            for (path, names) in [(a, &na), (b, &nb)] {
                if !names.iter().any(|n| n == c) {
                    bail!(
                        "{}: --channel {c}: no such channel (its channels: {})",
                        path.display(),
                        names.join(", ")
                    );
                }
            }
            vec![c.to_string()]
        }
        // The same channels, in A's order (an image written by another program may order
        // them otherwise).
        None if same_set(&na, &nb) => na,
        None => bail!(
            "the images' channels differ: {} has {}, {} has {}; name the channel to compare with --channel",
            a.display(),
            na.join(", "),
            b.display(),
            nb.join(", ")
        ),
    };
    // Several channels, several heat maps: `HEATMAP.<light>.png`.
    let heatmaps: Vec<PathBuf> = match heatmap {
        Some(h) if names.len() > 1 => names
            .iter()
            .map(|n| light_png(h, n.strip_suffix(".V").unwrap_or(n)))
            .collect(),
        Some(h) => vec![h.to_path_buf()],
        None => Vec::new(),
    };
    if names.len() > 1 {
        let outputs: Vec<&Path> = heatmaps.iter().map(PathBuf::as_path).collect();
        check_outputs(&[a.to_path_buf(), b.to_path_buf()], &outputs)?;
    }
    // The heat maps' folders made and each checked writable before the images are read.
    let outputs: Vec<&Path> = heatmaps.iter().map(PathBuf::as_path).collect();
    let prepared = prepare(&outputs)?;
    let ia = VisibilityChannels::read_exr(a)?;
    let ib = VisibilityChannels::read_exr(b)?;
    let mut results: Vec<(String, Comparison)> = Vec::with_capacity(names.len());
    for (k, name) in names.iter().enumerate() {
        let [ca, cb] = [(&ia, a), (&ib, b)].map(|(img, path)| {
            img.get(name)
                .with_context(|| format!("{}: no channel {name}", path.display()))
        });
        let (ca, cb) = (ca?, cb?);
        // A non-finite pixel is named with its file (and its channel, of several).
        for (img, path) in [(ca, a), (cb, b)] {
            img.check().with_context(|| {
                if names.len() > 1 {
                    format!("{}, channel {name}", path.display())
                } else {
                    format!("{}", path.display())
                }
            })?;
        }
        let c = geom::compare(ca, cb)?;
        if let Some(h) = heatmaps.get(k) {
            let rgb = geom::heatmap(ca, cb, 0.1);
            geom::write_png_bytes(h, ca.width, ca.height, geom::PngColor::Rgb, &rgb)?;
        }
        results.push((name.clone(), c));
    }
    for d in prepared.keep() {
        eprintln!("created folder {}", d.display());
    }
    if json {
        if let [(_, c)] = &results[..] {
            println!("{}", serde_json::to_string_pretty(c)?);
        } else {
            let mut all = Vec::with_capacity(results.len());
            for (name, c) in &results {
                let mut v = serde_json::json!({ "channel": name });
                if let (Some(o), serde_json::Value::Object(fields)) =
                    (v.as_object_mut(), serde_json::to_value(c)?)
                {
                    o.extend(fields);
                }
                all.push(v);
            }
            println!("{}", serde_json::to_string_pretty(&all)?);
        }
        return Ok(());
    }
    for (k, (name, c)) in results.iter().enumerate() {
        if results.len() > 1 {
            if k > 0 {
                println!();
            }
            println!("channel {name}");
        }
        print_table(c);
    }
    Ok(())
}

/// Whether `a` and `b` hold the same names, whatever their order.
fn same_set(a: &[String], b: &[String]) -> bool {
    let sorted = |v: &[String]| {
        let mut v = v.to_vec();
        v.sort();
        v
    };
    sorted(a) == sorted(b)
}

/// Prints one comparison as the table of `penumbra compare`.
fn print_table(c: &Comparison) {
    println!(
        "{:<10} {:>8} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}",
        "pixels", "count", "MAE", "RMSE", "p99", "max", ">0.05", "equal"
    );
    for (name, m) in [("all", c.all), ("penumbra", c.penumbra)] {
        println!(
            "{:<10} {:>8} {:>10.6} {:>10.6} {:>10.6} {:>10.6} {:>9.3}% {:>9.3}%",
            name,
            m.pixels,
            m.mae,
            m.rmse,
            m.p99,
            m.max,
            100.0 * m.share_over,
            100.0 * m.equal
        );
    }
    println!(
        "penumbra mean signed error {:+.6}; umbra {} pixels, {:.3}% of them lit (V > 0.5)",
        c.penumbra_signed,
        c.umbra_pixels,
        100.0 * c.umbra_lit
    );
}
