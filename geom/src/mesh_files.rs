//! Mesh files by format: the scene file's key (`obj`, `gltf`, `ply`) names the reader, and the
//! file's first bytes must agree with it (glTF and PLY have signatures, OBJ has none). The
//! readers are `obj.rs`, `gltf.rs` and `ply.rs`; all end in [`TriangleMesh::from_raw_at`]'s
//! welding, through `corners.rs` where they make their own triangles.

use std::path::Path;

use crate::mesh::{MeshError, TriangleMesh};
use crate::mesh_format::MeshFormat;

impl TriangleMesh {
    /// Loads the mesh file at `path` as `format`, welded as [`TriangleMesh::from_raw`] welds.
    ///
    /// The file's first bytes must agree with `format` ([`MeshFormat::sniff`]): a glTF or PLY
    /// file given as another format is an error naming what it is. Errors name the file and,
    /// where the format has lines, the line.
    pub fn load(path: &Path, format: MeshFormat) -> Result<Self, MeshError> {
        let bytes = crate::input::read_bytes(path).map_err(|error| MeshError::Io {
            path: path.to_path_buf(),
            error,
        })?;
        Self::parse(path, format, &bytes)
    }

    /// [`TriangleMesh::load`] of the bytes of a file; `path` names it in errors and, for glTF,
    /// is where its external buffers are found (relative to its folder).
    pub fn parse(path: &Path, format: MeshFormat, bytes: &[u8]) -> Result<Self, MeshError> {
        let found = MeshFormat::sniff(bytes);
        if found != Some(format) && (format != MeshFormat::Obj || found.is_some()) {
            return Err(MeshError::WrongFormat {
                path: path.to_path_buf(),
                key: format,
                found,
            });
        }
        match format {
            MeshFormat::Obj => {
                let text = std::str::from_utf8(bytes).map_err(|_| MeshError::Io {
                    path: path.to_path_buf(),
                    error: std::io::Error::new(
                        std::io::ErrorKind::InvalidData,
                        "stream did not contain valid UTF-8",
                    ),
                })?;
                Self::parse_obj(path, text)
            }
            MeshFormat::Gltf => crate::gltf::parse_gltf(path, bytes),
            MeshFormat::Ply => crate::ply::parse_ply(path, bytes),
        }
    }
}

/// `bytes` changed a few times at random (bytes set, copied, cut out, or the end cut off), for
/// the readers' tests: whatever comes of them must be a mesh or an error, never a panic.
#[cfg(test)]
pub(crate) fn mutated(rng: &mut crate::rng::Rng, bytes: &[u8]) -> Vec<u8> {
    let mut b = bytes.to_vec();
    for _ in 0..1 + rng.below(3) {
        let i = rng.below(b.len().max(1)).min(b.len());
        match rng.below(5) {
            0 => b.truncate(i),
            1 if i < b.len() => b[i] = rng.below(256) as u8,
            2 if i < b.len() => {
                let set = b"0123456789-.e ,[]{}\n\xff";
                b[i] = set[rng.below(set.len())];
            }
            3 => {
                let end = (i + 1 + rng.below(16)).min(b.len());
                b.drain(i..end);
            }
            _ => {
                let from = rng.below(b.len().max(1)).min(b.len());
                let piece: Vec<u8> = b[from..(from + rng.below(8)).min(b.len())].to_vec();
                b.splice(i..i, piece);
            }
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::corners::from_corners;
    use glam::DVec3;

    #[test]
    fn each_format_is_told_by_its_signature_and_obj_by_having_none() {
        assert_eq!(MeshFormat::sniff(b"glTF\x02\0\0\0"), Some(MeshFormat::Gltf));
        assert_eq!(
            MeshFormat::sniff(b"\xef\xbb\xbf \n{\"asset\":{}}"),
            Some(MeshFormat::Gltf)
        );
        assert_eq!(MeshFormat::sniff(b"ply\r\nformat"), Some(MeshFormat::Ply));
        assert_eq!(MeshFormat::sniff(b"v 0 0 0\nply\n"), None);
        assert_eq!(MeshFormat::sniff(b"plyx\n"), None);
        assert_eq!(MeshFormat::sniff(b""), None);
    }

    #[test]
    fn a_file_under_another_format_s_key_says_what_it_is_and_lists_the_keys() {
        let obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        let ply = b"ply\nformat ascii 1.0\nend_header\n";
        let gltf = b"{\"asset\": {\"version\": \"2.0\"}}";
        for (bytes, key, want) in [
            (
                &gltf[..],
                MeshFormat::Obj,
                "a glTF file given as `obj = ...`: write `gltf = ...`",
            ),
            (
                &ply[..],
                MeshFormat::Obj,
                "a PLY file given as `obj = ...`: write `ply = ...`",
            ),
            (
                &ply[..],
                MeshFormat::Gltf,
                "a PLY file given as `gltf = ...`: write `ply = ...`",
            ),
            (
                &gltf[..],
                MeshFormat::Ply,
                "a glTF file given as `ply = ...`: write `gltf = ...`",
            ),
            (
                &obj[..],
                MeshFormat::Gltf,
                "not a glTF file (a .glb starts with `glTF`",
            ),
            (
                &obj[..],
                MeshFormat::Ply,
                "not a PLY file (a PLY file starts with the line `ply`)",
            ),
        ] {
            let e = TriangleMesh::parse(Path::new("m.x"), key, bytes).unwrap_err();
            let e = e.to_string();
            assert!(e.starts_with("m.x: "), "{e}");
            assert!(e.contains(want), "{e}");
            assert!(
                e.ends_with("(a mesh file is named by its format's key: `obj`, `gltf` or `ply`)"),
                "{e}"
            );
        }
        let m = TriangleMesh::parse(Path::new("m.obj"), MeshFormat::Obj, obj).unwrap();
        assert_eq!(m.triangles.len(), 1);
    }

    #[test]
    fn corners_are_numbered_in_order_of_first_use_and_unused_vertices_left_out() {
        let p = [
            DVec3::new(9.0, 9.0, 9.0),
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y,
            DVec3::Z,
        ];
        let m = from_corners(Path::new("m"), &p, &[[3, 1, 2], [4, 1, 3]]).unwrap();
        assert_eq!(m.positions, [DVec3::Y, DVec3::ZERO, DVec3::X, DVec3::Z]);
        assert_eq!(m.triangles, [[0, 1, 2], [3, 1, 0]]);
        let obj = TriangleMesh::parse_obj(
            Path::new("m.obj"),
            "v 9 9 9\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 4 2 3\nf 5 2 4\n",
        )
        .unwrap();
        assert_eq!(m, obj);
        assert!(matches!(
            from_corners(Path::new("m"), &p, &[]),
            Err(MeshError::Empty { .. })
        ));
    }
}
