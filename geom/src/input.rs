//! Reading the files a run takes (scenes, meshes): only regular files, and none larger than the
//! memory can hold. A FIFO would block the reader until some writer came; a device such as
//! `/dev/zero` has no end; both are refused by their kind before they are opened.

use std::io::Read;
use std::path::Path;

/// What a file system entry is, in words, for a message: "FIFO", "device", "socket",
/// "directory", "regular file" or "special file".
pub fn kind(m: &std::fs::Metadata) -> &'static str {
    let t = m.file_type();
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "FIFO";
        }
        if t.is_block_device() || t.is_char_device() {
            return "device";
        }
        if t.is_socket() {
            return "socket";
        }
    }
    if t.is_dir() {
        "directory"
    } else if t.is_file() {
        "regular file"
    } else {
        "special file"
    }
}

/// The metadata of the regular file at `path` (following links); anything else is an error of
/// kind `InvalidInput` naming what it is.
pub fn regular_file(path: &Path) -> std::io::Result<std::fs::Metadata> {
    let m = std::fs::metadata(path)?;
    if m.is_file() {
        Ok(m)
    } else {
        Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("a {}, not a regular file", kind(&m)),
        ))
    }
}

/// The text of the regular file at `path` (or the regular file a link there points to). Anything
/// else is refused before it is opened, and a file larger than the memory available
/// ([`crate::memory::available_memory`]) before it is read; reading stops at the size the file had
/// when it was checked, should it grow meanwhile.
pub fn read_text(path: &Path) -> std::io::Result<String> {
    use std::io::{Error, ErrorKind};
    let m = regular_file(path)?;
    if let Some(a) = crate::memory::available_memory().filter(|&a| m.len() > a / 2) {
        return Err(Error::new(
            ErrorKind::OutOfMemory,
            format!(
                "{:.1} GB, more than the memory available ({:.1} GB) can hold with what is made of it",
                m.len() as f64 / 1e9,
                a as f64 / 1e9
            ),
        ));
    }
    let mut text = String::with_capacity(m.len() as usize);
    std::fs::File::open(path)?
        .take(m.len())
        .read_to_string(&mut text)?;
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regular_files_are_read_and_devices_and_folders_refused_by_kind() {
        let dir = std::env::temp_dir().join(format!("penumbra-input-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("a.txt");
        std::fs::write(&f, "v 0 0 0\n").unwrap();
        assert_eq!(read_text(&f).unwrap(), "v 0 0 0\n");
        let e = read_text(&dir).unwrap_err();
        assert!(
            e.to_string().contains("a directory, not a regular file"),
            "{e}"
        );
        #[cfg(unix)]
        {
            let e = read_text(Path::new("/dev/zero")).unwrap_err();
            assert!(
                e.to_string().contains("a device, not a regular file"),
                "{e}"
            );
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
