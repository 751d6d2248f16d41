//! The `penumbra` command end to end: renders that read back, and every kind of bad input
//! answered by a clear error, a non-zero exit and no output file.

use std::path::{Path, PathBuf};
use std::process::Output;

mod common;
use common::{GOOD_OBJ, GOOD_SCENE, case_dir, fixtures, penumbra, scratch};

/// Writes `scene` and `obj` into a scratch folder, renders, and returns the folder and output.
fn render_case(name: &str, scene: &str, obj: &str) -> (PathBuf, Output) {
    render_case_with(name, scene, obj, &[])
}

/// [`render_case`] with more arguments for `penumbra render`.
fn render_case_with(name: &str, scene: &str, obj: &str, args: &[&str]) -> (PathBuf, Output) {
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

fn files_in(d: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Asserts a failed run whose message contains every piece of `want`, and that only the inputs
/// remain in the folder.
fn assert_refused(name: &str, scene: &str, obj: &str, want: &[&str]) {
    assert_refused_with(name, scene, obj, &[], want)
}

/// [`assert_refused`] with more arguments for `penumbra render`.
fn assert_refused_with(name: &str, scene: &str, obj: &str, args: &[&str], want: &[&str]) {
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

#[test]
fn arrays_of_the_wrong_length_or_beyond_f32_name_their_line() {
    // GOOD_SCENE's line 3 is the eye, 11 the light's centre, 18 the first mesh's `scale`.
    let s = GOOD_SCENE.replace("eye = [0.0, 3.0, 4.0]", "eye = [0.0, 3.0, 4.0, 1.0]");
    assert_refused(
        "eye4",
        &s,
        GOOD_OBJ,
        &["s.toml:3", "exactly 3 numbers, found 4"],
    );
    let s = GOOD_SCENE.replace("center = [0.0, 4.0, 0.0]", "center = [0.0, 1e39, 0.0]");
    assert_refused(
        "f32",
        &s,
        GOOD_OBJ,
        &["s.toml:11", "does not fit in 32-bit floats"],
    );
    let s = GOOD_SCENE.replace("scale = 4.0", "scale = [1, 2]");
    assert_refused(
        "scale2",
        &s,
        GOOD_OBJ,
        &["s.toml:18", "exactly 3 numbers, found 2"],
    );
    let s = GOOD_SCENE.replace("[camera]", "[[camera]]");
    assert_refused(
        "camera-array",
        &s,
        GOOD_OBJ,
        &["s.toml:2", "not `[[name]]`"],
    );
}

#[cfg(unix)]
#[test]
fn special_files_are_refused_as_outputs_and_left_alone() {
    let d = scratch("special-out");
    std::fs::write(d.join("s.toml"), GOOD_SCENE).unwrap();
    std::fs::write(d.join("m.obj"), GOOD_OBJ).unwrap();
    let fifo = d.join("v.exr");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    let out = penumbra()
        .args(["render", "--technique", "hard", "--backend", "cpu", "--out"])
        .arg(&fifo)
        .arg(d.join("s.toml"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("is a FIFO"), "{err}");
    use std::os::unix::fs::FileTypeExt;
    assert!(
        std::fs::symlink_metadata(&fifo)
            .unwrap()
            .file_type()
            .is_fifo()
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn images_too_large_for_the_gpu_or_the_memory_are_refused_or_go_to_the_cpu() {
    // Wider than any GPU's textures (16384 on lavapipe, 32768 at most elsewhere).
    let wide = GOOD_SCENE
        .replace("width = 24", "width = 40000")
        .replace("height = 16", "height = 1");
    assert_refused_with(
        "wide-gpu",
        &wide,
        GOOD_OBJ,
        &["--technique", "hard", "--backend", "gpu"],
        &["40000 x 1"],
    );
    // Under `auto` the CPU renders it.
    let (d, out) = render_case_with("wide-auto", &wide, GOOD_OBJ, &["--technique", "hard"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        penumbra_geom::VisibilityImage::read_exr(&d.join("v.exr"))
            .unwrap()
            .width,
        40000
    );
    // 4e10 pixels: refused before any allocation, where the CPU path aborted.
    let huge = GOOD_SCENE
        .replace("width = 24", "width = 200000")
        .replace("height = 16", "height = 200000");
    assert_refused_with(
        "huge-cpu",
        &huge,
        GOOD_OBJ,
        &["--technique", "hard", "--backend", "cpu"],
        &["200000 x 200000", "too large", "GB"],
    );
}

#[test]
fn compare_names_the_file_with_a_non_finite_pixel() {
    use exr::prelude::*;
    let d = scratch("compare-nan");
    let (good, bad) = (d.join("good.exr"), d.join("bad.exr"));
    penumbra_geom::VisibilityImage::filled(3, 2, 0.5)
        .write_exr(&good)
        .unwrap();
    // A V channel with a NaN, as another tool might write it.
    let data = vec![0.5, 0.5, f32::NAN, 0.5, 0.5, 0.5];
    let channel = AnyChannel::new("V", FlatSamples::F32(data));
    let layer = Layer::new(
        (3, 2),
        LayerAttributes::default(),
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(SmallVec::from_vec(vec![channel])),
    );
    Image::from_layer(layer).write().to_file(&bad).unwrap();
    for (a, b) in [(&good, &bad), (&bad, &good)] {
        let out = penumbra().arg("compare").arg(a).arg(b).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{err}");
        assert!(
            err.contains("bad.exr") && err.contains("pixel (2, 0) is not finite"),
            "{err}"
        );
    }
    let _ = std::fs::remove_dir_all(&d);
}

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
    for sub in ["meshes", "scenes", "bench"] {
        let names = files_in(&d.join(sub));
        let mut committed = files_in(&fixtures().join(sub));
        if sub == "meshes" {
            for c in COPIED_MESHES {
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
fn an_interrupted_write_leaves_no_temporary_file() {
    // A render whose EXR takes a while to write: SIGINT while its temporary file exists.
    for side in [3000, 4500, 6000] {
        let scene = GOOD_SCENE
            .replace("width = 24", &format!("width = {side}"))
            .replace("height = 16", &format!("height = {side}"));
        let d = case_dir(&format!("interrupted-{side}"), &scene, GOOD_OBJ);
        let mut child = penumbra()
            .arg("render")
            .arg(d.join("s.toml"))
            .args(["--technique", "hard", "--backend", "cpu", "--out"])
            .arg(d.join("v.exr"))
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        let start = std::time::Instant::now();
        let mut seen = false;
        while start.elapsed() < std::time::Duration::from_secs(60) {
            if files_in(&d).iter().any(|f| f.contains(".tmp-")) {
                seen = true;
                let kill = std::process::Command::new("kill")
                    .args(["-INT", &child.id().to_string()])
                    .status()
                    .unwrap();
                assert!(kill.success());
                break;
            }
            if child.try_wait().unwrap().is_some() {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        let status = child.wait().unwrap();
        if !seen {
            // The write was too quick to catch: try a larger image.
            let _ = std::fs::remove_dir_all(&d);
            continue;
        }
        assert_eq!(status.code(), Some(130), "exit status {status:?}");
        assert_eq!(files_in(&d), ["m.obj", "s.toml"], "left files behind");
        let _ = std::fs::remove_dir_all(&d);
        return;
    }
    panic!("never caught the render while it wrote its temporary file");
}

#[test]
fn thousands_of_meshes_render_on_either_back_end() {
    // 1500 small quads in the air, each its own silhouette, over a ground: more passes than one
    // timestamp query set can time on the GPU, and more silhouettes than `auto` blends there.
    let mut scene = GOOD_SCENE
        .replace("width = 24", "width = 12")
        .replace("height = 16", "height = 8");
    let mut rng = penumbra::geom::Rng::new(5);
    for _ in 0..1500 {
        scene.push_str(&format!(
            "\n[[mesh]]\nobj = \"m.obj\"\nscale = 0.05\ntranslate = [{:.3}, {:.3}, {:.3}]\n",
            rng.range(-1.0, 1.0),
            rng.range(0.5, 2.0),
            rng.range(-1.0, 1.0)
        ));
    }
    let d = case_dir("thousands", &scene, GOOD_OBJ);
    let mut images = Vec::new();
    for backend in ["auto", "gpu"] {
        let out = penumbra()
            .arg("render")
            .arg(d.join("s.toml"))
            .args(["--technique", "wedges-blend", "--backend", backend, "--out"])
            .arg(d.join(format!("{backend}.exr")))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        if backend == "gpu" && err.contains("no GPU") && std::env::var_os("CI").is_none() {
            return;
        }
        assert!(out.status.success(), "{backend}: {err}");
        if backend == "auto" {
            assert!(
                err.contains("(cpu,"),
                "auto should render 1500 silhouettes on the CPU: {err}"
            );
        }
        images
            .push(penumbra::VisibilityImage::read_exr(&d.join(format!("{backend}.exr"))).unwrap());
    }
    let c = penumbra::geom::image::compare(&images[1], &images[0]).unwrap();
    assert!(c.all.mae <= 1e-3, "GPU against CPU: {c:?}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn scenes_beyond_the_supported_range_are_refused_with_their_line() {
    // GOOD_SCENE's line 3 is the eye, 6 the field of view, 14 the light's size, 17 the first
    // mesh's `obj`. The ray caster's hierarchy panicked on coordinates of 1e20, and the CPU and
    // the GPU disagreed on a field of view of 1e-30 degrees and a light 1e30 wide.
    let cases = [
        (
            "scale",
            GOOD_SCENE.replace("scale = 4.0", "scale = 1e20"),
            GOOD_OBJ.to_owned(),
            "s.toml:17",
        ),
        (
            "translate",
            GOOD_SCENE.replace("scale = 4.0", "translate = [1e30, 0, 0]"),
            GOOD_OBJ.to_owned(),
            "s.toml:17",
        ),
        (
            "vertex",
            GOOD_SCENE.to_owned(),
            GOOD_OBJ.replace("v 0.5 0 0.5", "v 0.5 1e20 0.5"),
            "s.toml:17",
        ),
        (
            "eye",
            GOOD_SCENE.replace("eye = [0.0, 3.0, 4.0]", "eye = [0.0, 3.0, 1e20]"),
            GOOD_OBJ.to_owned(),
            "s.toml:3",
        ),
        (
            "fov",
            GOOD_SCENE.replace("fov_y_deg = 45.0", "fov_y_deg = 1e-30"),
            GOOD_OBJ.to_owned(),
            "s.toml:6",
        ),
        (
            "light",
            GOOD_SCENE.replace("size = [1.0, 1.0]", "size = [1e30, 1.0]"),
            GOOD_OBJ.to_owned(),
            "s.toml:14",
        ),
    ];
    for (name, scene, obj, line) in &cases {
        assert_refused(
            &format!("range-{name}"),
            scene,
            obj,
            &[line, "supported range"],
        );
        // `probe` refuses it the same way, without a panic.
        let d = case_dir(&format!("range-probe-{name}"), scene, obj);
        let out = penumbra()
            .arg("probe")
            .arg(d.join("s.toml"))
            .args(["--pixel", "1,1"])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(line) && !err.contains("panicked"),
            "{name}: {err}"
        );
        let _ = std::fs::remove_dir_all(&d);
    }
}
