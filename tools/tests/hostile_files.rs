//! Hostile files from the command line: links to inputs given as outputs, special files given
//! as inputs, EXR headers that ask for more than they hold, images named as another format, and
//! readers that stop early. Each ends in a clear error with the inputs intact, never a panic or
//! a blocked read.

mod common;
use common::{GOOD_OBJ, GOOD_SCENE, case_dir, files_in, penumbra, scratch};

/// Rewrites the data and display windows in an EXR's header to declare `w x h` pixels: a small
/// file whose header asks for far more than it holds.
fn declare_size(path: &std::path::Path, w: i32, h: i32) {
    let mut bytes = std::fs::read(path).unwrap();
    for name in [&b"dataWindow\0box2i\0"[..], &b"displayWindow\0box2i\0"[..]] {
        let at = bytes
            .windows(name.len())
            .position(|x| x == name)
            .expect("an EXR header has both windows")
            + name.len()
            + 4;
        bytes[at..at + 16].copy_from_slice(
            &[0, 0, w - 1, h - 1]
                .iter()
                .flat_map(|v: &i32| v.to_le_bytes())
                .collect::<Vec<_>>(),
        );
    }
    std::fs::write(path, bytes).unwrap();
}

#[test]
fn compare_refuses_a_header_larger_than_the_other_image_or_the_memory_before_reading_it() {
    let d = scratch("compare-header");
    let (small, big, big2) = (d.join("small.exr"), d.join("big.exr"), d.join("big2.exr"));
    let img = penumbra_geom::VisibilityImage::filled(3, 2, 0.5);
    for p in [&small, &big, &big2] {
        img.write_exr(p).unwrap();
    }
    for p in [&big, &big2] {
        declare_size(p, 30000, 30000);
    }
    // Under a 2 GB address-space limit: one image of 30000 x 30000 floats alone is 3.6 GB.
    let limited = |args: &[&std::path::Path]| {
        let out = std::process::Command::new("sh")
            .arg("-c")
            .arg("ulimit -v 2000000; exec \"$0\" compare \"$@\"")
            .arg(env!("CARGO_BIN_EXE_penumbra"))
            .args(args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        err
    };
    let err = limited(&[&small, &big]);
    assert!(
        err.contains("image sizes differ")
            && err.contains("small.exr is 3 x 2")
            && err.contains("big.exr is 30000 x 30000"),
        "{err}"
    );
    let err = limited(&[&big, &big2]);
    assert!(
        err.contains("big.exr: the header declares 30000 x 30000 pixels")
            && err.contains("of memory are available"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn links_to_inputs_are_refused_as_outputs_and_the_inputs_kept() {
    use std::os::unix::fs::symlink;
    let d = scratch("links");
    let (scene, mesh) = (d.join("s.toml"), d.join("m.obj"));
    std::fs::write(&scene, GOOD_SCENE).unwrap();
    std::fs::write(&mesh, GOOD_OBJ).unwrap();
    let (a, b) = (d.join("a.exr"), d.join("b.exr"));
    penumbra_geom::VisibilityImage::filled(3, 2, 0.5)
        .write_exr(&a)
        .unwrap();
    penumbra_geom::VisibilityImage::filled(3, 2, 0.25)
        .write_exr(&b)
        .unwrap();
    let a_bytes = std::fs::read(&a).unwrap();
    let link = |name: &str, to: &std::path::Path, hard: bool| {
        let l = d.join(name);
        let _ = std::fs::remove_file(&l);
        if hard {
            std::fs::hard_link(to, &l).unwrap();
        } else {
            symlink(to, &l).unwrap();
        }
        l
    };
    for hard in [false, true] {
        let kind = if hard { "hard" } else { "symbolic" };
        // The scene as the EXR, the mesh as the PNG, and image A as the heat map.
        let render = |out: &std::path::Path, png: Option<std::path::PathBuf>| {
            let mut c = penumbra();
            c.args(["render", "--technique", "hard", "--backend", "cpu"])
                .arg(&scene)
                .arg("--out")
                .arg(out);
            if let Some(p) = png {
                c.arg("--png").arg(p);
            }
            c
        };
        let mut heatmap = penumbra();
        heatmap
            .arg("compare")
            .arg(&a)
            .arg(&b)
            .arg("--heatmap")
            .arg(link("heat.png", &a, hard));
        let cases = [
            render(&link("out.exr", &scene, hard), None),
            render(&d.join("v.exr"), Some(link("out.png", &mesh, hard))),
            heatmap,
        ];
        for mut c in cases {
            let out = c.output().unwrap();
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(
                !out.status.success() && err.contains("is an input of this run"),
                "{kind} link, {:?}: {err}",
                c.get_args().collect::<Vec<_>>()
            );
        }
        assert_eq!(
            std::fs::read_to_string(&scene).unwrap(),
            GOOD_SCENE,
            "{kind}"
        );
        assert_eq!(std::fs::read_to_string(&mesh).unwrap(), GOOD_OBJ, "{kind}");
        assert_eq!(std::fs::read(&a).unwrap(), a_bytes, "{kind}");
        assert!(!d.join("v.exr").exists(), "{kind}: partial output left");
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// Runs `c` and returns its exit status and stderr; fails the test if it runs for a minute (a
/// read blocked on a FIFO never ends).
fn within_a_minute(mut c: std::process::Command) -> (std::process::ExitStatus, String) {
    use std::io::Read;
    let mut child = c
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            child
                .stderr
                .take()
                .unwrap()
                .read_to_string(&mut err)
                .unwrap();
            return (status, err);
        }
        if start.elapsed() > std::time::Duration::from_secs(60) {
            let _ = child.kill();
            panic!("{c:?} still running after a minute");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

#[test]
fn special_files_are_refused_as_inputs_before_they_are_read() {
    let d = scratch("special-in");
    let fifo = |name: &str| {
        let p = d.join(name);
        assert!(
            std::process::Command::new("mkfifo")
                .arg(&p)
                .status()
                .unwrap()
                .success()
        );
        p
    };
    std::fs::write(d.join("m.obj"), GOOD_OBJ).unwrap();
    for (name, obj) in [("zero", "/dev/zero"), ("random", "/dev/urandom")] {
        std::fs::write(
            d.join(format!("{name}.toml")),
            GOOD_SCENE.replace("m.obj", obj),
        )
        .unwrap();
    }
    fifo("fifo.obj");
    std::fs::write(
        d.join("fifo-mesh.toml"),
        GOOD_SCENE.replace("m.obj", "fifo.obj"),
    )
    .unwrap();
    let fifo_scene = fifo("fifo-scene.toml");
    let render = |scene: &std::path::Path| {
        let mut c = penumbra();
        c.args(["render", "--technique", "hard", "--backend", "cpu", "--out"])
            .arg(d.join("v.exr"))
            .arg(scene);
        c
    };
    let cases = [
        (
            render(&d.join("zero.toml")),
            "/dev/zero: cannot read mesh: a device, not a regular file",
        ),
        (
            render(&d.join("random.toml")),
            "/dev/urandom: cannot read mesh: a device",
        ),
        (
            render(std::path::Path::new("/dev/zero")),
            "cannot read scene: a device",
        ),
        (
            render(&d.join("fifo-mesh.toml")),
            "fifo.obj: cannot read mesh: a FIFO",
        ),
        (
            render(&fifo_scene),
            "fifo-scene.toml: cannot read scene: a FIFO",
        ),
    ];
    for (c, want) in cases {
        let (status, err) = within_a_minute(c);
        assert!(
            !status.success() && err.contains(want),
            "want {want:?}: {err}"
        );
    }
    assert!(!d.join("v.exr").exists());
    // A FIFO among the scenes `accuracy` reads.
    let scenes = d.join("scenes");
    std::fs::create_dir(&scenes).unwrap();
    std::fs::rename(&fifo_scene, scenes.join("a.toml")).unwrap();
    let mut c = penumbra();
    c.args([
        "accuracy",
        "--samples",
        "4",
        "--technique-samples",
        "4",
        "--scenes",
    ])
    .arg(&scenes);
    let (status, err) = within_a_minute(c);
    assert!(
        !status.success() && err.contains("a.toml: cannot read scene: a FIFO"),
        "{err}"
    );
    // A FIFO where `gen-fixtures` writes a mesh.
    let out = d.join("gen");
    std::fs::create_dir_all(out.join("meshes")).unwrap();
    let blocker = out.join("meshes").join("quad.obj");
    assert!(
        std::process::Command::new("mkfifo")
            .arg(&blocker)
            .status()
            .unwrap()
            .success()
    );
    let mut c = penumbra();
    c.arg("gen-fixtures").arg("--out").arg(&out);
    let (status, err) = within_a_minute(c);
    assert!(!status.success() && err.contains("is a FIFO"), "{err}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn an_image_named_as_another_format_is_refused_and_compare_says_it_reads_exr() {
    let d = case_dir("formats", GOOD_SCENE, GOOD_OBJ);
    let out = penumbra()
        .args(["render", "--technique", "hard", "--backend", "cpu", "--out"])
        .arg(d.join("v.png"))
        .arg(d.join("s.toml"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("writes an OpenEXR image") && err.contains("--png"),
        "{err}"
    );
    assert!(!d.join("v.png").exists());
    // A PNG given to compare.
    let png = d.join("a.png");
    penumbra_geom::VisibilityImage::filled(3, 2, 0.5)
        .write_png(&png)
        .unwrap();
    let out = penumbra()
        .arg("compare")
        .arg(&png)
        .arg(&png)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("a.png: not an OpenEXR file"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_reader_that_stops_early_ends_the_command_quietly() {
    let d = scratch("pipe");
    let a = d.join("a.exr");
    penumbra_geom::VisibilityImage::filled(3, 2, 0.5)
        .write_exr(&a)
        .unwrap();
    // `true` reads nothing and exits at once, closing the pipe before compare (which reads two
    // files first) prints its table.
    let out = std::process::Command::new("sh")
        .arg("-c")
        .arg("\"$0\" compare \"$1\" \"$1\" | true")
        .arg(env!("CARGO_BIN_EXE_penumbra"))
        .arg(&a)
        .stderr(std::process::Stdio::piped())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    let _ = std::fs::remove_dir_all(&d);
}

/// Outputs resolved as they will be once their folders are made: `new/../s.toml` is the scene
/// and `./n/v.png` is `n/v.png`, whether or not `new` and `n` exist, and through a link to a
/// folder `..` is taken from the link's target. Every command's outputs are refused before any
/// work, the inputs kept and no folder made.
#[test]
fn outputs_through_missing_folders_and_dot_dot_are_resolved_before_any_work() {
    use std::os::unix::fs::symlink;
    let d = case_dir("dot-dot", GOOD_SCENE, GOOD_OBJ);
    let (a, b) = (d.join("a.exr"), d.join("b.exr"));
    penumbra_geom::VisibilityImage::filled(3, 2, 0.5)
        .write_exr(&a)
        .unwrap();
    penumbra_geom::VisibilityImage::filled(3, 2, 0.25)
        .write_exr(&b)
        .unwrap();
    std::fs::create_dir(d.join("sub")).unwrap();
    symlink(d.join("sub"), d.join("up")).unwrap();
    let before = files_in(&d);
    let render = |extra: &[&str]| {
        let mut c = penumbra();
        c.current_dir(&d)
            .args([
                "render",
                "s.toml",
                "--technique",
                "hard",
                "--backend",
                "cpu",
            ])
            .args(extra);
        c
    };
    let compare = |heatmap: &str| {
        let mut c = penumbra();
        c.current_dir(&d)
            .args(["compare", "a.exr", "b.exr", "--heatmap", heatmap]);
        c
    };
    let cases = [
        (
            render(&["--out", "v.exr", "--png", "nd/../s.toml"]),
            "is an input of this run",
        ),
        (
            render(&["--out", "nd/./deeper/../../m.obj"]),
            "is an input of this run",
        ),
        (
            render(&[
                "--out",
                "v.exr",
                "--png",
                "./n/v.png",
                "--shaded",
                "n/v.png",
            ]),
            "are the same file",
        ),
        (
            render(&["--out", "n/x/../v.exr", "--png", "n/v.exr"]),
            "are the same file",
        ),
        // `up` is a link to `sub`: `up/../s.toml` is `s.toml` beside `sub`, not beside `up`.
        (
            render(&["--out", "sub/v.exr", "--png", "up/nd/../v.exr"]),
            "are the same file",
        ),
        (compare("nd/../a.exr"), "is an input of this run"),
        (compare("./nd/../b.exr"), "is an input of this run"),
    ];
    for (mut c, want) in cases {
        let out = c.output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        let args: Vec<_> = c.get_args().collect();
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: {err}");
        assert_eq!(files_in(&d), before, "{args:?}: something was written");
        assert!(files_in(&d.join("sub")).is_empty(), "{args:?}");
    }
    assert_eq!(
        std::fs::read_to_string(d.join("s.toml")).unwrap(),
        GOOD_SCENE
    );
    assert_eq!(std::fs::read_to_string(d.join("m.obj")).unwrap(), GOOD_OBJ);
    // The same outputs under distinct names are written, the missing folder made.
    let out = render(&["--out", "nd/../v.exr", "--png", "n/v.png"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(d.join("v.exr").is_file() && d.join("n").join("v.png").is_file());
    let _ = std::fs::remove_dir_all(&d);
}
