//! `penumbra render --shaded`: the shaded preview, a diffuse picture of the scene lit by the
//! visibility images of the render, beside V outputs it leaves unchanged; bad paths refused
//! before the render, leaving no output.

mod common;
use std::path::Path;

use common::{GOOD_OBJ, GOOD_SCENE, assert_refused_with, case_dir, files_in, penumbra};
use penumbra_geom::{
    SHADED_AMBIENT, SHADED_BACKGROUND, VisibilityChannels, VisibilityImage, srgb_byte,
};

/// The light table of [`GOOD_SCENE`].
const LIGHT: &str = "[light]\ncenter = [0.0, 4.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\n\
    tangent = [1.0, 0.0, 0.0]\nsize = [1.0, 1.0]\n";

/// The ground mesh of [`GOOD_SCENE`], before its floating quad.
const GROUND: &str = "[[mesh]]\nobj = \"m.obj\"\nscale = 4.0\n\n";

fn ok(out: &std::process::Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Width, height and RGB pixels of a PNG.
fn read_rgb(path: &Path) -> (u32, u32, Vec<[u8; 3]>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    let rgb = buf[..info.buffer_size()]
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    (info.width, info.height, rgb)
}

/// Renders `scene` (with [`GOOD_OBJ`]) in a fresh folder to `v.exr`, `v.png` and, with
/// `shaded`, `shaded.png`; returns the folder.
fn render(name: &str, scene: &str, technique: &str, shaded: bool) -> std::path::PathBuf {
    let d = case_dir(name, scene, GOOD_OBJ);
    let mut cmd = penumbra();
    cmd.arg("render")
        .arg(d.join("s.toml"))
        .args(["--samples", "4", "--technique", technique, "--out"])
        .arg(d.join("v.exr"))
        .arg("--png")
        .arg(d.join("v.png"));
    if shaded {
        cmd.arg("--shaded").arg(d.join("shaded.png"));
    }
    ok(&cmd.output().unwrap());
    d
}

/// The grey of a surface pixel (R = G = B), `None` for the background.
fn grey(c: [u8; 3]) -> Option<u8> {
    if c == SHADED_BACKGROUND {
        return None;
    }
    assert!(c[0] == c[1] && c[1] == c[2], "a surface is grey: {c:?}");
    Some(c[0])
}

#[test]
fn lit_ground_is_brighter_than_its_umbra_and_v_outputs_are_unchanged() {
    let d = render("shaded", GOOD_SCENE, "reference", true);
    assert_eq!(
        files_in(&d),
        ["m.obj", "s.toml", "shaded.png", "v.exr", "v.png"]
    );
    let (w, h, rgb) = read_rgb(&d.join("shaded.png"));
    assert_eq!((w, h), (24, 16), "the camera's size");
    let v = VisibilityImage::read_exr(&d.join("v.exr")).unwrap();
    let ambient = srgb_byte(SHADED_AMBIENT);
    let (mut umbra, mut lit, mut background) = (0, Vec::new(), 0);
    for (c, &v) in rgb.iter().zip(&v.data) {
        match grey(*c) {
            None => background += 1,
            // The quad's umbra on the ground: the ambient alone.
            Some(g) if v == 0.0 => {
                assert_eq!(g, ambient);
                umbra += 1;
            }
            Some(g) if v == 1.0 => lit.push(g),
            Some(_) => {}
        }
    }
    assert!(umbra > 0 && background > 0 && !lit.is_empty());
    assert!(
        lit.iter().all(|&g| g > ambient + 60),
        "lit surfaces are well above the umbra: {lit:?}"
    );
    // The top row sees the sky.
    assert!(rgb[..w as usize].iter().all(|&c| c == SHADED_BACKGROUND));
    // The V outputs are the same bytes with and without the preview.
    let plain = render("plain", GOOD_SCENE, "reference", false);
    for f in ["v.exr", "v.png"] {
        assert_eq!(
            std::fs::read(d.join(f)).unwrap(),
            std::fs::read(plain.join(f)).unwrap(),
            "{f}"
        );
    }
    let _ = std::fs::remove_dir_all(&d);
    let _ = std::fs::remove_dir_all(&plain);
}

#[test]
fn a_floating_quad_over_nothing_is_seen_lit_or_not() {
    // The quad alone: its V image is 1 everywhere (lit, and where the rays miss).
    let alone = GOOD_SCENE.replace(GROUND, "");
    assert_ne!(alone, GOOD_SCENE);
    // The same under a light that faces away from it: V = 0 on the quad.
    let away = alone.replace("normal = [0.0, -1.0, 0.0]", "normal = [0.0, 1.0, 0.0]");
    assert_ne!(away, alone);
    for (name, scene, lit) in [("floating", &alone, true), ("floating-away", &away, false)] {
        let d = render(name, scene, "wedges-blend", true);
        let v = VisibilityImage::read_exr(&d.join("v.exr")).unwrap();
        let (_, _, rgb) = read_rgb(&d.join("shaded.png"));
        let quad: Vec<u8> = rgb.iter().filter_map(|&c| grey(c)).collect();
        assert!(
            quad.len() > 4 && quad.len() < rgb.len() / 4,
            "{name}: the quad is seen, not the whole picture ({} px)",
            quad.len()
        );
        if lit {
            assert!(v.data.iter().all(|&x| x == 1.0), "{name}: V shows nothing");
            assert!(quad.iter().all(|&g| g > 200), "{name}: {quad:?}");
        } else {
            assert!(quad.iter().all(|&g| g == srgb_byte(SHADED_AMBIENT)));
        }
        let _ = std::fs::remove_dir_all(&d);
    }
}

#[test]
fn where_two_lights_reach_is_brighter_than_where_one_does() {
    let entry = |x: f64| {
        format!(
            "[[light]]\ncenter = [{x:?}, 4.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\n\
             tangent = [1.0, 0.0, 0.0]\nsize = [1.0, 1.0]\n"
        )
    };
    let two = GOOD_SCENE.replace(LIGHT, &format!("{}\n{}", entry(-0.8), entry(0.9)));
    assert_ne!(two, GOOD_SCENE);
    for technique in ["reference", "depth-complexity", "wedges-blend"] {
        let d = render(&format!("two-{technique}"), &two, technique, true);
        assert_eq!(
            files_in(&d),
            [
                "m.obj",
                "s.toml",
                "shaded.png",
                "v.exr",
                "v.light0.png",
                "v.light1.png"
            ]
        );
        let (w, h, rgb) = read_rgb(&d.join("shaded.png"));
        assert_eq!((w, h), (24, 16));
        let channels = VisibilityChannels::read_exr(&d.join("v.exr")).unwrap();
        let [a, b] = channels.channels() else {
            panic!("two channels")
        };
        let (mut one, mut both) = (Vec::new(), Vec::new());
        for (k, c) in rgb.iter().enumerate() {
            let Some(g) = grey(*c) else { continue };
            match (a.image.data[k], b.image.data[k]) {
                (1.0, 1.0) => both.push(g),
                (1.0, 0.0) | (0.0, 1.0) => one.push(g),
                _ => {}
            }
        }
        assert!(!one.is_empty() && !both.is_empty(), "{technique}");
        let (max_one, min_both) = (one.iter().max().unwrap(), both.iter().min().unwrap());
        assert!(
            max_one < min_both,
            "{technique}: one light up to {max_one}, both from {min_both}"
        );
        let _ = std::fs::remove_dir_all(&d);
    }
}

#[test]
fn bad_shaded_paths_are_refused_before_the_render_leaving_nothing() {
    let d = std::env::temp_dir();
    let tmp = d.display();
    for (name, path, want) in [
        (
            "jpg",
            format!("{tmp}/x.jpg"),
            vec!["--shaded", ".jpg", "name it .png"],
        ),
        ("exr", format!("{tmp}/x.EXR"), vec![".exr", "8-bit RGB PNG"]),
        (
            "bare",
            format!("{tmp}/x"),
            vec!["has no extension", "name it .png"],
        ),
    ] {
        assert_refused_with(
            &format!("shaded-{name}"),
            GOOD_SCENE,
            GOOD_OBJ,
            &["--shaded", &path],
            &want,
        );
        assert!(!Path::new(&path).exists());
    }
}

#[test]
fn unwritable_shaded_paths_leave_no_output() {
    // A folder where the file would go; the PNG of V again; a folder that is a file; and a
    // folder no one can write in, found before the render too: nothing is written.
    let d = case_dir("shaded-unwritable", GOOD_SCENE, GOOD_OBJ);
    std::fs::create_dir(d.join("dir.png")).unwrap();
    let mut cases = vec![
        (d.join("dir.png"), "not a regular file"),
        (d.join("v.png"), "named twice"),
        (d.join("m.obj").join("x.png"), "x.png"),
    ];
    if Path::new("/proc/self").exists() {
        cases.push((
            Path::new("/proc/x.png").to_path_buf(),
            "/proc/x.png: cannot be written",
        ));
    }
    for (path, want) in cases {
        let out = penumbra()
            .arg("render")
            .arg(d.join("s.toml"))
            .args(["--samples", "4", "--technique", "reference", "--out"])
            .arg(d.join("v.exr"))
            .arg("--png")
            .arg(d.join("v.png"))
            .arg("--shaded")
            .arg(&path)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{}", path.display());
        assert!(!err.contains("panicked"), "{err}");
        assert!(err.contains(want), "{}: {err}", path.display());
        assert_eq!(files_in(&d), ["dir.png", "m.obj", "s.toml"], "{err}");
    }
    let _ = std::fs::remove_dir_all(&d);
}
