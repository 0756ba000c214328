//! Running the binary as a user does, for the tests that check what it writes.

use std::path::Path;
use std::process::{Command, Output};

/// A trade-off study of one option, one stretch and a 1 × 4 mesh: seconds to run.
pub const SMALL_TRADEOFF: &str =
    "[[study]]\nkind = \"tradeoff\"\noptions = [\"newton-tolerance\"]\n\
    stretch = [1.1]\nnr = 1\nnz = 4\ntolerances = [1e-6, 1e-10]\n";

/// `activemuscle run [SCENE] --out OUT --quiet` (the embedded paper scene without `scene`);
/// asserts that it succeeds and returns its output.
pub fn run_quiet(scene: Option<&Path>, out: &Path) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_activemuscle"));
    command.arg("run");
    if let Some(scene) = scene {
        command.arg(scene);
    }
    let output = command
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .output()
        .expect("run binary");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

/// `activemuscle ARGS…` without any assertion: its output, status included.
pub fn run_args<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_activemuscle"))
        .args(args)
        .output()
        .expect("run binary")
}

/// `activemuscle COMMAND SCENE --out OUT --quiet` (`run` or `tradeoff`) without any assertion:
/// its output, status included.
pub fn quietly(command: &str, scene: &Path, out: &Path) -> Output {
    run_args(&[
        command.as_ref(),
        scene.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ])
}
