//! The formats of mesh files a scene names, one key of its `[[mesh]]` entries each, and how a
//! file announces its format by its first bytes.

/// The formats a scene file's `[[mesh]]` entry can name, one key each.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MeshFormat {
    /// Wavefront OBJ (`obj = ...`).
    Obj,
    /// glTF 2.0, `.gltf` or `.glb` (`gltf = ...`).
    Gltf,
    /// PLY, ASCII or binary (`ply = ...`).
    Ply,
}

impl MeshFormat {
    /// Every format, in the order of the scene file's keys.
    pub const ALL: [MeshFormat; 3] = [MeshFormat::Obj, MeshFormat::Gltf, MeshFormat::Ply];

    /// The scene file's key: `obj`, `gltf` or `ply`.
    pub fn key(self) -> &'static str {
        match self {
            MeshFormat::Obj => "obj",
            MeshFormat::Gltf => "gltf",
            MeshFormat::Ply => "ply",
        }
    }

    /// How a file of the format starts, in words.
    pub(crate) fn signature(self) -> &'static str {
        match self {
            MeshFormat::Obj => "text of `v` and `f` statements",
            MeshFormat::Gltf => "a .glb starts with `glTF`, a .gltf with `{`",
            MeshFormat::Ply => "a PLY file starts with the line `ply`",
        }
    }

    /// The format that `bytes` announce by their signature: glTF (binary `glTF`, or JSON's
    /// `{` after any byte-order mark and white space) or PLY (a first line `ply`); `None` for
    /// anything else, which an OBJ is.
    pub fn sniff(bytes: &[u8]) -> Option<MeshFormat> {
        if bytes.starts_with(b"glTF") {
            return Some(MeshFormat::Gltf);
        }
        if bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r\n") {
            return Some(MeshFormat::Ply);
        }
        let text = bytes.strip_prefix("\u{feff}".as_bytes()).unwrap_or(bytes);
        match text.iter().find(|b| !b.is_ascii_whitespace()) {
            Some(b'{') => Some(MeshFormat::Gltf),
            _ => None,
        }
    }
}

impl std::fmt::Display for MeshFormat {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            MeshFormat::Obj => "OBJ",
            MeshFormat::Gltf => "glTF",
            MeshFormat::Ply => "PLY",
        })
    }
}
