//! `penumbra bench`: its report, its comparisons of techniques and its refusals.

use std::path::PathBuf;
use std::process::Output;

mod common;
use common::{GOOD_OBJ, GOOD_SCENE, case_dir, no_adapter_here, penumbra, stdout_of};

/// `penumbra bench` on GOOD_SCENE in a scratch folder, with `args`.
fn bench_case(name: &str, args: &[&str]) -> (PathBuf, Output) {
    let d = case_dir(name, GOOD_SCENE, GOOD_OBJ);
    let out = penumbra()
        .arg("bench")
        .arg(d.join("s.toml"))
        .args(args)
        .output()
        .unwrap();
    (d, out)
}

fn json_of(out: &Output) -> serde_json::Value {
    serde_json::from_str(&stdout_of(out)).unwrap()
}

#[test]
fn bench_compares_techniques_round_by_round() {
    let (d, out) = bench_case(
        "bench-ratio",
        &[
            "--technique",
            "hard,wedges-blend",
            "--frames",
            "3",
            "--rounds",
            "2",
            "--backend",
            "cpu",
            "--json",
        ],
    );
    let j = json_of(&out);
    let runs = j["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 2);
    assert_eq!(runs[0]["technique"], "Hard");
    assert_eq!(runs[1]["technique"], "WedgesBlend");
    let wall = |r: &serde_json::Value| r["median_ms"]["frame_wall"].as_f64().unwrap();
    for r in runs {
        assert_eq!(r["frames"], 3);
        assert_eq!(r["rounds"], 2);
        assert!(wall(r) > 0.0 && wall(r).is_finite(), "{r}");
    }
    let ratios = j["ratios"].as_array().unwrap();
    assert_eq!(ratios.len(), 1);
    let r = &ratios[0];
    assert_eq!(r["technique"], "WedgesBlend");
    assert_eq!(r["to"], "Hard");
    let ratio = r["frame_wall"].as_f64().unwrap();
    assert!(
        (ratio - wall(&runs[1]) / wall(&runs[0])).abs() < 1e-9 * ratio,
        "{r}"
    );
    let per_round = r["per_round"].as_array().unwrap();
    assert_eq!(per_round.len(), 2);
    assert!(
        per_round
            .iter()
            .all(|x| x.as_f64().is_some_and(|x| x > 0.0 && x.is_finite())),
        "{r}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn bench_times_every_gpu_pass() {
    let (d, out) = bench_case(
        "bench-gpu",
        &[
            "--technique",
            "wedges-blend",
            "--frames",
            "2",
            "--backend",
            "gpu",
            "--json",
        ],
    );
    if no_adapter_here(&out) {
        return;
    }
    // One technique: the report is the object itself, as before lists were accepted.
    let j = json_of(&out);
    assert_eq!(j["technique"], "WedgesBlend");
    let ms = &j["median_ms"];
    for pass in ["depth", "stencil", "wedge", "blend", "resolve"] {
        let t = ms[pass].as_f64();
        assert!(t.is_some_and(|t| t >= 0.0 && t.is_finite()), "{pass}: {ms}");
    }
    let (total, wall) = (
        ms["gpu_total"].as_f64().unwrap(),
        ms["frame_wall"].as_f64().unwrap(),
    );
    assert!(total > 0.0 && wall > 0.0, "{ms}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn bench_refuses_bad_arguments() {
    for (name, args, want) in [
        ("bench-rounds", &["--rounds", "0"][..], "--rounds"),
        ("bench-frames", &["--frames", "0"][..], "--frames"),
        (
            "bench-cpu-only",
            &["--technique", "wedges,reference", "--backend", "gpu"][..],
            "--backend gpu: reference runs on the CPU only",
        ),
    ] {
        let (d, out) = bench_case(name, args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{name}");
        assert!(err.contains(want), "{name}: {err}");
        let _ = std::fs::remove_dir_all(&d);
    }
}

#[test]
fn bench_counters_count_every_gpu_pass() {
    // GOOD_SCENE at 40 x 24 with a ground wide enough to cover every pixel, so that the depth
    // pre-pass shades each pixel at least once.
    let covered = GOOD_SCENE
        .replace("width = 24\nheight = 16", "width = 40\nheight = 24")
        .replace("scale = 4.0", "scale = 100.0");
    assert!(covered.contains("width = 40") && covered.contains("scale = 100.0"));
    let d = case_dir("bench-counters", &covered, GOOD_OBJ);
    let out = penumbra()
        .arg("bench")
        .arg(d.join("s.toml"))
        .args(["--technique", "hard,wedges-blend,depth-complexity,pcf"])
        .args([
            "--samples",
            "16",
            "--backend",
            "gpu",
            "--counters",
            "--json",
        ])
        .output()
        .unwrap();
    if no_adapter_here(&out) {
        return;
    }
    let j = json_of(&out);
    let reports = j.as_array().expect("one report per technique");
    assert_eq!(reports.len(), 4, "{j}");
    let pixels = 40 * 24;
    // The pass `name` of the report of `technique`, and one of its statistics.
    let pass = |technique: &str, name: &str| -> serde_json::Value {
        let r = reports
            .iter()
            .find(|r| r["technique"] == technique)
            .unwrap_or_else(|| panic!("no report of {technique}: {j}"));
        assert_eq!(r["counters"]["pixels"], pixels, "{r}");
        r["counters"]["passes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["pass"] == name)
            .unwrap_or_else(|| panic!("{technique}: no {name} pass: {r}"))
            .clone()
    };
    let stat = |p: &serde_json::Value, s: &str| -> u64 {
        p["statistics"][s]
            .as_u64()
            .unwrap_or_else(|| panic!("no statistic {s} (lavapipe has them): {p}"))
    };
    for (technique, passes) in [
        ("Hard", &["depth", "stencil", "resolve"][..]),
        (
            "WedgesBlend",
            &["depth", "stencil", "wedge", "blend", "resolve"],
        ),
        (
            "DepthComplexity",
            &["depth", "stencil", "edge_lists", "count", "resolve"],
        ),
        ("Pcf", &["depth", "light_map", "filter"]),
    ] {
        for name in passes {
            let p = pass(technique, name);
            assert!(
                p["passes"].as_u64().unwrap() >= 1,
                "{technique} {name}: {p}"
            );
            for b in ["bytes_read", "bytes_written"] {
                assert!(p[b].as_u64().unwrap() > 0, "{technique} {name} {b}: {p}");
            }
        }
        // Every pixel is covered: the depth pre-pass shades each at least once, from the four
        // triangles of the two quads (clipping may split them, never drop the ground).
        let depth = pass(technique, "depth");
        assert!(stat(&depth, "fragments") >= pixels, "{technique}: {depth}");
        assert!(stat(&depth, "vertices") >= 12, "{technique}: {depth}");
        assert!(stat(&depth, "primitives") >= 1, "{technique}: {depth}");
        assert_eq!(stat(&depth, "compute"), 0, "{technique}: {depth}");
        // It writes at least a depth and a position per pixel.
        assert!(
            depth["bytes_written"].as_u64().unwrap() >= 20 * pixels,
            "{technique}: {depth}"
        );
    }
    for (technique, name) in [("Hard", "resolve"), ("Pcf", "filter")] {
        let p = pass(technique, name);
        assert!(stat(&p, "fragments") >= pixels, "{technique} {name}: {p}");
    }
    // The occluder's volume and wedges are drawn; the blend and the counting pass run compute
    // threads, the counting pass at least one per pixel.
    assert!(stat(&pass("Hard", "stencil"), "vertices") > 0);
    assert!(stat(&pass("WedgesBlend", "wedge"), "fragments") > 0);
    assert!(stat(&pass("WedgesBlend", "blend"), "compute") > 0);
    assert!(stat(&pass("DepthComplexity", "count"), "compute") >= pixels);
    let tiles = 40u64.div_ceil(8) * 24u64.div_ceil(8);
    assert!(stat(&pass("DepthComplexity", "edge_lists"), "compute") >= tiles);
    let _ = std::fs::remove_dir_all(&d);
}
