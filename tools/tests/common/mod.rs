//! Helpers shared by the command's test binaries.
#![allow(dead_code, reason = "each test binary uses a part of them")]

use std::path::PathBuf;
use std::process::Command;

pub fn penumbra() -> Command {
    Command::new(env!("CARGO_BIN_EXE_penumbra"))
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
