//! The lights of a scene file: its one `[light]`, or the named lights of `[[light]]`, each
//! checked as `[light]` is, their names valid and unique (see `docs/scene-format.md`).

use std::ops::Range;

use glam::{DVec2, DVec3};
use toml::Spanned;

use crate::light::RectLight;
use crate::lights::{NamedLight, check_light_name, default_light_name};
use crate::range::{MAX_COORDINATE, UNIT_TOLERANCE};
use crate::scene_file::{LightDesc, SceneError};
use crate::scene_values::{OneOrMany, Vector};

/// Makes the error of a value at a span of the scene file.
pub(crate) type Invalid<'a> = dyn Fn(Range<usize>, String) -> SceneError + 'a;

/// Reads a point of the scene file, named by its key, within the supported range.
pub(crate) type Point<'a> = dyn Fn(&Spanned<Vector<3>>, &str) -> Result<DVec3, SceneError> + 'a;

/// The scene's light ([`crate::Scene::light`]) and its named lights ([`crate::Scene::lights`],
/// empty for a `[light]`) from the file's `light`: `invalid` makes the error of a value at a
/// span, `finite3` reads a point within the supported range.
pub(crate) fn read_lights(
    light: &Spanned<OneOrMany<LightDesc, LightDesc>>,
    invalid: &Invalid,
    finite3: &Point,
) -> Result<(RectLight, Vec<NamedLight>), SceneError> {
    // A light's keys, named `key` (`light`, or `light[k]` of several) in messages.
    let read_light = |l: &LightDesc, key: &str| -> Result<RectLight, SceneError> {
        let center = finite3(&l.center, &format!("{key}.center"))?;
        let normal = finite3(&l.normal, &format!("{key}.normal"))?;
        let tangent = finite3(&l.tangent, &format!("{key}.tangent"))?;
        if (normal.length() - 1.0).abs() > UNIT_TOLERANCE {
            return Err(invalid(
                l.normal.span(),
                format!(
                    "{key}.normal {normal} is not unit length (|n| = {})",
                    normal.length()
                ),
            ));
        }
        if (tangent.length() - 1.0).abs() > UNIT_TOLERANCE {
            return Err(invalid(
                l.tangent.span(),
                format!(
                    "{key}.tangent {tangent} is not unit length (|t| = {})",
                    tangent.length()
                ),
            ));
        }
        if normal.dot(tangent).abs() > UNIT_TOLERANCE {
            return Err(invalid(
                l.tangent.span(),
                format!("{key}.tangent {tangent} is not orthogonal to {key}.normal {normal}"),
            ));
        }
        let size = DVec2::from(l.size.get_ref().0);
        if !(size.x > 0.0 && size.y > 0.0 && size.is_finite()) {
            return Err(invalid(
                l.size.span(),
                format!("{key}.size {size} must be two positive finite lengths"),
            ));
        }
        if size.max_element() > MAX_COORDINATE {
            return Err(invalid(
                l.size.span(),
                format!(
                    "{key}.size {size} lies outside the supported range (sides up to {MAX_COORDINATE:e})"
                ),
            ));
        }
        // Remove the tolerated rounding so that the light frame is exactly orthonormal.
        let n = normal.normalize();
        let t = (tangent - n * n.dot(tangent)).normalize();
        Ok(RectLight::new(center, n, t, size))
    };
    match light.get_ref() {
        OneOrMany::One(l) => {
            if let Some(name) = &l.name {
                return Err(invalid(
                    name.span(),
                    "light.name: a name is for the lights of `[[light]]`; the one light of \
                     `[light]` has none (its channel is `V`)"
                        .to_string(),
                ));
            }
            Ok((read_light(l, "light")?, Vec::new()))
        }
        OneOrMany::Many(entries) => {
            if entries.is_empty() {
                return Err(invalid(
                    light.span(),
                    "light: an empty array; a scene needs one light at least".to_string(),
                ));
            }
            let mut lights: Vec<NamedLight> = Vec::with_capacity(entries.len());
            for (k, entry) in entries.iter().enumerate() {
                let l = &entry.get_ref().0;
                let key = format!("light[{k}]");
                let name = match &l.name {
                    None => default_light_name(k),
                    Some(n) => {
                        check_light_name(n.get_ref())
                            .map_err(|e| invalid(n.span(), format!("{key}.name: {e}")))?;
                        n.get_ref().clone()
                    }
                };
                if let Some(first) = lights.iter().position(|o| o.name == name) {
                    let (span, whose) = match &l.name {
                        Some(n) => (n.span(), format!("{key}.name: {name:?}")),
                        None => (entry.span(), format!("{key}'s default name {name:?}")),
                    };
                    return Err(invalid(
                        span,
                        format!(
                            "{whose} is already the name of light[{first}]; light names are unique"
                        ),
                    ));
                }
                lights.push(NamedLight {
                    name,
                    light: read_light(l, &key)?,
                });
            }
            Ok((lights[0].light, lights))
        }
    }
}
