//! Visibility images: one `f32` per pixel, row 0 the top, stored as an OpenEXR file with a single
//! channel named `V`; an 8-bit greyscale PNG for people; and the metrics by which two images are
//! compared.

use std::path::{Path, PathBuf};

pub use crate::output::{output_target, remove_temporaries_in_progress, write_atomically};

/// Name of the one channel of a visibility EXR.
pub const CHANNEL: &str = "V";

/// Lower and upper bound of "penumbra" in the reference image for [`compare`]: pixels with
/// `PENUMBRA.0 < V < PENUMBRA.1`.
pub const PENUMBRA: (f32, f32) = (0.02, 0.98);

/// Error threshold counted by [`Metrics::share_over`].
pub const ERROR_THRESHOLD: f32 = 0.05;

/// What can go wrong reading or writing images.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// I/O or encoding failure.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What failed.
        message: String,
    },
    /// The EXR has no channel `V`.
    #[error("{path}: no channel named `V` (found {found:?})")]
    NoVChannel {
        /// The file.
        path: PathBuf,
        /// The channels it has.
        found: Vec<String>,
    },
    /// Two images of different sizes were compared.
    #[error("image sizes differ: {a:?} vs {b:?}")]
    SizeMismatch {
        /// First size.
        a: (u32, u32),
        /// Second size.
        b: (u32, u32),
    },
    /// An EXR whose header declares more pixels than the memory holds (or than `compare`'s other
    /// image has), refused before its pixels are read.
    #[error("{path}: the header declares {width} x {height} pixels; {why}")]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Declared width.
        width: u64,
        /// Declared height.
        height: u64,
        /// What it does not fit.
        why: String,
    },
    /// A value is NaN or infinite.
    #[error("pixel ({x}, {y}) is not finite")]
    NonFinite {
        /// Column.
        x: u32,
        /// Row.
        y: u32,
    },
}

/// A visibility image, row-major, row 0 the top: per pixel, the share of the light's area its
/// surface point sees (1 where the ray from the camera hits nothing).
///
/// ```
/// use penumbra_geom::VisibilityImage;
///
/// let mut v = VisibilityImage::filled(4, 3, 1.0);
/// v.data[4 + 2] = 0.25; // column 2, row 1
/// assert_eq!(v.get(2, 1), 0.25);
/// let path = std::env::temp_dir().join(format!("doc-{}.exr", std::process::id()));
/// v.write_exr(&path)?;
/// assert_eq!(VisibilityImage::read_exr(&path)?, v);
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct VisibilityImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` values.
    pub data: Vec<f32>,
}

pub(crate) fn io_err(path: &Path, e: impl std::fmt::Display) -> ImageError {
    ImageError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

impl VisibilityImage {
    /// An image filled with `value`.
    pub fn filled(width: u32, height: u32, value: f32) -> Self {
        VisibilityImage {
            width,
            height,
            data: vec![value; width as usize * height as usize],
        }
    }

    /// Value at column `x`, row `y`.
    pub fn get(&self, x: u32, y: u32) -> f32 {
        self.data[y as usize * self.width as usize + x as usize]
    }

    /// The first non-finite pixel, if any.
    pub fn check_finite(&self) -> Result<(), ImageError> {
        match self.data.iter().position(|v| !v.is_finite()) {
            None => Ok(()),
            Some(i) => Err(ImageError::NonFinite {
                x: (i % self.width as usize) as u32,
                y: (i / self.width as usize) as u32,
            }),
        }
    }

    /// Writes the image as an EXR with one `f32` channel `V` (atomically).
    pub fn write_exr(&self, path: &Path) -> Result<(), ImageError> {
        use exr::prelude::*;
        self.check_finite()?;
        write_atomically(path, |tmp| {
            let channel = AnyChannel::new(CHANNEL, FlatSamples::F32(self.data.clone()));
            let layer = Layer::new(
                (self.width as usize, self.height as usize),
                LayerAttributes::default(),
                Encoding::FAST_LOSSLESS,
                AnyChannels::sort(SmallVec::from_vec(vec![channel])),
            );
            Image::from_layer(layer)
                .write()
                .to_file(tmp)
                .map_err(|e| io_err(tmp, e))
        })
    }

    /// Reads the `V` channel of an EXR file (its first layer holding one).
    pub fn read_exr(path: &Path) -> Result<Self, ImageError> {
        use exr::prelude::*;
        let (width, height, bytes) = exr_layout(path)?;
        if let Some(a) = crate::memory::available().filter(|&a| bytes > a / 2) {
            return Err(ImageError::TooLarge {
                path: path.to_path_buf(),
                width,
                height,
                why: format!(
                    "reading it takes about {:.1} GB and {:.1} GB of memory are available",
                    2.0 * bytes as f64 / 1e9,
                    a as f64 / 1e9
                ),
            });
        }
        let image = read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .all_layers()
            .all_attributes()
            .from_file(path)
            .map_err(|e| io_err(path, e))?;
        let mut found = Vec::new();
        for layer in &image.layer_data {
            for ch in &layer.channel_data.list {
                if ch.name.to_string() == CHANNEL {
                    let size = layer.size;
                    return Ok(VisibilityImage {
                        width: size.width() as u32,
                        height: size.height() as u32,
                        data: ch.sample_data.values_as_f32().collect(),
                    });
                }
                found.push(ch.name.to_string());
            }
        }
        Err(ImageError::NoVChannel {
            path: path.to_path_buf(),
            found,
        })
    }

    /// The width and height of the EXR's layer that holds `V`, read from its header alone (no
    /// pixel is read or allocated).
    pub fn read_exr_size(path: &Path) -> Result<(u64, u64), ImageError> {
        exr_layout(path).map(|(w, h, _)| (w, h))
    }

    /// Writes V in `[0, 1]` as an 8-bit greyscale PNG (linear, atomically).
    pub fn write_png(&self, path: &Path) -> Result<(), ImageError> {
        let bytes: Vec<u8> = self
            .data
            .iter()
            .map(|&v| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8)
            .collect();
        write_png_bytes(path, self.width, self.height, PngColor::Grey, &bytes)
    }
}

/// Pixel layout of an 8-bit PNG.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PngColor {
    /// One byte per pixel.
    Grey,
    /// Three bytes per pixel.
    Rgb,
}

/// Refuses what is not a regular file starting with OpenEXR's magic number, with words a user
/// can act on (the EXR reader says "file identifier missing" of a PNG).
fn exr_file(path: &Path) -> Result<(), ImageError> {
    use std::io::Read;
    crate::input::regular_file(path).map_err(|e| io_err(path, e))?;
    let mut magic = [0u8; 4];
    let read = std::fs::File::open(path)
        .and_then(|f| f.take(4).read(&mut magic))
        .map_err(|e| io_err(path, e))?;
    if read < 4 || magic != [0x76, 0x2f, 0x31, 0x01] {
        return Err(io_err(
            path,
            "not an OpenEXR file: visibility images are read as the EXRs `penumbra render --out` writes",
        ));
    }
    Ok(())
}

/// The size of the EXR's layer that holds `V`, and the bytes that reading every layer and
/// channel of it takes, from its header alone.
fn exr_layout(path: &Path) -> Result<(u64, u64, u64), ImageError> {
    exr_file(path)?;
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(|e| io_err(path, e))?;
    let mut bytes = 0u64;
    let mut size = None;
    let mut found = Vec::new();
    for h in meta.headers.iter() {
        let (w, ht) = (h.layer_size.width() as u64, h.layer_size.height() as u64);
        for ch in &h.channels.list {
            // Every channel is read (and `V` copied once more as f32).
            let per = ch.sample_type.bytes_per_sample() as u64 + 4;
            bytes = bytes.saturating_add(w.saturating_mul(ht).saturating_mul(per));
            let name = ch.name.to_string();
            if name == CHANNEL {
                size.get_or_insert((w, ht));
            } else if size.is_none() {
                found.push(name);
            }
        }
    }
    let (w, h) = size.ok_or_else(|| ImageError::NoVChannel {
        path: path.to_path_buf(),
        found,
    })?;
    Ok((w, h, bytes))
}

/// Writes 8-bit pixels as a PNG (atomically).
pub fn write_png_bytes(
    path: &Path,
    width: u32,
    height: u32,
    color: PngColor,
    bytes: &[u8],
) -> Result<(), ImageError> {
    let color = match color {
        PngColor::Grey => png::ColorType::Grayscale,
        PngColor::Rgb => png::ColorType::Rgb,
    };
    write_atomically(path, |tmp| {
        let file = std::fs::File::create(tmp).map_err(|e| io_err(tmp, e))?;
        let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width, height);
        enc.set_color(color);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header().map_err(|e| io_err(tmp, e))?;
        w.write_image_data(bytes).map_err(|e| io_err(tmp, e))?;
        w.finish().map_err(|e| io_err(tmp, e))
    })
}

/// Error statistics of one set of pixels.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Metrics {
    /// Number of pixels measured.
    pub pixels: usize,
    /// Mean absolute error.
    pub mae: f64,
    /// Root mean square error.
    pub rmse: f64,
    /// 99th percentile of the absolute error (nearest rank).
    pub p99: f64,
    /// Largest absolute error.
    pub max: f64,
    /// Share of pixels whose absolute error exceeds [`ERROR_THRESHOLD`].
    pub share_over: f64,
    /// Share of pixels whose values are identical (error 0).
    pub equal: f64,
}

impl Metrics {
    /// Statistics of absolute errors.
    pub fn of(mut errors: Vec<f64>) -> Self {
        if errors.is_empty() {
            return Metrics::default();
        }
        let n = errors.len();
        let mae = errors.iter().sum::<f64>() / n as f64;
        let rmse = (errors.iter().map(|e| e * e).sum::<f64>() / n as f64).sqrt();
        let over = errors
            .iter()
            .filter(|&&e| e > ERROR_THRESHOLD as f64)
            .count();
        let equal = errors.iter().filter(|&&e| e == 0.0).count();
        errors.sort_by(f64::total_cmp);
        let rank = ((0.99 * n as f64).ceil() as usize).clamp(1, n) - 1;
        Metrics {
            pixels: n,
            mae,
            rmse,
            p99: errors[rank],
            max: errors[n - 1],
            share_over: over as f64 / n as f64,
            equal: equal as f64 / n as f64,
        }
    }
}

/// The comparison of an image `a` against a reference `b`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Comparison {
    /// Over all pixels.
    pub all: Metrics,
    /// Over the penumbra pixels of `b`, `0.02 < V_b < 0.98`.
    pub penumbra: Metrics,
    /// Mean of `V_a - V_b` over the penumbra pixels of `b`: negative where `a` is too dark.
    pub penumbra_signed: f64,
    /// The umbra pixels of `b`, `V_b <= 0.02`.
    pub umbra_pixels: usize,
    /// The share of them that `a` shows lit, `V_a > 0.5`: shadows lost.
    pub umbra_lit: f64,
}

/// Compares `a` against the reference `b`: all pixels, and penumbra pixels of `b` alone.
///
/// ```
/// use penumbra_geom::VisibilityImage;
/// use penumbra_geom::image::compare;
///
/// let truth = VisibilityImage { width: 2, height: 1, data: vec![0.5, 1.0] };
/// let test = VisibilityImage { width: 2, height: 1, data: vec![0.6, 1.0] };
/// let c = compare(&test, &truth)?;
/// assert_eq!(c.penumbra.pixels, 1); // 0.02 < V < 0.98 in the reference
/// assert!((c.all.mae - 0.05).abs() < 1e-6);
/// # Ok::<(), penumbra_geom::image::ImageError>(())
/// ```
pub fn compare(a: &VisibilityImage, b: &VisibilityImage) -> Result<Comparison, ImageError> {
    if (a.width, a.height) != (b.width, b.height) {
        return Err(ImageError::SizeMismatch {
            a: (a.width, a.height),
            b: (b.width, b.height),
        });
    }
    a.check_finite()?;
    b.check_finite()?;
    let mut all = Vec::with_capacity(a.data.len());
    let mut pen = Vec::new();
    let (mut signed, mut umbra, mut lit) = (0.0, 0usize, 0usize);
    for (&x, &y) in a.data.iter().zip(&b.data) {
        let e = (x as f64 - y as f64).abs();
        all.push(e);
        if y > PENUMBRA.0 && y < PENUMBRA.1 {
            pen.push(e);
            signed += x as f64 - y as f64;
        } else if y <= PENUMBRA.0 {
            umbra += 1;
            lit += usize::from(x > 0.5);
        }
    }
    Ok(Comparison {
        all: Metrics::of(all),
        penumbra_signed: signed / pen.len().max(1) as f64,
        penumbra: Metrics::of(pen),
        umbra_pixels: umbra,
        umbra_lit: lit as f64 / umbra.max(1) as f64,
    })
}

/// An RGB heat map of `|a - b|`: black for no error, through red and yellow to white at an
/// error of `full_scale` or more.
pub fn heatmap(a: &VisibilityImage, b: &VisibilityImage, full_scale: f32) -> Vec<u8> {
    a.data
        .iter()
        .zip(&b.data)
        .flat_map(|(&x, &y)| {
            let e = ((x - y).abs() / full_scale).clamp(0.0, 1.0) * 3.0;
            let r = e.min(1.0);
            let g = (e - 1.0).clamp(0.0, 1.0);
            let b = (e - 2.0).clamp(0.0, 1.0);
            [r, g, b].map(|c| (c * 255.0 + 0.5) as u8)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::temporary;

    #[cfg(unix)]
    #[test]
    fn outputs_are_regular_files_links_keep_and_stale_temporaries_go() {
        let d = std::env::temp_dir().join(format!("penumbra-out-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        let img = VisibilityImage::filled(2, 2, 0.5);
        // A directory and a device are refused, untouched.
        let e = img.write_exr(&d).unwrap_err().to_string();
        assert!(e.contains("directory"), "{e}");
        let e = img
            .write_exr(Path::new("/dev/null"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("device"), "{e}");
        use std::os::unix::fs::FileTypeExt;
        assert!(
            std::fs::metadata("/dev/null")
                .unwrap()
                .file_type()
                .is_char_device()
        );
        // A link to a regular file: the target gets the image, the link stays a link.
        let target = d.join("target.exr");
        std::fs::write(&target, b"old").unwrap();
        let link = d.join("link.exr");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        img.write_exr(&link).unwrap();
        assert!(
            std::fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(VisibilityImage::read_exr(&target).unwrap(), img);
        // A link to a directory is refused.
        let to_dir = d.join("to-dir.exr");
        std::os::unix::fs::symlink(&d, &to_dir).unwrap();
        assert!(img.write_exr(&to_dir).is_err());
        // A dead run's temporary is removed by the next write of the same output; a live
        // one's (ours stands for it) is kept.
        let out = d.join("v.exr");
        let dead = temporary(&out, std::ffi::OsStr::new("v.exr"), u32::MAX - 7);
        let live = temporary(&out, std::ffi::OsStr::new("v.exr"), 1);
        std::fs::write(&dead, b"partial").unwrap();
        std::fs::write(&live, b"partial").unwrap();
        img.write_exr(&out).unwrap();
        if Path::new("/proc/self").exists() {
            assert!(!dead.exists());
            assert_eq!(live.exists(), Path::new("/proc/1").exists());
        }
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn exr_round_trips_exactly_and_keeps_row_order() {
        let mut img = VisibilityImage::filled(5, 3, 0.0);
        for (i, v) in img.data.iter_mut().enumerate() {
            *v = i as f32 / 14.0 + 1e-7;
        }
        let dir = std::env::temp_dir().join(format!("penumbra-img-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.exr");
        img.write_exr(&p).unwrap();
        let back = VisibilityImage::read_exr(&p).unwrap();
        assert_eq!(back, img);
        assert_eq!(back.get(4, 0), img.data[4]);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn nan_image_is_refused_and_leaves_no_file() {
        let mut img = VisibilityImage::filled(2, 2, 1.0);
        img.data[3] = f32::NAN;
        let dir = std::env::temp_dir().join(format!("penumbra-nan-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("n.exr");
        assert!(matches!(
            img.write_exr(&p),
            Err(ImageError::NonFinite { x: 1, y: 1 })
        ));
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn metrics_by_hand() {
        let m = Metrics::of(vec![0.0, 0.1, 0.0, 0.02]);
        assert!((m.mae - 0.03).abs() < 1e-12);
        assert!((m.share_over - 0.25).abs() < 1e-12);
        assert_eq!(m.p99, 0.1);
        let a = VisibilityImage {
            width: 2,
            height: 1,
            data: vec![0.5, 1.0],
        };
        let b = VisibilityImage {
            width: 2,
            height: 1,
            data: vec![0.4, 1.0],
        };
        let c = compare(&a, &b).unwrap();
        assert_eq!(c.penumbra.pixels, 1);
        assert!((c.penumbra.mae - 0.1).abs() < 1e-6);
        assert!((c.all.mae - 0.05).abs() < 1e-6);
    }
}
