//! Paths that are not UTF-8 (a byte 0xFF in a file or directory name, legal on Unix): the
//! scene path, `--out` and the data files a scene names are used by their bytes; `run`,
//! `tradeoff` and `check` compute and write as with any other path, and the report shows the
//! command with U+FFFD where the byte was.

#![cfg(unix)]

use crate::binary::{quietly, run_args, SMALL_TRADEOFF};
use crate::scratch::scratch;
use std::ffi::OsString;
use std::os::unix::ffi::OsStringExt;
use std::path::{Path, PathBuf};

/// `dir/<prefix>\xFF<suffix>`: a name that is not UTF-8.
fn not_utf8(dir: &Path, prefix: &str, suffix: &str) -> PathBuf {
    let mut bytes = prefix.as_bytes().to_vec();
    bytes.push(0xFF);
    bytes.extend_from_slice(suffix.as_bytes());
    let name = OsString::from_vec(bytes);
    assert!(name.to_str().is_none(), "the name must not be UTF-8");
    dir.join(name)
}

const SCENE: &str = "[[study]]\nkind = \"uniaxial\"\nstretch = [1.0, 1.1]\n";

#[test]
fn run_writes_into_an_output_directory_whose_name_is_not_utf8() {
    let dir = scratch("os-paths-out");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let out = not_utf8(&dir, "o", "ut");
    let output = quietly("run", &scene, &out);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let curves = std::fs::read_to_string(out.join("curves.csv")).unwrap();
    // A header and one row per (curve, stretch): the passive and the implicit law's curves.
    assert_eq!(curves.lines().count(), 1 + 2 * 2, "{curves}");
    let report = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(report.contains("o\u{FFFD}ut"), "the command line, as shown");
}

#[test]
fn a_scene_in_a_directory_whose_name_is_not_utf8_reads_its_data_file_beside_it() {
    let dir = scratch("os-paths-scene");
    let home = not_utf8(&dir, "sc", "ene");
    std::fs::create_dir(&home).unwrap();
    // A passive fit to a data file named relative to the scene.
    std::fs::write(
        home.join("data.csv"),
        "lambda,P\n1.0,0\n1.1,0.5\n1.2,1.4\n1.3,3.2\n1.4,7.5\n",
    )
    .unwrap();
    let scene = home.join("fit.toml");
    std::fs::write(
        &scene,
        "[[study]]\nkind = \"fit\"\nfit = \"passive\"\ndata = \"data.csv\"\nfree = [\"mu\"]\n",
    )
    .unwrap();
    let check = run_args(&["check".as_ref(), scene.as_os_str()]);
    assert_eq!(
        check.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&check.stderr)
    );
    let out = dir.join("out");
    let output = quietly("run", &scene, &out);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let fits = std::fs::read_to_string(out.join("fits.csv")).unwrap();
    assert!(fits.lines().any(|l| l.contains(",mu,")), "{fits}");
}

#[test]
fn tradeoff_writes_into_an_output_directory_whose_name_is_not_utf8() {
    let dir = scratch("os-paths-tradeoff");
    let scene = dir.join("tradeoff.toml");
    std::fs::write(&scene, SMALL_TRADEOFF).unwrap();
    let out = not_utf8(&dir, "t", "");
    let output = quietly("tradeoff", &scene, &out);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    let html = std::fs::read_to_string(out.join("tradeoff.html")).unwrap();
    assert!(html.contains("t\u{FFFD}"), "the command line, as shown");
    assert!(out.join("tradeoff.csv").is_file());
}
