//! The files a user names (a scene, a data file): read only if they are regular files, and only
//! up to a stated size. A FIFO or a terminal would block the read, and a device such as
//! `/dev/zero` never ends; a file of gigabytes would be held in memory whole.

use std::io::Read;
use std::path::Path;

/// Why a user's file was not read.
#[derive(Debug, thiserror::Error)]
pub enum UserFileError {
    /// Not a regular file (a directory, FIFO, socket or device).
    #[error("not a regular file (it is {0}): give the path of a file")]
    NotAFile(&'static str),
    /// Larger than the cap.
    #[error("larger than {max} bytes, the most this file may hold ({why})")]
    TooLarge {
        /// The cap \[bytes\].
        max: u64,
        /// Why the cap is what it is.
        why: &'static str,
    },
    /// The operating system's error.
    #[error("{0}")]
    Io(#[from] std::io::Error),
}

/// Opens `path` if it is a regular file (followed through symbolic links).
pub fn open(path: &Path) -> Result<std::fs::File, UserFileError> {
    let kind = std::fs::metadata(path)?.file_type();
    if !kind.is_file() {
        return Err(UserFileError::NotAFile(describe(kind)));
    }
    Ok(std::fs::File::open(path)?)
}

/// The bytes of the regular file `path`, at most `max` of them; `why` says why in the error.
pub fn read(path: &Path, max: u64, why: &'static str) -> Result<Vec<u8>, UserFileError> {
    let mut bytes = Vec::new();
    open(path)?.take(max + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max {
        return Err(UserFileError::TooLarge { max, why });
    }
    Ok(bytes)
}

/// What a file that is not regular is, in words.
fn describe(kind: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a FIFO";
        }
        if kind.is_char_device() {
            return "a character device";
        }
        if kind.is_block_device() {
            return "a block device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    if kind.is_dir() {
        "a directory"
    } else {
        "not a regular file"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_directories_and_oversized_files_are_refused_and_a_small_file_is_read() {
        let dir = std::env::temp_dir().join(format!("user-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let small = dir.join("small.txt");
        std::fs::write(&small, "0123456789").unwrap();
        assert_eq!(read(&small, 10, "test").unwrap(), b"0123456789");
        assert!(matches!(
            read(&small, 9, "test"),
            Err(UserFileError::TooLarge { max: 9, .. })
        ));
        assert!(matches!(
            read(&dir, 10, "test"),
            Err(UserFileError::NotAFile("a directory"))
        ));
        #[cfg(unix)]
        assert!(matches!(
            read(Path::new("/dev/zero"), 10, "test"),
            Err(UserFileError::NotAFile("a character device"))
        ));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
