//! Visibility images as files: an OpenEXR file with a single channel named `V` (what the
//! command writes and reads back), and an 8-bit greyscale PNG for people.

use std::path::Path;

use crate::image::{ImageError, VisibilityImage, io_err};
use crate::output::write_atomically;

/// Name of the one channel of a visibility EXR.
pub const CHANNEL: &str = "V";

/// Writes `data` (`width` x `height` values, rows from the top) as an EXR with one `f32`
/// channel named `channel` (atomically): for images of other quantities than V, such as hours
/// of sun.
pub fn write_exr_channel(
    path: &Path,
    (width, height): (u32, u32),
    channel: &str,
    data: &[f32],
) -> Result<(), ImageError> {
    use exr::prelude::*;
    if width == 0 || height == 0 || data.len() != width as usize * height as usize {
        return Err(ImageError::Shape {
            width,
            height,
            values: data.len(),
        });
    }
    write_atomically(path, |tmp| {
        let channel = AnyChannel::new(channel, FlatSamples::F32(data.to_vec()));
        let layer = Layer::new(
            (width as usize, height as usize),
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

impl VisibilityImage {
    /// Writes the image as an EXR with one `f32` channel `V` (atomically).
    pub fn write_exr(&self, path: &Path) -> Result<(), ImageError> {
        self.check()?;
        write_exr_channel(path, (self.width, self.height), CHANNEL, &self.data)
    }

    /// Reads the `V` channel of an EXR file (its first layer holding one); a value that is not
    /// finite is refused, naming the file and the pixel.
    pub fn read_exr(path: &Path) -> Result<Self, ImageError> {
        let (width, height, bytes) = exr_layout(path, |name| name == CHANNEL)?;
        fits_memory(path, width, height, bytes)?;
        let image = read_flat(path)?;
        let mut found = Vec::new();
        for layer in &image.layer_data {
            for ch in &layer.channel_data.list {
                if ch.name.to_string() == CHANNEL {
                    let size = layer.size;
                    let image = VisibilityImage {
                        width: size.width() as u32,
                        height: size.height() as u32,
                        data: ch.sample_data.values_as_f32().collect(),
                    };
                    image.check().map_err(|e| io_err(path, e))?;
                    return Ok(image);
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
        exr_layout(path, |name| name == CHANNEL).map(|(w, h, _)| (w, h))
    }

    /// Writes V in `[0, 1]` as an 8-bit greyscale PNG (linear, atomically).
    pub fn write_png(&self, path: &Path) -> Result<(), ImageError> {
        self.check_shape()?;
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
pub(crate) fn exr_file(path: &Path) -> Result<(), ImageError> {
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

/// Refuses to read an EXR of `width x height` pixels whose every layer and channel take `bytes`
/// where that is more than half the available memory.
/// Every layer and channel of the EXR at `path`, at its largest resolution level.
pub(crate) fn read_flat(path: &Path) -> Result<exr::image::FlatImage, ImageError> {
    use exr::prelude::*;
    read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_file(path)
        .map_err(|e| io_err(path, e))
}

pub(crate) fn fits_memory(
    path: &Path,
    width: u64,
    height: u64,
    bytes: u64,
) -> Result<(), ImageError> {
    if let Some(a) = crate::memory::available_memory().filter(|&a| bytes > a / 2) {
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
    Ok(())
}

/// The size of the EXR's first layer with a channel whose name passes `wanted`, and the bytes
/// that reading every layer and channel of it takes, from its header alone.
pub(crate) fn exr_layout(
    path: &Path,
    wanted: impl Fn(&str) -> bool,
) -> Result<(u64, u64, u64), ImageError> {
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
            if wanted(&name) {
                if ch.sample_type == exr::meta::attribute::SampleType::U32 {
                    return Err(io_err(
                        path,
                        format!(
                            "channel {name} holds 32-bit unsigned integers; a visibility \
                             channel holds floats (16 or 32 bit)"
                        ),
                    ));
                }
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
    let (color, per_pixel) = match color {
        PngColor::Grey => (png::ColorType::Grayscale, 1),
        PngColor::Rgb => (png::ColorType::Rgb, 3),
    };
    let values = (width as usize)
        .checked_mul(height as usize)
        .and_then(|n| n.checked_mul(per_pixel));
    if width == 0 || height == 0 || values != Some(bytes.len()) {
        return Err(ImageError::Shape {
            width,
            height,
            values: bytes.len() / per_pixel,
        });
    }
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
}
