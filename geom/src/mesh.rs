//! Triangle meshes, welded by exact position (read from Wavefront OBJ files in `obj.rs`, glTF in
//! `gltf.rs` and PLY in `ply.rs`, chosen by the scene file's key in `mesh_files.rs`).
//!
//! Welding makes adjacency real: two corners with bit-identical coordinates (with `-0.0` read as
//! `0.0`) become one vertex, whatever the OBJ's own indices say. Zero-area triangles (repeated
//! vertices after welding, or collinear corners) are dropped and counted, never fatal.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{DMat4, DVec3};
use thiserror::Error;

use crate::mesh_format::MeshFormat;

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
    /// A glTF or PLY file is malformed, or holds what is not read (each reader's documentation
    /// says what it reads).
    #[error("{}: {format}: {message}", at_line(path, *line))]
    Format {
        /// The mesh file.
        path: PathBuf,
        /// Its format.
        format: MeshFormat,
        /// 1-based line where the format has lines and the error one (ASCII PLY, glTF JSON).
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// The file's contents are not of the format its scene-file key names (a glTF file given
    /// as `obj`, an OBJ as `gltf`, ...).
    #[error(
        "{path}: {} (a mesh file is named by its format's key: `obj`, `gltf` or `ply`)",
        what_it_is(*key, *found)
    )]
    WrongFormat {
        /// The mesh file.
        path: PathBuf,
        /// The format its key named.
        key: MeshFormat,
        /// What its first bytes show it is: glTF or PLY by their signatures, `None` for neither
        /// (an OBJ has no signature).
        found: Option<MeshFormat>,
    },
    /// The file holds no triangle at all.
    #[error("{path}: mesh has no triangles")]
    Empty {
        /// The mesh file.
        path: PathBuf,
    },
}

/// `path`, or `path:line`.
fn at_line(path: &Path, line: Option<usize>) -> String {
    match line {
        Some(line) => format!("{}:{line}", path.display()),
        None => path.display().to_string(),
    }
}

/// What [`MeshError::WrongFormat`] says of a file given as `key` that is `found`.
fn what_it_is(key: MeshFormat, found: Option<MeshFormat>) -> String {
    let given = format!("given as `{} = ...`", key.key());
    match found {
        Some(f) => format!("a {f} file {given}: write `{} = ...`", f.key()),
        None => format!(
            "not a {key} file ({}) but {given}: an OBJ file is given as `obj = ...`",
            key.signature()
        ),
    }
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
    pub(crate) fn from_raw_at(
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

    /// The unit square `[-0.5, 0.5]^2` in the plane `y = 0`, facing `+y`: corners
    /// `(-0.5, 0, -0.5)`, `(-0.5, 0, 0.5)`, `(0.5, 0, 0.5)`, `(0.5, 0, -0.5)` in that order, as the
    /// two triangles `[0, 1, 2]` and `[0, 2, 3]`, counter-clockwise seen from above. Scaled and
    /// moved by a matrix it is a ground or a square occluder.
    ///
    /// ```
    /// use penumbra::glam::{DMat4, DVec3};
    /// use penumbra::geom::TriangleMesh;
    ///
    /// let ground = TriangleMesh::quad().transformed(&DMat4::from_scale(DVec3::splat(12.0)));
    /// assert_eq!(ground.positions[0], DVec3::new(-6.0, 0.0, -6.0));
    /// let [a, b, c] = ground.triangle(0);
    /// assert!((b - a).cross(c - a).dot(DVec3::Y) > 0.0);
    /// ```
    pub fn quad() -> TriangleMesh {
        let c = DVec3::new;
        TriangleMesh::from_raw(
            "quad",
            &[
                c(-0.5, 0.0, -0.5),
                c(-0.5, 0.0, 0.5),
                c(0.5, 0.0, 0.5),
                c(0.5, 0.0, -0.5),
            ],
            &[[0, 1, 2], [0, 2, 3]],
        )
        .expect("finite positions and in-range indices by construction")
    }

    /// The unit cube `[-0.5, 0.5]^3` around the origin, closed and wound outwards
    /// (counter-clockwise seen from outside): the corners `(-,-,-)`, `(+,-,-)`, `(+,+,-)`,
    /// `(-,+,-)` at `z = -0.5`, then the same four at `z = +0.5` (each coordinate `±0.5`), as 12
    /// triangles, two per face. Scaled, turned and moved by a matrix it is any box.
    ///
    /// ```
    /// use penumbra::geom::{HalfEdgeMesh, TriangleMesh};
    ///
    /// let cube = TriangleMesh::cube();
    /// assert_eq!((cube.positions.len(), cube.triangles.len()), (8, 12));
    /// let h = HalfEdgeMesh::build(&cube);
    /// assert!(h.validate().is_ok() && h.is_closed() && !h.has_inconsistent_orientation());
    /// ```
    pub fn cube() -> TriangleMesh {
        let c = DVec3::new;
        TriangleMesh::from_raw(
            "cube",
            &[
                c(-0.5, -0.5, -0.5),
                c(0.5, -0.5, -0.5),
                c(0.5, 0.5, -0.5),
                c(-0.5, 0.5, -0.5),
                c(-0.5, -0.5, 0.5),
                c(0.5, -0.5, 0.5),
                c(0.5, 0.5, 0.5),
                c(-0.5, 0.5, 0.5),
            ],
            &[
                [0, 2, 1],
                [0, 3, 2],
                [4, 5, 6],
                [4, 6, 7],
                [0, 1, 5],
                [0, 5, 4],
                [2, 3, 7],
                [2, 7, 6],
                [1, 2, 6],
                [1, 6, 5],
                [0, 4, 7],
                [0, 7, 3],
            ],
        )
        .expect("finite positions and in-range indices by construction")
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The welded mesh of an OBJ text (reading files is `obj.rs`'s, and tested there).
    fn load_str(text: &str) -> Result<TriangleMesh, MeshError> {
        TriangleMesh::parse_obj(Path::new("mem.obj"), text)
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

    /// Six times the signed volume that `m`'s triangles enclose (positive: wound outwards).
    fn six_volumes(m: &TriangleMesh) -> f64 {
        (0..m.triangles.len())
            .map(|t| {
                let [a, b, c] = m.triangle(t);
                a.dot(b.cross(c))
            })
            .sum()
    }

    #[test]
    fn the_unit_cube_is_closed_wound_outwards_and_of_volume_one() {
        let cube = TriangleMesh::cube();
        let h = crate::HalfEdgeMesh::build(&cube);
        h.validate().unwrap();
        assert!(h.is_closed() && !h.has_inconsistent_orientation());
        assert_eq!(six_volumes(&cube), 6.0);
        assert!(cube.positions.iter().all(|p| p.abs() == DVec3::splat(0.5)));
        assert_eq!((cube.dropped_degenerate, cube.dropped_duplicate), (0, 0));
    }

    #[test]
    fn the_unit_quad_faces_up_with_area_one() {
        let quad = TriangleMesh::quad();
        crate::HalfEdgeMesh::build(&quad).validate().unwrap();
        let up: f64 = (0..2)
            .map(|t| {
                let [a, b, c] = quad.triangle(t);
                (b - a).cross(c - a).dot(DVec3::Y) / 2.0
            })
            .sum();
        assert_eq!(up, 1.0);
        assert!(
            quad.positions
                .iter()
                .all(|p| p.y == 0.0 && p.x.abs() == 0.5 && p.z.abs() == 0.5)
        );
    }

    #[test]
    fn bad_index_in_memory_is_an_error() {
        let e = TriangleMesh::from_raw("mem", &[DVec3::ZERO; 3], &[[0, 1, 3]]);
        assert!(matches!(e, Err(MeshError::BadIndex { index: 3, .. })));
    }
}
