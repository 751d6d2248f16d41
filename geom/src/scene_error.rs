//! What can be wrong with a scene file: the errors of `scene_file.rs` and
//! `scene_file_lights.rs`, each naming the file and the line.

use std::path::PathBuf;

use crate::mesh::MeshError;

/// What can be wrong with a scene file.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("{path}: cannot read scene: {error}")]
    Io {
        /// The scene file.
        path: PathBuf,
        /// The underlying error.
        error: std::io::Error,
    },
    /// Not valid TOML, an unknown key, a missing key or a value of the wrong type.
    #[error("{path}:{line}: {message}")]
    Syntax {
        /// The scene file.
        path: PathBuf,
        /// 1-based line (0 when the parser gave no position).
        line: usize,
        /// The parser's message, naming the key.
        message: String,
    },
    /// Well-formed but meaningless: zero-size light, empty image, `eye == target`, ...
    #[error("{path}:{line}: {message}")]
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// 1-based line of the offending value.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A mesh of the scene failed to load.
    #[error("{path}:{line}: mesh {mesh}: {error}")]
    Mesh {
        /// The scene file.
        path: PathBuf,
        /// Line of the mesh's file key (`obj`, `gltf` or `ply`).
        line: usize,
        /// 0-based index of the `[[mesh]]` entry.
        mesh: usize,
        /// The mesh error, naming the mesh file and its line.
        error: MeshError,
    },
}
