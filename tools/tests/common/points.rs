//! Helpers of the `penumbra points` tests: points files written and read, the library's values,
//! and runs of the command.

use std::path::{Path, PathBuf};
use std::process::Output;

use penumbra::glam::DVec3;
use penumbra::{Backend, RenderOptions, Renderer, Scene, Technique};

use super::{files_in, fixtures, penumbra, scratch};

/// Points on the ground of `quad-over-plane.toml`, facing up: under the quad's centre (umbra),
/// in its penumbra on two sides, and far from it (lit).
pub const GROUND: [[f64; 3]; 6] = [
    [0.0, 0.0, 0.0],
    [1.2, 0.0, 0.0],
    [0.3, 0.0, -1.1],
    [8.0, 0.0, 0.0],
    [-7.0, 0.0, 3.5],
    [0.25, 0.0, 0.25],
];

pub fn scene_file(name: &str) -> PathBuf {
    fixtures().join("scenes").join(name)
}

/// The rows x, y, z, nx, ny, nz of [`GROUND`], normals up.
pub fn ground_rows() -> Vec<[f64; 6]> {
    GROUND
        .iter()
        .map(|p| [p[0], p[1], p[2], 0.0, 1.0, 0.0])
        .collect()
}

/// The library's visibility at `rows` under light `light` of the scene file `scene`.
pub fn library(
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
pub fn write_npy(path: &Path, dict: &str, data: &[u8]) {
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
pub fn write_rows_f8(path: &Path, rows: &[Vec<f64>]) {
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
pub fn read_npy_f4(path: &Path) -> (Vec<usize>, Vec<f32>) {
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
pub fn read_csv(path: &Path) -> (String, Vec<Vec<f32>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().to_string();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

/// `rows` as CSV text, with a header and a comment.
pub fn csv_text(rows: &[[f64; 6]]) -> String {
    let mut s = String::from("# sensors on the ground\nx,y,z,nx,ny,nz\n");
    for r in rows {
        let r: Vec<String> = r.iter().map(|v| format!("{v}")).collect();
        s.push_str(&r.join(","));
        s.push('\n');
    }
    s
}

/// Runs `penumbra points SCENE --points POINTS --out OUT ARGS...`.
pub fn points(scene: &Path, pts: &Path, out: &Path, args: &[&str]) -> Output {
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

pub fn succeeded(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A run refused: exit status 1, no panic, every piece of `want` in the message, and the folder
/// left holding only `inputs`.
pub fn refused(d: &Path, out: &Output, inputs: &[&str], want: &[&str]) {
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
pub fn refuse_points(case: &str, name: &str, bytes: &[u8], args: &[&str], want: &[&str]) {
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
pub fn npy_bytes(dict: &str, data: &[u8]) -> Vec<u8> {
    let d = scratch("points-npy-bytes");
    let p = d.join("a.npy");
    write_npy(&p, dict, data);
    let b = std::fs::read(&p).unwrap();
    let _ = std::fs::remove_dir_all(&d);
    b
}

pub fn f8(values: &[f64]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}
