//! The lights of a scene file: its one `[light]`, or the named lights of `[[light]]`, each
//! checked as `[light]` is, their names valid and unique (see `docs/scene-format.md`).

use std::ops::Range;

use glam::{DVec2, DVec3};
use toml::Spanned;

use crate::distant::{DistantLight, Light};
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
) -> Result<(Light, Vec<NamedLight>), SceneError> {
    // A light's keys, named `key` (`light`, or `light[k]` of several) in messages; `span` is
    // its table's.
    let read_light = |l: &LightDesc, key: &str, span: Range<usize>| -> Result<Light, SceneError> {
        let distant = l.distant.as_ref().is_some_and(|d| *d.get_ref());
        // The keys that differ between the forms, where the table has them.
        let keys = [
            ("center", l.center.as_ref().map(Spanned::span)),
            ("normal", l.normal.as_ref().map(Spanned::span)),
            ("size", l.size.as_ref().map(Spanned::span)),
            ("direction", l.direction.as_ref().map(Spanned::span)),
            ("angular_size", l.angular_size.as_ref().map(Spanned::span)),
        ];
        let (form, own): (&str, &[&str]) = if distant {
            (
                "a distant light (`distant = true`)",
                &["direction", "angular_size"],
            )
        } else {
            ("a rectangle light", &["center", "normal", "size"])
        };
        if let Some((name, _)) = keys.iter().find(|(n, s)| own.contains(n) && s.is_none()) {
            return Err(invalid(span, format!("{key}: {form} needs `{name}`")));
        }
        if let Some((name, Some(at))) = keys.iter().find(|(n, s)| !own.contains(n) && s.is_some()) {
            return Err(invalid(
                at.clone(),
                format!("{key}.{name} is not a key of {form}"),
            ));
        }
        let unit = |v: &Spanned<Vector<3>>, name: &str| -> Result<DVec3, SceneError> {
            let x = finite3(v, &format!("{key}.{name}"))?;
            if (x.length() - 1.0).abs() > UNIT_TOLERANCE {
                return Err(invalid(
                    v.span(),
                    format!(
                        "{key}.{name} {x} is not unit length (|{name}| = {})",
                        x.length()
                    ),
                ));
            }
            Ok(x)
        };
        let (axis, axis_name) = if distant {
            let d = l.direction.as_ref().expect("checked above");
            (unit(d, "direction")?, "direction")
        } else {
            let n = l.normal.as_ref().expect("checked above");
            (unit(n, "normal")?, "normal")
        };
        let tangent = unit(&l.tangent, "tangent")?;
        if axis.dot(tangent).abs() > UNIT_TOLERANCE {
            return Err(invalid(
                l.tangent.span(),
                format!("{key}.tangent {tangent} is not orthogonal to {key}.{axis_name} {axis}"),
            ));
        }
        // Remove the tolerated rounding so that the light frame is exactly orthonormal.
        let n = axis.normalize();
        let t = (tangent - n * n.dot(tangent)).normalize();
        if distant {
            let angles = l.angular_size.as_ref().expect("checked above");
            let a = DVec2::from(angles.get_ref().0);
            if !(a.x > 0.0 && a.x <= 90.0 && a.y > 0.0 && a.y <= 90.0) {
                return Err(invalid(
                    angles.span(),
                    format!(
                        "{key}.angular_size {a} must be two full angles in degrees, each in (0, 90]"
                    ),
                ));
            }
            return Ok(Light::Distant(DistantLight::new(n, t, a)));
        }
        let center = finite3(
            l.center.as_ref().expect("checked above"),
            &format!("{key}.center"),
        )?;
        let size_at = l.size.as_ref().expect("checked above");
        let size = DVec2::from(size_at.get_ref().0);
        if !(size.x > 0.0 && size.y > 0.0 && size.is_finite()) {
            return Err(invalid(
                size_at.span(),
                format!("{key}.size {size} must be two positive finite lengths"),
            ));
        }
        if size.max_element() > MAX_COORDINATE {
            return Err(invalid(
                size_at.span(),
                format!(
                    "{key}.size {size} lies outside the supported range (sides up to {MAX_COORDINATE:e})"
                ),
            ));
        }
        Ok(Light::Rect(RectLight::new(center, n, t, size)))
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
            Ok((read_light(l, "light", light.span())?, Vec::new()))
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
                    light: read_light(l, &key, entry.span())?,
                });
            }
            Ok((lights[0].light, lights))
        }
    }
}
