//! Triangle meshes loaded from Wavefront OBJ (through `tobj`), welded by exact position.
//!
//! Welding makes adjacency real: two corners with bit-identical coordinates (with `-0.0` read as
//! `0.0`) become one vertex, whatever the OBJ's own indices say. Zero-area triangles (repeated
//! vertices after welding, or collinear corners) are dropped and counted, never fatal.

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{DMat4, DVec3};
use thiserror::Error;

/// What can be wrong with a mesh file. Every variant names the file, and the line where there is
/// one (1-based).
#[derive(Debug, Error)]
pub enum MeshError {
    /// The file could not be read.
    #[error("{path}: cannot read mesh: {error}")]
    Io {
        /// The mesh file.
        path: PathBuf,
        /// The underlying error.
        error: std::io::Error,
    },
    /// The OBJ text is malformed.
    #[error("{path}:{line}: malformed OBJ: {message}")]
    Parse {
        /// The mesh file.
        path: PathBuf,
        /// 1-based line of the offending statement (0 when it could not be located).
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("{path}:{line}: vertex {index} has a non-finite coordinate")]
    NonFiniteVertex {
        /// The mesh file.
        path: PathBuf,
        /// 1-based line of the `v` statement.
        line: usize,
        /// 0-based vertex index in the file.
        index: usize,
    },
    /// A triangle refers to a vertex that does not exist.
    #[error("{path}: triangle {triangle} refers to vertex {index}, but the mesh has {count}")]
    BadIndex {
        /// The mesh file (or mesh name for meshes built in memory).
        path: PathBuf,
        /// 0-based triangle index.
        triangle: usize,
        /// The offending vertex index.
        index: usize,
        /// Number of vertices.
        count: usize,
    },
    /// The file holds no triangle at all.
    #[error("{path}: mesh has no triangles")]
    Empty {
        /// The mesh file.
        path: PathBuf,
    },
}

/// An indexed triangle mesh with welded vertices.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions, unique.
    pub positions: Vec<DVec3>,
    /// Counter-clockwise (as authored) vertex index triples.
    pub triangles: Vec<[u32; 3]>,
    /// How many zero-area triangles were dropped while building.
    pub dropped_degenerate: usize,
    /// How many triangles were dropped as repeats of an earlier one: the same three vertices
    /// (after welding) in either winding, as a face listed twice or a double-sided sheet
    /// listed once per side. Both copies cast the same shadow; kept, each silhouette edge
    /// would get two wedges that blend as two occluders.
    pub dropped_duplicate: usize,
}

/// The key under which a position is welded: its bits, with `-0.0` mapped to `0.0`.
fn weld_key(p: DVec3) -> [u64; 3] {
    let k = |x: f64| if x == 0.0 { 0u64 } else { x.to_bits() };
    [k(p.x), k(p.y), k(p.z)]
}

impl TriangleMesh {
    /// The same mesh with every triangle's winding reversed (each normal turned around).
    pub fn flipped(&self) -> TriangleMesh {
        TriangleMesh {
            positions: self.positions.clone(),
            triangles: self.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect(),
            dropped_degenerate: self.dropped_degenerate,
            dropped_duplicate: self.dropped_duplicate,
        }
    }

    /// Builds a welded mesh from raw positions and triangles. Non-finite positions and
    /// out-of-range indices are errors naming the mesh by `name`; degenerate and repeated
    /// triangles are dropped and counted.
    ///
    /// ```
    /// use penumbra::glam::DVec3;
    /// use penumbra::geom::TriangleMesh;
    ///
    /// let p = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::X]; // the last repeats the second
    /// let m = TriangleMesh::from_raw("tri", &p, &[[0, 1, 2], [0, 3, 1]])?;
    /// assert_eq!((m.positions.len(), m.triangles.len(), m.dropped_degenerate), (3, 1, 1));
    /// assert!(TriangleMesh::from_raw("bad", &p, &[[0, 1, 9]]).is_err());
    /// # Ok::<(), penumbra::geom::MeshError>(())
    /// ```
    pub fn from_raw(
        name: &str,
        positions: &[DVec3],
        triangles: &[[u32; 3]],
    ) -> Result<Self, MeshError> {
        Self::from_raw_at(Path::new(name), positions, triangles)
    }

    /// [`TriangleMesh::from_raw`] of a mesh read from the file `name` (errors name the file).
    fn from_raw_at(
        name: &Path,
        positions: &[DVec3],
        triangles: &[[u32; 3]],
    ) -> Result<Self, MeshError> {
        if let Some(index) = positions.iter().position(|p| !p.is_finite()) {
            return Err(MeshError::NonFiniteVertex {
                path: name.to_path_buf(),
                line: 0,
                index,
            });
        }
        let mut mesh = TriangleMesh::default();
        let mut remap = Vec::with_capacity(positions.len());
        let mut seen: HashMap<[u64; 3], u32> = HashMap::with_capacity(positions.len());
        for &p in positions {
            let p = DVec3::new(p.x + 0.0, p.y + 0.0, p.z + 0.0); // -0 -> +0
            let id = *seen.entry(weld_key(p)).or_insert_with(|| {
                mesh.positions.push(p);
                (mesh.positions.len() - 1) as u32
            });
            remap.push(id);
        }
        let mut faces: std::collections::HashSet<[u32; 3]> =
            std::collections::HashSet::with_capacity(triangles.len());
        for (t, tri) in triangles.iter().enumerate() {
            let mut w = [0u32; 3];
            for k in 0..3 {
                let i = tri[k] as usize;
                if i >= positions.len() {
                    return Err(MeshError::BadIndex {
                        path: name.to_path_buf(),
                        triangle: t,
                        index: i,
                        count: positions.len(),
                    });
                }
                w[k] = remap[i];
            }
            let [a, b, c] = w.map(|i| mesh.positions[i as usize]);
            let mut key = w;
            key.sort_unstable();
            if (b - a).cross(c - a) == DVec3::ZERO {
                mesh.dropped_degenerate += 1;
            } else if !faces.insert(key) {
                mesh.dropped_duplicate += 1;
            } else {
                mesh.triangles.push(w);
            }
        }
        Ok(mesh)
    }

    /// Loads every object of an OBJ file, triangulated, into one welded mesh.
    ///
    /// Materials are ignored (a missing `.mtl` is not an error). Errors name the file and, where
    /// the statement can be located, its line.
    pub fn load_obj(path: &Path) -> Result<Self, MeshError> {
        let text = crate::input::read_text(path).map_err(|error| MeshError::Io {
            path: path.to_path_buf(),
            error,
        })?;
        Self::parse_obj(path, &text)
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

    /// A closed UV sphere of radius 1 around the origin, outward-facing: a pole at `+y` and one
    /// at `-y`, `stacks - 1` rings of `slices` vertices, `2 * slices * (stacks - 1)` triangles.
    ///
    /// # Panics
    ///
    /// If `stacks < 2` or `slices < 3`.
    pub fn uv_sphere(stacks: u32, slices: u32) -> TriangleMesh {
        assert!(
            stacks >= 2 && slices >= 3,
            "uv_sphere({stacks}, {slices}) is degenerate"
        );
        let mut p = vec![DVec3::Y];
        for i in 1..stacks {
            let theta = std::f64::consts::PI * i as f64 / stacks as f64;
            for k in 0..slices {
                let phi = std::f64::consts::TAU * k as f64 / slices as f64;
                p.push(DVec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    -theta.sin() * phi.sin(),
                ));
            }
        }
        p.push(DVec3::NEG_Y);
        let ring = |i: u32, k: u32| 1 + (i - 1) * slices + k % slices;
        let south = p.len() as u32 - 1;
        let mut t = Vec::new();
        for k in 0..slices {
            t.push([0, ring(1, k), ring(1, k + 1)]);
            t.push([south, ring(stacks - 1, k + 1), ring(stacks - 1, k)]);
        }
        for i in 1..stacks - 1 {
            for k in 0..slices {
                let (a, b) = (ring(i, k), ring(i, k + 1));
                let (c, d) = (ring(i + 1, k), ring(i + 1, k + 1));
                t.push([a, c, d]);
                t.push([a, d, b]);
            }
        }
        TriangleMesh::from_raw("uv_sphere", &p, &t)
            .expect("finite positions and in-range indices by construction")
    }

    /// The mesh with `m` applied to every position (triangles and welding unchanged).
    pub fn transformed(&self, m: &DMat4) -> TriangleMesh {
        TriangleMesh {
            positions: self
                .positions
                .iter()
                .map(|&p| m.transform_point3(p))
                .collect(),
            triangles: self.triangles.clone(),
            dropped_degenerate: self.dropped_degenerate,
            dropped_duplicate: self.dropped_duplicate,
        }
    }

    /// The three corners of triangle `t`.
    pub fn triangle(&self, t: usize) -> [DVec3; 3] {
        self.triangles[t].map(|i| self.positions[i as usize])
    }

    /// Writes the mesh as OBJ text (one object, 1-based indices), full `f64` precision.
    pub fn to_obj_string(&self, comment: &str) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        for line in comment.lines() {
            let _ = writeln!(s, "# {line}");
        }
        for p in &self.positions {
            let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
        }
        for t in &self.triangles {
            let _ = writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        s
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
    fn welds_split_vertices_and_negative_zero() {
        let m = load_str(
            "o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\no b\nv -0 0 0\nv 0 1 0\nv -1 0 0\nf 4 5 6\n",
        )
        .unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.triangles.len(), 2);
        assert_eq!(m.triangles[0][0], m.triangles[1][0]);
    }

    #[test]
    fn triangulates_quads_and_drops_degenerates() {
        let m =
            load_str("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nf 1 2 3 4\nf 1 2 5\n").unwrap();
        assert_eq!(m.triangles.len(), 2);
        assert_eq!(m.dropped_degenerate, 1);
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
    fn repeated_faces_in_either_winding_are_dropped_and_counted() {
        // A quad, the same quad again, and its first triangle once more wound the other way
        // (a double-sided sheet of triangles).
        let m = load_str(
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf 1 2 3 4\nf 3 2 1\nf 2 3 1\n",
        )
        .unwrap();
        assert_eq!(m.triangles, [[0, 1, 2], [0, 2, 3]]);
        assert_eq!((m.dropped_duplicate, m.dropped_degenerate), (4, 0));
    }

    #[test]
    fn nan_vertex_names_line_and_index() {
        let e = load_str("v 0 0 0\nv 1 0 0\n# c\nv nan 1 0\nf 1 2 3\n").unwrap_err();
        match e {
            MeshError::NonFiniteVertex { line, index, .. } => assert_eq!((line, index), (4, 2)),
            other => panic!("unexpected {other}"),
        }
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

    #[test]
    fn bad_index_in_memory_is_an_error() {
        let e = TriangleMesh::from_raw("mem", &[DVec3::ZERO; 3], &[[0, 1, 3]]);
        assert!(matches!(e, Err(MeshError::BadIndex { index: 3, .. })));
    }
}
