//! The disk an output directory lives on, for the message of a write that ran out of space:
//! its mount point, its file system and the space left on it.

use std::io::ErrorKind;
use std::path::{Path, PathBuf};

/// Whether a write failed because the disk (or the user's quota on it) is full, or the file
/// grew past the largest the system allows: ENOSPC, EDQUOT, EFBIG.
pub fn is_full(e: &std::io::Error) -> bool {
    matches!(
        e.kind(),
        ErrorKind::StorageFull | ErrorKind::QuotaExceeded | ErrorKind::FileTooLarge
    )
}

/// The disk holding a path.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Disk {
    /// Where it is mounted (`/`, `/home`, `/tmp/out`); the directory itself where the mount
    /// table cannot be read.
    pub mount: PathBuf,
    /// Its file system and device (`ext4 /dev/sda2`), when the mount table says.
    pub device: Option<String>,
    /// Bytes an unprivileged writer may still use, when known.
    pub free: Option<u64>,
}

impl Disk {
    /// The disk holding `dir` (which must exist): the longest mount point of
    /// `/proc/self/mounts` that contains it, and its free space (`statvfs`).
    pub fn of(dir: &Path) -> Self {
        let dir = std::fs::canonicalize(dir).unwrap_or_else(|_| dir.to_path_buf());
        let (mount, device) = mount_of(&dir).unwrap_or((dir.clone(), None));
        Self {
            free: free_bytes(&dir),
            mount,
            device,
        }
    }

    /// `/tmp/out (tmpfs tmpfs)` or `/` as a reader sees it.
    pub fn describe(&self) -> String {
        match &self.device {
            Some(d) => format!("{} ({d})", self.mount.display()),
            None => self.mount.display().to_string(),
        }
    }
}

/// The mount point containing `dir` and its file system, from `/proc/self/mounts` (Linux).
fn mount_of(dir: &Path) -> Option<(PathBuf, Option<String>)> {
    let table = std::fs::read_to_string("/proc/self/mounts").ok()?;
    table
        .lines()
        .filter_map(|line| {
            let mut fields = line.split_whitespace();
            let device = fields.next()?;
            let mount = PathBuf::from(unescape(fields.next()?));
            let kind = fields.next()?;
            dir.starts_with(&mount)
                .then(|| (mount, Some(format!("{kind} {}", unescape(device)))))
        })
        // The longest (the last mounted on top, for equal lengths) holds the directory.
        .fold(
            None,
            |best: Option<(PathBuf, Option<String>)>, m| match &best {
                Some(b) if b.0.as_os_str().len() > m.0.as_os_str().len() => best,
                _ => Some(m),
            },
        )
}

/// The mount table writes a space, tab, newline and backslash as `\040`, `\011`, `\012`, `\134`.
fn unescape(field: &str) -> String {
    let mut out = String::with_capacity(field.len());
    let mut rest = field;
    while let Some(i) = rest.find('\\') {
        out.push_str(&rest[..i]);
        let code = rest
            .get(i + 1..i + 4)
            .and_then(|o| u8::from_str_radix(o, 8).ok());
        match code {
            Some(c) => {
                out.push(char::from(c));
                rest = &rest[i + 4..];
            }
            None => {
                out.push('\\');
                rest = &rest[i + 1..];
            }
        }
    }
    out.push_str(rest);
    out
}

/// The bytes an unprivileged writer may still use on the file system of `dir`.
#[cfg(unix)]
fn free_bytes(dir: &Path) -> Option<u64> {
    use std::os::unix::ffi::OsStrExt;
    let path = std::ffi::CString::new(dir.as_os_str().as_bytes()).ok()?;
    // SAFETY: `path` is a NUL-terminated string and `stats` a properly sized, writable
    // `statvfs` that the call fills in (or leaves untouched when it fails).
    let mut stats: libc::statvfs = unsafe { std::mem::zeroed() };
    let status = unsafe { libc::statvfs(path.as_ptr(), &mut stats) };
    (status == 0).then(|| (stats.f_bavail as u64).saturating_mul(stats.f_frsize as u64))
}

#[cfg(not(unix))]
fn free_bytes(_: &Path) -> Option<u64> {
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_mount_table_escapes_are_read_back() {
        assert_eq!(unescape(r"/mnt/my\040disk"), "/mnt/my disk");
        assert_eq!(unescape(r"a\134b\011c"), "a\\b\tc");
        assert_eq!(unescape(r"trailing\"), "trailing\\");
    }

    #[test]
    fn a_full_disk_a_quota_and_a_too_large_file_are_full() {
        for kind in [
            ErrorKind::StorageFull,
            ErrorKind::QuotaExceeded,
            ErrorKind::FileTooLarge,
        ] {
            assert!(is_full(&std::io::Error::from(kind)));
        }
        #[cfg(target_os = "linux")]
        assert!(is_full(&std::io::Error::from_raw_os_error(28)));
        assert!(!is_full(&std::io::Error::from(ErrorKind::PermissionDenied)));
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn the_root_directory_is_on_the_root_mount_with_its_free_space() {
        let disk = Disk::of(Path::new("/"));
        assert_eq!(disk.mount, Path::new("/"));
        assert!(disk.free.is_some());
    }
}
