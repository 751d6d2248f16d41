//! The lights of a scene file: its one `[light]`, or the named lights of `[[light]]`, each
//! checked as `[light]` is, their names valid and unique (see `docs/scene-format.md`).

use std::ops::Range;

use glam::{DVec2, DVec3};
use toml::Spanned;

use serde::Deserialize;

use crate::distant::DistantLight;
use crate::light::RectLight;
use crate::light_error::LightError;
use crate::lights::{Light, NamedLight, check_light_name, default_light_name};
use crate::scene_error::SceneError;
use crate::scene_values::{OneOrMany, Vector};

/// A `[light]` table, or one entry of `[[light]]` (the only one with a `name`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct LightDesc {
    pub(crate) name: Option<Spanned<String>>,
    pub(crate) distant: Option<Spanned<bool>>,
    pub(crate) center: Option<Spanned<Vector<3>>>,
    pub(crate) normal: Option<Spanned<Vector<3>>>,
    pub(crate) target: Option<Spanned<Vector<3>>>,
    pub(crate) tangent: Option<Spanned<Vector<3>>>,
    pub(crate) size: Option<Spanned<Vector<2>>>,
    pub(crate) direction: Option<Spanned<Vector<3>>>,
    pub(crate) azimuth_deg: Option<Spanned<f64>>,
    pub(crate) elevation_deg: Option<Spanned<f64>>,
    pub(crate) angular_size: Option<Spanned<Vector<2>>>,
}

/// Makes the error of a value at a span of the scene file.
pub(crate) type Invalid<'a> = dyn Fn(Range<usize>, String) -> SceneError + 'a;

/// Reads a point of the scene file, named by its key, within the supported range.
pub(crate) type Point<'a> = dyn Fn(&Spanned<Vector<3>>, &str) -> Result<DVec3, SceneError> + 'a;

/// The scene's lights from the file's `light`, and whether they are `[[light]]` (each image
/// channel `<name>.V`) rather than the one `[light]` (channel `V`): `invalid` makes the error of
/// a value at a span, `finite3` reads a point within the supported range.
pub(crate) fn read_lights(
    light: &Spanned<OneOrMany<LightDesc, LightDesc>>,
    invalid: &Invalid,
    finite3: &Point,
) -> Result<(Vec<NamedLight>, bool), SceneError> {
    // A light's keys, named `key` (`light`, or `light[k]` of several) in messages; `span` is
    // its table's.
    let read_light = |l: &LightDesc, key: &str, span: Range<usize>| -> Result<Light, SceneError> {
        let distant = l.distant.as_ref().is_some_and(|d| *d.get_ref());
        let angles = l.azimuth_deg.is_some() || l.elevation_deg.is_some();
        // The keys that differ between the forms, where the table has them.
        let keys = [
            ("center", l.center.as_ref().map(Spanned::span)),
            ("normal", l.normal.as_ref().map(Spanned::span)),
            ("target", l.target.as_ref().map(Spanned::span)),
            ("size", l.size.as_ref().map(Spanned::span)),
            ("direction", l.direction.as_ref().map(Spanned::span)),
            ("azimuth_deg", l.azimuth_deg.as_ref().map(Spanned::span)),
            ("elevation_deg", l.elevation_deg.as_ref().map(Spanned::span)),
            ("angular_size", l.angular_size.as_ref().map(Spanned::span)),
        ];
        let (form, own): (&str, &[&str]) = match (distant, angles, l.target.is_some()) {
            (true, false, _) => (
                "a distant light (`distant = true`)",
                &["direction", "angular_size"],
            ),
            (true, true, _) => (
                "a distant light given by its angles",
                &["azimuth_deg", "elevation_deg", "angular_size"],
            ),
            (false, _, false) => ("a rectangle light", &["center", "normal", "size"]),
            (false, _, true) => (
                "a rectangle light aimed at a target",
                &["center", "target", "size"],
            ),
        };
        if distant && angles && l.direction.is_some() {
            let at = l.direction.as_ref().map(Spanned::span).expect("present");
            return Err(invalid(
                at,
                format!("{key}: give `direction`, or `azimuth_deg` and `elevation_deg`, not both"),
            ));
        }
        if !distant && l.target.is_some() && l.normal.is_some() {
            let at = l.normal.as_ref().map(Spanned::span).expect("present");
            return Err(invalid(
                at,
                format!("{key}: give `normal` or `target`, not both"),
            ));
        }
        if let Some((name, _)) = keys.iter().find(|(n, s)| own.contains(n) && s.is_none()) {
            return Err(invalid(span, format!("{key}: {form} needs `{name}`")));
        }
        if let Some((name, Some(at))) = keys.iter().find(|(n, s)| !own.contains(n) && s.is_some()) {
            return Err(invalid(
                at.clone(),
                format!("{key}.{name} is not a key of {form}"),
            ));
        }
        // The tangent may be left out only where the light is aimed by a target or by angles.
        if l.tangent.is_none() && (l.normal.is_some() || l.direction.is_some()) {
            return Err(invalid(span, format!("{key}: {form} needs `tangent`")));
        }
        // A constructor's error at the span of the field it names.
        let refused = |e: LightError| {
            let field = match &e {
                LightError::NotFinite { field, .. }
                | LightError::OutOfRange { field, .. }
                | LightError::ZeroLength { field, .. }
                | LightError::NotUnit { field, .. }
                | LightError::Angle { field, .. } => *field,
                LightError::NotOrthogonal { .. } => "tangent",
                LightError::Size { .. } | LightError::SizeOutOfRange { .. } => "size",
                LightError::AngularSize { .. } => "angular_size",
                LightError::TargetAtCenter { .. } => "target",
                LightError::SunFrame { .. } => "azimuth_deg",
            };
            let at = keys
                .iter()
                .chain([("tangent", l.tangent.as_ref().map(Spanned::span))].iter())
                .find(|(n, _)| *n == field)
                .and_then(|(_, s)| s.clone())
                .unwrap_or_else(|| span.clone());
            let message = match &e {
                LightError::NotOrthogonal {
                    tangent,
                    axis_field,
                    axis,
                } => format!(
                    "{key}.tangent {tangent} is not orthogonal to {key}.{axis_field} {axis}"
                ),
                _ => format!("{key}.{e}"),
            };
            invalid(at, message)
        };
        let vector = |v: &Option<Spanned<Vector<3>>>, name: &str| -> Result<DVec3, SceneError> {
            finite3(v.as_ref().expect("checked above"), &format!("{key}.{name}"))
        };
        let tangent = match &l.tangent {
            Some(t) => Some(finite3(t, &format!("{key}.tangent"))?),
            None => None,
        };
        if distant {
            let a = DVec2::from(l.angular_size.as_ref().expect("checked above").get_ref().0);
            let light = if angles {
                let angle =
                    |v: &Option<Spanned<f64>>| *v.as_ref().expect("checked above").get_ref();
                let sun = DistantLight::sun_in(
                    DVec3::NEG_Z,
                    DVec3::Y,
                    angle(&l.azimuth_deg),
                    angle(&l.elevation_deg),
                    a,
                )
                .map_err(refused)?;
                match tangent {
                    Some(t) => DistantLight::new(sun.direction, t, a),
                    None => Ok(sun),
                }
            } else {
                let direction = vector(&l.direction, "direction")?;
                DistantLight::new(direction, tangent.expect("checked above"), a)
            };
            return Ok(Light::Distant(light.map_err(refused)?));
        }
        let center = vector(&l.center, "center")?;
        let size = DVec2::from(l.size.as_ref().expect("checked above").get_ref().0);
        let light = match (&l.target, tangent) {
            (Some(_), None) => RectLight::aimed(center, vector(&l.target, "target")?, size),
            (Some(_), Some(t)) => {
                let target = vector(&l.target, "target")?;
                let normal = (target - center)
                    .try_normalize()
                    .ok_or(LightError::TargetAtCenter { target })
                    .map_err(refused)?;
                RectLight::new(center, normal, t, size)
            }
            (None, t) => RectLight::new(
                center,
                vector(&l.normal, "normal")?,
                t.expect("checked above"),
                size,
            ),
        };
        Ok(Light::Rect(light.map_err(refused)?))
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
            let light = read_light(l, "light", light.span())?;
            Ok((
                vec![NamedLight {
                    name: default_light_name(0),
                    light,
                }],
                false,
            ))
        }
        OneOrMany::Many(entries) => {
            if entries.is_empty() {
                return Err(invalid(
                    light.span(),
                    "light: an empty array; a scene needs one light at least".to_string(),
                ));
            }
            let mut lights: Vec<NamedLight> = Vec::with_capacity(entries.len());
            // Each name, in lower case, and the first light that has it.
            let mut seen: std::collections::HashMap<String, usize> =
                std::collections::HashMap::with_capacity(entries.len());
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
                if let Some(&first) = seen.get(&name.to_ascii_lowercase()) {
                    let (span, whose) = match &l.name {
                        Some(n) => (n.span(), format!("{key}.name: {name:?}")),
                        None => (entry.span(), format!("{key}'s default name {name:?}")),
                    };
                    let other = &lights[first].name;
                    return Err(invalid(
                        span,
                        if *other == name {
                            format!(
                                "{whose} is already the name of light[{first}]; light names are unique"
                            )
                        } else {
                            format!(
                                "{whose} differs from light[{first}]'s name {other:?} only in case; \
                                 light names are unique in any case (their files would collide on a \
                                 file system that ignores case)"
                            )
                        },
                    ));
                }
                seen.insert(name.to_ascii_lowercase(), k);
                lights.push(NamedLight {
                    name,
                    light: read_light(l, &key, entry.span())?,
                });
            }
            Ok((lights, true))
        }
    }
}
