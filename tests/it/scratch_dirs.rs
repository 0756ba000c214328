//! The tests' scratch directories (tests/scratch/) leave nothing behind: each is removed when the
//! test that made it ends, also when that test fails.

use crate::scratch;
use scratch::scratch;

#[test]
fn a_scratch_directory_is_removed_when_its_guard_drops() {
    let dir = scratch("scratch-ok");
    std::fs::create_dir_all(dir.join("out/vtk")).unwrap();
    std::fs::write(dir.join("out/vtk/a.vtu"), "x").unwrap();
    let path = dir.to_path_buf();
    assert!(path.is_dir());
    assert!(path
        .file_name()
        .and_then(|n| n.to_str())
        .is_some_and(|n| n.starts_with("activemuscle-scratch-ok-")));
    drop(dir);
    if std::env::var_os("ACTIVEMUSCLE_KEEP_TEST_DIRS").is_some_and(|v| v == "1") {
        assert!(path.is_dir(), "kept on request");
        std::fs::remove_dir_all(&path).unwrap();
    }
    assert!(!path.exists(), "{} left behind", path.display());
}

#[test]
fn a_scratch_directory_is_removed_when_its_test_panics() {
    let (sender, receiver) = std::sync::mpsc::channel();
    let failed = std::thread::spawn(move || {
        let dir = scratch("scratch-panic");
        std::fs::write(dir.join("scene.toml"), "x").unwrap();
        sender.send(dir.to_path_buf()).unwrap();
        panic!("a failing test");
    })
    .join();
    assert!(failed.is_err());
    let path = receiver.recv().unwrap();
    if std::env::var_os("ACTIVEMUSCLE_KEEP_TEST_DIRS").is_some_and(|v| v == "1") {
        std::fs::remove_dir_all(&path).unwrap();
    }
    assert!(!path.exists(), "{} left behind", path.display());
}
