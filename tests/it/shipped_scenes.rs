//! Every scene shipped under `scenes/` passes `activemuscle check` as a user runs it: valid,
//! resolved with every default written out, one line per study of what `run` would compute; and
//! the resolved scene is itself a scene that resolves to the same text (nothing `check` prints
//! is lost or changed by reading it back).

use crate::binary::run_args;
use activemuscle::scene::Scene;
use std::path::{Path, PathBuf};

/// The `.toml` files under `dir`, recursively, sorted.
fn scenes(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).expect("read scenes/") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            out.extend(scenes(&path));
        } else if path.extension().is_some_and(|e| e == "toml") {
            out.push(path);
        }
    }
    out.sort();
    out
}

/// The number of `[[study]]` tables in a scene file's text.
fn studies_in(text: &str) -> usize {
    text.lines().filter(|l| l.trim() == "[[study]]").count()
}

#[test]
fn every_shipped_scene_passes_check_and_resolves_to_itself() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let all = scenes(&root);
    let names: Vec<String> = all
        .iter()
        .map(|p| p.strip_prefix(&root).unwrap().display().to_string())
        .collect();
    // The examples no other test parses, and the two top-level scenes, are among them.
    for name in [
        "paper.toml",
        "tradeoff.toml",
        "examples/4c_passive_block.toml",
        "examples/activation_in_time.toml",
        "examples/biaxial_strip.toml",
        "examples/compressible_block_in_time.toml",
        "examples/shear_approaches.toml",
    ] {
        assert!(names.iter().any(|n| n == name), "{name} not in {names:?}");
    }
    for (path, name) in all.iter().zip(&names) {
        let output = run_args(&["check".as_ref(), path.as_os_str()]);
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert!(
            output.status.success(),
            "{name}: {}{stdout}",
            String::from_utf8_lossy(&output.stderr)
        );
        let (head, rest) = stdout.split_once('\n').expect("a first line");
        assert!(
            head.ends_with(": valid. Resolved scene (every default written out):"),
            "{name}: {head}"
        );
        let (resolved, plan) = rest
            .split_once("# What `activemuscle run` would compute:")
            .unwrap_or_else(|| panic!("{name}: no plan in {stdout}"));
        // One line per study of the file (the paper scene: as many as it declares).
        let source = std::fs::read_to_string(path).expect("the scene");
        let planned = plan.lines().filter(|l| l.starts_with("#   ")).count();
        assert_eq!(planned, studies_in(&source), "{name}: {plan}");
        // The resolved scene reads back to itself (data files named relative to the scene's
        // directory, as in the file).
        let resolved = resolved.trim();
        let again = Scene::parse(resolved, &path.display().to_string())
            .unwrap_or_else(|e| panic!("{name}: the resolved scene does not parse: {e}"));
        assert_eq!(
            again.resolved_toml().expect("resolved").trim(),
            resolved,
            "{name}"
        );
    }
}
