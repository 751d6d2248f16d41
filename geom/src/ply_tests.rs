//! Tests of the PLY reader (`ply.rs`), on files made here.

use std::path::Path;

use crate::mesh::{MeshError, TriangleMesh};
use crate::mesh_format::MeshFormat;

fn parse(name: &str, bytes: &[u8]) -> Result<TriangleMesh, MeshError> {
    TriangleMesh::parse(Path::new(name), MeshFormat::Ply, bytes)
}

fn obj(text: &str) -> TriangleMesh {
    TriangleMesh::parse_obj(Path::new("m.obj"), text).unwrap()
}

/// A value of a binary PLY body.
#[derive(Clone, Copy)]
pub(crate) enum B {
    F(f32),
    D(f64),
    U8(u8),
    I32(i32),
    U32(u32),
}

/// The bytes of `values`, big-endian where `big`.
pub(crate) fn body(values: &[B], big: bool) -> Vec<u8> {
    let mut out = Vec::new();
    for v in values {
        let mut b = match *v {
            B::F(x) => x.to_le_bytes().to_vec(),
            B::D(x) => x.to_le_bytes().to_vec(),
            B::U8(x) => vec![x],
            B::I32(x) => x.to_le_bytes().to_vec(),
            B::U32(x) => x.to_le_bytes().to_vec(),
        };
        if big {
            b.reverse();
        }
        out.extend(b);
    }
    out
}

/// Five vertices: a unit square in z = 0 and an apex over it.
const SQUARE_AND_APEX: [[f32; 3]; 5] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.5, 0.5, 1.0],
];

const OBJ_VERTICES: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\n";

/// An ASCII PLY of the square and apex with a quad, two triangles and a pentagon-free mix of
/// extra properties and elements that the reader passes over.
const ASCII: &str = "ply\r\nformat ascii 1.0\ncomment made by hand\nelement vertex 5\n\
property float x\nproperty float y\nproperty float z\nproperty uchar red\n\
property list uchar float weights\nelement face 3\nproperty list uchar int vertex_indices\n\
property int flags\nelement edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n\
0 0 0 255 0\n1 0 0 0 2 0.5 0.5\n1 1 0 9 0\n\n0 1 0 9 1 1.0\n0.5 0.5 1 0 0\n\
4 0 1 2 3 7\n3 0 1 4 0\n3 1 2 4 0\n0 1\n";

const ASCII_AS_OBJ: &str = "f 1 2 3 4\nf 1 2 5\nf 2 3 5\n";

#[test]
fn ascii_faces_are_fan_triangulated_as_obj_polygons_are() {
    let m = parse("a.ply", ASCII.as_bytes()).unwrap();
    assert_eq!(m, obj(&format!("{OBJ_VERTICES}{ASCII_AS_OBJ}")));
    assert_eq!(m.triangles.len(), 4);
    // `vertex_index`, and a face element before the vertices.
    let alias = "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar uint vertex_index\n\
        element vertex 3\nproperty double x\nproperty double y\nproperty double z\nend_header\n\
        3 0 1 2\n0 0 0\n1 0 0\n0 1 0";
    let m = parse("b.ply", alias.as_bytes()).unwrap();
    assert_eq!(m, obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
}

/// The binary PLY of [`ASCII`]'s mesh, little- or big-endian.
fn binary(big: bool) -> Vec<u8> {
    let format = if big {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    };
    let mut out = format!(
        "ply\nformat {format} 1.0\nelement vertex 5\nproperty float x\nproperty float y\n\
         property float z\nproperty double w\nelement face 3\nproperty list uchar int vertex_indices\n\
         end_header\n"
    )
    .into_bytes();
    let mut values = Vec::new();
    for p in SQUARE_AND_APEX {
        values.extend(p.map(B::F));
        values.push(B::D(1.0));
    }
    for f in [&[0, 1, 2, 3][..], &[0, 1, 4], &[1, 2, 4]] {
        values.push(B::U8(f.len() as u8));
        values.extend(f.iter().map(|&i| B::I32(i)));
    }
    out.extend(body(&values, big));
    out
}

#[test]
fn binary_files_of_either_byte_order_read_as_the_ascii_one() {
    let ascii = parse("a.ply", ASCII.as_bytes()).unwrap();
    assert_eq!(parse("le.ply", &binary(false)).unwrap(), ascii);
    assert_eq!(parse("be.ply", &binary(true)).unwrap(), ascii);
    // Every prefix of a binary file: an error naming the file, never a panic.
    let whole = binary(false);
    for n in 0..whole.len() {
        let e = parse("t.ply", &whole[..n]).expect_err("a cut file");
        assert!(e.to_string().starts_with("t.ply"), "{e}");
    }
}

#[test]
fn tristrips_restart_at_minus_one_and_alternate_their_winding() {
    let mut file = b"ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty float x\n\
        property float y\nproperty float z\nelement tristrips 1\nproperty list int int vertex_indices\n\
        end_header\n"
        .to_vec();
    let mut values: Vec<B> = SQUARE_AND_APEX.iter().flat_map(|p| p.map(B::F)).collect();
    // Strip 0 1 3 2 (two triangles), restart, strip 1 2 4.
    let strip = [0, 1, 3, 2, -1, 1, 2, 4];
    values.push(B::I32(strip.len() as i32));
    values.extend(strip.map(B::I32));
    file.extend(body(&values, false));
    let m = parse("s.ply", &file).unwrap();
    // (0 1 3), then odd (1 2 3) as (k, k+2, k+1); after the restart (1 2 4).
    assert_eq!(
        m,
        obj(&format!("{OBJ_VERTICES}f 1 2 4\nf 2 3 4\nf 2 3 5\n"))
    );
}

#[test]
fn hostile_files_are_errors_that_name_the_file_the_line_and_the_fault() {
    let head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
        property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    let tri = "0 0 0\n1 0 0\n0 1 0\n";
    let cases: Vec<(String, &str)> = vec![
        // Indices out of range, negative, or -1 outside a strip, with the face's line.
        (
            format!("{head}{tri}3 0 1 3\n"),
            "a.ply:13: PLY: face 0: index 2 is 3, but the file has 3 vertices",
        ),
        (
            format!("{head}{tri}3 0 -1 2\n"),
            "a.ply:13: PLY: face 0: index 1 is -1",
        ),
        // Non-finite positions; no number; beyond the type; values left over; too few.
        (
            format!("{head}0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n"),
            "a.ply:11: PLY: vertex 1: a non-finite coordinate",
        ),
        (
            format!("{head}0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n"),
            "a.ply:11: PLY: vertex 1: `zero` is not a F32 value",
        ),
        (
            format!("{head}{tri}300 0 1 2\n"),
            "a.ply:13: PLY: face 0: 300 is out of range for U8",
        ),
        (
            format!("{head}{tri}3 0 1 2 5\n"),
            "a.ply:13: PLY: face 0: 1 values more than its properties take",
        ),
        (
            format!("{head}{tri}3 0 1\n"),
            "a.ply:13: PLY: face 0: fewer values than its properties take",
        ),
        (
            format!("{head}{tri}2 0 1\n"),
            "a.ply:13: PLY: face 0: a face needs at least 3 vertices, found 2",
        ),
        (
            format!("{head}{tri}"),
            "a.ply:7: PLY: element face of 1 elements, with those before it, needs at least",
        ),
        // A count no file holds: refused before anything is made of it.
        (
            head.replace("vertex 3", "vertex 1000000000000000"),
            "a.ply:3: PLY: element vertex of 1000000000000000 elements",
        ),
        (
            head.replace("vertex 3", "vertex -3"),
            "a.ply:3: PLY: element vertex: `-3` is not a count",
        ),
        // The header's faults, each with its line.
        (
            format!("{}{tri}", head.replace("end_header\n", "")),
            "a.ply:9: PLY: `0 0 0` is not a header line",
        ),
        (
            head.replace("end_header\n", ""),
            "a.ply:9: PLY: truncated: the header ends without `end_header`",
        ),
        (
            head.replace("ascii", "utf8"),
            "a.ply:2: PLY: unknown format `utf8`",
        ),
        (
            head.replace("float y", "real y"),
            "a.ply:5: PLY: unknown property type `real`",
        ),
        (
            head.replace("uchar int", "float int"),
            "a.ply:8: PLY: list vertex_indices: its length's type is not an integer type",
        ),
        (
            head.replace("uchar int", "uchar float"),
            "a.ply:8: PLY: list vertex_indices: vertex indices of a non-integer type",
        ),
        (
            format!("{}{tri}3 0 1 2\n", head.replace("float z", "float w")),
            "a.ply:3: PLY: element vertex has no scalar property z",
        ),
        (
            format!(
                "{}{tri}3 0 1 2\n",
                head.replace("vertex_indices", "corners")
            ),
            "a.ply:7: PLY: element face has no list property `vertex_indices`",
        ),
        (
            format!(
                "{}{tri}",
                head.replace(
                    "element face 1\nproperty list uchar int vertex_indices\n",
                    ""
                )
            ),
            "a.ply: PLY: no `element face` or `element tristrips`: points cast no shadow",
        ),
        (
            head.replace("format ascii 1.0\n", ""),
            "a.ply: PLY: no `format` line",
        ),
    ];
    for (text, want) in cases {
        let e = parse("a.ply", text.as_bytes()).expect_err(want).to_string();
        assert!(e.starts_with(want), "{e}\nwanted: {want}");
    }
    // Binary: a list longer than the file, and a NaN, name the element.
    let bin = "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\n\
        property float y\nproperty float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n";
    let mut values: Vec<B> = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
        .iter()
        .flat_map(|p: &[f32; 3]| p.map(B::F))
        .collect();
    values.extend([B::U32(u32::MAX), B::I32(0)]);
    let mut file = bin.as_bytes().to_vec();
    file.extend(body(&values, true));
    let e = parse("b.ply", &file).unwrap_err().to_string();
    assert!(
        e.starts_with("b.ply: PLY: face 0: truncated: a list of 4294967295 items of 4 bytes"),
        "{e}"
    );
    values[4] = B::F(f32::INFINITY);
    let mut file = bin.as_bytes().to_vec();
    file.extend(body(&values, true));
    let e = parse("b.ply", &file).unwrap_err().to_string();
    assert!(
        e.starts_with("b.ply: PLY: vertex 1: a non-finite coordinate"),
        "{e}"
    );
}

#[test]
fn mutated_files_are_read_or_refused_never_a_panic() {
    let mut rng = crate::rng::Rng::new(7);
    for good in [ASCII.as_bytes().to_vec(), binary(false), binary(true)] {
        parse("g.ply", &good).unwrap();
        for _ in 0..3000 {
            let _ = parse("g.ply", &crate::mesh_files::mutated(&mut rng, &good));
        }
    }
}
