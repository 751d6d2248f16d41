//! `penumbra probe` and `depth-complexity` from the command line, and what a GPU render prints.

mod common;
use common::{fixtures, penumbra, scratch, stdout_of};

/// `penumbra probe` of a fixture scene at `pixel` with 64 samples: what it prints, asserting
/// success.
fn probe(scene: &str, pixel: &str) -> String {
    let out = penumbra()
        .arg("probe")
        .arg(fixtures().join("scenes").join(scene))
        .args(["--pixel", pixel, "--samples", "64"])
        .output()
        .unwrap();
    stdout_of(&out)
}

#[test]
fn probe_prints_point_and_both_values() {
    let text = probe("quad-over-plane.toml", "160,200");
    for w in ["P ", "V exact", "V ref"] {
        assert!(text.contains(w), "{text}");
    }
    let out = penumbra()
        .arg("probe")
        .arg(fixtures().join("scenes/quad-over-plane.toml"))
        .args(["--pixel", "999,0"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("outside"));
}

/// The value printed after `key =` in `text`, e.g. `V ref      = 0.25 (...)`.
fn printed(text: &str, key: &str) -> f64 {
    let line = text
        .lines()
        .find(|l| l.starts_with(key))
        .unwrap_or_else(|| panic!("no {key:?} line in {text}"));
    line.split('=')
        .nth(1)
        .unwrap()
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn probe_prints_the_depth_complexity_value_and_its_edges() {
    // A ground pixel in the penumbra of the sphere, at the reference's own 64 samples.
    let text = probe("sphere-over-plane.toml", "160,160");
    let (reference, depth) = (printed(&text, "V ref"), printed(&text, "V depth"));
    assert!(
        reference > 0.0 && reference < 1.0,
        "not a penumbra pixel: {text}"
    );
    assert_eq!(depth, reference, "{text}");
    let edges: usize = text
        .split(" edges touched it")
        .next()
        .and_then(|t| t.rsplit(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no edge count in {text}"));
    assert!(edges > 0, "{text}");
}

#[test]
fn depth_complexity_with_jitter_renders_the_reference_image() {
    let d = scratch("depth-complexity");
    let scene = fixtures().join("scenes/nonmanifold.toml");
    for (tech, file, extra) in [
        ("reference", "r.exr", vec![]),
        ("depth-complexity", "j.exr", vec!["--jitter"]),
        ("depth-complexity", "g.exr", vec![]),
    ] {
        let out = penumbra()
            .arg("render")
            .arg(&scene)
            .args(["--technique", tech, "--samples", "64", "--backend", "cpu"])
            .args(extra)
            .arg("--out")
            .arg(d.join(file))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let read = |f: &str| penumbra_geom::VisibilityImage::read_exr(&d.join(f)).unwrap();
    let (r, j, g) = (read("r.exr"), read("j.exr"), read("g.exr"));
    let differ = |a: &penumbra_geom::VisibilityImage| {
        a.data.iter().zip(&r.data).filter(|(x, y)| x != y).count()
    };
    // The reference's samples: its image. The multi-jittered ones: another sampling of the
    // same shadow, equal in the umbra and the light, not in the penumbra.
    assert!(differ(&j) <= 8, "jittered: {} pixels differ", differ(&j));
    // --jitter means nothing to a technique without light samples: refused, nothing written.
    let out = penumbra()
        .arg("render")
        .arg(&scene)
        .args([
            "--technique",
            "wedges",
            "--jitter",
            "--backend",
            "cpu",
            "--out",
        ])
        .arg(d.join("w.exr"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--jitter"));
    assert!(!d.join("w.exr").exists());
    assert!(
        differ(&g) > 1000,
        "the multi-jittered samples should differ in the penumbra: {}",
        differ(&g)
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_gpu_render_prints_no_window_system_noise() {
    // Mesa's device-select layer says "XDG_RUNTIME_DIR is invalid" on a machine without a
    // display, unless turned off; the command turns it off itself.
    let d = scratch("xdg");
    let out = penumbra()
        .env_remove("NODEVICE_SELECT")
        .env_remove("XDG_RUNTIME_DIR")
        .arg("render")
        .arg(fixtures().join("scenes/quad-over-plane.toml"))
        .args(["--technique", "hard", "--backend", "gpu", "--out"])
        .arg(d.join("h.exr"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(!err.contains("XDG_RUNTIME_DIR"), "{err}");
    let _ = std::fs::remove_dir_all(&d);
}
