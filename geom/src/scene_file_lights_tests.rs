//! Scene files of several lights (`[[light]]`): what they read as, and the errors of bad ones.

use std::path::Path;

use crate::{Light, Scene, SceneError};

const CAMERA: &str = "[camera]\neye = [0.0, 3.0, 4.0]\ntarget = [0.0, 0.0, 0.0]\n\
    up = [0.0, 1.0, 0.0]\nfov_y_deg = 45.0\nwidth = 8\nheight = 6\n\n";

/// A light entry: `header` (`[light]` or `[[light]]`), extra lines, its centre's x.
fn light(header: &str, extra: &str, x: f64) -> String {
    format!(
        "{header}\n{extra}center = [{x:?}, 4.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\n\
         tangent = [1.0, 0.0, 0.0]\nsize = [1.0, 1.0]\n\n"
    )
}

/// The error of `text`: its line and message.
fn error(text: &str) -> (usize, String) {
    match Scene::from_toml(text, Path::new("s.toml")) {
        Err(
            SceneError::Invalid { line, message, .. } | SceneError::Syntax { line, message, .. },
        ) => (line, message),
        other => panic!("expected an error, got {other:?}"),
    }
}

/// The 1-based line of the `n`th (0-based) line of `text` that contains `needle`.
fn line_with(text: &str, needle: &str, n: usize) -> usize {
    text.lines()
        .enumerate()
        .filter(|(_, l)| l.contains(needle))
        .nth(n)
        .unwrap_or_else(|| panic!("no {needle:?} #{n}"))
        .0
        + 1
}

#[test]
fn one_light_table_has_no_names_and_one_channel_v() {
    let s = Scene::from_toml(
        &format!("{CAMERA}{}", light("[light]", "", 0.5)),
        Path::new("s.toml"),
    )
    .unwrap();
    assert!(!s.named_channels);
    assert_eq!(s.light_count(), 1);
    assert_eq!(s.channel_names(), ["V"]);
    assert_eq!(s.lit(0).light.center.x, 0.5);
}

#[test]
fn an_array_of_lights_reads_in_file_order_with_default_names() {
    let text = format!(
        "{CAMERA}{}{}{}",
        light("[[light]]", "name = \"key\"\n", 1.0),
        light("[[light]]", "", 2.0),
        light("[[light]]", "name = \"rim_2\"\n", 3.0)
    );
    let s = Scene::from_toml(&text, Path::new("s.toml")).unwrap();
    assert_eq!(s.light_names(), ["key", "light1", "rim_2"]);
    assert_eq!(s.channel_names(), ["key.V", "light1.V", "rim_2.V"]);
    assert_eq!(Light::Rect(s.lit(0).light), s.lights[0].light);
    for (k, x) in [1.0, 2.0, 3.0].into_iter().enumerate() {
        let one = s.for_light(k);
        assert_eq!(one.lit(0).light.center.x, x);
        assert_eq!(one.lights, [s.lights[k].clone()]);
        assert_eq!(one.channel_names(), ["V"]);
        assert_eq!(one.triangle_count(), s.triangle_count());
    }
    // One entry is still an array: its channel is named.
    let text = format!("{CAMERA}{}", light("[[light]]", "", 2.0));
    let s = Scene::from_toml(&text, Path::new("s.toml")).unwrap();
    assert_eq!(s.channel_names(), ["light0.V"]);
}

#[test]
fn both_forms_in_one_file_are_refused_at_the_later() {
    for (a, b) in [("[light]", "[[light]]"), ("[[light]]", "[light]")] {
        let text = format!("{CAMERA}{}{}", light(a, "", 0.0), light(b, "", 1.0));
        let (line, message) = error(&text);
        assert_eq!(line, line_with(&text, "light]", 1), "{message}");
        assert!(
            message.contains("`[light]` and `[[light]]` in one file"),
            "{message}"
        );
    }
}

#[test]
fn bad_names_and_an_empty_array_name_their_line() {
    let text = format!(
        "{CAMERA}{}{}",
        light("[[light]]", "", 0.0),
        light("[[light]]", "name = \"light0\"\n", 1.0)
    );
    let (line, message) = error(&text);
    assert_eq!(line, line_with(&text, "name = ", 0));
    assert!(
        message.contains("light[1].name") && message.contains("light[0]"),
        "{message}"
    );
    let text = format!(
        "{CAMERA}{}{}",
        light("[[light]]", "name = \"key\"\n", 0.0),
        light("[[light]]", "name = \"key light\"\n", 1.0)
    );
    let (line, message) = error(&text);
    assert_eq!(line, line_with(&text, "name = ", 1));
    assert!(
        message.contains("\"key light\"") && message.contains("' '"),
        "{message}"
    );
    // A default name taken by an earlier light: the entry's line.
    let text = format!(
        "{CAMERA}{}{}",
        light("[[light]]", "name = \"light1\"\n", 0.0),
        light("[[light]]", "", 1.0)
    );
    let (line, message) = error(&text);
    assert_eq!(line, line_with(&text, "[[light]]", 1));
    assert!(
        message.contains("light[1]'s default name \"light1\""),
        "{message}"
    );
    let text = format!("light = []\n{CAMERA}");
    assert_eq!(error(&text).0, 1);
    assert!(error(&text).1.contains("empty array"));
    // An entry that is not a table says what it should be.
    let text = format!("light = [3]\n{CAMERA}");
    let (line, message) = error(&text);
    assert_eq!(line, 1);
    assert!(
        message.contains("one entry of the array of tables"),
        "{message}"
    );
    // A name is for the lights of `[[light]]`.
    let text = format!("{CAMERA}{}", light("[light]", "name = \"key\"\n", 0.0));
    assert_eq!(error(&text).0, line_with(&text, "name = ", 0));
    // A bad value of a later light names that light.
    let text = format!(
        "{CAMERA}{}{}",
        light("[[light]]", "", 0.0),
        light("[[light]]", "", 1.0).replace("size = [1.0, 1.0]", "size = [1.0, 0.0]")
    );
    let (line, message) = error(&text);
    assert_eq!(line, line_with(&text, "size = [1.0, 0.0]", 0));
    assert!(message.starts_with("light[1].size"), "{message}");
}

#[test]
fn the_documented_example_reads_as_documented() {
    let doc = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/scene-format.md"),
    )
    .unwrap();
    let section = &doc[doc.find("## Several lights").expect("the section")..];
    let start = section.find("```toml\n").expect("its example") + "```toml\n".len();
    let example = &section[start..start + section[start..].find("```").unwrap()];
    let s = Scene::from_toml(&format!("{CAMERA}{example}"), Path::new("s.toml")).unwrap();
    assert_eq!(s.channel_names(), ["key.V", "light1.V"]);
    assert_eq!(s.lights[1].light.as_rect().unwrap().size.y, 3.0);
}

#[test]
fn the_documented_distant_light_reads_as_documented() {
    let doc = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/scene-format.md"),
    )
    .unwrap();
    let section = &doc[doc.find("## Distant lights").expect("the section")..];
    let start = section.find("```toml\n").expect("its example") + "```toml\n".len();
    let example = &section[start..start + section[start..].find("```").unwrap()];
    let s = Scene::from_toml(&format!("{CAMERA}{example}"), Path::new("s.toml")).unwrap();
    let d = s.lights[0]
        .light
        .as_distant()
        .copied()
        .expect("a distant light");
    assert_eq!(d.angular_size_deg, glam::DVec2::splat(0.53));
    assert!(d.direction.y > 0.0);
}

#[test]
fn a_transform_moves_every_light() {
    let text = format!(
        "{CAMERA}{}{}",
        light("[[light]]", "name = \"a\"\n", 1.0),
        light("[[light]]", "name = \"b\"\n", -2.0)
    );
    let s = Scene::from_toml(&text, Path::new("s.toml")).unwrap();
    let m = glam::DMat4::from_scale_rotation_translation(
        glam::DVec3::splat(2.5),
        glam::DQuat::from_axis_angle(glam::DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7),
        glam::DVec3::new(10.0, -3.0, 4.0),
    );
    let moved = s.transformed(&m);
    assert_eq!(moved.light_names(), ["a", "b"]);
    for k in 0..2 {
        // Moving the scene, then taking a light alone, is taking it alone, then moving it.
        assert_eq!(
            moved.for_light(k).lit(0).light,
            s.for_light(k).transformed(&m).lit(0).light
        );
        let c = m.transform_point3(s.lights[k].light.as_rect().unwrap().center);
        assert!((moved.lights[k].light.as_rect().unwrap().center - c).length() < 1e-12);
        assert!((moved.lights[k].light.as_rect().unwrap().size.x - 2.5).abs() < 1e-12);
    }
    assert_eq!(Light::Rect(moved.lit(0).light), moved.lights[0].light);
}

/// A distant light entry: `header`, extra lines, then its keys.
fn distant(header: &str, extra: &str) -> String {
    format!(
        "{header}\n{extra}distant = true\ndirection = [0.0, 0.6, 0.8]\n\
         tangent = [1.0, 0.0, 0.0]\nangular_size = [0.53, 2.0]\n\n"
    )
}

#[test]
fn a_distant_light_reads_as_the_rectangle_of_its_warp() {
    let s = Scene::from_toml(
        &format!("{CAMERA}{}", distant("[light]", "")),
        Path::new("s.toml"),
    )
    .unwrap();
    assert_eq!(s.channel_names(), ["V"]);
    let lit = s.lit(0);
    let d = lit.distant.as_ref().expect("a distant light");
    assert_eq!(d.light.direction, glam::DVec3::new(0.0, 0.6, 0.8));
    assert_eq!(d.light.angular_size_deg, glam::DVec2::new(0.53, 2.0));
    // B = (-D) x T.
    assert!((d.light.bitangent - glam::DVec3::new(0.0, -0.8, 0.6)).length() < 1e-15);
    assert_eq!(lit.light, d.warp.light(&d.light));
    assert_eq!(lit.world_light(), Light::Distant(d.light));
    assert_eq!(s.lights[0].light, Light::Distant(d.light));
    assert_eq!(*lit.world_camera(), s.camera);
    // `distant = false` is a rectangle light.
    let text = format!("{CAMERA}{}", light("[light]", "distant = false\n", 0.5));
    let s = Scene::from_toml(&text, Path::new("s.toml")).unwrap();
    assert!(s.lit(0).distant.is_none());
    // Mixed with a rectangle light: each light alone is its own form.
    let text = format!(
        "{CAMERA}{}{}",
        distant("[[light]]", "name = \"sun\"\n"),
        light("[[light]]", "name = \"lamp\"\n", 1.0)
    );
    let s = Scene::from_toml(&text, Path::new("s.toml")).unwrap();
    assert_eq!(s.channel_names(), ["sun.V", "lamp.V"]);
    assert!(s.lit(0).distant.is_some() && s.for_light(0).lit(0).distant.is_some());
    let lamp = s.for_light(1);
    assert!(lamp.lit(0).distant.is_none());
    assert_eq!(lamp.lit(0).light.center.x, 1.0);
    assert_eq!(lamp.camera, s.camera);
    // The meshes are shared, not copied, by the scene of one light and its rectangle's view.
    assert!(std::sync::Arc::ptr_eq(&lamp.meshes, &s.meshes));
    assert!(std::sync::Arc::ptr_eq(&lamp.lit(0).meshes, &s.meshes));
}

#[test]
fn bad_distant_lights_name_their_line() {
    let cases = [
        // (replace, with, the line's text, the message's words)
        (
            "angular_size = [0.53, 2.0]\n",
            "",
            "[light]",
            "needs `angular_size`",
        ),
        (
            "direction = [0.0, 0.6, 0.8]\n",
            "",
            "[light]",
            "needs `direction`",
        ),
        (
            "angular_size = [0.53, 2.0]",
            "angular_size = [0.53, 2.0]\ncenter = [0.0, 4.0, 0.0]",
            "center = ",
            "light.center is not a key of a distant light",
        ),
        (
            "[0.53, 2.0]",
            "[0.0, 2.0]",
            "angular_size = ",
            "each in (0, 90]",
        ),
        (
            "[0.53, 2.0]",
            "[0.53, 90.5]",
            "angular_size = ",
            "each in (0, 90]",
        ),
        (
            "[0.0, 0.6, 0.8]",
            "[0.0, 0.6, 0.9]",
            "direction = ",
            "light.direction [0, 0.6, 0.9] is not unit length",
        ),
        (
            "tangent = [1.0, 0.0, 0.0]",
            "tangent = [0.0, 0.6, 0.8]",
            "tangent = ",
            "not orthogonal to light.direction",
        ),
    ];
    for (from, to, at, says) in cases {
        let text = format!("{CAMERA}{}", distant("[light]", "")).replace(from, to);
        let (line, message) = error(&text);
        assert_eq!(line, line_with(&text, at, 0), "{message}");
        assert!(message.contains(says), "{says:?} in {message}");
    }
    // A rectangle light with a distant light's key.
    let text = format!(
        "{CAMERA}{}",
        light("[light]", "angular_size = [1.0, 1.0]\n", 0.0)
    );
    let (line, message) = error(&text);
    assert_eq!(line, line_with(&text, "angular_size", 0));
    assert!(
        message.contains("light.angular_size is not a key of a rectangle light"),
        "{message}"
    );
    let text = format!("{CAMERA}{}", light("[light]", "", 0.0)).replace("size = [1.0, 1.0]\n", "");
    assert!(error(&text).1.contains("a rectangle light needs `size`"));
}

/// The one light of `text` (camera first), or its error.
fn only_light(text: &str) -> Result<Light, SceneError> {
    Scene::from_toml(&format!("{CAMERA}{text}"), Path::new("s.toml")).map(|s| s.lights[0].light)
}

#[test]
fn a_light_aimed_at_a_target_is_the_light_of_its_normal() {
    let aimed = only_light(
        "[light]\ncenter = [1.0, 3.0, 0.0]\ntarget = [1.0, 0.0, 0.0]\nsize = [1.2, 0.6]\n",
    )
    .unwrap();
    let explicit = only_light(
        "[light]\ncenter = [1.0, 3.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\ntangent = [1.0, 0.0, 0.0]\n\
         size = [1.2, 0.6]\n",
    )
    .unwrap();
    assert_eq!(aimed, explicit);
    // With a tangent of its own.
    let turned = only_light(
        "[light]\ncenter = [1.0, 3.0, 0.0]\ntarget = [1.0, 0.0, 0.0]\ntangent = [0.0, 0.0, 1.0]\n\
         size = [1.2, 0.6]\n",
    )
    .unwrap();
    assert_eq!(turned.as_rect().unwrap().tangent, glam::DVec3::Z);
    for (text, at, says) in [
        (
            "[light]\ncenter = [1.0, 3.0, 0.0]\ntarget = [1.0, 3.0, 0.0]\nsize = [1.0, 1.0]\n",
            "target = [1.0, 3.0",
            "light.target [1, 3, 0] is the light's center",
        ),
        (
            "[light]\ncenter = [0.0, 3.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\n\
             size = [1.0, 1.0]\n",
            "normal = ",
            "give `normal` or `target`, not both",
        ),
        (
            "[light]\ncenter = [0.0, 3.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\nsize = [1.0, 1.0]\n",
            "[light]",
            "a rectangle light needs `tangent`",
        ),
        (
            "[light]\ncenter = [0.0, 3.0, 0.0]\nnormal = [0.0, -2.0, 0.0]\ntangent = [1.0, 0.0, 0.0]\n\
             size = [1.0, 1.0]\n",
            "normal = ",
            "light.normal [0, -2, 0] is not unit length (|normal| = 2); normalised it is [0, -1, 0]",
        ),
    ] {
        let text = format!("{CAMERA}{text}");
        let (line, message) = error(&text);
        assert_eq!(line, line_with(&text, at, 0), "{message}");
        assert!(message.contains(says), "{says:?} in {message}");
    }
}

#[test]
fn a_sun_given_by_its_angles_is_the_sun_of_its_direction() {
    let angles = only_light(
        "[light]\ndistant = true\nazimuth_deg = 135\nelevation_deg = 30\nangular_size = [0.53, 0.53]\n",
    )
    .unwrap();
    let sun = crate::DistantLight::sun(135.0, 30.0, 0.53).unwrap();
    assert_eq!(angles, Light::Distant(sun));
    let (c, s) = (30f64.to_radians().cos(), 0.5);
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert!((sun.direction - glam::DVec3::new(c * h, s, c * h)).length() < 1e-12);
    // The same direction written out, with the tangent the angles chose.
    let d = sun.direction;
    let t = sun.tangent;
    let explicit = only_light(&format!(
        "[light]\ndistant = true\ndirection = [{:?}, {:?}, {:?}]\ntangent = [{:?}, {:?}, {:?}]\n\
         angular_size = [0.53, 0.53]\n",
        d.x, d.y, d.z, t.x, t.y, t.z
    ))
    .unwrap();
    let e = explicit.as_distant().unwrap();
    assert!((e.direction - d).length() < 1e-15 && (e.tangent - t).length() < 1e-15);
    for (text, at, says) in [
        (
            "[light]\ndistant = true\nazimuth_deg = 10\nelevation_deg = 95\nangular_size = [1, 1]\n",
            "elevation_deg = ",
            "light.elevation_deg 95 must be in [-90, 90] degrees",
        ),
        (
            "[light]\ndistant = true\nazimuth_deg = 10\nelevation_deg = 5\ndirection = [0, 1, 0]\n\
             tangent = [1, 0, 0]\nangular_size = [1, 1]\n",
            "direction = ",
            "not both",
        ),
        (
            "[light]\ndistant = true\nazimuth_deg = 10\nangular_size = [1, 1]\n",
            "[light]",
            "needs `elevation_deg`",
        ),
        (
            "[light]\ncenter = [0, 3, 0]\nnormal = [0, -1, 0]\ntangent = [1, 0, 0]\nsize = [1, 1]\n\
             azimuth_deg = 3\n",
            "azimuth_deg = ",
            "light.azimuth_deg is not a key of a rectangle light",
        ),
    ] {
        let text = format!("{CAMERA}{text}");
        let (line, message) = error(&text);
        assert_eq!(line, line_with(&text, at, 0), "{message}");
        assert!(message.contains(says), "{says:?} in {message}");
    }
}
