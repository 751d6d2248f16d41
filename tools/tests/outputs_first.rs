//! Outputs checked before the work, and names from files not trusted: an output that cannot be
//! written is refused before the render or the comparison, an error names the output (never
//! its hidden temporary), a signal removes the folders made for the outputs, and a file's
//! channel names reach neither the terminal nor a file name unless they are lights' names.

mod common;
use common::{GOOD_OBJ, GOOD_SCENE, case_dir, files_in, penumbra, scratch, stdout_of};

use std::path::Path;

/// Renders `s.toml` of `d` with `args` after the scene; its status and standard error.
fn render(d: &Path, args: &[&str]) -> (Option<i32>, String) {
    let out = penumbra()
        .current_dir(d)
        .args([
            "render",
            "s.toml",
            "--technique",
            "hard",
            "--backend",
            "cpu",
        ])
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn outputs_that_cannot_be_written_are_refused_before_the_render() {
    let d = case_dir("first-unwritable", GOOD_SCENE, GOOD_OBJ);
    let mut cases = vec![
        (vec!["--out", "t1/"], "names a folder"),
        (vec!["--out", "v.exr", "--png", "t1/"], "names a folder"),
    ];
    // A folder no one can write in, root included.
    if Path::new("/proc/self").exists() {
        cases.push((
            vec!["--out", "/proc/v.exr"],
            "/proc/v.exr: cannot be written",
        ));
        cases.push((
            vec!["--out", "v.exr", "--shaded", "/proc/s.png"],
            "/proc/s.png: cannot be written",
        ));
    }
    for (args, want) in cases {
        let (code, err) = render(&d, &args);
        assert_eq!(code, Some(1), "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: {err}");
        // Refused before the render: no summary, no temporary named, nothing written.
        assert!(
            !err.contains(" px, ") && !err.contains(".tmp-"),
            "{args:?}: {err}"
        );
        assert_eq!(files_in(&d), ["m.obj", "s.toml"], "{args:?}");
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// A name of 247 bytes is written: its temporary's name is cut to fit the file system.
#[test]
fn a_name_as_long_as_the_file_system_takes_is_written() {
    let d = case_dir("first-long-name", GOOD_SCENE, GOOD_OBJ);
    let name = format!("{}.exr", "v".repeat(243));
    assert_eq!(name.len(), 247);
    let (code, err) = render(&d, &["--out", &name, "--png", &format!("{name}.png")]);
    assert_eq!(code, Some(0), "{err}");
    assert!(d.join(&name).is_file());
    assert!(
        files_in(&d).iter().all(|f| !f.starts_with('.')),
        "{:?}",
        files_in(&d)
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// Two small images as EXR files in `d`.
fn images(d: &Path) {
    penumbra_geom::VisibilityImage::filled(3, 2, 0.5)
        .write_exr(&d.join("a.exr"))
        .unwrap();
    penumbra_geom::VisibilityImage::filled(3, 2, 0.25)
        .write_exr(&d.join("b.exr"))
        .unwrap();
}

#[test]
fn a_heat_map_in_a_new_folder_is_written_and_one_that_cannot_be_is_named() {
    let d = scratch("first-heatmap");
    images(&d);
    let compare = |heatmap: &str| {
        penumbra()
            .current_dir(&d)
            .args(["compare", "a.exr", "b.exr", "--heatmap", heatmap])
            .output()
            .unwrap()
    };
    let out = compare("nodir/h.png");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("created folder nodir"), "{err}");
    assert!(d.join("nodir/h.png").is_file());
    if Path::new("/proc/self").exists() {
        let out = compare("/proc/h.png");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert!(
            err.contains("/proc/h.png") && !err.contains(".tmp-"),
            "{err}"
        );
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// SIGTERM during a render: the temporaries and the folders made for the outputs are removed.
#[test]
fn a_signal_removes_the_folders_made_for_the_outputs() {
    let d = case_dir("first-signal", GOOD_SCENE, GOOD_OBJ);
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scenes/spheres-9x9.toml");
    // A render of many seconds (the reference at 4096 samples over 320 x 240 pixels).
    let mut child = penumbra()
        .current_dir(&d)
        .arg("render")
        .arg(&scene)
        .args([
            "--technique",
            "reference",
            "--samples",
            "4096",
            "--backend",
            "cpu",
        ])
        .args(["--out", "new/deeper/v.exr"])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while !d.join("new/deeper").exists() {
        assert!(
            start.elapsed().as_secs() < 60,
            "the folders were never made"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let killed = std::process::Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "{status:?}");
    assert_eq!(files_in(&d), ["m.obj", "s.toml"]);
    let _ = std::fs::remove_dir_all(&d);
}

/// Writes an EXR of one layer of 3 x 2 pixels whose channels are `channels` (name, f32 or u32).
fn raw_exr(path: &Path, channels: &[(&str, bool)]) {
    use exr::prelude::*;
    let list: Vec<AnyChannel<FlatSamples>> = channels
        .iter()
        .map(|&(name, float)| {
            let samples = if float {
                FlatSamples::F32(vec![0.5; 6])
            } else {
                FlatSamples::U32(vec![1; 6])
            };
            AnyChannel::new(name, samples)
        })
        .collect();
    let layer = Layer::new(
        (3, 2),
        LayerAttributes::default(),
        Encoding::UNCOMPRESSED,
        AnyChannels::sort(SmallVec::from_vec(list)),
    );
    Image::from_layer(layer).write().to_file(path).unwrap();
}

#[test]
fn channel_names_and_types_from_a_file_are_not_trusted() {
    let d = scratch("first-names");
    images(&d);
    // A terminal escape, a newline and a path in channel names: not lights' names, so not
    // visibility channels; printed escaped in the list of what the file has.
    raw_exr(
        &d.join("odd.exr"),
        &[("\u{1b}[2J.V", true), ("x\ny.V", true), ("../up.V", true)],
    );
    raw_exr(&d.join("int.exr"), &[("V", false)]);
    raw_exr(&d.join("case.exr"), &[("Key.V", true), ("key.V", true)]);
    let compare = |a: &str, extra: &[&str]| {
        let out = penumbra()
            .current_dir(&d)
            .args(["compare", a, a])
            .args(extra)
            .output()
            .unwrap();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stdout).into_owned()
                + &String::from_utf8_lossy(&out.stderr),
        )
    };
    let (code, text) = compare("odd.exr", &["--heatmap", "h.png"]);
    assert_eq!(code, Some(1), "{text}");
    assert!(
        text.contains("no channel named `V` or `<light>.V`"),
        "{text}"
    );
    assert!(
        !text.contains('\u{1b}') && !text.contains("x\ny"),
        "{text:?}"
    );
    let (code, text) = compare("int.exr", &[]);
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("32-bit unsigned integers"), "{text}");
    let (code, text) = compare("case.exr", &["--heatmap", "h.png"]);
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("only in case"), "{text}");
    assert_eq!(
        files_in(&d),
        ["a.exr", "b.exr", "case.exr", "int.exr", "odd.exr"]
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// Light names equal but for case are refused in a scene file: their PNGs would be one file
/// on a file system that ignores case.
#[test]
fn light_names_equal_but_for_case_are_refused() {
    let scene = GOOD_SCENE.replace("[light]", "[[light]]\nname = \"Key\"");
    let light =
        &GOOD_SCENE[GOOD_SCENE.find("[light]").unwrap()..GOOD_SCENE.find("[[mesh]]").unwrap()];
    let scene = format!(
        "{scene}\n{}",
        light.replace("[light]", "[[light]]\nname = \"key\"")
    );
    let d = case_dir("first-case", &scene, GOOD_OBJ);
    let (code, err) = render(&d, &["--out", "v.exr", "--png", "v.png"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("only in case"), "{err}");
    assert_eq!(files_in(&d), ["m.obj", "s.toml"]);
    let _ = std::fs::remove_dir_all(&d);
}

/// Work in proportion to the file: two images of 2,000 lights each, one with a light-order
/// attribute of 300,000 entries (most naming no channel), are compared channel by channel,
/// in the attribute's order where it lists them. Each channel and each entry is looked up
/// once (a lookup per pair took minutes).
#[test]
fn thousands_of_channels_and_a_long_light_order_are_compared() {
    use exr::meta::attribute::{AttributeValue, Text};
    use exr::prelude::*;
    let d = scratch("first-thousands");
    let n = 2000;
    let write = |name: &str, order: Option<Vec<Text>>| {
        let list: Vec<AnyChannel<FlatSamples>> = (0..n)
            .map(|k| AnyChannel::new(format!("l{k}.V").as_str(), FlatSamples::F32(vec![0.5; 6])))
            .collect();
        let mut attributes = LayerAttributes::default();
        if let Some(order) = order {
            attributes.other.insert(
                Text::from(penumbra_geom::LIGHTS_ATTRIBUTE),
                AttributeValue::TextVector(order),
            );
        }
        let layer = Layer::new(
            (3, 2),
            attributes,
            Encoding::UNCOMPRESSED,
            AnyChannels::sort(SmallVec::from_vec(list)),
        );
        Image::from_layer(layer)
            .write()
            .to_file(d.join(name))
            .unwrap();
    };
    // Lights listed from the last to the first, among 298,000 names of no channel.
    let order: Vec<Text> = (0..300_000)
        .map(|k| {
            let name = if k % 150 == 0 && k / 150 < n {
                format!("l{}.V", n - 1 - k / 150)
            } else {
                format!("m{k}.V")
            };
            Text::from(name.as_str())
        })
        .collect();
    write("a.exr", Some(order));
    write("b.exr", None);
    let out = penumbra()
        .current_dir(&d)
        .args(["compare", "a.exr", "b.exr", "--json"])
        .output()
        .unwrap();
    let rows: serde_json::Value = serde_json::from_str(&stdout_of(&out)).unwrap();
    let rows = rows.as_array().unwrap();
    assert_eq!(rows.len(), n);
    assert_eq!(rows[0]["channel"], format!("l{}.V", n - 1));
    assert_eq!(rows[n - 1]["channel"], "l0.V");
    assert!(rows.iter().all(|r| r["all"]["mae"] == 0.0));
    let _ = std::fs::remove_dir_all(&d);
}
