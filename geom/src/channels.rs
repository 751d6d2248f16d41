//! The visibility images of a scene's lights, one channel each, and their EXR file: one layer
//! whose channels are `V` (a scene of one `[light]`, the file [`VisibilityImage::write_exr`]
//! writes, byte for byte) or `<name>.V` for each light of `[[light]]` (the OpenEXR layer
//! convention, the light the layer).
//!
//! OpenEXR stores a layer's channels sorted by name; the header's text-vector attribute
//! [`LIGHTS_ATTRIBUTE`] lists them in the scene's order, in which they are read back.

use std::path::Path;

use crate::image::{ImageError, VisibilityImage, io_err};
use crate::image_files::{CHANNEL, exr_layout, fits_memory};
use crate::output::write_atomically;

/// The header attribute listing a file's channels in the scene's order of its lights.
pub const LIGHTS_ATTRIBUTE: &str = "penumbraLights";

/// Whether `name` is a visibility channel: `V`, or `<light>.V` where `<light>` is a light's
/// name ([`crate::check_light_name`]): a channel of another name, from another program or
/// written by hand, is not read as visibility, so no name from a file reaches a terminal or a
/// file name unchecked.
pub fn is_visibility_channel(name: &str) -> bool {
    name == CHANNEL
        || name
            .strip_suffix(".V")
            .is_some_and(|l| crate::lights::check_light_name(l).is_ok())
}

/// One light's image and the name of its channel.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// `V` or `<light>.V`.
    pub name: String,
    /// The light's visibility image.
    pub image: VisibilityImage,
}

/// The visibility images of a scene's lights, in the scene's order, all of one size.
///
/// ```
/// use penumbra::geom::{Channel, VisibilityChannels, VisibilityImage};
///
/// let v = VisibilityChannels::new(vec![
///     Channel { name: "key.V".into(), image: VisibilityImage::filled(4, 3, 0.25) },
///     Channel { name: "fill.V".into(), image: VisibilityImage::filled(4, 3, 1.0) },
/// ])?;
/// let path = std::env::temp_dir().join(format!("doc-channels-{}.exr", std::process::id()));
/// v.write_exr(&path)?;
/// let back = VisibilityChannels::read_exr(&path)?;
/// assert_eq!(back.names(), ["key.V", "fill.V"]);
/// assert_eq!(back, v);
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct VisibilityChannels {
    channels: Vec<Channel>,
}

impl VisibilityChannels {
    /// The one image of a scene of one `[light]`: channel `V`.
    pub fn single(image: VisibilityImage) -> VisibilityChannels {
        VisibilityChannels {
            channels: vec![Channel {
                name: CHANNEL.to_string(),
                image,
            }],
        }
    }

    /// The images of `channels`, in order: one at least, all of one size, names unique and
    /// each a visibility channel (`V` or `<light>.V`).
    pub fn new(channels: Vec<Channel>) -> Result<VisibilityChannels, ImageError> {
        let bad = |c: &Channel, problem: String| ImageError::BadChannels {
            channel: c.name.clone(),
            problem,
        };
        let Some(first) = channels.first() else {
            return Err(ImageError::BadChannels {
                channel: String::new(),
                problem: "no channel: a scene has one light at least".to_string(),
            });
        };
        let size = (first.image.width, first.image.height);
        let mut seen = std::collections::HashMap::with_capacity(channels.len());
        for c in &channels {
            if !is_visibility_channel(&c.name) {
                return Err(bad(c, "a channel is named `V` or `<light>.V`".to_string()));
            }
            if let Some(other) = seen.insert(c.name.to_ascii_lowercase(), c.name.as_str()) {
                return Err(bad(
                    c,
                    if other == c.name {
                        "named twice".to_string()
                    } else {
                        format!(
                            "differs from channel {other} only in case: their files would \
                             collide on a file system that ignores case"
                        )
                    },
                ));
            }
            if (c.image.width, c.image.height) != size {
                return Err(bad(
                    c,
                    format!(
                        "{} x {} pixels, where {} is {} x {}",
                        c.image.width, c.image.height, first.name, size.0, size.1
                    ),
                ));
            }
            if let Err(e) = c.image.check_shape() {
                return Err(bad(c, e.to_string()));
            }
        }
        Ok(VisibilityChannels { channels })
    }

    /// The channels, in the scene's order.
    pub fn channels(&self) -> &[Channel] {
        &self.channels
    }

    /// The channels, in the scene's order, given up.
    pub fn into_channels(self) -> Vec<Channel> {
        self.channels
    }

    /// The channels' names, in order.
    pub fn names(&self) -> Vec<&str> {
        self.channels.iter().map(|c| c.name.as_str()).collect()
    }

    /// The image of the channel `name`.
    pub fn get(&self, name: &str) -> Option<&VisibilityImage> {
        self.channels
            .iter()
            .find(|c| c.name == name)
            .map(|c| &c.image)
    }

    /// Width and height, in pixels, of every channel.
    pub fn size(&self) -> (u32, u32) {
        let i = &self.channels[0].image;
        (i.width, i.height)
    }

    /// Whether this is the one channel `V` of a scene of one `[light]`.
    pub fn is_single(&self) -> bool {
        self.channels.len() == 1 && self.channels[0].name == CHANNEL
    }

    /// The first channel that cannot be written ([`VisibilityImage::check`]), with its name.
    pub fn check(&self) -> Result<(), ImageError> {
        for c in &self.channels {
            c.image.check().map_err(|e| ImageError::BadChannels {
                channel: c.name.clone(),
                problem: e.to_string(),
            })?;
        }
        Ok(())
    }

    /// Writes every channel as one `f32` channel of an EXR (atomically): the file of
    /// [`VisibilityImage::write_exr`] for the one channel `V`, and for several lights one layer
    /// of channels `<light>.V` with [`LIGHTS_ATTRIBUTE`] giving their order.
    pub fn write_exr(&self, path: &Path) -> Result<(), ImageError> {
        use exr::prelude::*;
        if self.is_single() {
            return self.channels[0].image.write_exr(path);
        }
        self.check()?;
        let (width, height) = self.size();
        write_atomically(path, |tmp| {
            let list: Vec<AnyChannel<FlatSamples>> = self
                .channels
                .iter()
                .map(|c| AnyChannel::new(c.name.as_str(), FlatSamples::F32(c.image.data.clone())))
                .collect();
            let mut attributes = LayerAttributes::default();
            attributes.other.insert(
                Text::from(LIGHTS_ATTRIBUTE),
                AttributeValue::TextVector(
                    self.channels
                        .iter()
                        .map(|c| Text::from(c.name.as_str()))
                        .collect(),
                ),
            );
            let layer = Layer::new(
                (width as usize, height as usize),
                attributes,
                Encoding::FAST_LOSSLESS,
                AnyChannels::sort(SmallVec::from_vec(list)),
            );
            Image::from_layer(layer)
                .write()
                .to_file(tmp)
                .map_err(|e| io_err(tmp, e))
        })
    }

    /// Reads the visibility channels of an EXR (`V`, `<light>.V`) from its first layer holding
    /// one: in the order of [`LIGHTS_ATTRIBUTE`] where the header has it, else in the file's. A
    /// channel with a value that is not finite is refused, naming the file and the pixel.
    pub fn read_exr(path: &Path) -> Result<VisibilityChannels, ImageError> {
        use exr::prelude::*;
        let (width, height, bytes) =
            exr_layout(path, is_visibility_channel).map_err(|e| match e {
                ImageError::NoVChannel { path, found } => {
                    ImageError::NoLightChannels { path, found }
                }
                other => other,
            })?;
        fits_memory(path, width, height, bytes)?;
        let image = crate::image_files::read_flat(path)?;
        let Some(layer) = image.layer_data.iter().find(|l| {
            l.channel_data
                .list
                .iter()
                .any(|c| is_visibility_channel(&c.name.to_string()))
        }) else {
            return Err(ImageError::NoLightChannels {
                path: path.to_path_buf(),
                found: Vec::new(),
            });
        };
        let (w, h) = (layer.size.width() as u32, layer.size.height() as u32);
        let mut channels: Vec<Channel> = layer
            .channel_data
            .list
            .iter()
            .map(|c| (c.name.to_string(), c))
            .filter(|(name, _)| is_visibility_channel(name))
            .map(|(name, c)| Channel {
                name,
                image: VisibilityImage {
                    width: w,
                    height: h,
                    data: c.sample_data.values_as_f32().collect(),
                },
            })
            .collect();
        if let Some(AttributeValue::TextVector(order)) =
            layer.attributes.other.get(&Text::from(LIGHTS_ATTRIBUTE))
        {
            // The listed channels first, in the listed order; any others after them.
            let rank = ranks(order.iter().map(|t| t.to_string()));
            channels.sort_by_key(|c| rank.get(&c.name).copied().unwrap_or(usize::MAX));
        }
        // Visibility is a number: a channel holding NaN or an infinity is not one.
        for c in &channels {
            if let Err(e) = c.image.check() {
                return Err(io_err(path, format_args!("channel {}: {e}", c.name)));
            }
        }
        VisibilityChannels::new(channels).map_err(|e| io_err(path, e))
    }

    /// The width, height and visibility channels' names (in the order [`Self::read_exr`] gives
    /// them) of an EXR, from its header alone.
    pub fn read_exr_names(path: &Path) -> Result<(u64, u64, Vec<String>), ImageError> {
        let (w, h, _) = exr_layout(path, is_visibility_channel).map_err(|e| match e {
            ImageError::NoVChannel { path, found } => ImageError::NoLightChannels { path, found },
            other => other,
        })?;
        let meta = exr::meta::MetaData::read_from_file(path, false).map_err(|e| io_err(path, e))?;
        let header = meta.headers.iter().find(|h| {
            h.channels
                .list
                .iter()
                .any(|c| is_visibility_channel(&c.name.to_string()))
        });
        let mut names: Vec<String> = header
            .map(|h| {
                h.channels
                    .list
                    .iter()
                    .map(|c| c.name.to_string())
                    .filter(|n| is_visibility_channel(n))
                    .collect()
            })
            .unwrap_or_default();
        if let Some(exr::meta::attribute::AttributeValue::TextVector(order)) =
            header.and_then(|h| {
                h.own_attributes
                    .other
                    .get(&exr::meta::attribute::Text::from(LIGHTS_ATTRIBUTE))
            })
        {
            let rank = ranks(order.iter().map(|t| t.to_string()));
            names.sort_by_key(|n| rank.get(n).copied().unwrap_or(usize::MAX));
        }
        Ok((w, h, names))
    }

    /// The channel `name` of an EXR, or an error naming the file and the channels it has.
    pub fn read_exr_channel(path: &Path, name: &str) -> Result<VisibilityImage, ImageError> {
        let all = VisibilityChannels::read_exr(path)?;
        match all.get(name) {
            Some(image) => Ok(image.clone()),
            None => Err(ImageError::NoChannel {
                path: path.to_path_buf(),
                channel: name.to_string(),
                found: all.names().iter().map(|n| n.to_string()).collect(),
            }),
        }
    }
}

/// Each name's first place in `order`: a light-order attribute of any length is applied in time
/// proportional to it and to the channels.
fn ranks(order: impl Iterator<Item = String>) -> std::collections::HashMap<String, usize> {
    let mut rank = std::collections::HashMap::new();
    for (k, name) in order.enumerate() {
        rank.entry(name).or_insert(k);
    }
    rank
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(width: u32, height: u32, offset: f32) -> VisibilityImage {
        let mut img = VisibilityImage::filled(width, height, 0.0);
        for (i, v) in img.data.iter_mut().enumerate() {
            *v = (i as f32 / (width * height) as f32 + offset).fract();
        }
        img
    }

    fn dir(name: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("penumbra-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn one_channel_v_is_the_single_image_file_byte_for_byte() {
        let d = dir("channels-single");
        let img = ramp(7, 5, 0.3);
        img.write_exr(&d.join("a.exr")).unwrap();
        VisibilityChannels::single(img.clone())
            .write_exr(&d.join("b.exr"))
            .unwrap();
        assert_eq!(
            std::fs::read(d.join("a.exr")).unwrap(),
            std::fs::read(d.join("b.exr")).unwrap()
        );
        let back = VisibilityChannels::read_exr(&d.join("b.exr")).unwrap();
        assert!(back.is_single());
        assert_eq!(back.get("V"), Some(&img));
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn several_channels_round_trip_in_the_scene_s_order() {
        let d = dir("channels-many");
        // Not in the sorted order that OpenEXR keeps in the file.
        let names = ["zeta.V", "alpha.V", "m-1.V"];
        let v = VisibilityChannels::new(
            names
                .iter()
                .enumerate()
                .map(|(k, n)| Channel {
                    name: n.to_string(),
                    image: ramp(6, 4, k as f32 * 0.25),
                })
                .collect(),
        )
        .unwrap();
        let p = d.join("m.exr");
        v.write_exr(&p).unwrap();
        let back = VisibilityChannels::read_exr(&p).unwrap();
        assert_eq!(back, v);
        assert_eq!(
            VisibilityChannels::read_exr_names(&p).unwrap(),
            (6, 4, names.map(String::from).to_vec())
        );
        assert_eq!(
            VisibilityChannels::read_exr_channel(&p, "alpha.V").unwrap(),
            ramp(6, 4, 0.25)
        );
        let e = VisibilityChannels::read_exr_channel(&p, "V").unwrap_err();
        assert!(
            matches!(&e, ImageError::NoChannel { channel, found, .. } if channel == "V" && found.len() == 3),
            "{e}"
        );
        // The single-image reader wants `V`, and says what it found.
        assert!(matches!(
            VisibilityImage::read_exr(&p),
            Err(ImageError::NoVChannel { .. })
        ));
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn bad_channel_sets_are_refused() {
        let c = |name: &str, w: u32| Channel {
            name: name.to_string(),
            image: VisibilityImage::filled(w, 2, 1.0),
        };
        assert!(VisibilityChannels::new(Vec::new()).is_err());
        assert!(VisibilityChannels::new(vec![c("a.V", 2), c("a.V", 2)]).is_err());
        assert!(VisibilityChannels::new(vec![c("a.V", 2), c("b.V", 3)]).is_err());
        assert!(VisibilityChannels::new(vec![c("a.R", 2)]).is_err());
        assert!(VisibilityChannels::new(vec![c(".V", 2)]).is_err());
        assert!(VisibilityChannels::new(vec![c("a.V", 2), c("b.V", 2)]).is_ok());
    }
}
