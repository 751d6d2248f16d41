//! A scene file's `[[mesh]]` entries by format: exactly one of `obj`, `gltf` and `ply`, each
//! file read by its key's reader.

use std::path::{Path, PathBuf};

use glam::DVec3;

use crate::gltf_tests::Doc;
use crate::scene::Scene;
use crate::scene_error::SceneError;

const CAMERA_AND_LIGHT: &str = "[camera]\neye = [0.0, 3.0, 4.0]\ntarget = [0.0, 0.0, 0.0]\n\
    up = [0.0, 1.0, 0.0]\nfov_y_deg = 45.0\nwidth = 8\nheight = 6\n\n[light]\n\
    center = [0.0, 4.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\ntangent = [1.0, 0.0, 0.0]\n\
    size = [1.0, 1.0]\n\n";

/// A folder holding one triangle as `t.obj`, `t.glb` and `t.ply`.
fn folder() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("penumbra-meshkeys-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("t.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let mut d = Doc::default();
    let p = d.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let m = d.mesh(&[(p, None, 4)]);
    d.node(&format!(r#"{{"mesh": {m}}}"#));
    std::fs::write(dir.join("t.glb"), d.glb("")).unwrap();
    std::fs::write(
        dir.join("t.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    )
    .unwrap();
    dir
}

fn load(dir: &Path, meshes: &str) -> Result<Scene, SceneError> {
    Scene::from_toml(&format!("{CAMERA_AND_LIGHT}{meshes}"), &dir.join("s.toml"))
}

/// The line of `needle` in the scene text made of `meshes`.
fn line_of(meshes: &str, needle: &str) -> usize {
    let text = format!("{CAMERA_AND_LIGHT}{meshes}");
    text[..text.find(needle).unwrap()].lines().count() + 1
}

#[test]
fn each_key_reads_its_format_with_the_entry_s_transform() {
    let dir = folder();
    let meshes = "[[mesh]]\nobj = \"t.obj\"\ntranslate = [0, 0, 1]\n\n\
        [[mesh]]\ngltf = \"t.glb\"\ntranslate = [0, 0, 1]\n\n\
        [[mesh]]\nply = \"t.ply\"\ntranslate = [0, 0, 1]\n";
    let scene = load(&dir, meshes).unwrap();
    assert_eq!(scene.meshes.len(), 3);
    for m in scene.meshes.iter() {
        assert_eq!(m.mesh, scene.meshes[0].mesh, "{}", m.source.display());
        assert_eq!(m.mesh.positions[0], DVec3::new(0.0, 0.0, 1.0));
    }
    assert!(scene.meshes[1].source.ends_with("t.glb"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_entry_names_exactly_one_file() {
    let dir = folder();
    let none = "[[mesh]]\nscale = 2.0\n";
    match load(&dir, none) {
        Err(SceneError::Invalid { line, message, .. }) => {
            assert_eq!(line, line_of(none, "[[mesh]]"), "{message}");
            assert_eq!(
                message,
                "mesh 0 names no mesh file: give one of `obj`, `gltf` or `ply`"
            );
        }
        other => panic!("{other:?}"),
    }
    let two = "[[mesh]]\nply = \"t.ply\"\nscale = 2.0\nobj = \"t.obj\"\n";
    match load(&dir, two) {
        Err(SceneError::Invalid { line, message, .. }) => {
            assert_eq!(line, line_of(two, "obj ="), "{message}");
            assert_eq!(
                message,
                "mesh 0 names 2 mesh files (`obj`, `ply`): give exactly one of `obj`, `gltf` or `ply`"
            );
        }
        other => panic!("{other:?}"),
    }
    // A key of no format is unknown, and the parser lists the keys there are.
    let e = load(&dir, "[[mesh]]\nglb = \"t.glb\"\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("`glb`") && e.contains("`gltf`") && e.contains("`ply`"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_file_under_another_format_s_key_is_refused_with_the_key_s_line() {
    let dir = folder();
    for (meshes, want) in [
        (
            "[[mesh]]\nobj = \"t.glb\"\n",
            "mesh 0: {dir}/t.glb: a glTF file given as `obj = ...`: write `gltf = ...`",
        ),
        (
            "[[mesh]]\nscale = 1.0\nply = \"t.obj\"\n",
            "mesh 0: {dir}/t.obj: not a PLY file (a PLY file starts with the line `ply`) but given as `ply = ...`",
        ),
        (
            "[[mesh]]\ngltf = \"t.ply\"\n",
            "mesh 0: {dir}/t.ply: a PLY file given as `gltf = ...`: write `ply = ...`",
        ),
        // One file under two keys is read by each (the second fails).
        (
            "[[mesh]]\nobj = \"t.obj\"\n[[mesh]]\ngltf = \"t.obj\"\n",
            "mesh 1: {dir}/t.obj: not a glTF file",
        ),
    ] {
        let e = load(&dir, meshes).unwrap_err();
        let SceneError::Mesh { line, .. } = &e else {
            panic!("{e:?}")
        };
        // The last key's line.
        let key = meshes[..meshes.rfind(" = \"").unwrap()]
            .rfind('\n')
            .unwrap()
            + 1;
        assert_eq!(*line, line_of(meshes, &meshes[key..]), "{e}");
        let want = want.replace("{dir}", &dir.display().to_string());
        assert!(e.to_string().contains(&want), "{e}\nwanted: {want}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
