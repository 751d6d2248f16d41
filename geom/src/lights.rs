//! A scene's several lights (`[[light]]` in a scene file): each light's name, the name of its
//! image channel (`<name>.V`), and the rules a name keeps.

use crate::distant::DistantLight;
use crate::light::RectLight;

/// A light of a scene: a rectangle at a finite distance, or a distant light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// A one-sided rectangular area light (`[light]` with `center`, `normal`, `tangent`,
    /// `size`).
    Rect(RectLight),
    /// A distant light (`distant = true`, `direction`, `tangent`, `angular_size`).
    Distant(DistantLight),
}

impl Light {
    /// The rectangle light, if this is one.
    pub fn as_rect(&self) -> Option<&RectLight> {
        match self {
            Light::Rect(l) => Some(l),
            Light::Distant(_) => None,
        }
    }

    /// The distant light, if this is one.
    pub fn as_distant(&self) -> Option<&DistantLight> {
        match self {
            Light::Distant(l) => Some(l),
            Light::Rect(_) => None,
        }
    }
}

impl From<RectLight> for Light {
    fn from(l: RectLight) -> Light {
        Light::Rect(l)
    }
}

impl From<DistantLight> for Light {
    fn from(l: DistantLight) -> Light {
        Light::Distant(l)
    }
}

/// The longest light name, in bytes: a name becomes part of file names (`OUT.<name>.png`).
pub const MAX_LIGHT_NAME: usize = 64;

/// One light of a scene with several, and its name.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedLight {
    /// The name: ASCII letters, digits, `-` and `_`, unique in its scene; `light0`, `light1`,
    /// ... by position where the scene file gives none.
    pub name: String,
    /// The light: a rectangle or a distant light.
    pub light: Light,
}

impl NamedLight {
    /// The light with `name`, checked by [`check_light_name`].
    pub fn new(name: &str, light: impl Into<Light>) -> Result<NamedLight, LightNameError> {
        check_light_name(name)?;
        Ok(NamedLight {
            name: name.to_string(),
            light: light.into(),
        })
    }

    /// The name of this light's channel in an image file: `<name>.V`, the OpenEXR layer
    /// convention (the layer is the light, the channel `V`).
    pub fn channel(&self) -> String {
        light_channel(&self.name)
    }
}

/// The channel of the light named `name`: `<name>.V`.
pub fn light_channel(name: &str) -> String {
    format!("{name}.{}", crate::image_files::CHANNEL)
}

/// The name a light is given where its scene file gives none: `light<index>`, `index` its
/// 0-based position among the scene's lights.
pub fn default_light_name(index: usize) -> String {
    format!("light{index}")
}

/// What is wrong with a light's name, or with the names of a scene's lights.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LightNameError {
    /// An empty name.
    #[error("a light's name must not be empty")]
    Empty,
    /// A name longer than [`MAX_LIGHT_NAME`] bytes.
    #[error("light name {name:?} is longer than {MAX_LIGHT_NAME} bytes")]
    TooLong {
        /// The name.
        name: String,
    },
    /// A name with a character other than ASCII letters, digits, `-` and `_`.
    #[error(
        "light name {name:?} has the character {bad:?}: a name takes ASCII letters, digits, `-` and `_`"
    )]
    BadCharacter {
        /// The name.
        name: String,
        /// Its first character that a name cannot hold.
        bad: char,
    },
    /// Two lights of one scene with the same name.
    #[error("light {index}'s name {name:?} is already light {first}'s")]
    Duplicate {
        /// The name.
        name: String,
        /// The 0-based position of the first light with this name.
        first: usize,
        /// The 0-based position of the light that repeats it.
        index: usize,
    },
    /// Two lights whose names differ only in case: their files (`OUT.<name>.png`) would be one
    /// file on a file system that ignores case.
    #[error(
        "light {index}'s name {name:?} differs from light {first}'s {other:?} only in case: their \
         files would collide on a file system that ignores case"
    )]
    SameButCase {
        /// The name.
        name: String,
        /// The other light's name.
        other: String,
        /// The 0-based position of the first light.
        first: usize,
        /// The 0-based position of the light that repeats it.
        index: usize,
    },
    /// A scene of several lights given none.
    #[error("a scene of several lights needs at least one light")]
    NoLights,
}

/// Whether `name` can name a light: 1 to [`MAX_LIGHT_NAME`] ASCII letters, digits, `-` and
/// `_` (so that `<name>.V` is one EXR layer and `OUT.<name>.png` one file name).
pub fn check_light_name(name: &str) -> Result<(), LightNameError> {
    if name.is_empty() {
        return Err(LightNameError::Empty);
    }
    if let Some(bad) = name
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || *c == '-' || *c == '_'))
    {
        return Err(LightNameError::BadCharacter {
            name: name.to_string(),
            bad,
        });
    }
    if name.len() > MAX_LIGHT_NAME {
        return Err(LightNameError::TooLong {
            name: name.to_string(),
        });
    }
    Ok(())
}

/// Whether `lights` can be a scene's lights: at least one, every name valid, no name twice,
/// not even in another case.
pub fn check_light_names(lights: &[NamedLight]) -> Result<(), LightNameError> {
    if lights.is_empty() {
        return Err(LightNameError::NoLights);
    }
    let mut seen: std::collections::HashMap<String, usize> =
        std::collections::HashMap::with_capacity(lights.len());
    for (index, l) in lights.iter().enumerate() {
        check_light_name(&l.name)?;
        if let Some(&first) = seen.get(&l.name.to_ascii_lowercase()) {
            let other = &lights[first].name;
            return Err(if *other == l.name {
                LightNameError::Duplicate {
                    name: l.name.clone(),
                    first,
                    index,
                }
            } else {
                LightNameError::SameButCase {
                    name: l.name.clone(),
                    other: other.clone(),
                    first,
                    index,
                }
            });
        }
        seen.insert(l.name.to_ascii_lowercase(), index);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec2, DVec3};

    fn light() -> RectLight {
        RectLight::new(DVec3::Y, DVec3::NEG_Y, DVec3::X, DVec2::ONE).unwrap()
    }

    #[test]
    fn names_take_letters_digits_dashes_and_underscores() {
        for good in [
            "key",
            "fill-2",
            "Rim_light",
            "0",
            &"a".repeat(MAX_LIGHT_NAME),
        ] {
            assert_eq!(check_light_name(good), Ok(()), "{good}");
        }
        assert_eq!(check_light_name(""), Err(LightNameError::Empty));
        for (bad, c) in [("a.b", '.'), ("key light", ' '), ("é", 'é'), ("a/b", '/')] {
            assert_eq!(
                check_light_name(bad),
                Err(LightNameError::BadCharacter {
                    name: bad.to_string(),
                    bad: c
                })
            );
        }
        let long = "a".repeat(MAX_LIGHT_NAME + 1);
        assert_eq!(
            check_light_name(&long),
            Err(LightNameError::TooLong { name: long.clone() })
        );
    }

    #[test]
    fn a_scene_s_names_are_unique_and_it_has_one_light_at_least() {
        let named = |n: &str| NamedLight::new(n, light()).unwrap();
        assert_eq!(check_light_names(&[named("a"), named("b")]), Ok(()));
        assert_eq!(
            check_light_names(&[named("a"), named("b"), named("a")]),
            Err(LightNameError::Duplicate {
                name: "a".to_string(),
                first: 0,
                index: 2
            })
        );
        assert_eq!(check_light_names(&[]), Err(LightNameError::NoLights));
        assert_eq!(named("key").channel(), "key.V");
        assert_eq!(default_light_name(3), "light3");
    }
}
