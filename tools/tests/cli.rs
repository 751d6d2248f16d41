//! The `penumbra` command end to end: renders that read back, and every kind of bad input
//! answered by a clear error, a non-zero exit and no output file.

mod common;
use common::{
    GOOD_OBJ, GOOD_SCENE, assert_refused, assert_refused_with, files_in, fixtures, penumbra,
    render_case, render_case_with, scratch, stdout_of,
};

#[test]
fn renders_a_small_scene_to_exr_and_png() {
    let (d, out) = render_case("good", GOOD_SCENE, GOOD_OBJ);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(files_in(&d), ["m.obj", "s.toml", "v.exr", "v.png"]);
    let img = penumbra_geom::VisibilityImage::read_exr(&d.join("v.exr")).unwrap();
    assert_eq!((img.width, img.height), (24, 16));
    assert!(img.data.iter().all(|v| (0.0..=1.0).contains(v)));
    assert!(
        img.data.contains(&0.0),
        "the quad shadows the ground's centre"
    );
    assert!(img.data.contains(&1.0));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn malformed_toml() {
    let s = GOOD_SCENE.replace("fov_y_deg = 45.0", "fov_y_deg = = 45.0");
    assert_refused("toml", &s, GOOD_OBJ, &["s.toml:6", "extra `=`"]);
}

#[cfg(unix)]
#[test]
fn unknown_key_names_key_and_line() {
    let s = GOOD_SCENE.replace("size = [1.0, 1.0]", "size = [1.0, 1.0]\ncolour = 3");
    assert_refused("key", &s, GOOD_OBJ, &["s.toml:15", "colour"]);
}

#[test]
fn missing_obj() {
    let s = GOOD_SCENE.replace("obj = \"m.obj\"\nscale", "obj = \"nothere.obj\"\nscale");
    assert_refused(
        "missing",
        &s,
        GOOD_OBJ,
        &["s.toml:17", "nothere.obj", "mesh 0"],
    );
}

#[test]
fn malformed_obj() {
    let obj = GOOD_OBJ.replace("v 0.5 0 0.5", "v 0.5 zero 0.5");
    assert_refused("badobj", GOOD_SCENE, &obj, &["m.obj:3", "zero"]);
    let obj = GOOD_OBJ.replace("f 1 2 3 4", "f 1 2 7");
    assert_refused("badindex", GOOD_SCENE, &obj, &["m.obj:5", "7"]);
}

#[test]
fn nan_vertex() {
    let obj = GOOD_OBJ.replace("v -0.5 0 0.5", "v -0.5 NaN 0.5");
    assert_refused(
        "nan",
        GOOD_SCENE,
        &obj,
        &["m.obj:2", "vertex 1", "non-finite"],
    );
}

#[test]
fn zero_size_light() {
    let s = GOOD_SCENE.replace("size = [1.0, 1.0]", "size = [1.0, 0.0]");
    assert_refused("light", &s, GOOD_OBJ, &["s.toml:14", "light.size"]);
}

#[test]
fn zero_image_size() {
    let s = GOOD_SCENE.replace("height = 16", "height = 0");
    assert_refused("size", &s, GOOD_OBJ, &["s.toml:8", "empty"]);
}

#[test]
fn eye_equal_to_target() {
    let s = GOOD_SCENE.replace("eye = [0.0, 3.0, 4.0]", "eye = [0.0, 0.0, 0.0]");
    assert_refused(
        "eye",
        &s,
        GOOD_OBJ,
        &["s.toml:4", "eye and target coincide"],
    );
}

#[test]
fn up_parallel_to_view() {
    let s = GOOD_SCENE.replace("eye = [0.0, 3.0, 4.0]", "eye = [0.0, 3.0, 0.0]");
    assert_refused("up", &s, GOOD_OBJ, &["s.toml:5", "parallel"]);
}

#[test]
fn light_frame_must_be_orthonormal() {
    let s = GOOD_SCENE.replace("tangent = [1.0, 0.0, 0.0]", "tangent = [0.0, 1.0, 0.0]");
    assert_refused("ortho", &s, GOOD_OBJ, &["s.toml:13", "orthogonal"]);
}

#[test]
fn out_equal_to_an_input() {
    let d = scratch("outin");
    std::fs::write(d.join("s.toml"), GOOD_SCENE).unwrap();
    std::fs::write(d.join("m.obj"), GOOD_OBJ).unwrap();
    for target in ["s.toml", "m.obj"] {
        let out = penumbra()
            .arg("render")
            .arg(d.join("s.toml"))
            .arg("--out")
            .arg(d.join(".").join(target))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains("input"),
            "{target}: {err}"
        );
        assert_eq!(
            std::fs::read_to_string(d.join("s.toml")).unwrap(),
            GOOD_SCENE
        );
        assert_eq!(std::fs::read_to_string(d.join("m.obj")).unwrap(), GOOD_OBJ);
    }
    assert_eq!(files_in(&d), ["m.obj", "s.toml"]);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn samples_must_be_a_perfect_square_up_to_65536() {
    let d = scratch("samples");
    // 200 is no square; 65536^2 (a square) would run for days.
    for samples in ["200", "4294967296"] {
        let out = penumbra()
            .arg("render")
            .arg(fixtures().join("scenes/quad-over-plane.toml"))
            .args(["--technique", "reference", "--samples", samples, "--out"])
            .arg(d.join("v.exr"))
            .output()
            .unwrap();
        assert!(!out.status.success());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("perfect square") && err.contains("up to 65536"),
            "{err}"
        );
        assert!(files_in(&d).is_empty());
    }
}

#[test]
fn hard_reference_is_binary_and_compare_reports_metrics() {
    let d = scratch("compare");
    let scene = fixtures().join("scenes/sphere-over-plane.toml");
    for (tech, file, extra) in [
        ("hard-reference", "h.exr", vec![]),
        ("reference", "r.exr", vec!["--samples", "16"]),
    ] {
        let out = penumbra()
            .arg("render")
            .arg(&scene)
            .args(["--technique", tech])
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
    let hard = penumbra_geom::VisibilityImage::read_exr(&d.join("h.exr")).unwrap();
    assert!(hard.data.iter().all(|&v| v == 0.0 || v == 1.0));
    let out = penumbra()
        .arg("compare")
        .arg(d.join("h.exr"))
        .arg(d.join("r.exr"))
        .arg("--json")
        .arg("--heatmap")
        .arg(d.join("heat.png"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let pen = &v["penumbra"];
    assert!(pen["pixels"].as_u64().unwrap() > 100);
    // A hard shadow is wrong by about half in the penumbra.
    assert!(pen["mae"].as_f64().unwrap() > 0.1);
    assert!(v["all"]["mae"].as_f64().unwrap() < pen["mae"].as_f64().unwrap());
    assert!(d.join("heat.png").exists());
    // Comparing with itself is exact.
    let out = penumbra()
        .arg("compare")
        .arg(d.join("r.exr"))
        .arg(d.join("r.exr"))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("0.000000"), "{text}");
    let _ = std::fs::remove_dir_all(&d);
}

/// The real meshes of `fixtures/meshes/`, copied byte for byte from common-3d-test-models: data
/// that the generator never writes, though it writes a scene for each.
const COPIED_MESHES: [&str; 5] = [
    "beetle.obj",
    "cheburashka.obj",
    "fandisk.obj",
    "spot.obj",
    "woody.obj",
];

/// The large meshes copied from the same collection, used by the scale scenes only.
const SCALE_MESHES: [&str; 3] = ["nefertiti.obj", "beetle-alt.obj", "igea.ply"];

#[test]
fn committed_fixtures_are_what_the_generator_writes() {
    let d = scratch("gen");
    let out = penumbra()
        .arg("gen-fixtures")
        .arg("--out")
        .arg(&d)
        .output()
        .unwrap();
    assert!(out.status.success());
    for sub in ["meshes", "scenes", "bench", "scale"] {
        let names = files_in(&d.join(sub));
        let mut committed = files_in(&fixtures().join(sub));
        if sub == "meshes" {
            for c in COPIED_MESHES.iter().chain(&SCALE_MESHES) {
                assert!(
                    !names.iter().any(|n| n == c),
                    "the generator wrote {c}, which is copied data"
                );
                let at = committed.iter().position(|n| n == c);
                committed.remove(at.unwrap_or_else(|| panic!("fixtures/meshes/{c} is missing")));
            }
        }
        assert_eq!(names, committed, "{sub}");
        for n in names {
            assert!(
                std::fs::read(d.join(sub).join(&n)).unwrap()
                    == std::fs::read(fixtures().join(sub).join(&n)).unwrap(),
                "fixtures/{sub}/{n} differs from the generator's output: run `penumbra gen-fixtures`"
            );
        }
    }
    // Each copied mesh has a generated scene of its name that uses it and keeps its attribution.
    for c in COPIED_MESHES {
        let scene = c.replace(".obj", ".toml");
        let text = std::fs::read_to_string(d.join("scenes").join(&scene)).unwrap();
        assert!(
            text.contains(&format!("obj = \"../meshes/{c}\"")),
            "{scene}"
        );
        assert!(
            text.contains("common-3d-test-models by Alec Jacobson"),
            "{scene}: attribution"
        );
    }
    let scale = std::fs::read_to_string(d.join("scale/scale.toml")).unwrap();
    let gallery = std::fs::read_to_string(d.join("scale/gallery.toml")).unwrap();
    for c in SCALE_MESHES {
        let key = if c.ends_with(".ply") { "ply" } else { "obj" };
        assert!(
            [&scale, &gallery]
                .iter()
                .any(|s| s.contains(&format!("{key} = \"../meshes/{c}\""))),
            "the scale scenes: {c}"
        );
    }
    for (name, text) in [("scale.toml", &scale), ("gallery.toml", &gallery)] {
        assert!(
            text.contains("common-3d-test-models by Alec Jacobson"),
            "{name}: attribution"
        );
    }
    let _ = std::fs::remove_dir_all(&d);
}

const SHADOW_MAP_TECHNIQUES: [&str; 5] = ["pcf", "pcss", "fractional-disk", "mdsm", "gaussian"];

#[test]
fn every_shadow_map_technique_renders_from_the_command_line() {
    for t in SHADOW_MAP_TECHNIQUES {
        let mut args = vec!["--technique", t, "--shadow-map-resolution", "128"];
        if t == "gaussian" {
            // Its screen-space blur, sized for full images, would blur the few shadowed pixels
            // of a 24x16 one away: D = 0 leaves the hard shadow (Cherry & Kooima's identity case).
            args.extend(["--gaussian-dm", "0"]);
        }
        let (d, out) = render_case_with(t, GOOD_SCENE, GOOD_OBJ, &args);
        let err = String::from_utf8_lossy(&out.stderr);
        if !out.status.success()
            && err.contains("needs a GPU adapter")
            && std::env::var_os("CI").is_none()
        {
            println!("SKIPPED (no adapter): {err}");
            return;
        }
        assert!(out.status.success(), "{t}: {err}");
        assert_eq!(files_in(&d), ["m.obj", "s.toml", "v.exr", "v.png"]);
        let img = penumbra_geom::VisibilityImage::read_exr(&d.join("v.exr")).unwrap();
        assert!(img.data.iter().all(|v| (0.0..=1.0).contains(v)), "{t}");
        assert!(
            img.data.contains(&0.0),
            "{t}: the quad shadows the ground's centre"
        );
        assert!(img.data.contains(&1.0), "{t}");
        let _ = std::fs::remove_dir_all(&d);
    }
}

#[test]
fn shadow_map_parameters_out_of_range_name_table_key_and_line() {
    let s = format!("{GOOD_SCENE}\n[pcf]\nkernel = 7\n");
    let line = format!("s.toml:{}", s.lines().count());
    assert_refused("pcf-table", &s, GOOD_OBJ, &[&line, "pcf.kernel", "7"]);
    let s = format!("{GOOD_SCENE}\n[pcss]\nsearch = 4\nsamples = 3\n");
    assert_refused("pcss-key", &s, GOOD_OBJ, &["s.toml", "samples"]);
    assert_refused_with(
        "pcf-flag",
        GOOD_SCENE,
        GOOD_OBJ,
        &["--technique", "pcf", "--pcf-kernel", "9"],
        &["pcf.kernel", "9", "--pcf-kernel"],
    );
    assert_refused_with(
        "fd-flag",
        GOOD_SCENE,
        GOOD_OBJ,
        &["--technique", "fractional-disk", "--fd-max-radius", "40"],
        &["fractional_disk.passes", "--fd-passes"],
    );
    // A negative value is read as the flag's value, out of range, not as an unknown flag.
    assert_refused_with(
        "negative-flag",
        GOOD_SCENE,
        GOOD_OBJ,
        &["--technique", "gaussian", "--gaussian-dm", "-1"],
        &["gaussian.dm", "-1"],
    );
}

#[test]
fn shadow_map_techniques_refuse_the_cpu_backend() {
    assert_refused_with(
        "cpu",
        GOOD_SCENE,
        GOOD_OBJ,
        &["--technique", "pcss", "--backend", "cpu"],
        &["GPU only"],
    );
}

#[test]
fn render_help_lists_the_shadow_map_parameters() {
    let out = penumbra().args(["render", "--help"]).output().unwrap();
    let help = String::from_utf8_lossy(&out.stdout);
    for flag in [
        "--shadow-map-resolution",
        "--depth-bias",
        "--pcf-kernel",
        "--pcss-dither",
        "--fd-max-samples",
        "--mdsm-depths",
        "--gaussian-variant",
        "fractional-disk",
    ] {
        assert!(help.contains(flag), "render --help lacks {flag}");
    }
}

#[test]
fn a_light_shut_in_a_mesh_seen_from_outside_is_warned_of_on_stderr() {
    // A sphere of radius 0.6 centred 0.3 beside the light's centre, in the light's plane.
    let scene = GOOD_SCENE.replace(
        "obj = \"m.obj\"\ntranslate = [0.0, 1.0, 0.0]",
        "obj = \"sphere.obj\"\nscale = 0.6\ntranslate = [0.3, 4.0, 0.0]",
    );
    assert_ne!(scene, GOOD_SCENE);
    let d = scratch("light-inside");
    std::fs::write(d.join("s.toml"), &scene).unwrap();
    std::fs::write(d.join("m.obj"), GOOD_OBJ).unwrap();
    let sphere = penumbra_geom::TriangleMesh::uv_sphere(12, 16).to_obj_string("sphere");
    std::fs::write(d.join("sphere.obj"), sphere).unwrap();
    let render = |technique: &str| {
        let out = penumbra()
            .args([
                "render",
                "--technique",
                technique,
                "--backend",
                "cpu",
                "--out",
            ])
            .arg(d.join("v.exr"))
            .arg(d.join("s.toml"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{technique}: {err}");
        err
    };
    for technique in ["wedges", "wedges-blend"] {
        let err = render(technique);
        let want = format!(
            "warning: mesh 1 ({}) closes round the light's centre and the eye is outside it: {technique} builds its shadow from that centre, and is right for a light inside a closed mesh only with the eye inside it too (a room lit from its ceiling; see docs/accuracy.md); hard, depth-complexity and the reference are exact here\n",
            d.join("sphere.obj").display()
        );
        assert!(err.contains(&want), "{want}: {err}");
    }
    // The hard shadow is the hard reference's there.
    for technique in ["depth-complexity", "hard"] {
        let err = render(technique);
        assert!(!err.contains("warning"), "{err}");
    }
    assert!(render("hard").contains("the hard reference, the light's centre being shut in mesh 1"));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn accuracy_measures_each_sample_count_against_one_truth() {
    let d = scratch("accuracy-counts");
    std::fs::write(d.join("s.toml"), GOOD_SCENE).unwrap();
    std::fs::write(d.join("m.obj"), GOOD_OBJ).unwrap();
    let run = |counts: &str| {
        let mut c = penumbra();
        c.args([
            "accuracy",
            "--samples",
            "1024",
            "--technique-samples",
            counts,
        ])
        .args([
            "--backend",
            "cpu",
            "--techniques",
            "reference,depth-complexity,hard",
        ])
        .arg("--scenes")
        .arg(&d);
        stdout_of(&c.output().unwrap())
    };
    // A row's cells but the time, by its technique's label.
    let row = |table: &str, label: &str| -> Vec<String> {
        let rows: Vec<Vec<String>> = table
            .lines()
            .map(|l| l.split('|').map(|c| c.trim().to_string()).collect())
            .filter(|c: &Vec<String>| c.len() > 3 && c[2] == label)
            .collect();
        assert_eq!(rows.len(), 1, "one row {label:?} in {table}");
        rows[0][..rows[0].len() - 2].to_vec()
    };
    let penumbra_mae = |table: &str, label: &str| row(table, label)[7].parse::<f64>().unwrap();
    let out = run("4,64");
    // Two counts of the reference: a second table, each other row against the reference of
    // its penumbra error.
    let (both, equal) = out
        .split_once("Against the reference of the same penumbra MAE")
        .unwrap_or_else(|| panic!("a table of equal errors: {out}"));
    assert!(both.contains("with 4 and 64 samples"), "{both}");
    let equal_rows: Vec<&str> = equal.lines().filter(|l| l.starts_with("| s |")).collect();
    assert_eq!(equal_rows.len(), 3, "{equal}");
    for (r, t) in equal_rows.iter().zip([
        "depth-complexity --samples 4",
        "depth-complexity --samples 64",
        "hard",
    ]) {
        assert!(r.starts_with(&format!("| s | {t} |")), "{equal}");
    }
    // `hard`'s error is beyond the 4-sample reference's.
    assert!(equal_rows[2].contains("fewer than 4"), "{equal}");
    for t in ["reference", "depth-complexity"] {
        let (few, many) = (format!("{t} --samples 4"), format!("{t} --samples 64"));
        assert!(
            penumbra_mae(both, &many) < penumbra_mae(both, &few),
            "{both}"
        );
    }
    // The techniques without samples once; a single count names none.
    row(both, "hard");
    let one = run("64");
    assert!(
        one.contains("with 64 samples") && !one.contains("--samples") && !one.contains("Against"),
        "{one}"
    );
    for t in ["reference", "depth-complexity"] {
        assert_eq!(
            row(&one, t)[3..],
            row(both, &format!("{t} --samples 64"))[3..]
        );
    }
    let _ = std::fs::remove_dir_all(&d);
}
