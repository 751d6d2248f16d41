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

/// `Err` with a message when `bytes` more would not fit in the memory available
/// ([`crate::memory::available_memory`]), keeping half of it for what is made of them.
pub fn within_memory(bytes: u64) -> Result<(), String> {
    match crate::memory::available_memory().filter(|&a| bytes > a / 2) {
        Some(a) => Err(format!(
            "{:.1} GB, more than the memory available ({:.1} GB) can hold with what is made of it",
            bytes as f64 / 1e9,
            a as f64 / 1e9
        )),
        None => Ok(()),
    }
}

/// The size of the regular file at `path`, refused (kind `OutOfMemory`) when the memory
/// available could not hold it.
fn checked_len(path: &Path) -> std::io::Result<u64> {
    let m = regular_file(path)?;
    within_memory(m.len())
        .map_err(|message| std::io::Error::new(std::io::ErrorKind::OutOfMemory, message))?;
    Ok(m.len())
}

/// The text of the regular file at `path` (or the regular file a link there points to). Anything
/// else is refused before it is opened, and a file larger than the memory available
/// ([`crate::memory::available_memory`]) before it is read; reading stops at the size the file had
/// when it was checked, should it grow meanwhile.
pub fn read_text(path: &Path) -> std::io::Result<String> {
    let len = checked_len(path)?;
    let mut text = String::with_capacity(len as usize);
    std::fs::File::open(path)?
        .take(len)
        .read_to_string(&mut text)?;
    Ok(text)
}

/// The bytes of the regular file at `path`, under the checks of [`read_text`].
pub fn read_bytes(path: &Path) -> std::io::Result<Vec<u8>> {
    let len = checked_len(path)?;
    let mut bytes = Vec::with_capacity(len as usize);
    std::fs::File::open(path)?
        .take(len)
        .read_to_end(&mut bytes)?;
    Ok(bytes)
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
        assert_eq!(read_bytes(&f).unwrap(), b"v 0 0 0\n");
        assert!(read_bytes(&dir).is_err());
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
