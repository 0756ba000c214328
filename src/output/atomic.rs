//! Atomic outputs: every file of a run is written into a hidden staging directory inside the
//! output directory, then renamed into place one by one (a rename within one file system is
//! atomic). A run that fails before [`Staging::commit`] removes the staging directory, so it
//! never leaves a half-written file under a final name.

use crate::app_error::AppError;
use std::path::{Path, PathBuf};

/// The staging area of one run.
#[derive(Debug)]
pub struct Staging {
    dir: PathBuf,
    root: PathBuf,
    files: Vec<PathBuf>,
    committed: bool,
}

impl Staging {
    /// Creates `root` if needed and a fresh staging directory inside it.
    pub fn new(root: &Path) -> Result<Self, AppError> {
        std::fs::create_dir_all(root)
            .map_err(|e| AppError::io("create the output directory", root, e))?;
        let dir = root.join(format!(".activemuscle-partial-{}", std::process::id()));
        if dir.exists() {
            std::fs::remove_dir_all(&dir).map_err(|e| AppError::io("clear", &dir, e))?;
        }
        std::fs::create_dir_all(&dir).map_err(|e| AppError::io("create", &dir, e))?;
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
    pub fn path(&mut self, relative: &Path) -> Result<PathBuf, AppError> {
        let p = self.dir.join(relative);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).map_err(|e| AppError::io("create", parent, e))?;
        }
        if !self.files.iter().any(|f| f == relative) {
            self.files.push(relative.to_path_buf());
        }
        Ok(p)
    }

    /// Registers a file some other writer has already put into the staging directory.
    pub fn adopt(&mut self, relative: &Path) -> Result<(), AppError> {
        let p = self.dir.join(relative);
        if !p.is_file() {
            return Err(AppError::Output {
                file: p.display().to_string(),
                message: "expected staged file is missing".into(),
            });
        }
        if !self.files.iter().any(|f| f == relative) {
            self.files.push(relative.to_path_buf());
        }
        Ok(())
    }

    /// Writes `bytes` to the staged `relative`.
    pub fn write(&mut self, relative: &str, bytes: &[u8]) -> Result<PathBuf, AppError> {
        let p = self.path(Path::new(relative))?;
        std::fs::write(&p, bytes).map_err(|e| AppError::io("write", &p, e))?;
        Ok(p)
    }

    /// Moves every staged file into the output directory, in the order registered (so the file
    /// registered last — the report — appears last), and removes the staging directory.
    pub fn commit(mut self) -> Result<Vec<PathBuf>, AppError> {
        let mut done = Vec::new();
        for rel in &self.files {
            let from = self.dir.join(rel);
            let to = self.root.join(rel);
            if let Some(parent) = to.parent() {
                std::fs::create_dir_all(parent).map_err(|e| AppError::io("create", parent, e))?;
            }
            std::fs::rename(&from, &to).map_err(|e| AppError::io("move into place", &to, e))?;
            done.push(to);
        }
        self.committed = true;
        std::fs::remove_dir_all(&self.dir).map_err(|e| AppError::io("remove", &self.dir, e))?;
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
