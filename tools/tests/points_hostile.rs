//! `penumbra points` given hostile points files, lights and outputs: each refused with a message
//! naming the file (and the CSV line and column), exit status 1 and no output, before any work.

mod common;
use common::points::*;
use common::{files_in, scratch};

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
