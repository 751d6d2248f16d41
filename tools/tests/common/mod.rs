//! Helpers shared by the command's test binaries.
#![allow(dead_code, reason = "each test binary uses a part of them")]

pub mod points;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn penumbra() -> Command {
    Command::new(env!("CARGO_BIN_EXE_penumbra"))
}

/// The standard output of a run that succeeded (its standard error in the failure otherwise).
pub fn stdout_of(out: &Output) -> String {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Whether a GPU run failed for want of an adapter outside CI (which must have one), where a
/// test says so and skips the rest.
pub fn no_adapter_here(out: &Output) -> bool {
    let err = String::from_utf8_lossy(&out.stderr);
    let skip = !out.status.success() && err.contains("adapter") && std::env::var_os("CI").is_none();
    if skip {
        println!("SKIPPED (no adapter): {err}");
    }
    skip
}

pub fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures")
}

/// A fresh folder for one test.
pub fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("penumbra-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

pub const GOOD_SCENE: &str = r#"
[camera]
eye = [0.0, 3.0, 4.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov_y_deg = 45.0
width = 24
height = 16

[light]
center = [0.0, 4.0, 0.0]
normal = [0.0, -1.0, 0.0]
tangent = [1.0, 0.0, 0.0]
size = [1.0, 1.0]

[[mesh]]
obj = "m.obj"
scale = 4.0

[[mesh]]
obj = "m.obj"
translate = [0.0, 1.0, 0.0]
"#;

pub const GOOD_OBJ: &str = "v -0.5 0 -0.5\nv -0.5 0 0.5\nv 0.5 0 0.5\nv 0.5 0 -0.5\nf 1 2 3 4\n";

/// A scratch folder holding `scene` as `s.toml` and `obj` as `m.obj`.
pub fn case_dir(name: &str, scene: &str, obj: &str) -> PathBuf {
    let d = scratch(name);
    std::fs::write(d.join("s.toml"), scene).unwrap();
    std::fs::write(d.join("m.obj"), obj).unwrap();
    d
}

/// Writes `scene` and `obj` into a scratch folder, renders, and returns the folder and output.
pub fn render_case(name: &str, scene: &str, obj: &str) -> (PathBuf, Output) {
    render_case_with(name, scene, obj, &[])
}

/// [`render_case`] with more arguments for `penumbra render`.
pub fn render_case_with(name: &str, scene: &str, obj: &str, args: &[&str]) -> (PathBuf, Output) {
    let d = case_dir(name, scene, obj);
    let out = penumbra()
        .arg("render")
        .arg(d.join("s.toml"))
        .args(["--samples", "4", "--out"])
        .arg(d.join("v.exr"))
        .arg("--png")
        .arg(d.join("v.png"))
        .args(args)
        .output()
        .unwrap();
    (d, out)
}

pub fn files_in(d: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Asserts a failed run whose message contains every piece of `want`, and that only the inputs
/// remain in the folder.
pub fn assert_refused(name: &str, scene: &str, obj: &str, want: &[&str]) {
    assert_refused_with(name, scene, obj, &[], want)
}

/// [`assert_refused`] with more arguments for `penumbra render`.
pub fn assert_refused_with(name: &str, scene: &str, obj: &str, args: &[&str], want: &[&str]) {
    let (d, out) = render_case_with(name, scene, obj, args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{name}: should fail");
    assert!(!err.contains("panicked"), "{name}: panicked: {err}");
    for w in want {
        assert!(err.contains(w), "{name}: error should mention {w:?}: {err}");
    }
    assert_eq!(
        files_in(&d),
        ["m.obj", "s.toml"],
        "{name}: left output behind"
    );
    let _ = std::fs::remove_dir_all(&d);
}
