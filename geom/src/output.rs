//! Writing outputs safely: only to a new path, a regular file or a link to one, through a hidden
//! temporary file renamed into place (so a failed or interrupted write leaves the previous
//! content), with the temporaries in progress known so that a signal handler can remove them.

use std::path::Path;

use crate::image::{ImageError, io_err};

/// Where writing `path` puts the file: `path` itself when it is new or a regular file; for a
/// symbolic link, its final target when that is a regular file (the link is kept, never
/// replaced). Directories, devices, FIFOs, sockets and links to anything else are refused.
pub fn output_target(path: &Path) -> Result<std::path::PathBuf, ImageError> {
    use crate::input::kind;
    match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(path.to_path_buf()),
        Err(e) => Err(io_err(path, e)),
        Ok(m) if m.is_file() => Ok(path.to_path_buf()),
        Ok(m) if m.file_type().is_symlink() => {
            let target = std::fs::canonicalize(path).map_err(|e| {
                io_err(
                    path,
                    format!(
                        "a symbolic link whose target cannot be resolved ({e}); refusing to write"
                    ),
                )
            })?;
            match std::fs::metadata(&target) {
                Ok(t) if t.is_file() => Ok(target),
                Ok(t) => Err(io_err(
                    path,
                    format!(
                        "a symbolic link to a {} ({}), not to a regular file; refusing to write",
                        kind(&t),
                        target.display()
                    ),
                )),
                Err(e) => Err(io_err(path, e)),
            }
        }
        Ok(m) => Err(io_err(
            path,
            format!(
                "is a {}, not a regular file; refusing to replace it",
                kind(&m)
            ),
        )),
    }
}

/// The hidden temporary name beside `path` that process `pid` writes it through.
pub(crate) fn temporary(path: &Path, name: &std::ffi::OsStr, pid: u32) -> std::path::PathBuf {
    path.with_file_name(format!(".{}.tmp-{pid}", name.to_string_lossy()))
}

/// Removes the temporary files beside `path` left by runs that died while writing it (killed,
/// crashed): those of processes that no longer exist. Only where `/proc` tells.
fn remove_stale_temporaries(path: &Path, name: &std::ffi::OsStr) {
    let proc = Path::new("/proc");
    if !proc.join("self").exists() {
        return;
    }
    let prefix = format!(".{}.tmp-", name.to_string_lossy());
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let file = e.file_name();
        let Some(pid) = file
            .to_str()
            .and_then(|f| f.strip_prefix(&prefix))
            .and_then(|p| p.parse::<u32>().ok())
        else {
            continue;
        };
        if pid != std::process::id() && !proc.join(pid.to_string()).exists() {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// Writes through `write` into a hidden temporary file beside the output, then renames it into
/// place, so that a failed write leaves nothing behind. The output is `path`, or the regular
/// file a symbolic link at `path` points to ([`output_target`], which refuses anything else);
/// temporaries of earlier runs that died while writing it are removed first.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), ImageError>,
) -> Result<(), ImageError> {
    let target = output_target(path)?;
    let name = target
        .file_name()
        .ok_or_else(|| io_err(path, "not a file path"))?
        .to_os_string();
    remove_stale_temporaries(&target, &name);
    let tmp = temporary(&target, &name, std::process::id());
    in_progress().push(tmp.clone());
    let result =
        write(&tmp).and_then(|()| std::fs::rename(&tmp, &target).map_err(|e| io_err(path, e)));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    in_progress().retain(|t| t != &tmp);
    result
}

/// The temporary files [`write_atomically`] is writing now.
fn in_progress() -> std::sync::MutexGuard<'static, Vec<std::path::PathBuf>> {
    static WRITING: std::sync::Mutex<Vec<std::path::PathBuf>> = std::sync::Mutex::new(Vec::new());
    WRITING.lock().unwrap_or_else(|e| e.into_inner())
}

/// Removes the temporary files being written at this moment, for a program about to exit on a
/// signal (SIGINT, SIGTERM): the outputs keep their previous content, and no `.tmp-` file is
/// left behind. Returns how many were removed.
pub fn remove_temporaries_in_progress() -> usize {
    in_progress()
        .drain(..)
        .filter(|t| std::fs::remove_file(t).is_ok())
        .count()
}
