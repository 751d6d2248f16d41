//! A crate outside the repository, depending on `penumbra` by path, builds a scene in code with
//! `use penumbra::...` only, renders it and checks the image: what a user's first program does.
//! It builds offline against the workspace's lockfile, profiles and build folder, with the
//! features the workspace turns on in shared dependencies, so that it compiles the workspace's
//! own crates and one small crate, and reuses every dependency.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The user's program: every name it takes from a crate comes through `penumbra::`.
const MAIN: &str = r#"use penumbra::glam::{DMat4, DVec2, DVec3};
use penumbra::{
    Backend, Camera, RectLight, RenderOptions, Renderer, Scene, Technique, TriangleMesh,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let camera = Camera::look_at(DVec3::new(0.0, 4.0, 5.0), DVec3::ZERO, DVec3::Y, 45.0, 32, 24)?;
    let light = RectLight::aimed(DVec3::new(0.0, 5.0, 0.0), DVec3::ZERO, DVec2::ONE)?;
    let ground = DMat4::from_scale(DVec3::splat(8.0));
    let ball = DMat4::from_translation(DVec3::Y) * DMat4::from_scale(DVec3::splat(0.5));
    let scene = Scene::new(camera)
        .with_mesh("ground", &TriangleMesh::quad(), ground)
        .with_light(light)
        .with_mesh("ball", &TriangleMesh::uv_sphere(8, 12), ball);
    let mut renderer = Renderer::new(Backend::Cpu);
    let v = renderer.render(&scene, Technique::WedgesBlend, &RenderOptions::default())?;
    let dark = v.data.iter().filter(|&&x| x < 0.5).count();
    let lit = v.data.iter().filter(|&&x| x == 1.0).count();
    println!("{} x {}: {dark} dark, {lit} lit", v.width, v.height);
    assert!(dark > 0 && lit > dark, "{dark} dark, {lit} lit");
    Ok(())
}
"#;

/// Features that other members of the workspace turn on in dependencies they share with
/// `penumbra`, as `(table, dependency line)`: the command's `clap` (`syn/full`, for its derive)
/// and `ctrlc` (`libc/extra_traits`, through `nix`), the benchmarks' `criterion` (`serde/alloc`
/// and `either/use_std`). `cargo test --workspace` builds each dependency once, with the union
/// of the features; a crate that turned on fewer would build `wgpu` and the rest of the tree
/// anew (13 minutes on two loaded cores). A dependency that the lockfile no longer holds is left
/// out.
const SHARED_FEATURES: [(&str, &str); 4] = [
    (
        "dependencies",
        r#"libc = { version = "0.2", features = ["extra_traits"] }"#,
    ),
    (
        "dependencies",
        r#"serde = { version = "1", features = ["alloc"] }"#,
    ),
    (
        "dependencies",
        r#"either = { version = "1", default-features = false, features = ["use_std"] }"#,
    ),
    (
        "build-dependencies",
        r#"syn = { version = "3", features = ["full"] }"#,
    ),
];

/// The lines of `table` of [`SHARED_FEATURES`] whose dependency `lock` (a `Cargo.lock`) holds
/// at the version asked for.
fn shared_features(table: &str, lock: &str) -> String {
    SHARED_FEATURES
        .iter()
        .filter(|(t, _)| *t == table)
        .filter(|(_, line)| {
            let name = line.split(' ').next().unwrap();
            let major = line.split('"').nth(1).unwrap();
            lock.contains(&format!("name = \"{name}\"\nversion = \"{major}."))
        })
        .map(|(_, line)| format!("{line}\n"))
        .collect()
}

/// The crates of this workspace that `penumbra` is built from. The scratch crate builds them
/// anew whatever it does (cargo keys a path package's build by its path from the root of the
/// workspace that builds it), unoptimised and without debug information: a minute less than
/// the workspace's profile on two cores, for a render of 32 x 24 pixels.
const OWN_CRATES: [&str; 5] = [
    "penumbra",
    "penumbra-params",
    "penumbra-geom",
    "penumbra-volumes",
    "penumbra-gpu",
];

/// The crate paths a program names in its `use` lines.
fn used_crates(source: &str) -> Vec<&str> {
    source
        .lines()
        .filter_map(|l| l.trim().strip_prefix("use "))
        .filter_map(|l| l.split("::").next())
        .collect()
}

#[test]
fn a_crate_outside_the_repository_renders_a_scene_built_in_code() {
    assert!(
        used_crates(MAIN).iter().all(|c| *c == "penumbra"),
        "{:?}",
        used_crates(MAIN)
    );
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = std::env::temp_dir().join(format!("penumbra-outside-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("src")).unwrap();
    // The workspace's profiles, so that the dependencies built for it are the ones reused.
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).unwrap();
    let mut profiles = manifest[manifest
        .find("\n[profile.")
        .expect("the workspace's profiles")..]
        .to_owned();
    for name in OWN_CRATES {
        profiles += &format!("\n[profile.test.package.{name}]\nopt-level = 0\ndebug = false\n");
    }
    let lock = std::fs::read_to_string(root.join("Cargo.lock")).unwrap();
    std::fs::write(
        dir.join("Cargo.toml"),
        format!(
            "[package]\nname = \"outside\"\nversion = \"0.0.0\"\nedition = \"2024\"\npublish = false\n\n\
             [dependencies]\npenumbra = {{ path = {:?} }}\n{}\n[build-dependencies]\n{}\n\
             [workspace]\n{profiles}",
            root.display().to_string(),
            shared_features("dependencies", &lock),
            shared_features("build-dependencies", &lock),
        ),
    )
    .unwrap();
    std::fs::write(dir.join("Cargo.lock"), &lock).unwrap();
    std::fs::write(dir.join("src/main.rs"), MAIN).unwrap();
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target"));
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let out = Command::new(cargo)
        .current_dir(&dir)
        // The profile `cargo test` builds the workspace's crates with.
        .args(["run", "--offline", "--quiet", "--profile", "test"])
        .env("CARGO_TARGET_DIR", &target)
        .output()
        .unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("32 x 24"), "{stdout}");
    let _ = std::fs::remove_dir_all(&dir);
}
