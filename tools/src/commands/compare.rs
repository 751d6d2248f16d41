//! `penumbra compare`: the error metrics of one image against another.

use std::path::Path;

use anyhow::{Context, Result, bail};
use penumbra::geom::{self, VisibilityImage};

use crate::outputs::check_outputs;

pub(crate) fn compare(a: &Path, b: &Path, heatmap: Option<&Path>, json: bool) -> Result<()> {
    if let Some(h) = heatmap {
        check_outputs(&[a.to_path_buf(), b.to_path_buf()], &[h])?;
    }
    // Sizes from the headers first: an image that declares more pixels than the other is
    // refused before either is read.
    let (sa, sb) = (
        VisibilityImage::read_exr_size(a)?,
        VisibilityImage::read_exr_size(b)?,
    );
    if sa != sb {
        bail!(
            "image sizes differ: {} is {} x {} pixels, {} is {} x {}",
            a.display(),
            sa.0,
            sa.1,
            b.display(),
            sb.0,
            sb.1
        );
    }
    let ia = VisibilityImage::read_exr(a)?;
    let ib = VisibilityImage::read_exr(b)?;
    // A non-finite pixel is named with its file.
    for (img, path) in [(&ia, a), (&ib, b)] {
        img.check_finite()
            .with_context(|| format!("{}", path.display()))?;
    }
    let c = geom::compare(&ia, &ib)?;
    if let Some(h) = heatmap {
        let rgb = geom::heatmap(&ia, &ib, 0.1);
        geom::write_png_bytes(h, ia.width, ia.height, geom::PngColor::Rgb, &rgb)?;
    }
    if json {
        println!("{}", serde_json::to_string_pretty(&c)?);
    } else {
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
    Ok(())
}
