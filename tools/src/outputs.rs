//! The outputs of a run: refused before any work when they would overwrite an input or each
//! other, or are not regular files.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};

/// Refuses outputs that would overwrite an input or each other, or that are not regular files
/// (or links to one).
pub(crate) fn check_outputs(inputs: &[PathBuf], outputs: &[&Path]) -> Result<()> {
    for (k, out) in outputs.iter().enumerate() {
        // Before any work: a directory, device, FIFO or socket is refused, not replaced.
        penumbra::geom::output_target(out)?;
        if let Some(i) = inputs.iter().find(|i| same_file(i, out)) {
            bail!(
                "output {} is an input of this run ({}); refusing to overwrite it",
                out.display(),
                i.display()
            );
        }
        if outputs[..k].iter().any(|o| same_file(o, out)) {
            bail!("output {} is named twice", out.display());
        }
    }
    Ok(())
}

/// The same file, whether or not it exists yet. Two existing paths are the same file when they
/// reach the same inode: through a symbolic link (the image writers write through links) or as
/// two hard links of one file. A path that does not exist yet is compared by its canonical folder
/// and name.
fn same_file(a: &Path, b: &Path) -> bool {
    if let (Some(x), Some(y)) = (identity(a), identity(b)) {
        return x == y;
    }
    let canon = |p: &Path| -> Option<PathBuf> {
        let parent = match p.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        Some(parent.canonicalize().ok()?.join(p.file_name()?))
    };
    match (canon(a), canon(b)) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    }
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
