//! `penumbra points` end to end: sensor points read from `.npy` and `.csv` files give the
//! library's visibility at them (`Renderer::visibility_at`), of one light or of each light of a
//! scene of several, written as float32 `.npy` or `.csv`; and hostile points files refused with
//! a message naming the file (and the CSV line), exit status 1 and no output.

mod common;
use std::path::{Path, PathBuf};
use std::process::Output;

use common::{files_in, fixtures, penumbra, scratch};
use penumbra::glam::DVec3;
use penumbra::{Backend, RenderOptions, Renderer, Scene, Technique};

/// Points on the ground of `quad-over-plane.toml`, facing up: under the quad's centre (umbra),
/// in its penumbra on two sides, and far from it (lit).
const GROUND: [[f64; 3]; 6] = [
    [0.0, 0.0, 0.0],
    [1.2, 0.0, 0.0],
    [0.3, 0.0, -1.1],
    [8.0, 0.0, 0.0],
    [-7.0, 0.0, 3.5],
    [0.25, 0.0, 0.25],
];

fn scene_file(name: &str) -> PathBuf {
    fixtures().join("scenes").join(name)
}

/// The rows x, y, z, nx, ny, nz of [`GROUND`], normals up.
fn ground_rows() -> Vec<[f64; 6]> {
    GROUND
        .iter()
        .map(|p| [p[0], p[1], p[2], 0.0, 1.0, 0.0])
        .collect()
}

/// The library's visibility at `rows` under light `light` of the scene file `scene`.
fn library(
    scene: &str,
    light: usize,
    rows: &[[f64; 6]],
    technique: Technique,
    samples: usize,
) -> Vec<f32> {
    let scene = Scene::load(&scene_file(scene)).unwrap();
    let positions: Vec<DVec3> = rows.iter().map(|r| DVec3::new(r[0], r[1], r[2])).collect();
    let normals: Vec<DVec3> = rows.iter().map(|r| DVec3::new(r[3], r[4], r[5])).collect();
    let options = RenderOptions {
        samples,
        jitter: false,
    };
    Renderer::new(Backend::Cpu)
        .visibility_at(&scene, light, &positions, &normals, technique, &options)
        .unwrap()
}

/// A `.npy` file of format 1.0: the header dict `dict` (padded to 64 bytes), then `data`.
fn write_npy(path: &Path, dict: &str, data: &[u8]) {
    let unpadded = 10 + dict.len() + 1;
    let header = format!(
        "{dict}{}\n",
        " ".repeat(unpadded.next_multiple_of(64) - unpadded)
    );
    let mut b = b"\x93NUMPY\x01\x00".to_vec();
    b.extend_from_slice(&(header.len() as u16).to_le_bytes());
    b.extend_from_slice(header.as_bytes());
    b.extend_from_slice(data);
    std::fs::write(path, b).unwrap();
}

/// `rows` as a C-ordered `<f8` array of shape (n, columns).
fn write_rows_f8(path: &Path, rows: &[Vec<f64>]) {
    let cols = rows[0].len();
    let data: Vec<u8> = rows
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    write_npy(
        path,
        &format!(
            "{{'descr': '<f8', 'fortran_order': False, 'shape': ({}, {cols}), }}",
            rows.len()
        ),
        &data,
    );
}

/// The shape and values of a `<f4` `.npy` file.
fn read_npy_f4(path: &Path) -> (Vec<usize>, Vec<f32>) {
    let b = std::fs::read(path).unwrap();
    assert_eq!(&b[..8], b"\x93NUMPY\x01\x00");
    let len = u16::from_le_bytes([b[8], b[9]]) as usize;
    assert_eq!((10 + len) % 64, 0, "the data is aligned");
    let header = std::str::from_utf8(&b[10..10 + len]).unwrap();
    assert!(header.contains("'descr': '<f4'") && header.contains("'fortran_order': False"));
    let shape = header
        .split("'shape': (")
        .nth(1)
        .unwrap()
        .split(')')
        .next()
        .unwrap()
        .split(',')
        .filter(|s| !s.trim().is_empty())
        .map(|s| s.trim().parse().unwrap())
        .collect();
    let values = b[10 + len..]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
        .collect();
    (shape, values)
}

/// The header and the rows of a CSV file the command wrote.
fn read_csv(path: &Path) -> (String, Vec<Vec<f32>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().to_string();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

/// `rows` as CSV text, with a header and a comment.
fn csv_text(rows: &[[f64; 6]]) -> String {
    let mut s = String::from("# sensors on the ground\nx,y,z,nx,ny,nz\n");
    for r in rows {
        let r: Vec<String> = r.iter().map(|v| format!("{v}")).collect();
        s.push_str(&r.join(","));
        s.push('\n');
    }
    s
}

/// Runs `penumbra points SCENE --points POINTS --out OUT ARGS...`.
fn points(scene: &Path, pts: &Path, out: &Path, args: &[&str]) -> Output {
    penumbra()
        .arg("points")
        .arg(scene)
        .arg("--points")
        .arg(pts)
        .arg("--out")
        .arg(out)
        .args(args)
        .output()
        .unwrap()
}

fn succeeded(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

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

/// A run refused: exit status 1, no panic, every piece of `want` in the message, and the folder
/// left holding only `inputs`.
fn refused(d: &Path, out: &Output, inputs: &[&str], want: &[&str]) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "should fail with 1: {err}");
    assert!(!err.contains("panicked"), "panicked: {err}");
    for w in want {
        assert!(err.contains(w), "the message should say {w:?}: {err}");
    }
    let mut inputs: Vec<String> = inputs.iter().map(|s| s.to_string()).collect();
    inputs.sort();
    assert_eq!(files_in(d), inputs, "left output behind: {err}");
}

/// Writes `bytes` as `name` into a fresh folder and runs the command on quad-over-plane with it
/// as the points and `out` as the output; asserts the refusal.
fn refuse_points(case: &str, name: &str, bytes: &[u8], args: &[&str], want: &[&str]) {
    let d = scratch(&format!("points-{case}"));
    let p = d.join(name);
    std::fs::write(&p, bytes).unwrap();
    let out = points(
        &scene_file("quad-over-plane.toml"),
        &p,
        &d.join("v.npy"),
        args,
    );
    refused(&d, &out, &[name], want);
    let _ = std::fs::remove_dir_all(&d);
}

/// The `.npy` bytes of `dict` and `data`.
fn npy_bytes(dict: &str, data: &[u8]) -> Vec<u8> {
    let d = scratch("points-npy-bytes");
    let p = d.join("a.npy");
    write_npy(&p, dict, data);
    let b = std::fs::read(&p).unwrap();
    let _ = std::fs::remove_dir_all(&d);
    b
}

fn f8(values: &[f64]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

#[test]
fn hostile_npy_files_are_refused_naming_the_file_and_the_problem() {
    let two_rows = f8(&[0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 8.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let good = "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 6), }";
    let truncated = npy_bytes(good, &two_rows[..70]);
    refuse_points(
        "truncated",
        "p.npy",
        &truncated,
        &[],
        &["p.npy", "truncated", "96 bytes", "holds 70"],
    );
    // The header itself cut short.
    refuse_points(
        "cut-header",
        "p.npy",
        &truncated[..40],
        &[],
        &["p.npy", "header is truncated"],
    );
    let i4: Vec<u8> = [1i32; 12].iter().flat_map(|v| v.to_le_bytes()).collect();
    refuse_points(
        "i4",
        "p.npy",
        &npy_bytes(
            "{'descr': '<i4', 'fortran_order': False, 'shape': (2, 6), }",
            &i4,
        ),
        &[],
        &["p.npy", "dtype '<i4'", "'<f8' or '<f4'"],
    );
    refuse_points(
        "fortran",
        "p.npy",
        &npy_bytes(
            "{'descr': '<f8', 'fortran_order': True, 'shape': (2, 6), }",
            &two_rows,
        ),
        &[],
        &["p.npy", "Fortran", "C-ordered"],
    );
    refuse_points(
        "shape5",
        "p.npy",
        &npy_bytes(
            "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 5), }",
            &two_rows[..80],
        ),
        &[],
        &["p.npy", "shape is (2, 5)", "(n, 6)"],
    );
    refuse_points(
        "positions-only",
        "p.npy",
        &npy_bytes(
            "{'descr': '<f8', 'fortran_order': False, 'shape': (4, 3), }",
            &two_rows,
        ),
        &[],
        &["p.npy", "no normals", "--normal"],
    );
    let mut nan = two_rows.clone();
    nan[8 * 7..8 * 8].copy_from_slice(&f64::NAN.to_le_bytes());
    refuse_points(
        "npy-nan",
        "p.npy",
        &npy_bytes(good, &nan),
        &[],
        &["p.npy", "point 1", "y = NaN", "not a finite number"],
    );
    let zero = f8(&[0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 8.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    refuse_points(
        "npy-zero-normal",
        "p.npy",
        &npy_bytes(good, &zero),
        &[],
        &["p.npy", "point 1", "normal (0, 0, 0) is zero"],
    );
    refuse_points(
        "npy-empty",
        "p.npy",
        b"",
        &[],
        &["p.npy", "empty", "NumPy header"],
    );
    refuse_points(
        "not-npy",
        "p.npy",
        b"x,y,z,nx,ny,nz\n",
        &[],
        &["p.npy", "not a NumPy .npy file"],
    );
    refuse_points(
        "no-points",
        "p.npy",
        &npy_bytes(
            "{'descr': '<f8', 'fortran_order': False, 'shape': (0, 6), }",
            &[],
        ),
        &[],
        &["p.npy", "no points"],
    );
    let mut long = two_rows.clone();
    long.extend_from_slice(&[0; 8]);
    refuse_points(
        "trailing",
        "p.npy",
        &npy_bytes(good, &long),
        &[],
        &["p.npy", "104 bytes after its header", "96"],
    );
}

#[test]
fn hostile_csv_files_are_refused_naming_the_file_line_and_column() {
    let csv = |rows: &str| format!("x,y,z,nx,ny,nz\n{rows}").into_bytes();
    refuse_points(
        "csv-word",
        "p.csv",
        &csv("0,0,0,0,1,0\n1,zero,0,0,1,0\n"),
        &[],
        &["p.csv:3", "column 2 (y)", "\"zero\" is not a number"],
    );
    refuse_points(
        "csv-nan",
        "p.csv",
        &csv("0,0,0,0,1,0\n\n# a comment\n1,0,NaN,0,1,0\n"),
        &[],
        &["p.csv:5", "column 3 (z)", "NaN is not a finite number"],
    );
    refuse_points(
        "csv-zero-normal",
        "p.csv",
        &csv("0,0,0,0,1,0\n1,0,0,0,0,0\n"),
        &[],
        &["p.csv:3", "normal (0, 0, 0) is zero"],
    );
    refuse_points(
        "csv-columns",
        "p.csv",
        &csv("0,0,0,0,1,0\n1,0,0,0,1\n"),
        &[],
        &["p.csv:3", "5 columns", "x,y,z,nx,ny,nz"],
    );
    refuse_points(
        "csv-no-normals",
        "p.csv",
        b"0,0,0\n1,0,0\n",
        &[],
        &[
            "p.csv:1",
            "no normals",
            "--normal X,Y,Z supplies one normal for every point",
        ],
    );
    refuse_points(
        "csv-normals-and-flag",
        "p.csv",
        &csv("0,0,0,0,1,0\n"),
        &["--normal", "0,1,0"],
        &["p.csv:1", "--normal is for files of positions only"],
    );
    refuse_points("csv-empty", "p.csv", b"", &[], &["p.csv", "no points"]);
    refuse_points(
        "csv-header-only",
        "p.csv",
        &csv("# nothing\n"),
        &[],
        &["p.csv", "no points"],
    );
    // Finite but beyond the supported coordinates: the library's refusal, placed in the file.
    refuse_points(
        "csv-far",
        "p.csv",
        &csv("0,0,0,0,1,0\n1e300,0,0,0,1,0\n"),
        &[],
        &["p.csv:3", "point 1", "beyond the supported coordinates"],
    );
    refuse_points(
        "csv-bad-normal-flag",
        "p.csv",
        b"0,0,0\n",
        &["--normal", "0,0,0"],
        &["--normal", "no direction"],
    );
    refuse_points(
        "points-txt",
        "p.txt",
        b"0,0,0,0,1,0\n",
        &[],
        &["--points", "p.txt", ".npy or .csv"],
    );
}

#[test]
fn bad_lights_and_outputs_are_refused_before_any_work() {
    let d = scratch("points-outputs");
    let pts = d.join("p.csv");
    let text = csv_text(&ground_rows());
    std::fs::write(&pts, &text).unwrap();
    let out = points(
        &scene_file("two-lights.toml"),
        &pts,
        &d.join("v.npy"),
        &["--light", "sun"],
    );
    refused(
        &d,
        &out,
        &["p.csv"],
        &["--light sun", "two-lights.toml", "key, fill"],
    );
    let quad = scene_file("quad-over-plane.toml");
    let out = points(&quad, &pts, &d.join("v.txt"), &[]);
    refused(&d, &out, &["p.csv"], &["--out", "v.txt", ".npy or .csv"]);
    // The points file as the output, by another name of it too.
    for target in [pts.clone(), d.join(".").join("p.csv")] {
        let out = points(&quad, &pts, &target, &[]);
        refused(&d, &out, &["p.csv"], &["p.csv", "is an input of this run"]);
        assert_eq!(std::fs::read_to_string(&pts).unwrap(), text);
    }
    let out = points(&quad, &pts, &quad, &[]);
    refused(
        &d,
        &out,
        &["p.csv"],
        &["quad-over-plane.toml", ".npy or .csv"],
    );
    // A technique that gives no visibility at points, and bad samples.
    let out = points(&quad, &pts, &d.join("v.npy"), &["--technique", "wedges"]);
    assert!(!out.status.success());
    assert_eq!(files_in(&d), ["p.csv"]);
    let out = points(&quad, &pts, &d.join("v.npy"), &["--samples", "10"]);
    refused(&d, &out, &["p.csv"], &["--samples 10", "perfect square"]);
    let _ = std::fs::remove_dir_all(&d);
}

#[cfg(target_os = "linux")]
#[test]
fn points_beyond_the_memory_are_refused_before_they_are_read() {
    let d = scratch("points-memory");
    let p = d.join("p.npy");
    // 50 million points of (50_000_000, 6) <f8: a sparse file of 2.4 GB, refused under a 2 GB
    // address-space limit before any of it is read.
    write_npy(
        &p,
        "{'descr': '<f8', 'fortran_order': False, 'shape': (50000000, 6), }",
        &[],
    );
    let f = std::fs::OpenOptions::new().write(true).open(&p).unwrap();
    let header = f.metadata().unwrap().len();
    f.set_len(header + 50_000_000 * 48).unwrap();
    drop(f);
    let out = std::process::Command::new("sh")
        .arg("-c")
        .arg("ulimit -v 2000000; exec \"$0\" points \"$@\"")
        .arg(env!("CARGO_BIN_EXE_penumbra"))
        .arg(scene_file("quad-over-plane.toml"))
        .arg("--points")
        .arg(&p)
        .arg("--out")
        .arg(d.join("v.npy"))
        .output()
        .unwrap();
    refused(
        &d,
        &out,
        &["p.npy"],
        &["p.npy", "50000000 points", "memory available"],
    );
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
