//! A disk that fills up while a run writes: the data is written first (the CSV tables,
//! datapackage.json), and what was written whole before the disk filled is kept; one line names
//! the disk (its mount point), the file and the space left, and the run exits 4. The disk is
//! simulated: the staging area takes a number of free bytes and fails the write that would pass
//! them as a full disk does (ENOSPC); the binary's test build reads it from
//! `ACTIVEMUSCLE_TEST_DISK_SPACE`.

use crate::binary::{quietly, SMALL_TRADEOFF};
use crate::scratch::scratch;
use activemuscle::output::{write_run, RunMeta, Staging, Writer};
use activemuscle::scene::{RunOptions, Scene};
use activemuscle::AppError;
use std::path::Path;
use std::process::Command;

const SCENE: &str = "[[study]]\nkind = \"uniaxial\"\nstretch = [0.9, 1.0, 1.1, 1.2]\n\
                     [[study]]\nkind = \"stability\"\nstretch = [1.0, 1.1]\n";

/// The data files of `SCENE`'s run, in the order they are written.
const DATA: [&str; 4] = [
    "curves.csv",
    "stability.csv",
    "scene.toml",
    "datapackage.json",
];

/// The mount point of the file system holding `dir`, as `df` says (not this crate's reading of
/// the mount table).
fn mount_point(dir: &Path) -> String {
    let out = Command::new("df")
        .arg("-P")
        .arg(dir)
        .output()
        .expect("run df");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let last = text.lines().last().expect("a line of df");
    last.split_whitespace()
        .last()
        .expect("a mount point")
        .to_string()
}

fn size(p: &Path) -> u64 {
    std::fs::metadata(p)
        .unwrap_or_else(|e| panic!("{}: {e}", p.display()))
        .len()
}

/// Runs `SCENE` into `out` without a limit; returns the bytes of its data files.
fn unlimited(out: &Path) -> u64 {
    let scene = out.parent().unwrap().join("scene.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let o = quietly("run", &scene, out);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    DATA.iter().map(|f| size(&out.join(f))).sum()
}

#[test]
fn a_full_disk_keeps_the_data_written_before_it_byte_for_byte() {
    let dir = scratch("full-disk-library");
    let whole = dir.join("whole");
    let data = unlimited(&whole);
    let scene = Scene::parse(SCENE, &dir.join("scene.toml").display().to_string()).unwrap();
    let results = scene.run(&RunOptions::default());
    let out = dir.join("full");
    // Room for the data and 100 bytes more: the first figure does not fit.
    let mut staging = Staging::open(&out, Writer::Run, false)
        .unwrap()
        .with_space(data + 100);
    let meta = RunMeta {
        command: "activemuscle run scene.toml".into(),
        started: std::time::Instant::now(),
        rustc: None,
    };
    let e = write_run(&mut staging, &scene, &results, &meta).unwrap_err();
    let AppError::DiskFull {
        file, free, disk, ..
    } = &e
    else {
        panic!("not a full disk: {e}")
    };
    assert!(file.starts_with("fig_") && file.ends_with(".png"), "{e}");
    assert_eq!(*free, Some(100), "{e}");
    assert!(disk.starts_with(&mount_point(&dir)), "{disk}");
    let staged: Vec<String> = staging
        .staged()
        .iter()
        .map(|p| p.display().to_string())
        .collect();
    assert_eq!(
        staged, DATA,
        "the data, in the order written, and nothing else"
    );
    staging.commit().unwrap();
    for f in DATA {
        assert_eq!(
            std::fs::read(out.join(f)).unwrap(),
            std::fs::read(whole.join(f)).unwrap(),
            "{f}"
        );
    }
    assert!(!out.join("report.html").exists());
}

#[test]
fn run_on_a_full_disk_exits_4_with_one_line_naming_the_disk_the_file_and_the_free_space() {
    let dir = scratch("full-disk-binary");
    let data = unlimited(&dir.join("whole"));
    let out = dir.join("full");
    let o = Command::new(env!("CARGO_BIN_EXE_activemuscle"))
        .arg("run")
        .arg(dir.join("scene.toml"))
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        .env("ACTIVEMUSCLE_TEST_DISK_SPACE", (data + 100).to_string())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(4), "{stdout}");
    let lines: Vec<&str> = stdout
        .lines()
        .filter(|l| l.starts_with("DISK FULL:"))
        .collect();
    assert_eq!(lines.len(), 1, "{stdout}");
    let line = lines[0];
    assert!(
        line.contains(&format!("mounted at {}", mount_point(&dir))),
        "{line}"
    );
    assert!(
        line.contains("writing fig_") && line.contains("100 bytes free"),
        "{line}"
    );
    assert!(
        line.contains("curves.csv") && line.contains("datapackage.json"),
        "{line}"
    );
    // What is kept: the data, listed in the manifest, and nothing else.
    let manifest = std::fs::read_to_string(out.join(".activemuscle-manifest")).unwrap();
    let listed: Vec<&str> = manifest.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(listed, DATA);
    let mut entries: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect();
    entries.sort();
    let mut expected: Vec<String> = DATA.iter().map(|s| s.to_string()).collect();
    expected.sort();
    assert_eq!(entries, expected);
}

#[test]
fn tradeoff_on_a_full_disk_keeps_its_table_and_exits_4() {
    let dir = scratch("full-disk-tradeoff");
    let scene = dir.join("tradeoff.toml");
    std::fs::write(&scene, SMALL_TRADEOFF).unwrap();
    let out = dir.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_activemuscle"))
        .arg("tradeoff")
        .arg(&scene)
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        .env("ACTIVEMUSCLE_TEST_DISK_SPACE", "3000")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(4), "{stdout}");
    assert!(
        stdout.contains("DISK FULL") && stdout.contains("tradeoff.csv"),
        "{stdout}"
    );
    assert!(out.join("tradeoff.csv").is_file());
    assert!(!out.join("tradeoff.html").exists());
}
