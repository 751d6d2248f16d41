//! The outputs of a run: refused before any work when they would overwrite an input or each
//! other, are not regular files or cannot be written; their missing folders made before the
//! work and removed again when it fails or a signal ends it.

use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

use anyhow::{Context, Result, bail};

/// Refuses outputs that would overwrite an input or each other, or that are not regular files
/// (or links to one). Each path is resolved once ([`file_key`]), so a run of thousands of
/// outputs is checked in time proportional to their number.
pub(crate) fn check_outputs(inputs: &[PathBuf], outputs: &[&Path]) -> Result<()> {
    let inputs: HashMap<FileKey, &PathBuf> = inputs.iter().map(|i| (file_key(i), i)).collect();
    let mut seen: HashMap<FileKey, &Path> = HashMap::with_capacity(outputs.len());
    for out in outputs {
        // Before any work: a directory, device, FIFO or socket is refused, not replaced.
        penumbra::geom::output_target(out)?;
        let key = file_key(out);
        if let Some(i) = inputs.get(&key) {
            bail!(
                "output {} is an input of this run ({}); refusing to overwrite it",
                out.display(),
                i.display()
            );
        }
        if let Some(first) = seen.insert(key, out) {
            if first == *out {
                bail!("output {} is named twice", out.display());
            }
            bail!(
                "outputs {} and {} are the same file",
                first.display(),
                out.display()
            );
        }
    }
    Ok(())
}

/// What names a file whether or not it exists yet.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum FileKey {
    /// An existing file's device and inode: one key for every link to it, hard or symbolic.
    Inode(u64, u64),
    /// Where a file that does not exist yet will be ([`resolved`]).
    Path(PathBuf),
}

/// The key of the file `p` names (see [`FileKey`]).
fn file_key(p: &Path) -> FileKey {
    let at = resolved(p).unwrap_or_else(|| p.to_path_buf());
    match identity(&at) {
        Some((dev, ino)) => FileKey::Inode(dev, ino),
        None => FileKey::Path(at),
    }
}

/// Where `p` will be once the folders it names are made, taken component by component: `.`
/// is dropped, `..` removes the folder before it, and wherever the path so far exists it is
/// made canonical (symbolic links followed). A folder the writer makes is a real folder, so
/// `new/..` is the folder that holds `new`: `new/../scene.toml` is `scene.toml`. `None` where
/// the current folder cannot be read.
fn resolved(p: &Path) -> Option<PathBuf> {
    let mut at = std::env::current_dir().ok()?.canonicalize().ok()?;
    for c in p.components() {
        match c {
            Component::Prefix(_) | Component::RootDir => at = PathBuf::from(c.as_os_str()),
            Component::CurDir => {}
            Component::ParentDir => {
                at.pop();
            }
            Component::Normal(name) => at.push(name),
        }
        // Wherever the path so far exists, links are followed: `..` after a link to a folder
        // is taken from its target, and a link to a file is the file.
        if let Ok(real) = at.canonicalize() {
            at = real;
        }
    }
    Some(at)
}

/// The device and inode of the file a path reaches, following symbolic links; `None` where
/// nothing is there (or the platform has no inodes: then the canonical path stands for it).
fn identity(p: &Path) -> Option<(u64, u64)> {
    let m = std::fs::metadata(p).ok()?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        Some((m.dev(), m.ino()))
    }
    #[cfg(not(unix))]
    {
        let _ = m;
        None
    }
}

/// The missing folders of a run's outputs, made before its work ([`prepare`]): removed again
/// (innermost first, each only if empty) when dropped, unless [`Prepared::keep`] kept them.
pub(crate) struct Prepared {
    created: Vec<PathBuf>,
}

/// Makes the missing folders of `outputs` (each said on success by [`Prepared::keep`]), then
/// checks that each output can be written ([`penumbra::geom::check_writable`]): a read-only
/// folder, a name the file system refuses or a name that ends in a folder separator is found
/// before any work, not after it.
pub(crate) fn prepare(outputs: &[&Path]) -> Result<Prepared> {
    let mut prepared = Prepared {
        created: Vec::new(),
    };
    for o in outputs {
        let Some(dir) = o.parent().filter(|d| !d.as_os_str().is_empty()) else {
            continue;
        };
        let missing: Vec<&Path> = dir
            .ancestors()
            .filter(|a| !a.as_os_str().is_empty())
            .take_while(|a| std::fs::symlink_metadata(a).is_err())
            .collect();
        for d in missing.into_iter().rev() {
            match std::fs::create_dir(d) {
                Ok(()) => {
                    prepared.created.push(d.to_path_buf());
                    made().push(d.to_path_buf());
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
                Err(e) => {
                    return Err(e).with_context(|| {
                        format!("creating the folder {} of {}", d.display(), o.display())
                    });
                }
            }
        }
    }
    for o in outputs {
        penumbra::geom::check_writable(o)?;
    }
    Ok(prepared)
}

impl Prepared {
    /// Keeps the folders made, and gives them (outermost first) to be said.
    pub(crate) fn keep(mut self) -> Vec<PathBuf> {
        let created = std::mem::take(&mut self.created);
        made().retain(|d| !created.contains(d));
        created
    }
}

impl Drop for Prepared {
    fn drop(&mut self) {
        for d in self.created.iter().rev() {
            let _ = std::fs::remove_dir(d);
        }
        made().retain(|d| !self.created.contains(d));
    }
}

/// The folders made for outputs and not yet kept.
fn made() -> MutexGuard<'static, Vec<PathBuf>> {
    static MADE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
    MADE.lock().unwrap_or_else(|e| e.into_inner())
}

/// Removes the folders made for outputs and not yet kept, innermost first and each only if
/// empty: for a command about to exit on a signal, after its temporaries are removed.
pub(crate) fn remove_folders_in_progress() {
    for d in made().drain(..).rev() {
        let _ = std::fs::remove_dir(d);
    }
}
