//! The library's errors as Python exceptions: a missing file is `FileNotFoundError`, a bad
//! value `ValueError`, what stood in the way of a sound request (no GPU) `RuntimeError`; the
//! message is the library's, which names the file, line or value.

use std::path::Path;

use penumbra::geom::MeshError;
use penumbra::{RenderError, SceneError};
use pyo3::PyErr;
use pyo3::exceptions::{
    PyFileNotFoundError, PyKeyboardInterrupt, PyMemoryError, PyRuntimeError, PyValueError,
};

/// A bad value: `ValueError` with `e`'s message.
pub fn value(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// `FileNotFoundError` for `path` when it does not exist, else `ValueError` with `e`'s message
/// (the file exists, and what it holds is wrong).
pub fn file(path: &Path, e: impl std::fmt::Display) -> PyErr {
    if !path.exists() {
        PyFileNotFoundError::new_err((
            2,
            format!("{}: no such file", path.display()),
            path.display().to_string(),
        ))
    } else {
        value(e)
    }
}

/// A scene file's error: `FileNotFoundError` where the scene file or one of its mesh files
/// does not exist (the message names which, and the scene's line), else `ValueError`.
pub fn scene(path: &Path, e: SceneError) -> PyErr {
    let missing = |error: &std::io::Error| error.kind() == std::io::ErrorKind::NotFound;
    let (file, not_found) = match &e {
        SceneError::Io { error, .. } => (path.to_path_buf(), missing(error)),
        SceneError::Mesh {
            error: MeshError::Io { path, error },
            ..
        } => (path.clone(), missing(error)),
        _ => (path.to_path_buf(), false),
    };
    if not_found {
        PyFileNotFoundError::new_err((2, e.to_string(), file.display().to_string()))
    } else {
        value(e)
    }
}

/// A render's error: a bad request is `ValueError`, an interruption `KeyboardInterrupt`, an
/// image larger than the memory `MemoryError`, what the machine lacks (a GPU) or a GPU failure
/// `RuntimeError`.
pub fn render(e: RenderError) -> PyErr {
    match e {
        RenderError::Interrupted => PyKeyboardInterrupt::new_err("interrupted"),
        RenderError::OutOfMemory { .. } => PyMemoryError::new_err(e.to_string()),
        RenderError::NeedsGpu { .. } | RenderError::NoGpu { .. } | RenderError::Gpu { .. } => {
            PyRuntimeError::new_err(e.to_string())
        }
        _ => value(e),
    }
}
