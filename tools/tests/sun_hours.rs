//! `penumbra sun-hours` end to end: a day's hours of direct sun over a fixture, as an EXR of
//! one channel `hours` equal to the library's sum at the same sun, and a colour map; bad
//! requests refused with no output.

mod common;
use common::{fixtures, penumbra, scratch};

use std::path::Path;

/// The channel `hours` of an EXR: (width, height, values).
fn read_hours(path: &Path) -> (usize, usize, Vec<f32>) {
    use exr::prelude::*;
    let image = read_all_flat_layers_from_file(path).unwrap();
    let layer = &image.layer_data[0];
    let channel = &layer.channel_data.list[0];
    assert_eq!(channel.name.to_string(), "hours");
    let size = layer.size;
    (
        size.width(),
        size.height(),
        channel.sample_data.values_as_f32().collect(),
    )
}

/// `penumbra sun-hours SCENE`, its flags to be given.
fn sun_hours(scene: &Path) -> std::process::Command {
    let mut c = penumbra();
    c.arg("sun-hours").arg(scene);
    c
}

/// The fixture `sun.toml` seen at 40 x 30, its meshes named by absolute paths, in `d`.
fn small_sun_scene(d: &Path) -> std::path::PathBuf {
    let text = std::fs::read_to_string(fixtures().join("scenes/sun.toml")).unwrap();
    let meshes = fixtures().join("meshes").canonicalize().unwrap();
    let text = text
        .replace("width = 320", "width = 40")
        .replace("height = 240", "height = 30")
        .replace("\"../meshes/", &format!("\"{}/", meshes.display()));
    let p = d.join("sun.toml");
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn a_day_of_hours_over_a_fixture() {
    let d = scratch("sun-hours-day");
    let scene = small_sun_scene(&d);
    let (exr, png) = (d.join("out/h.exr"), d.join("out/h.png"));
    let out = sun_hours(&scene)
        .args(["--lat", "48.85", "--lon", "2.35"])
        .args(["--start", "2026-06-21T00:00:00+02:00"])
        .args(["--end", "2026-06-22T00:00:00+02:00", "--step", "1h"])
        .args(["--samples", "16", "--out"])
        .arg(&exr)
        .arg("--png")
        .arg(&png)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("24 steps of 60 min (16 in daylight)"), "{err}");
    let (w, h, hours) = read_hours(&exr);
    assert_eq!((w, h), (40, 30));
    // Open ground sees every daylight step; the cow and its shadow fewer.
    let max = hours.iter().copied().fold(0.0f32, f32::max);
    assert_eq!(max, 16.0);
    assert!(hours.iter().all(|&v| (0.0..=16.0).contains(&v)));
    assert!(hours.iter().filter(|&&v| v < 12.0).count() > 20, "shade");
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png).unwrap()));
    let info = decoder.read_info().unwrap().info().clone();
    assert!(
        info.width > 40 && info.height == 30,
        "the legend at the right"
    );
    assert_eq!(info.color_type, png::ColorType::Rgb);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn north_and_up_turn_the_sun_with_the_scene() {
    let d = scratch("sun-hours-frame");
    let scene = small_sun_scene(&d);
    let run = |out: &str, frame: &[&str]| {
        let path = d.join(out);
        let status = sun_hours(&scene)
            .args(["--lat", "48.85", "--lon", "2.35"])
            .args(["--start", "2026-06-21T08:00", "--end", "2026-06-21T12:00"])
            .args(["--samples", "16", "--out"])
            .arg(&path)
            .args(frame)
            .status()
            .unwrap();
        assert!(status.success());
        read_hours(&path).2
    };
    let plain = run("a.exr", &[]);
    assert_eq!(plain, run("b.exr", &["--north", "0,0,-1", "--up", "0,1,0"]));
    // North along +x instead: the morning sun comes from another side.
    assert_ne!(plain, run("c.exr", &["--north", "1,0,0"]));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn bad_requests_are_refused_with_no_output() {
    let d = scratch("sun-hours-bad");
    let scene = small_sun_scene(&d);
    let exr = d.join("h.exr");
    let run = |args: &[&str]| {
        let out = sun_hours(&scene)
            .args(args)
            .arg("--out")
            .arg(&exr)
            .output()
            .unwrap();
        assert!(!out.status.success(), "{args:?} succeeded");
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let day = ["--start", "2026-06-21", "--end", "2026-06-22"];
    let cases: [(Vec<&str>, &str); 7] = [
        (
            [&["--lat", "48", "--lon", "2", "--north", "0,1,0"][..], &day].concat(),
            "give two orthogonal directions",
        ),
        (
            [&["--lat", "48", "--lon", "2", "--up", "0,0,0"][..], &day].concat(),
            "--up \"0,0,0\": a zero vector has no direction",
        ),
        (
            [&["--lat", "91", "--lon", "0"][..], &day].concat(),
            "--lat 91",
        ),
        (
            vec![
                "--lat",
                "48",
                "--lon",
                "2",
                "--start",
                "2026-06-22",
                "--end",
                "2026-06-21",
            ],
            "is not after --start",
        ),
        (
            [&["--lat", "48", "--lon", "2", "--step", "fast"][..], &day].concat(),
            "--step \"fast\"",
        ),
        (
            vec![
                "--lat",
                "48",
                "--lon",
                "2",
                "--start",
                "midsummer",
                "--end",
                "2026-06-22",
            ],
            "--start \"midsummer\"",
        ),
        (
            [&["--lat", "48", "--lon", "2", "--samples", "10"][..], &day].concat(),
            "--samples 10",
        ),
    ];
    for (args, said) in cases {
        let err = run(&args);
        assert!(err.contains(said), "{args:?}: {err}");
        assert!(!exr.exists(), "{args:?} left {}", exr.display());
    }
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn sensor_points_from_a_file_give_their_hours() {
    let d = scratch("sun-hours-points");
    let scene = small_sun_scene(&d);
    let points = d.join("p.csv");
    std::fs::write(&points, "x,y,z\n5,0,5\n0.8,0,0.3\n").unwrap();
    let run = |out: &str, extra: &[&str]| {
        sun_hours(&scene)
            .args(["--lat", "48.85", "--lon", "2.35"])
            .args([
                "--start",
                "2026-06-21",
                "--end",
                "2026-06-22",
                "--samples",
                "16",
            ])
            .arg("--points")
            .arg(&points)
            .arg("--out")
            .arg(d.join(out))
            .args(extra)
            .output()
            .unwrap()
    };
    let out = run("h.csv", &["--normal", "0,1,0"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(d.join("h.csv")).unwrap();
    let rows: Vec<&str> = text.lines().collect();
    assert_eq!(rows[0], "hours");
    // Open ground sees all 16 daylight steps; beside the cow, its shadow takes some.
    assert_eq!(rows[1].parse::<f32>().unwrap(), 16.0);
    assert!(rows[2].parse::<f32>().unwrap() < 15.0, "{text}");
    for (extra, out, said) in [
        (&[][..], "a.csv", "positions only and no normals"),
        (
            &["--normal", "0,1,0", "--png", "m.png"][..],
            "b.csv",
            "--png draws the camera's pixels",
        ),
        (&["--normal", "0,1,0"][..], "c.exr", "name it .npy or .csv"),
    ] {
        let o = run(out, extra);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            !o.status.success() && err.contains(said),
            "{extra:?}: {err}"
        );
        assert!(!d.join(out).exists());
    }
    let _ = std::fs::remove_dir_all(&d);
}
