//! Scratch directories for the tests that write files. Each is removed when its guard is dropped,
//! also when the test fails (the guard drops while the panic unwinds). With
//! `ACTIVEMUSCLE_KEEP_TEST_DIRS=1` in the environment they are kept and their paths printed.

use std::ops::Deref;
use std::path::Path;

/// A fresh, empty directory `$TMPDIR/activemuscle-NAME-XXXXXX`, removed when dropped.
pub struct Scratch(tempfile::TempDir);

/// A new scratch directory whose name starts with `activemuscle-NAME-`.
pub fn scratch(name: &str) -> Scratch {
    let keep = std::env::var_os("ACTIVEMUSCLE_KEEP_TEST_DIRS").is_some_and(|v| v == "1");
    let dir = tempfile::Builder::new()
        .prefix(&format!("activemuscle-{name}-"))
        .disable_cleanup(keep)
        .tempdir()
        .expect("create a scratch directory");
    if keep {
        eprintln!("keeping the scratch directory {}", dir.path().display());
    }
    Scratch(dir)
}

impl Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        self.0.path()
    }
}
