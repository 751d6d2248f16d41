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

/// The hidden temporary name beside `path` that process `pid` writes it through: `.NAME.tmp-PID`,
/// NAME cut to its first [`TEMPORARY_NAME`] bytes so that any name a file system takes has a
/// temporary it takes too.
pub(crate) fn temporary(path: &Path, name: &std::ffi::OsStr, pid: u32) -> std::path::PathBuf {
    path.with_file_name(format!("{}{pid}", temporary_prefix(name)))
}

/// The most bytes of an output's name that its temporary's name holds.
const TEMPORARY_NAME: usize = 200;

/// `.NAME.tmp-`, the start of every temporary of the output `name`.
fn temporary_prefix(name: &std::ffi::OsStr) -> String {
    let name = name.to_string_lossy();
    let mut end = name.len().min(TEMPORARY_NAME);
    while !name.is_char_boundary(end) {
        end -= 1;
    }
    format!(".{}.tmp-", &name[..end])
}

/// Removes the temporary files beside `path` left by runs that died while writing it (killed,
/// crashed): those of processes that no longer exist. Only where `/proc` tells.
fn remove_stale_temporaries(path: &Path, name: &std::ffi::OsStr) {
    let proc = Path::new("/proc");
    if !proc.join("self").exists() {
        return;
    }
    let prefix = temporary_prefix(name);
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
    // The errors name the output, never the hidden temporary it is written through.
    let result = write(&tmp)
        .and_then(|()| std::fs::rename(&tmp, &target).map_err(|e| io_err(path, e)))
        .map_err(|e| match e {
            ImageError::Io { path: p, message } if p == tmp => io_err(path, message),
            other => other,
        });
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    in_progress().retain(|t| t != &tmp);
    result
}

/// Whether [`write_atomically`] can write `path`, found before any work: a name that does not
/// end in a folder separator, its target a regular file or nothing ([`output_target`]), and
/// its folder one where the temporary beside it can be made (not read-only, the temporary's
/// name not too long). The temporary is made and removed again. The folder must exist.
pub fn check_writable(path: &Path) -> Result<(), ImageError> {
    let text = path.as_os_str().to_string_lossy();
    if text.ends_with('/') || text.ends_with(std::path::MAIN_SEPARATOR) {
        return Err(io_err(path, "names a folder, not a file"));
    }
    let target = output_target(path)?;
    let name = target
        .file_name()
        .ok_or_else(|| io_err(path, "not a file path"))?
        .to_os_string();
    let tmp = temporary(&target, &name, std::process::id());
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&tmp)
    {
        Ok(_) => {
            let _ = std::fs::remove_file(&tmp);
            Ok(())
        }
        // Left by this very process: it can be made.
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Ok(()),
        Err(e) => Err(io_err(path, format!("cannot be written: {e}"))),
    }
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
