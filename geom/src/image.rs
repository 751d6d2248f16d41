//! Visibility images: one `f32` per pixel, row 0 the top, and what can go wrong with them. Their
//! files (EXR, PNG) are `image_files.rs`; the metrics by which two are compared, `metrics.rs`.

use std::path::{Path, PathBuf};

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
    /// The EXR has neither a channel `V` nor channels `<light>.V`.
    #[error("{path}: no channel named `V` or `<light>.V` (found {found:?})")]
    NoLightChannels {
        /// The file.
        path: PathBuf,
        /// The channels it has.
        found: Vec<String>,
    },
    /// The EXR has no channel of the name asked for.
    #[error("{path}: no channel named `{channel}` (its channels: {found:?})")]
    NoChannel {
        /// The file.
        path: PathBuf,
        /// The channel asked for.
        channel: String,
        /// The visibility channels it has.
        found: Vec<String>,
    },
    /// Images of several lights whose channels differ in size or repeat a name.
    #[error("channel {channel}: {problem}")]
    BadChannels {
        /// The offending channel.
        channel: String,
        /// What is wrong.
        problem: String,
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
    /// An image without pixels, or whose data is not one value per pixel.
    #[error(
        "an image of {width} x {height} pixels holding {values} values: an image has one value \
         per pixel and one pixel at least"
    )]
    Shape {
        /// Width.
        width: u32,
        /// Height.
        height: u32,
        /// How many values its data holds.
        values: usize,
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
/// use penumbra::geom::VisibilityImage;
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

    /// Whether the image can be written or compared: one pixel at least, one value per pixel
    /// ([`ImageError::Shape`]), every value finite ([`ImageError::NonFinite`]).
    pub fn check(&self) -> Result<(), ImageError> {
        self.check_shape()?;
        self.check_finite()
    }

    /// One pixel at least, and one value per pixel.
    pub fn check_shape(&self) -> Result<(), ImageError> {
        let pixels = (self.width as usize).checked_mul(self.height as usize);
        if self.width == 0 || self.height == 0 || pixels != Some(self.data.len()) {
            return Err(ImageError::Shape {
                width: self.width,
                height: self.height,
                values: self.data.len(),
            });
        }
        Ok(())
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
}
