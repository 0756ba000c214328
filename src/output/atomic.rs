//! Atomic outputs: every file of a run is written into a hidden staging directory inside the
//! output directory, then renamed into place one by one (a rename within one file system is
//! atomic). A run that fails before [`Staging::commit`] removes the staging directory, so it
//! never leaves a half-written file under a final name.

use std::path::{Path, PathBuf};

/// The staging area of one run.
#[derive(Debug)]
pub struct Staging {
    dir: PathBuf,
    root: PathBuf,
    files: Vec<PathBuf>,
    committed: bool,
}

/// An output error: which file, what went wrong.
#[derive(Debug)]
pub struct OutputError(pub String);

impl std::fmt::Display for OutputError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for OutputError {}

fn io(what: &str, path: &Path, e: std::io::Error) -> OutputError {
    OutputError(format!("cannot {what} {}: {e}", path.display()))
}

impl Staging {
    /// Creates `root` if needed and a fresh staging directory inside it.
    pub fn new(root: &Path) -> Result<Self, OutputError> {
        std::fs::create_dir_all(root).map_err(|e| io("create the output directory", root, e))?;
        let dir = root.join(format!(".activemuscle-partial-{}", std::process::id()));
        if dir.exists() {
            std::fs::remove_dir_all(&dir).map_err(|e| io("clear", &dir, e))?;
        }
        std::fs::create_dir_all(&dir).map_err(|e| io("create", &dir, e))?;
        Ok(Self {
            dir,
            root: root.to_path_buf(),
            files: Vec::new(),
            committed: false,
        })
    }

    /// The staging directory (for writers that take a path, e.g. the FE solver's VTK output).
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The staged path of `relative`, registered for the commit (parent directories created).
    pub fn path(&mut self, relative: &Path) -> Result<PathBuf, OutputError> {
        let p = self.dir.join(relative);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).map_err(|e| io("create", parent, e))?;
        }
        if !self.files.iter().any(|f| f == relative) {
            self.files.push(relative.to_path_buf());
        }
        Ok(p)
    }

    /// Registers a file some other writer has already put into the staging directory.
    pub fn adopt(&mut self, relative: &Path) -> Result<(), OutputError> {
        let p = self.dir.join(relative);
        if !p.is_file() {
            return Err(OutputError(format!(
                "expected staged file {} is missing",
                p.display()
            )));
        }
        if !self.files.iter().any(|f| f == relative) {
            self.files.push(relative.to_path_buf());
        }
        Ok(())
    }

    /// Writes `bytes` to the staged `relative`.
    pub fn write(&mut self, relative: &str, bytes: &[u8]) -> Result<PathBuf, OutputError> {
        let p = self.path(Path::new(relative))?;
        std::fs::write(&p, bytes).map_err(|e| io("write", &p, e))?;
        Ok(p)
    }

    /// Moves every staged file into the output directory, in the order registered (so the file
    /// registered last — the report — appears last), and removes the staging directory.
    pub fn commit(mut self) -> Result<Vec<PathBuf>, OutputError> {
        let mut done = Vec::new();
        for rel in &self.files {
            let from = self.dir.join(rel);
            let to = self.root.join(rel);
            if let Some(parent) = to.parent() {
                std::fs::create_dir_all(parent).map_err(|e| io("create", parent, e))?;
            }
            std::fs::rename(&from, &to).map_err(|e| io("move into place", &to, e))?;
            done.push(to);
        }
        self.committed = true;
        std::fs::remove_dir_all(&self.dir).map_err(|e| io("remove", &self.dir, e))?;
        Ok(done)
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }
}
