//! Scratch directories for the tests that write files. Each is removed when its guard is dropped,
//! also when the test fails (the guard drops while the panic unwinds). With
//! `ACTIVEMUSCLE_KEEP_TEST_DIRS=1` in the environment they are kept and their paths printed.

use std::ops::Deref;
use std::path::Path;

/// A fresh, empty directory `$TMPDIR/activemuscle-NAME-XXXXXX`, removed when dropped.
pub struct Scratch(Option<tempfile::TempDir>);

/// A new scratch directory whose name starts with `activemuscle-NAME-`.
pub fn scratch(name: &str) -> Scratch {
    let dir = tempfile::Builder::new()
        .prefix(&format!("activemuscle-{name}-"))
        .tempdir()
        .expect("create a scratch directory");
    Scratch(Some(dir))
}

impl Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        match &self.0 {
            Some(dir) => dir.path(),
            None => unreachable!("a scratch directory is only taken when dropped"),
        }
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let keep = std::env::var_os("ACTIVEMUSCLE_KEEP_TEST_DIRS").is_some_and(|v| v == "1");
        if let Some(dir) = self.0.take() {
            if keep {
                eprintln!("kept the scratch directory {}", dir.keep().display());
            }
            // Otherwise `dir` is dropped here, which removes it and everything in it.
        }
    }
}
