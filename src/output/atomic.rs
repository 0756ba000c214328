//! Atomic outputs in a directory one run owns.
//!
//! - **One run at a time**: a run holds `.activemuscle.lock` (its pid) from [`Staging::open`] to
//!   the end; a second run refuses while that pid lives, a lock left by a dead run is taken over.
//! - **Ownership**: each command keeps its own manifest of the files its last run wrote
//!   (`.activemuscle-manifest` for `run`, `.activemuscle-manifest-tradeoff` for `tradeoff`), and
//!   a commit replaces and removes only the files in its own: `run` and `tradeoff` into one
//!   directory keep each other's outputs. A file of the other command's that a commit writes
//!   again (a run's `tradeoff.csv`) becomes the committing command's. A non-empty directory
//!   without any manifest is not ours and is refused unless forced; `/`, the home directory, the
//!   working directory and its ancestors are always refused (they hold user files).
//! - **All or nothing**: every file is written into a staging directory
//!   `.activemuscle-partial-<pid>` inside the output directory, then [`Staging::commit`] moves
//!   the previous run's files aside, renames the new ones into place (a rename within one file
//!   system is atomic) and, if any rename fails, puts everything back as it was. Files of the
//!   command's previous run that this run did not write are removed: no stale file survives a
//!   re-run.
//! - **Cleaning**: staging directories of dead runs are removed when a run opens the directory;
//!   a run that fails before its commit removes its own.
//! - **A full disk**: a write that runs out of space (or quota) is [`AppError::DiskFull`],
//!   naming the file, the disk and its free space; the partly written file is removed from the
//!   staging area, so that a commit after it keeps exactly the files written whole before
//!   (the run writes its data first: [`super::write_run`]). The commit itself needs a little
//!   space for the manifests: [`RESERVE`] bytes are taken when the directory is opened (a disk
//!   without them is refused before anything is computed) and given back to write them.

use crate::app_error::AppError;
use std::path::{Path, PathBuf};

/// The lock file (content: the pid of the run holding it).
pub const LOCK: &str = ".activemuscle.lock";
/// The list of the files the last `run` wrote, one relative path a line (the prefix of every
/// command's manifest: [`Writer::manifest`]).
pub const MANIFEST: &str = ".activemuscle-manifest";
/// Prefix of staging directories.
pub const PARTIAL: &str = ".activemuscle-partial-";
/// Prefix of the directory a commit moves the previous run's files to.
const OLD: &str = ".activemuscle-old-";
/// Space \[bytes\] held in the staging directory from [`Staging::open`] to the commit, which
/// frees it to write the manifests (one line per file: 64 KiB lists about a thousand files).
pub const RESERVE: u64 = 64 * 1024;
/// The file holding [`RESERVE`] inside the staging directory.
const RESERVE_FILE: &str = ".activemuscle-reserve";

/// The command that writes into an output directory. Each owns the files in its own manifest and
/// removes no other.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Writer {
    /// `activemuscle run`: curves.csv, the tables, the figures, report.html, vtk/.
    Run,
    /// `activemuscle tradeoff`: tradeoff.csv, tradeoff.md, the tradeoff figures, tradeoff.html.
    Tradeoff,
}

impl Writer {
    /// Every command that writes outputs.
    pub const ALL: [Writer; 2] = [Writer::Run, Writer::Tradeoff];

    /// The file that lists what this command's last run wrote into a directory.
    pub fn manifest(self) -> &'static str {
        match self {
            Writer::Run => MANIFEST,
            Writer::Tradeoff => ".activemuscle-manifest-tradeoff",
        }
    }
}

/// The staging area of one run, holding its output directory's lock.
#[derive(Debug)]
pub struct Staging {
    writer: Writer,
    dir: PathBuf,
    root: PathBuf,
    files: Vec<PathBuf>,
    lock: Option<PathBuf>,
    committed: bool,
    /// Whether this run created the output directory (removed again, if still empty, when the
    /// run ends without a commit).
    created: bool,
    /// Bytes the staged files hold ([`Self::with_space`]).
    used: u64,
    /// The space of a simulated disk ([`Self::with_space`]); `None`: the real one.
    space: Option<u64>,
}

fn refuse(root: &Path, message: impl Into<String>) -> AppError {
    AppError::Output {
        file: root.display().to_string(),
        message: message.into(),
    }
}

/// Whether process `pid` is alive (Linux `/proc`; elsewhere every pid counts as alive).
fn alive(pid: u32) -> bool {
    !Path::new("/proc").is_dir() || Path::new(&format!("/proc/{pid}")).exists()
}

/// Directories that hold user files and are never an output directory: `/`, the home
/// directory, the working directory and its ancestors.
fn user_directory(root: &Path) -> Option<&'static str> {
    let root = std::fs::canonicalize(root).ok()?;
    if root.parent().is_none() {
        return Some("the root of the file system");
    }
    let home = std::env::var_os("HOME").and_then(|h| std::fs::canonicalize(h).ok());
    if home.as_deref() == Some(root.as_path()) {
        return Some("your home directory");
    }
    let cwd = std::env::current_dir()
        .ok()
        .and_then(|c| std::fs::canonicalize(c).ok());
    match cwd {
        Some(c) if c == root => Some("the working directory"),
        Some(c) if c.starts_with(&root) => Some("an ancestor of the working directory"),
        _ => None,
    }
}

/// Whether `name` is one of the run's own bookkeeping entries.
fn bookkeeping(name: &str) -> bool {
    name == LOCK
        || Writer::ALL.iter().any(|w| name == w.manifest())
        || name.starts_with(PARTIAL)
        || name.starts_with(OLD)
}

/// The files `writer`'s last run wrote into `root`, from its manifest (`None`: no manifest).
fn manifest(root: &Path, writer: Writer) -> Option<Vec<PathBuf>> {
    let text = std::fs::read_to_string(root.join(writer.manifest())).ok()?;
    Some(
        text.lines()
            .filter(|l| !l.is_empty() && !l.starts_with('#'))
            .map(PathBuf::from)
            // Never follow a manifest out of the directory.
            .filter(|p| {
                p.components()
                    .all(|c| matches!(c, std::path::Component::Normal(_)))
            })
            .collect(),
    )
}

/// Whether some command of ours has written into `dir` (it holds a manifest).
fn ours(dir: &Path) -> bool {
    Writer::ALL.iter().any(|w| dir.join(w.manifest()).is_file())
}

/// Writes `writer`'s manifest of `files` into `root`.
fn write_manifest(root: &Path, writer: Writer, files: &[PathBuf]) -> Result<(), AppError> {
    let command = match writer {
        Writer::Run => "run",
        Writer::Tradeoff => "tradeoff",
    };
    let mut text =
        format!("# files written by the last `activemuscle {command}` into this directory\n");
    for rel in files {
        text.push_str(&format!("{}\n", rel.display()));
    }
    let manifest = root.join(writer.manifest());
    std::fs::write(&manifest, text).map_err(|e| AppError::io("write", &manifest, e))
}

/// Takes `root`'s lock for this process, or says which live run holds it.
fn lock(root: &Path) -> Result<PathBuf, AppError> {
    let path = root.join(LOCK);
    for _ in 0..2 {
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&path)
        {
            Ok(mut f) => {
                use std::io::Write;
                writeln!(f, "{}", std::process::id())
                    .map_err(|e| AppError::io("write", &path, e))?;
                return Ok(path);
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                let holder = std::fs::read_to_string(&path)
                    .ok()
                    .and_then(|t| t.trim().parse::<u32>().ok());
                match holder {
                    Some(pid) if alive(pid) => {
                        return Err(refuse(
                            root,
                            format!(
                            "another run (pid {pid}) is writing into this directory; wait for it, \
                                 or remove {LOCK} if no such run is alive"
                        ),
                        ))
                    }
                    // A dead run's (or an unreadable) lock: taken over.
                    _ => {
                        std::fs::remove_file(&path)
                            .map_err(|e| AppError::io("remove the stale lock", &path, e))?;
                    }
                }
            }
            Err(e) => return Err(AppError::io("create the lock", &path, e)),
        }
    }
    Err(refuse(root, format!("could not take {LOCK}")))
}

impl Staging {
    /// [`Self::open`] without forcing.
    pub fn new(root: &Path, writer: Writer) -> Result<Self, AppError> {
        Self::open(root, writer, false)
    }

    /// Takes `root` for this run of `writer` (created if needed; see the module's rules): refuses a
    /// directory of user files, a directory another live run holds, and a non-empty directory
    /// that no run of ours wrote unless `force`; removes dead runs' staging directories; creates
    /// this run's staging directory.
    pub fn open(root: &Path, writer: Writer, force: bool) -> Result<Self, AppError> {
        if let Some(what) = user_directory(root) {
            return Err(refuse(
                root,
                format!("refusing to write outputs into {what}: give a directory of their own, e.g. --out out"),
            ));
        }
        if root.exists() && !root.is_dir() {
            return Err(refuse(
                root,
                "is a file, not a directory: give a directory for the outputs, e.g. --out out",
            ));
        }
        let created = !root.exists();
        std::fs::create_dir_all(root)
            .map_err(|e| AppError::io("create the output directory", root, e))?;
        let lock = lock(root)?;
        let staging = Self {
            writer,
            dir: root.join(format!("{PARTIAL}{}", std::process::id())),
            root: root.to_path_buf(),
            files: Vec::new(),
            lock: Some(lock),
            committed: false,
            created,
            used: 0,
            space: None,
        };
        let entries: Vec<String> = std::fs::read_dir(root)
            .map_err(|e| AppError::io("list", root, e))?
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        // Another output directory inside (e.g. `tradeoff --out out/tradeoff`) is ours too.
        let foreign = entries
            .iter()
            .filter(|n| !bookkeeping(n) && !ours(&root.join(n)))
            .count();
        if foreign > 0 && !ours(root) && !force {
            return Err(refuse(
                root,
                format!(
                    "the directory holds {foreign} {} that no activemuscle run wrote (no {MANIFEST}): \
                     refusing to mix outputs with them; choose an empty or new directory, or pass --force",
                    if foreign == 1 { "entry" } else { "entries" }
                ),
            ));
        }
        // Holding the lock, every other staging or set-aside directory is a dead run's.
        for name in entries
            .iter()
            .filter(|n| n.starts_with(PARTIAL) || n.starts_with(OLD))
        {
            let p = root.join(name);
            std::fs::remove_dir_all(&p)
                .map_err(|e| AppError::io("remove the dead run's", &p, e))?;
        }
        std::fs::create_dir_all(&staging.dir)
            .map_err(|e| staging.failed("create", &staging.dir, Path::new(PARTIAL), e))?;
        let reserve = staging.dir.join(RESERVE_FILE);
        std::fs::write(&reserve, vec![0u8; RESERVE as usize]).map_err(|e| {
            let what = Path::new("the space a run holds to write its manifests");
            staging.failed("write", &reserve, what, e).of_size(RESERVE)
        })?;
        Ok(staging)
    }

    /// The staging directory (for writers that take a path, e.g. the FE solver's VTK output).
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The same staging area on a simulated disk of `bytes` free: a write that would take the
    /// staged files past it writes what fits and fails as a full disk does (ENOSPC). The way a
    /// test fills a disk without one.
    pub fn with_space(mut self, bytes: u64) -> Self {
        self.space = Some(bytes);
        self
    }

    /// The staged path of `relative`, registered for the commit (parent directories created).
    pub fn path(&mut self, relative: &Path) -> Result<PathBuf, AppError> {
        let p = self.dir.join(relative);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent)
                .map_err(|e| self.failed("create", parent, relative, e))?;
        }
        if !self.files.iter().any(|f| f == relative) {
            self.files.push(relative.to_path_buf());
        }
        Ok(p)
    }

    /// Registers a file some other writer has already put into the staging directory.
    pub fn adopt(&mut self, relative: &Path) -> Result<(), AppError> {
        let p = self.dir.join(relative);
        let Ok(size) = std::fs::metadata(&p).map(|m| m.len()) else {
            return Err(AppError::Output {
                file: p.display().to_string(),
                message: "expected staged file is missing".into(),
            });
        };
        if let Err(e) = self.take_space(size) {
            let error = self.failed("write", &p, relative, e).of_size(size);
            let _ = std::fs::remove_file(&p);
            return Err(error);
        }
        if !self.files.iter().any(|f| f == relative) {
            self.files.push(relative.to_path_buf());
        }
        Ok(())
    }

    /// Writes `bytes` to the staged `relative`. On a failure nothing of it stays staged; a full
    /// disk is [`AppError::DiskFull`].
    pub fn write(&mut self, relative: &str, bytes: &[u8]) -> Result<PathBuf, AppError> {
        let rel = Path::new(relative);
        let p = self.path(rel)?;
        let written = match self.take_space(bytes.len() as u64) {
            Ok(()) => std::fs::write(&p, bytes),
            Err(full) => {
                // What fits of the file is written, as on a real disk.
                let room = self.space.unwrap_or(0).saturating_sub(self.used) as usize;
                std::fs::write(&p, &bytes[..room.min(bytes.len())]).and(Err(full))
            }
        };
        if let Err(e) = written {
            // The free space is read before the partial file gives its blocks back.
            let error = self.failed("write", &p, rel, e);
            let _ = std::fs::remove_file(&p);
            self.files.retain(|f| f != rel);
            return Err(error.of_size(bytes.len() as u64));
        }
        Ok(p)
    }

    /// Counts `bytes` more against a simulated disk ([`Self::with_space`]), or the error a full
    /// one gives.
    fn take_space(&mut self, bytes: u64) -> std::io::Result<()> {
        match self.space {
            Some(space) if self.used + bytes > space => {
                Err(std::io::Error::from(std::io::ErrorKind::StorageFull))
            }
            _ => {
                self.used += bytes;
                Ok(())
            }
        }
    }

    /// The error of `action` on `path` (the staged `relative`): [`AppError::DiskFull`] when
    /// the disk is full, naming its mount point and free space.
    fn failed(
        &self,
        action: &'static str,
        path: &Path,
        relative: &Path,
        e: std::io::Error,
    ) -> AppError {
        if !super::disk::is_full(&e) {
            return AppError::io(action, path, e);
        }
        let disk = super::disk::Disk::of(&self.root);
        AppError::DiskFull {
            file: relative.display().to_string(),
            size: None,
            disk: disk.describe(),
            free: match self.space {
                Some(space) => Some(space.saturating_sub(self.used)),
                None => disk.free,
            },
        }
    }

    /// The files staged so far, relative to the output directory, in the order registered.
    pub fn staged(&self) -> &[PathBuf] {
        &self.files
    }

    /// Replaces the previous run's files by the staged ones, all or nothing: the previous files
    /// (from this command's manifest, and those of another command's that this run writes
    /// again) are moved aside, the staged ones renamed into place in the order registered (the
    /// report last); if a rename fails, the new files go back and the old ones return. Then the
    /// manifests are written (a file taken over leaves the other command's), the old files and
    /// the staging directory removed, and the lock released. Files in another command's
    /// manifest that this run does not write are not touched.
    pub fn commit(mut self) -> Result<Vec<PathBuf>, AppError> {
        // The space held for the manifests.
        let _ = std::fs::remove_file(self.dir.join(RESERVE_FILE));
        let old_dir = self.root.join(format!("{OLD}{}", std::process::id()));
        let others: Vec<(Writer, Vec<PathBuf>)> = Writer::ALL
            .into_iter()
            .filter(|w| *w != self.writer)
            .filter_map(|w| manifest(&self.root, w).map(|files| (w, files)))
            .collect();
        let mut old: Vec<PathBuf> = manifest(&self.root, self.writer).unwrap_or_default();
        for (_, files) in &others {
            old.extend(files.iter().filter(|f| self.files.contains(f)).cloned());
        }
        old.sort();
        old.dedup();
        old.retain(|f| self.root.join(f).is_file());
        let mut aside = Vec::new();
        let mut placed = Vec::new();
        let result = (|| -> Result<(), AppError> {
            for rel in &old {
                move_file(&self.root.join(rel), &old_dir.join(rel))?;
                aside.push(rel.clone());
            }
            for rel in &self.files {
                move_file(&self.dir.join(rel), &self.root.join(rel))?;
                placed.push(rel.clone());
            }
            Ok(())
        })();
        if let Err(e) = result {
            // Put everything back: the new files into staging, the old ones into place.
            for rel in placed.iter().rev() {
                let _ = move_file(&self.root.join(rel), &self.dir.join(rel));
            }
            for rel in aside.iter().rev() {
                let _ = move_file(&old_dir.join(rel), &self.root.join(rel));
            }
            let _ = std::fs::remove_dir_all(&old_dir);
            return Err(
                e.within("nothing of this run was committed; the previous outputs are unchanged")
            );
        }
        write_manifest(&self.root, self.writer, &self.files)?;
        for (w, files) in &others {
            if files.iter().any(|f| self.files.contains(f)) {
                let kept: Vec<PathBuf> = files
                    .iter()
                    .filter(|f| !self.files.contains(f))
                    .cloned()
                    .collect();
                write_manifest(&self.root, *w, &kept)?;
            }
        }
        self.committed = true;
        // Directories the old files left empty (e.g. vtk/<sweep>/ of a study now gone).
        for rel in old.iter().filter(|r| !self.files.contains(r)) {
            let mut dir = rel.parent();
            while let Some(d) = dir.filter(|d| !d.as_os_str().is_empty()) {
                if std::fs::remove_dir(self.root.join(d)).is_err() {
                    break;
                }
                dir = d.parent();
            }
        }
        let _ = std::fs::remove_dir_all(&old_dir);
        std::fs::remove_dir_all(&self.dir).map_err(|e| AppError::io("remove", &self.dir, e))?;
        Ok(self.files.iter().map(|f| self.root.join(f)).collect())
    }
}

/// Renames `from` to `to`, creating `to`'s parent.
fn move_file(from: &Path, to: &Path) -> Result<(), AppError> {
    if let Some(parent) = to.parent() {
        std::fs::create_dir_all(parent).map_err(|e| AppError::io("create", parent, e))?;
    }
    std::fs::rename(from, to).map_err(|e| AppError::io("move into place", to, e))
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
        if let Some(lock) = self.lock.take() {
            let _ = std::fs::remove_file(lock);
        }
        if self.created && !self.committed {
            // Fails, harmlessly, unless the directory is empty.
            let _ = std::fs::remove_dir(&self.root);
        }
    }
}
