//! Reading Wavefront OBJ text into a [`TriangleMesh`]: statements joined across `\`
//! continuations, our own scan of the statements penumbra relies on (so that an error names its
//! line), then `tobj`'s parse, welded by [`TriangleMesh::from_raw`]'s rules.

use std::borrow::Cow;
use std::path::Path;

use glam::DVec3;

use crate::mesh::{MeshError, TriangleMesh};

impl TriangleMesh {
    /// Loads every object of an OBJ file, triangulated, into one welded mesh.
    ///
    /// Materials are ignored (a missing `.mtl` is not an error). Errors name the file and, where
    /// the statement can be located, its line; a glTF or PLY file is refused as such
    /// ([`TriangleMesh::load`]).
    pub fn load_obj(path: &Path) -> Result<Self, MeshError> {
        Self::load(path, crate::mesh_format::MeshFormat::Obj)
    }

    /// [`TriangleMesh::load_obj`] of the text of an OBJ file; `path` names it in errors.
    pub fn parse_obj(path: &Path, text: &str) -> Result<Self, MeshError> {
        // A UTF-8 byte-order mark (as some Windows editors write) is not part of line 1: left
        // there, it hid the first `v` from the parser and shifted every index.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        // A `\` ending a line continues the statement on the next line. The reader does not
        // know it, so the statements are joined first, each keeping the line it starts on.
        let statements = statements(text);
        // Our own scan first: it knows line numbers, which tobj's errors do not carry.
        scan_obj(path, &statements)?;
        let joined;
        let text = if statements.iter().any(|(_, s)| matches!(s, Cow::Owned(_))) {
            joined = statements
                .iter()
                .map(|(_, s)| s.as_ref())
                .collect::<Vec<&str>>()
                .join("\n");
            joined.as_str()
        } else {
            text
        };
        let opts = tobj::LoadOptions {
            triangulate: true,
            single_index: false,
            ..Default::default()
        };
        let (models, _materials) = tobj::load_obj_buf(&mut text.as_bytes(), &opts, |_| {
            Err(tobj::LoadError::OpenFileFailed)
        })
        .map_err(|e| MeshError::Parse {
            path: path.to_path_buf(),
            line: 0,
            message: e.to_string(),
        })?;
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for m in &models {
            let base = positions.len() as u32;
            positions.extend(
                m.mesh
                    .positions
                    .chunks_exact(3)
                    .map(|c| DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64)),
            );
            triangles.extend(
                m.mesh
                    .indices
                    .chunks_exact(3)
                    .map(|c| [base + c[0], base + c[1], base + c[2]]),
            );
        }
        if triangles.is_empty() {
            return Err(MeshError::Empty {
                path: path.to_path_buf(),
            });
        }
        TriangleMesh::from_raw_at(path, &positions, &triangles)
    }
}

/// The statements of an OBJ text, each with the 1-based line it starts on: a line ending in `\`
/// continues on the next one (the `\` becomes a space). Lines without one are borrowed.
fn statements(text: &str) -> Vec<(usize, Cow<'_, str>)> {
    let mut out: Vec<(usize, Cow<'_, str>)> = Vec::new();
    let mut open = false; // whether the last statement ended in `\`
    for (n, raw) in text.lines().enumerate() {
        let (body, continues) = match raw.strip_suffix('\\') {
            Some(b) => (b, true),
            None => (raw, false),
        };
        match out.last_mut() {
            Some((_, s)) if open => {
                let s = s.to_mut();
                s.push(' ');
                s.push_str(body);
            }
            _ if continues => out.push((n + 1, Cow::Owned(body.to_string()))),
            _ => out.push((n + 1, Cow::Borrowed(raw))),
        }
        open = continues;
    }
    out
}

/// Checks the statements penumbra relies on (`v`, `f` and `l`), so that errors carry a line
/// number: `v` needs three numbers, all finite, then an optional weight `w` (finite, non-zero: a
/// point at infinity has no place in a mesh) or three colour components; `f` needs at least
/// three vertex references, `l` any number, each a non-zero integer (negative ones relative)
/// naming a vertex defined before it, and where a reference gives a texture coordinate's or a
/// normal's index, that too is a non-zero integer, a relative one naming one defined before it
/// and a positive one at most 2^32 - 1.
fn scan_obj(path: &Path, statements: &[(usize, Cow<'_, str>)]) -> Result<(), MeshError> {
    let parse_err = |line: usize, message: String| MeshError::Parse {
        path: path.to_path_buf(),
        line,
        message,
    };
    let mut vertices = 0usize;
    let (mut texcoords, mut normals) = (0usize, 0usize);
    let mut colours: Option<(bool, usize)> = None;
    for (line, raw) in statements {
        let line = *line;
        let stmt = raw.split('#').next().unwrap_or("");
        let mut words = stmt.split_whitespace();
        match words.next() {
            Some("v") => {
                // The words on the stack: a list allocated per vertex cost as much as parsing.
                let mut kept = [""; 6];
                let mut count = 0;
                for w in words {
                    if let Some(k) = kept.get_mut(count) {
                        *k = w;
                    }
                    count += 1;
                }
                if count != 3 && count != 4 && count != 6 {
                    return Err(parse_err(
                        line,
                        format!(
                            "`v` needs 3 coordinates (then a weight w, or 3 colour components), found {count} numbers"
                        ),
                    ));
                }
                let nums = &kept[..count];
                let number = |w: &str| -> Result<f64, MeshError> {
                    w.parse()
                        .map_err(|_| parse_err(line, format!("`{w}` is not a number")))
                };
                for w in &nums[3..] {
                    number(w)?;
                }
                // The reader divides the coordinates by the weight.
                let weight = if nums.len() == 4 {
                    let w = number(nums[3])?;
                    if !(w as f32).is_finite() || w as f32 == 0.0 {
                        return Err(parse_err(
                            line,
                            format!(
                                "weight w = {} puts the vertex at infinity or out of 32-bit range; a mesh needs w finite and non-zero (usually 1)",
                                nums[3]
                            ),
                        ));
                    }
                    w
                } else {
                    1.0
                };
                for w in &nums[..3] {
                    let x: f64 = number(w)? / weight;
                    if !x.is_finite() {
                        return Err(MeshError::NonFiniteVertex {
                            path: path.to_path_buf(),
                            line,
                            index: vertices,
                        });
                    }
                    // The OBJ reader keeps 32-bit floats: a larger number would become infinite.
                    if x.abs() > f32::MAX as f64 {
                        return Err(parse_err(
                            line,
                            if weight == 1.0 {
                                format!(
                                    "`{w}` does not fit in 32-bit floats (largest magnitude 3.4e38)"
                                )
                            } else {
                                format!(
                                    "`{w}` divided by the weight {} does not fit in 32-bit floats (largest magnitude 3.4e38)",
                                    nums[3]
                                )
                            },
                        ));
                    }
                }
                // Vertex colours (3 more numbers) on every vertex or on none: the reader
                // refuses a mix without saying where.
                let coloured = nums.len() >= 6;
                match colours {
                    None => colours = Some((coloured, line)),
                    Some((c, first)) if c != coloured => {
                        return Err(parse_err(
                            line,
                            format!(
                                "vertex colours on some vertices only: this vertex {} them, the first (line {first}) {}",
                                if coloured { "has" } else { "lacks" },
                                if c { "has" } else { "lacks" }
                            ),
                        ));
                    }
                    Some(_) => {}
                }
                vertices += 1;
            }
            Some("vt") => texcoords += 1,
            Some("vn") => normals += 1,
            Some(kind @ ("f" | "l")) => {
                // The reader takes a line (`l`) of three or more points as a face, and reads
                // both kinds of reference alike.
                let count = words.clone().count();
                if kind == "f" && count < 3 {
                    return Err(parse_err(
                        line,
                        format!("a face needs at least 3 vertices, found {count}"),
                    ));
                }
                for r in words {
                    let mut parts = r.split('/');
                    let first = parts.next().unwrap_or("");
                    let i: i64 = first
                        .parse()
                        .map_err(|_| parse_err(line, format!("`{r}` is not a vertex index")))?;
                    let ok = (i > 0 && i as usize <= vertices)
                        || (i < 0 && (i.unsigned_abs() as usize) <= vertices);
                    if !ok {
                        return Err(parse_err(
                            line,
                            format!(
                                "vertex index {i} out of range ({vertices} vertices defined so far)"
                            ),
                        ));
                    }
                    // A texture coordinate's and a normal's index, where given: unused here,
                    // but the reader computes with them. A relative one two or more before the
                    // first, or a positive one near 2^63, made its index multiplication
                    // overflow (a panic in a build with overflow checks); zero and one just
                    // before the first it read as no index. All of them are refused here.
                    for (k, part) in parts.take(2).enumerate() {
                        if part.is_empty() {
                            continue;
                        }
                        let (what, defined) = if k == 0 {
                            ("texture coordinate", texcoords)
                        } else {
                            ("normal", normals)
                        };
                        let j: i64 = part.parse().map_err(|_| {
                            parse_err(line, format!("`{r}`: `{part}` is not a {what} index"))
                        })?;
                        let ok = (j > 0 && j <= i64::from(u32::MAX))
                            || (j < 0 && (j.unsigned_abs() as usize) <= defined);
                        if !ok {
                            return Err(parse_err(
                                line,
                                format!("{what} index {j} out of range ({defined} defined so far)"),
                            ));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load_str(text: &str) -> Result<TriangleMesh, MeshError> {
        let dir = std::env::temp_dir().join(format!("penumbra-mesh-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(format!(
            "{:x}.obj",
            text.len() * 31 + text.bytes().map(|b| b as usize).sum::<usize>()
        ));
        std::fs::write(&p, text).unwrap();
        let r = TriangleMesh::load_obj(&p);
        let _ = std::fs::remove_file(&p);
        r
    }

    #[test]
    fn a_byte_order_mark_keeps_every_vertex() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n";
        let plain = load_str(text).unwrap();
        let marked = load_str(&format!("\u{feff}{text}")).unwrap();
        assert_eq!(marked.positions, plain.positions);
        assert_eq!(marked.triangles, plain.triangles);
        assert_eq!(plain.positions.len(), 4);
    }

    #[test]
    fn malformed_statements_name_their_line() {
        for (text, want) in [
            ("v 0 0 0\nv 1 zero 0\n", 2),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", 4),
            ("v 0 0 0\nv 1 0 0\nf 1 2\n", 3),
            ("v 0 0\n", 1),
            // Beyond f32 (the reader's), and colours on some vertices only: both went to line 0.
            ("v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n", 2),
            ("v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0 1 1 1\nf 1 2 3\n", 2),
            // A weight of zero (a point at infinity), one too small for 32-bit floats, one
            // that is no number, and one that pushes the point beyond them; 7 numbers.
            ("v 0 0 0\nv 1 0 0\n\nv 0 1 0 0\nf 1 2 3\n", 4),
            ("v 0 0 0\nv 1 0 0 1e-300\nv 0 1 0\nf 1 2 3\n", 2),
            ("v 0 0 0\nv 1 0 0 one\nv 0 1 0\nf 1 2 3\n", 2),
            ("v 0 0 0\nv 1e30 0 0 1e-10\nv 0 1 0\nf 1 2 3\n", 2),
            ("v 0 0 0 1 0 0 1\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", 1),
            // After a continued statement, lines keep their numbers.
            ("v 0 0 \\\n 0\nv 1 0 0\nv 0 1 0\nf 1 2 \\\n3 \\\n 9\n", 5),
        ] {
            match load_str(text).unwrap_err() {
                MeshError::Parse { line, .. } => assert_eq!(line, want, "{text}"),
                other => panic!("unexpected {other}"),
            }
        }
    }

    #[test]
    fn texture_coordinate_and_normal_indices_are_checked_with_their_line() {
        let head = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n";
        // Relative ones before the first (the reader's index wrapped around and its arithmetic
        // overflowed), zero, beyond 2^32 - 1, no number; and a line's (`l`) vertices.
        for (face, what) in [
            ("f 1/-3 2/1 3/1", "texture coordinate index -3"),
            ("f 1//1 2//-5 3//1", "normal index -5"),
            ("f 1/1/1 2/1/0 3/1/1", "normal index 0"),
            (
                "f 1//7000000000000000000 2//1 3//1",
                "normal index 7000000000000000000",
            ),
            ("f 1/x 2/1 3/1", "`x` is not a texture coordinate index"),
            ("l -9 1", "vertex index -9"),
        ] {
            match load_str(&format!("{head}\n{face}\n")).unwrap_err() {
                MeshError::Parse { line, message, .. } => {
                    assert_eq!(line, 7, "{face}");
                    assert!(message.contains(what), "{face}: {message}");
                }
                other => panic!("{face}: unexpected {other}"),
            }
        }
        // Given ones, relative ones, empty ones and forward ones within range load.
        for face in [
            "f 1/1/1 2/-1/-1 3//1",
            "f 1/ 2// 3/1/",
            "f 1/2 2/2 3/2\nvt 1 1",
        ] {
            let m = load_str(&format!("{head}{face}\n")).unwrap_or_else(|e| panic!("{face}: {e}"));
            assert_eq!(m.triangles.len(), 1, "{face}");
        }
    }

    #[test]
    fn a_backslash_continues_a_statement_and_a_weight_divides() {
        let plain = load_str("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n").unwrap();
        let continued = load_str(
            "v 0 0 \\\n0\nv 1 \\\n  0 \\\n  0\nv 0 1 0\nv 0 0 2 2\nf 1 2 3\nf 1 \\\n 2 4\n",
        )
        .unwrap();
        assert_eq!(continued, plain);
    }
}
