//! Scene files: the public TOML contract (see `docs/scene-format.md`).
//!
//! ```toml
//! [camera]
//! eye = [x, y, z]
//! target = [x, y, z]
//! up = [0, 1, 0]
//! fov_y_deg = 45.0
//! width = 640
//! height = 480
//!
//! [light]                   # rectangular area light, emitting on the side its normal points to
//! center = [x, y, z]
//! normal = [0, -1, 0]       # unit
//! tangent = [1, 0, 0]       # unit, orthogonal to normal
//! size = [w, h]             # along tangent, along cross(normal, tangent)
//!
//! # or a distant light (the sun), the rectangle of directions around `direction`:
//! # [light]
//! # distant = true
//! # direction = [x, y, z]   # unit, from the scene towards the light's centre
//! # tangent = [1, 0, 0]     # unit, orthogonal to direction
//! # angular_size = [a, b]   # full angles in degrees, each in (0, 90]
//!
//! # or several lights, each rendered into its own channel `<name>.V`:
//! # [[light]]
//! # name = "key"            # optional: ASCII letters, digits, `-`, `_`; default light0, light1, ...
//! # center = ...            # and the other keys of `[light]`
//!
//! [[mesh]]                  # any number
//! obj = "meshes/foo.obj"    # relative to the scene file; or gltf = "x.glb", or ply = "x.ply"
//! scale = 1.0               # optional: number or [sx, sy, sz]
//! rotate_axis_angle = [ax, ay, az, degrees]   # optional
//! translate = [x, y, z]     # optional; world = translate * rotate * scale
//! ```
//!
//! Unknown keys are rejected with the key's name and line. Every error names the scene file and
//! the line of the offending value.

use std::path::{Path, PathBuf};

use glam::{DMat4, DQuat, DVec3};
use serde::Deserialize;
use toml::Spanned;

use crate::camera::{Camera, CameraError};
use crate::limits::{MAX_COORDINATE, MAX_FOV_DEG, MIN_FOV_DEG, within_coordinates};
use crate::mesh::TriangleMesh;
use crate::mesh_format::MeshFormat;
use crate::scene::{Scene, SceneMesh};
use crate::scene_error::SceneError;
use crate::scene_file_lights::{LightDesc, read_lights};
use crate::scene_values::{OneOrMany, Scale, Table, Vector};
use penumbra_params::TechniqueParams;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    camera: Spanned<Table<CameraDesc>>,
    light: Spanned<OneOrMany<LightDesc, LightDesc>>,
    #[serde(default)]
    mesh: Vec<Spanned<MeshDesc>>,
    // The shadow-map techniques' tables (`penumbra_params::TABLES`; a test checks that these
    // are the same), read key by key by `penumbra_params`.
    shadow_map: Option<Spanned<toml::Table>>,
    pcf: Option<Spanned<toml::Table>>,
    pcss: Option<Spanned<toml::Table>>,
    fractional_disk: Option<Spanned<toml::Table>>,
    mdsm: Option<Spanned<toml::Table>>,
    gaussian: Option<Spanned<toml::Table>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraDesc {
    eye: Spanned<Vector<3>>,
    target: Spanned<Vector<3>>,
    up: Spanned<Vector<3>>,
    fov_y_deg: Spanned<f64>,
    width: Spanned<u32>,
    height: Spanned<u32>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MeshDesc {
    obj: Option<Spanned<String>>,
    gltf: Option<Spanned<String>>,
    ply: Option<Spanned<String>>,
    scale: Option<Spanned<Scale>>,
    rotate_axis_angle: Option<Spanned<Vector<4>>>,
    translate: Option<Spanned<Vector<3>>>,
}

/// 1-based line of byte offset `at` in `text`.
fn line_of(text: &str, at: usize) -> usize {
    text.as_bytes()[..at.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// The line of a syntax error the parser reports without a position (a key of too many parts):
/// the first line whose text up to and including it already fails that way (0 when none does).
fn spanless_line(text: &str) -> usize {
    let ends: Vec<usize> = text
        .match_indices('\n')
        .map(|(i, _)| i + 1)
        .chain((!text.ends_with('\n')).then_some(text.len()))
        .collect();
    let fails = |k: usize| {
        toml::from_str::<toml::Table>(&text[..ends[k]]).is_err_and(|e| e.span().is_none())
    };
    // The parser reads in order: once the prefix holds the line, it fails there first.
    let (mut lo, mut hi) = (0, ends.len());
    if hi == 0 || !fails(hi - 1) {
        return 0;
    }
    while lo < hi {
        let mid = (lo + hi) / 2;
        if fails(mid) {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    lo + 1
}

impl Scene {
    /// Loads and validates a scene file and every mesh it names.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let text = crate::input::read_text(path).map_err(|error| SceneError::Io {
            path: path.to_path_buf(),
            error,
        })?;
        Scene::from_toml(&text, path)
    }

    /// Parses scene text as if read from `path` (mesh paths are relative to its folder).
    pub fn from_toml(text: &str, path: &Path) -> Result<Scene, SceneError> {
        // A UTF-8 byte-order mark is not part of the first line.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let file: SceneFile = toml::from_str(text).map_err(|e| {
            if let Some(line) = both_light_forms(text) {
                return SceneError::Syntax {
                    path: path.to_path_buf(),
                    line,
                    message:
                        "`[light]` and `[[light]]` in one file: write one light as `[light]`, \
                              or every light as `[[light]]`"
                            .to_string(),
                };
            }
            let mut message = e.message().trim().to_string();
            if message == "recursion limit" {
                message =
                    "a dotted key of more than 80 parts is beyond the parser's recursion limit"
                        .to_string();
            }
            SceneError::Syntax {
                path: path.to_path_buf(),
                line: e
                    .span()
                    .map_or_else(|| spanless_line(text), |s| line_of(text, s.start)),
                message,
            }
        })?;
        let invalid = |span: std::ops::Range<usize>, message: String| SceneError::Invalid {
            path: path.to_path_buf(),
            line: line_of(text, span.start),
            message,
        };
        let finite3 = |v: &Spanned<Vector<3>>, key: &str| -> Result<DVec3, SceneError> {
            let d = DVec3::from(v.get_ref().0);
            if d.is_finite() && !within_coordinates(d) {
                return Err(invalid(
                    v.span(),
                    format!(
                        "{key} = {d} lies outside the supported range (coordinates up to {MAX_COORDINATE:e})"
                    ),
                ));
            }
            if d.is_finite() {
                Ok(d)
            } else {
                Err(invalid(
                    v.span(),
                    format!("{key} = {:?} is not finite", v.get_ref().0),
                ))
            }
        };

        let c = &file.camera.get_ref().0;
        let fov = *c.fov_y_deg.get_ref();
        if fov.is_finite() && fov > 0.0 && !(MIN_FOV_DEG..=MAX_FOV_DEG).contains(&fov) {
            return Err(invalid(
                c.fov_y_deg.span(),
                format!(
                    "camera.fov_y_deg = {fov} lies outside the supported range [{MIN_FOV_DEG}, {MAX_FOV_DEG}] degrees"
                ),
            ));
        }
        let eye = finite3(&c.eye, "camera.eye")?;
        let target = finite3(&c.target, "camera.target")?;
        let up = finite3(&c.up, "camera.up")?;
        let camera = Camera::look_at(
            eye,
            target,
            up,
            *c.fov_y_deg.get_ref(),
            *c.width.get_ref(),
            *c.height.get_ref(),
        )
        .map_err(|e| {
            let span = match e {
                CameraError::EyeIsTarget => c.target.span(),
                CameraError::UpParallel { .. } | CameraError::UpZero(_) => c.up.span(),
                CameraError::EmptyImage { width: 0, .. } => c.width.span(),
                CameraError::EmptyImage { .. } => c.height.span(),
                CameraError::BadFov(_) => c.fov_y_deg.span(),
            };
            invalid(span, format!("camera: {e}"))
        })?;

        let (lights, named_channels) = read_lights(&file.light, &invalid, &finite3)?;

        let base = path.parent().unwrap_or(Path::new("."));
        let mut meshes = Vec::with_capacity(file.mesh.len());
        // Each file is read and parsed once, however many entries name it.
        let mut loaded: std::collections::HashMap<(PathBuf, MeshFormat), TriangleMesh> =
            std::collections::HashMap::new();
        for (index, entry) in file.mesh.iter().enumerate() {
            let (format, name) =
                mesh_file(entry, index).map_err(|(span, msg)| invalid(span, msg))?;
            let m = entry.get_ref();
            let transform = mesh_transform(m).map_err(|(span, msg)| invalid(span, msg))?;
            let source = base.join(name.get_ref());
            let mesh = match loaded.get(&(source.clone(), format)) {
                Some(mesh) => mesh,
                None => {
                    let mesh =
                        TriangleMesh::load(&source, format).map_err(|e| SceneError::Mesh {
                            path: path.to_path_buf(),
                            line: line_of(text, name.span().start),
                            mesh: index,
                            error: e,
                        })?;
                    loaded.entry((source.clone(), format)).or_insert(mesh)
                }
            };
            let world = mesh.transformed(&transform);
            if let Some(v) = world.positions.iter().find(|v| !within_coordinates(**v)) {
                return Err(invalid(
                    name.span(),
                    format!(
                        "mesh {index} ({}) has a vertex at {v} after its transform, outside the supported range (coordinates up to {MAX_COORDINATE:e})",
                        name.get_ref()
                    ),
                ));
            }
            meshes.push(SceneMesh {
                mesh: world,
                source,
                transform,
            });
        }
        let mut params = TechniqueParams::default();
        let tables = [
            ("shadow_map", &file.shadow_map),
            ("pcf", &file.pcf),
            ("pcss", &file.pcss),
            ("fractional_disk", &file.fractional_disk),
            ("mdsm", &file.mdsm),
            ("gaussian", &file.gaussian),
        ];
        // The line of `key` in table `table`, else of the table.
        let line_span = |table: &str, key: &str| {
            let Some((_, Some(t))) = tables.iter().find(|(n, _)| *n == table) else {
                return 0..0;
            };
            // The table's span may be its header alone: its keys run to the next header.
            let span = t.span();
            let rest = &text[span.start..];
            let end = rest
                .match_indices("\n[")
                .next()
                .map_or(rest.len(), |(i, _)| i);
            let body = &rest[..end];
            let at = body
                .match_indices(key)
                .find(|&(i, _)| {
                    let before = body[..i].chars().next_back();
                    let after = body[i + key.len()..].trim_start();
                    matches!(before, None | Some('\n' | ' ' | '\t')) && after.starts_with('=')
                })
                .map_or(0, |(i, _)| i);
            span.start + at..span.start + end
        };
        for (name, table) in &tables {
            if let Some(t) = table {
                params
                    .read_table(name, t.get_ref())
                    .map_err(|e| invalid(line_span(&e.table, &e.key), e.to_string()))?;
            }
        }
        params
            .validate()
            .map_err(|e| invalid(line_span(&e.table, &e.key), e.to_string()))?;
        Ok(Scene {
            path: path.to_path_buf(),
            camera,
            lights,
            meshes: std::sync::Arc::new(meshes),
            params,
            named_channels,
        })
    }
}

/// The line of the later of a `[light]` and a `[[light]]` header, where the text has both (the
/// TOML parser says only "duplicate key" of them).
fn both_light_forms(text: &str) -> Option<usize> {
    let header = |line: &str, open: &str, close: &str| {
        line.trim()
            .strip_prefix(open)
            .and_then(|r| r.split('#').next())
            .and_then(|r| r.trim_end().strip_suffix(close))
            .is_some_and(|k| matches!(k.trim(), "light" | "\"light\"" | "'light'"))
    };
    let (mut one, mut many) = (None, None);
    for (i, line) in text.lines().enumerate() {
        if header(line, "[[", "]]") {
            many.get_or_insert(i + 1);
        } else if header(line, "[", "]") {
            one.get_or_insert(i + 1);
        }
    }
    Some(one?.max(many?))
}

type SpanError = (std::ops::Range<usize>, String);

/// The mesh file of `[[mesh]]` entry `index` and its format: exactly one of its keys `obj`,
/// `gltf` and `ply`.
fn mesh_file(
    m: &Spanned<MeshDesc>,
    index: usize,
) -> Result<(MeshFormat, &Spanned<String>), SpanError> {
    let d = m.get_ref();
    let given: Vec<(MeshFormat, &Spanned<String>)> = [&d.obj, &d.gltf, &d.ply]
        .into_iter()
        .zip(MeshFormat::ALL)
        .filter_map(|(file, format)| Some((format, file.as_ref()?)))
        .collect();
    match given.as_slice() {
        [one] => Ok(*one),
        [] => Err((
            m.span(),
            format!("mesh {index} names no mesh file: give one of `obj`, `gltf` or `ply`"),
        )),
        [_, _, ..] => Err((
            // The later key's line.
            given
                .iter()
                .map(|(_, file)| file.span())
                .max_by_key(|span| span.start)
                .expect("two or more"),
            format!(
                "mesh {index} names {} mesh files ({}): give exactly one of `obj`, `gltf` or `ply`",
                given.len(),
                given
                    .iter()
                    .map(|(f, _)| format!("`{}`", f.key()))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )),
    }
}

fn mesh_transform(m: &MeshDesc) -> Result<DMat4, SpanError> {
    let scale = match m.scale.as_ref() {
        None => DVec3::ONE,
        Some(s) => {
            let v = match *s.get_ref() {
                Scale::Uniform(k) => DVec3::splat(k),
                Scale::PerAxis(a) => DVec3::from(a),
            };
            if !v.is_finite() || v.x == 0.0 || v.y == 0.0 || v.z == 0.0 {
                return Err((s.span(), format!("scale {v} must be finite and non-zero")));
            }
            v
        }
    };
    let rotation = match m.rotate_axis_angle.as_ref() {
        None => DQuat::IDENTITY,
        Some(r) => {
            let [x, y, z, deg] = r.get_ref().0;
            let axis = DVec3::new(x, y, z);
            match axis.try_normalize() {
                Some(a) if deg.is_finite() => DQuat::from_axis_angle(a, deg.to_radians()),
                _ => {
                    return Err((
                        r.span(),
                        format!(
                            "rotate_axis_angle {:?} needs a non-zero finite axis and a finite angle",
                            r.get_ref().0
                        ),
                    ));
                }
            }
        }
    };
    let translate = match m.translate.as_ref() {
        None => DVec3::ZERO,
        Some(t) => {
            let v = DVec3::from(t.get_ref().0);
            if !v.is_finite() {
                return Err((t.span(), format!("translate {v} is not finite")));
            }
            v
        }
    };
    Ok(DMat4::from_scale_rotation_translation(
        scale, rotation, translate,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    const CAMERA_AND_LIGHT: &str = "[camera]\neye = [0.0, 3.0, 4.0]\ntarget = [0.0, 0.0, 0.0]\n\
        up = [0.0, 1.0, 0.0]\nfov_y_deg = 45.0\nwidth = 8\nheight = 6\n\n[light]\n\
        center = [0.0, 4.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\ntangent = [1.0, 0.0, 0.0]\n\
        size = [1.0, 1.0]\n\n";

    #[test]
    fn every_shadow_map_table_is_read_and_errors_name_the_key_line() {
        // The documented block: every table of `penumbra_params::TABLES`, every key.
        let text = format!("{CAMERA_AND_LIGHT}{}", penumbra_params::toml_reference());
        let scene = Scene::from_toml(&text, Path::new("s.toml")).unwrap();
        assert_eq!(scene.params, TechniqueParams::default());
        let text = format!("{CAMERA_AND_LIGHT}[mdsm]\ndepths = 2\nextra = \"min\"\nkernel = 9\n");
        let scene = Scene::from_toml(&text, Path::new("s.toml"));
        let Err(SceneError::Invalid { line, message, .. }) = scene else {
            panic!("{scene:?}")
        };
        assert_eq!(line, text.lines().count(), "{message}");
        assert_eq!(message, "mdsm.kernel: 9 is not in 2..=5");
        let text = format!("{CAMERA_AND_LIGHT}[pcss]\nsearch = 4\n\n[pfc]\nkernel = 3\n");
        assert!(Scene::from_toml(&text, Path::new("s.toml")).is_err());
    }

    #[test]
    fn a_byte_order_mark_is_not_part_of_the_first_line() {
        let plain = Scene::from_toml(CAMERA_AND_LIGHT, Path::new("s.toml")).unwrap();
        let marked =
            Scene::from_toml(&format!("\u{feff}{CAMERA_AND_LIGHT}"), Path::new("s.toml")).unwrap();
        assert_eq!(marked.camera.width, plain.camera.width);
        // Errors keep their lines.
        let text = format!("\u{feff}{CAMERA_AND_LIGHT}[pcss]\nsearch = 0\n");
        let Err(SceneError::Invalid { line, .. }) = Scene::from_toml(&text, Path::new("s.toml"))
        else {
            panic!("search = 0 accepted")
        };
        assert_eq!(line, text.lines().count());
    }

    #[test]
    fn a_key_of_too_many_parts_names_its_line() {
        for parts in [81, 50_000] {
            let key = vec!["a"; parts].join(".");
            for body in [format!("{key} = 1\n"), format!("[{key}]\nb = 2\n")] {
                // After a multi-line array, which a shorter prefix would cut.
                let text = format!("{CAMERA_AND_LIGHT}[pcss]\nsearch = 4\nx = [\n1,\n2]\n{body}");
                let want = text.lines().count() - body.lines().count() + 1;
                let Err(SceneError::Syntax { line, message, .. }) =
                    Scene::from_toml(&text, Path::new("s.toml"))
                else {
                    panic!("{parts} parts accepted")
                };
                assert_eq!(line, want, "{message}");
                assert!(message.contains("more than 80 parts"), "{message}");
            }
        }
    }
}
