//! Hostile input from the command line: values beyond the supported range or beyond `f32`,
//! special files as outputs, images too large, interrupted writes, thousands of meshes. Each
//! ends in a clear error or a correct image, never a panic.

mod common;
use common::{
    GOOD_OBJ, GOOD_SCENE, assert_refused, assert_refused_with, case_dir, files_in, penumbra,
    render_case_with, scratch,
};

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
    let c = penumbra::geom::compare(&images[1], &images[0]).unwrap();
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

#[test]
fn obj_weights_and_continued_lines_name_their_line() {
    // A weight of zero is a point at infinity: refused on its own line (it said line 0).
    let obj = GOOD_OBJ.replace("v -0.5 0 0.5", "v -0.5 0 0.5 0");
    assert_refused(
        "obj-w0",
        GOOD_SCENE,
        &obj,
        &["m.obj:2", "weight w = 0", "at infinity"],
    );
    // A `\` continues a statement; the lines after it keep their numbers.
    let obj = "v -0.5 0 \\\n  -0.5\nv -0.5 0 0.5\nv 0.5 0 0.5\nv 0.5 0 -0.5\nf 1 2 \\\n 3 4\n";
    let (d, out) = render_case_with("obj-continued", GOOD_SCENE, obj, &["--technique", "hard"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let _ = std::fs::remove_dir_all(&d);
    let obj = format!("{obj}f 1 2 \\\n 9\n");
    assert_refused(
        "obj-continued-bad",
        GOOD_SCENE,
        &obj,
        &["m.obj:8", "vertex index 9"],
    );
}

#[test]
fn a_key_of_fifty_thousand_parts_names_its_line() {
    // GOOD_SCENE has 22 lines; the key is the 23rd (it said line 0).
    let s = format!("{GOOD_SCENE}{} = 1\n", vec!["a"; 50_000].join("."));
    assert_refused(
        "key-parts",
        &s,
        GOOD_OBJ,
        &["s.toml:23", "more than 80 parts"],
    );
}

#[test]
fn shadow_map_values_not_finite_or_beyond_f32_are_refused_by_key_and_line() {
    // A flag: named with the key, and said to be not finite (it said "inf is not >= 0").
    assert_refused_with(
        "dm-inf",
        GOOD_SCENE,
        GOOD_OBJ,
        &["--technique", "gaussian", "--gaussian-dm", "inf"],
        &["gaussian.dm: inf is not finite", "--gaussian-dm"],
    );
    assert_refused_with(
        "dm-f32-flag",
        GOOD_SCENE,
        GOOD_OBJ,
        &["--technique", "gaussian", "--gaussian-dm", "1e39"],
        &["gaussian.dm: 1e39 does not fit in 32-bit floats"],
    );
    // A scene key: its line (GOOD_SCENE has 22 lines, the table is the 24th, the key the 25th).
    for (value, want) in [
        ("1e39", "1e39 does not fit in 32-bit floats"),
        ("inf", "inf is not finite"),
        ("nan", "NaN is not finite"),
    ] {
        let s = format!("{GOOD_SCENE}\n[gaussian]\ndm = {value}\n");
        assert_refused(
            &format!("dm-scene-{value}"),
            &s,
            GOOD_OBJ,
            &["s.toml:25", want],
        );
    }
}

#[test]
fn a_missing_output_folder_is_created_and_said_or_removed_on_failure() {
    let d = case_dir("out-folder", GOOD_SCENE, GOOD_OBJ);
    let out = penumbra()
        .args(["render", "--technique", "hard", "--out"])
        .arg(d.join("new/sub/v.exr"))
        .arg(d.join("s.toml"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    for f in ["new", "new/sub"] {
        let said = format!("created folder {}\n", d.join(f).display());
        assert!(err.contains(&said), "{said:?}: {err}");
    }
    assert!(d.join("new/sub/v.exr").is_file());
    // A render that fails leaves no folder behind.
    let huge = GOOD_SCENE
        .replace("width = 24", "width = 200000")
        .replace("height = 16", "height = 200000");
    std::fs::write(d.join("s.toml"), huge).unwrap();
    let out = penumbra()
        .args(["render", "--technique", "hard", "--backend", "cpu", "--out"])
        .arg(d.join("other/v.exr"))
        .arg(d.join("s.toml"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("too large"), "{err}");
    assert!(!err.contains("created folder"), "{err}");
    assert_eq!(files_in(&d), ["m.obj", "new", "s.toml"]);
    let _ = std::fs::remove_dir_all(&d);
}
