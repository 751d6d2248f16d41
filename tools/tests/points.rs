//! `penumbra points` end to end: sensor points read from `.npy` and `.csv` files give the
//! library's visibility at them (`Renderer::visibility_at`), of one light or of each light of a
//! scene of several, written as float32 `.npy` or `.csv`.

mod common;
use common::points::*;
use common::{penumbra, scratch};
use penumbra::Technique;

#[test]
fn npy_and_csv_give_the_library_values_in_and_out_of_the_quads_shadow() {
    let d = scratch("points-ground");
    let scene = scene_file("quad-over-plane.toml");
    let rows = ground_rows();
    let want = library(
        "quad-over-plane.toml",
        0,
        &rows,
        Technique::DepthComplexity,
        256,
    );
    assert_eq!(want[0], 0.0, "under the quad's centre: umbra");
    assert_eq!(want[5], 0.0);
    assert_eq!((want[3], want[4]), (1.0, 1.0), "far from the quad: lit");
    for v in &want[1..3] {
        assert!(*v > 0.05 && *v < 0.95, "penumbra: {want:?}");
    }

    let (npy_in, csv_in) = (d.join("p.npy"), d.join("p.csv"));
    write_rows_f8(
        &npy_in,
        &rows.iter().map(|r| r.to_vec()).collect::<Vec<_>>(),
    );
    std::fs::write(&csv_in, csv_text(&rows)).unwrap();

    let out = points(&scene, &npy_in, &d.join("v.npy"), &[]);
    succeeded(&out);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("6 points") && err.contains("depth-complexity") && err.contains("v.npy"),
        "summary: {err}"
    );
    assert_eq!(read_npy_f4(&d.join("v.npy")), (vec![6], want.clone()));

    succeeded(&points(&scene, &csv_in, &d.join("v.csv"), &[]));
    let (header, values) = read_csv(&d.join("v.csv"));
    assert_eq!(header, "V");
    assert_eq!(values, want.iter().map(|v| vec![*v]).collect::<Vec<_>>());

    // Across formats, into a folder made for it.
    succeeded(&points(&scene, &npy_in, &d.join("new/v.csv"), &[]));
    assert_eq!(read_csv(&d.join("new/v.csv")).1, values);

    // Positions only, with one normal for all; float32 input.
    let positions: Vec<Vec<f64>> = GROUND.iter().map(|p| p.to_vec()).collect();
    write_rows_f8(&d.join("p3.npy"), &positions);
    succeeded(&points(
        &scene,
        &d.join("p3.npy"),
        &d.join("v3.npy"),
        &["--normal", "0,1,0"],
    ));
    assert_eq!(read_npy_f4(&d.join("v3.npy")).1, want);
    let data: Vec<u8> = rows
        .iter()
        .flatten()
        .flat_map(|v| (*v as f32).to_le_bytes())
        .collect();
    write_npy(
        &d.join("p4.npy"),
        "{'descr': '<f4', 'fortran_order': False, 'shape': (6, 6), }",
        &data,
    );
    succeeded(&points(&scene, &d.join("p4.npy"), &d.join("v4.npy"), &[]));
    assert_eq!(read_npy_f4(&d.join("v4.npy")).1, want);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn the_reference_technique_gives_the_librarys_reference() {
    let d = scratch("points-reference");
    let rows = ground_rows();
    let want = library("quad-over-plane.toml", 0, &rows, Technique::Reference, 64);
    assert_eq!((want[0], want[3]), (0.0, 1.0));
    let pts = d.join("p.csv");
    std::fs::write(&pts, csv_text(&rows)).unwrap();
    let out = points(
        &scene_file("quad-over-plane.toml"),
        &pts,
        &d.join("v.npy"),
        &["--technique", "reference", "--samples", "64"],
    );
    succeeded(&out);
    assert!(String::from_utf8_lossy(&out.stderr).contains("reference (64 samples)"));
    assert_eq!(read_npy_f4(&d.join("v.npy")), (vec![6], want));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_scene_of_two_lights_gives_a_column_per_light_and_light_picks_one() {
    let d = scratch("points-two");
    let scene = scene_file("two-lights.toml");
    // A line over the ground through the two casters' shadows, and a point far from both.
    let mut rows: Vec<[f64; 6]> = (0..24)
        .map(|k| {
            let (x, z) = (-2.5 + 0.25 * k as f64, 0.6 - 0.05 * k as f64);
            [x, 0.0, z, 0.0, 1.0, 0.0]
        })
        .collect();
    rows.push([-6.0, 0.0, -6.0, 0.0, 1.0, 0.0]);
    let key = library("two-lights.toml", 0, &rows, Technique::DepthComplexity, 256);
    let fill = library("two-lights.toml", 1, &rows, Technique::DepthComplexity, 256);
    assert_ne!(key, fill, "the lights cast different shadows");

    let pts = d.join("p.npy");
    write_rows_f8(&pts, &rows.iter().map(|r| r.to_vec()).collect::<Vec<_>>());
    let out = points(&scene, &pts, &d.join("v.npy"), &[]);
    succeeded(&out);
    assert!(String::from_utf8_lossy(&out.stderr).contains("2 lights (key, fill)"));
    let (shape, values) = read_npy_f4(&d.join("v.npy"));
    assert_eq!(shape, [rows.len(), 2]);
    let column = |c: usize| {
        values
            .iter()
            .skip(c)
            .step_by(2)
            .copied()
            .collect::<Vec<_>>()
    };
    assert_eq!((column(0), column(1)), (key.clone(), fill.clone()));

    succeeded(&points(&scene, &pts, &d.join("v.csv"), &[]));
    let (header, csv) = read_csv(&d.join("v.csv"));
    assert_eq!(header, "key,fill");
    assert_eq!(
        csv,
        key.iter()
            .zip(&fill)
            .map(|(k, f)| vec![*k, *f])
            .collect::<Vec<_>>()
    );

    succeeded(&points(
        &scene,
        &pts,
        &d.join("fill.npy"),
        &["--light", "fill"],
    ));
    assert_eq!(read_npy_f4(&d.join("fill.npy")), (vec![rows.len()], fill));
    succeeded(&points(
        &scene,
        &pts,
        &d.join("key.csv"),
        &["--light", "key"],
    ));
    let (header, csv) = read_csv(&d.join("key.csv"));
    assert_eq!(header, "key");
    assert_eq!(csv, key.iter().map(|v| vec![*v]).collect::<Vec<_>>());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn the_command_is_in_the_help() {
    let out = penumbra().arg("--help").output().unwrap();
    let help = String::from_utf8_lossy(&out.stdout);
    assert!(
        help.contains("points") && help.contains("sensor points"),
        "{help}"
    );
    let out = penumbra().args(["points", "--help"]).output().unwrap();
    let help = String::from_utf8_lossy(&out.stdout);
    for flag in [
        "--points",
        "--out",
        "--light",
        "--normal",
        "--samples",
        "--technique",
        "--jitter",
    ] {
        assert!(help.contains(flag), "points --help lacks {flag}");
    }
}
