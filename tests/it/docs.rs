//! The user documentation against the code: the generated scene reference is the committed one,
//! every key it lists is documented and is a key the scene reader takes, and every TOML block
//! the README and docs/ show is a scene that `check` accepts.

use activemuscle::scene::reference::{keys, markdown, tables};
use activemuscle::scene::Scene;
use activemuscle::studies::StudyKind;
use std::path::{Path, PathBuf};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// `docs/scene-reference.md` is what `activemuscle keys` prints. `ACTIVEMUSCLE_BLESS=1 cargo test
/// --test it docs::` rewrites it.
#[test]
fn committed_scene_reference_is_what_the_code_generates() {
    let path = Path::new(ROOT).join("docs/scene-reference.md");
    let generated = format!("{}\n", markdown().trim_end());
    if std::env::var_os("ACTIVEMUSCLE_BLESS").is_some() {
        std::fs::write(&path, &generated).expect("write docs/scene-reference.md");
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    if committed != generated {
        let first = committed
            .lines()
            .zip(generated.lines())
            .position(|(a, b)| a != b)
            .unwrap_or_else(|| committed.lines().count().min(generated.lines().count()));
        panic!(
            "docs/scene-reference.md differs from what the code generates from line {}: \
             regenerate it with `cargo run --release -- keys > docs/scene-reference.md`",
            first + 1
        );
    }
}

#[test]
fn every_key_of_the_reference_has_its_documentation_and_a_type() {
    let mut missing = Vec::new();
    for table in tables() {
        for key in keys(&table) {
            if key.doc.is_empty() {
                missing.push(format!("{} {} ({})", table.heading, key.name, table.spec));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "keys without a doc comment in scene::reference::SOURCES (add the spec's file there): {missing:?}"
    );
    assert!(tables().len() > StudyKind::ALL.len(), "{:?}", tables());
}

/// The keys a kind's error message lists (`its keys: a, b`) or serde's `expected one of`.
fn keys_the_reader_lists(scene: &str) -> Vec<String> {
    let e = Scene::parse(scene, "probe.toml").expect_err("an unknown key is refused");
    let message = e.to_string();
    let list: Vec<String> = match message.split_once("its keys: ") {
        Some((_, list)) => list.split(", ").map(str::to_string).collect(),
        None => message
            .split_once("expected one of ")
            .map(|(_, l)| {
                l.split('`')
                    .skip(1)
                    .step_by(2)
                    .map(str::to_string)
                    .collect()
            })
            .unwrap_or_default(),
    };
    assert!(!list.is_empty(), "no key list in {message}");
    list
}

/// The reference's keys come from serde's field lists; the scene reader's refusal of an unknown
/// key lists the keys it takes by another route (its error message): the two agree for every
/// study kind, `[activation]` and `[incompressibility]`.
#[test]
fn reference_lists_exactly_the_keys_the_scene_reader_takes() {
    let tables = tables();
    let of = |heading: &str| -> Vec<String> {
        let t = tables
            .iter()
            .find(|t| t.heading == heading)
            .unwrap_or_else(|| panic!("no table {heading}"));
        t.keys.iter().map(|k| k.to_string()).collect()
    };
    for kind in StudyKind::ALL {
        let scene = format!("[[study]]\nkind = \"{}\"\nnot_a_key = 1\n", kind.name());
        assert_eq!(
            of(&format!("[[study]] kind = \"{}\"", kind.name())),
            keys_the_reader_lists(&scene),
            "{}",
            kind.name()
        );
    }
    assert_eq!(
        of("[activation]"),
        keys_the_reader_lists("[activation]\nnot_a_key = 1\n")
    );
    assert_eq!(
        of("[incompressibility]"),
        keys_the_reader_lists("[incompressibility]\nnot_a_key = 1\n")
    );
}

/// README.md, BENCHMARKS.md and every page of docs/.
fn documents() -> Vec<PathBuf> {
    let mut files = vec![
        Path::new(ROOT).join("README.md"),
        Path::new(ROOT).join("BENCHMARKS.md"),
    ];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(Path::new(ROOT).join("docs"))
        .expect("docs/")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    docs.sort();
    files.extend(docs);
    files
}

/// The ```toml blocks of a Markdown text, with the line each starts on.
fn toml_blocks(text: &str) -> Vec<(usize, String)> {
    let mut blocks = Vec::new();
    let mut open: Option<(usize, String)> = None;
    for (i, line) in text.lines().enumerate() {
        let fence = line.trim_start();
        match (&mut open, fence.starts_with("```")) {
            (None, true) if fence.trim_end() == "```toml" => open = Some((i + 1, String::new())),
            (Some(_), true) => blocks.extend(open.take()),
            (Some((_, body)), false) => {
                body.push_str(line);
                body.push('\n');
            }
            (None, _) => {}
        }
    }
    blocks
}

/// Every TOML block the documentation shows is a whole scene that `check` accepts (data files
/// named relative to the repository's root, where the docs' commands run).
#[test]
fn every_toml_block_of_the_docs_is_a_scene_check_accepts() {
    let mut checked = 0;
    for doc in documents() {
        let text = std::fs::read_to_string(&doc).expect("read a doc");
        let name = doc.strip_prefix(ROOT).unwrap_or(&doc).display().to_string();
        for (line, block) in toml_blocks(&text) {
            let file = format!("{ROOT}/{} line {line}", name.replace('/', " "));
            if let Err(e) = Scene::parse(&block, &file) {
                panic!("{name}, the ```toml block at line {line} is not a valid scene: {e}");
            }
            checked += 1;
        }
    }
    assert!(checked >= 3, "only {checked} TOML blocks found");
}

/// `activemuscle keys` prints the committed reference (the command the reference names).
#[test]
fn keys_command_prints_the_committed_reference() {
    let output = crate::binary::run_args(&["keys"]);
    assert!(output.status.success(), "{output:?}");
    let committed = std::fs::read_to_string(Path::new(ROOT).join("docs/scene-reference.md"))
        .expect("read docs/scene-reference.md");
    assert!(
        String::from_utf8_lossy(&output.stdout) == committed,
        "`activemuscle keys` differs from docs/scene-reference.md"
    );
}

/// The README's own scene, saved as `my.toml`, runs as the README says: `check` prints it
/// resolved, `run --out my` writes the report and one row per stretch and model of the curves
/// (31 stretches × (the passive curve + one per damage of [activation]) = 93 rows).
#[test]
fn readme_scene_checks_and_runs_as_the_readme_says() {
    let readme = std::fs::read_to_string(Path::new(ROOT).join("README.md")).expect("README");
    let (_, scene) = toml_blocks(&readme)
        .into_iter()
        .next()
        .expect("a TOML block");
    let dir = crate::scratch::scratch("readme");
    let file = dir.join("my.toml");
    std::fs::write(&file, &scene).expect("write my.toml");
    let check = crate::binary::run_args(&[std::ffi::OsStr::new("check"), file.as_os_str()]);
    assert!(check.status.success(), "{check:?}");
    assert!(String::from_utf8_lossy(&check.stdout).contains("energy = \"ehret-bol-itskov\""));
    let out = dir.join("my");
    crate::binary::run_quiet(Some(&file), &out);
    assert!(out.join("report.html").is_file());
    let curves = std::fs::read_to_string(out.join("curves.csv")).expect("curves.csv");
    assert_eq!(curves.lines().count(), 1 + 31 * 3, "{curves}");
}

/// The README's two commands are `cargo run --release` and the test command exactly as CI runs
/// it (the line of `.ci/run` marked as the README's).
#[test]
fn readme_test_command_is_the_one_ci_runs() {
    let ci = std::fs::read_to_string(Path::new(ROOT).join(".ci/run")).expect(".ci/run");
    let command = ci
        .lines()
        .find(|l| l.contains("the README's test command"))
        .and_then(|l| l.split('#').next())
        .map(str::trim)
        .expect(".ci/run marks the README's test command");
    let readme = std::fs::read_to_string(Path::new(ROOT).join("README.md")).expect("README");
    let two = format!("```sh\ncargo run --release\n{command}\n```");
    assert!(
        readme.contains(&two),
        "README.md does not show the two commands as\n{two}"
    );
}

/// The README's table of what is inside names every entry of every registry: energies, active
/// curves, approaches, study kinds, elements and volumetric forms.
#[test]
fn readme_names_every_registry_entry() {
    use activemuscle::active::{Approach, CURVES};
    use activemuscle::energy::SHIPPED;
    use activemuscle::fem::Element;
    let readme = std::fs::read_to_string(Path::new(ROOT).join("README.md")).expect("README");
    let forms =
        activemuscle::scene::reference::keys_of::<activemuscle::models::IncompressibilityKind>()
            .map_or(&[][..], |(_, v)| v);
    let mut names: Vec<&str> = SHIPPED.iter().map(|e| e.name).collect();
    names.extend(CURVES.iter().map(|c| c.name));
    names.extend(Approach::NAMES.iter().copied());
    names.extend(StudyKind::ALL.iter().map(|k| k.name()));
    names.extend(Element::ALL.iter().map(|e| e.name()));
    names.extend(forms.iter().copied());
    let missing: Vec<&str> = names
        .into_iter()
        .filter(|n| !readme.contains(&format!("`{n}`")))
        .collect();
    assert!(
        missing.is_empty(),
        "README.md's \"What is inside\" misses {missing:?}"
    );
    assert!(forms.len() >= 4, "{forms:?}");
}

/// A heading's anchor as the repository's host makes it: lower case, punctuation dropped,
/// spaces as hyphens.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | ' '))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// Every relative link of README.md, BENCHMARKS.md, CHANGELOG.md and docs/ reaches a file, and
/// its `#anchor` a heading of that file (the links outside code blocks).
#[test]
fn every_relative_link_of_the_docs_reaches_its_file_and_heading() {
    let mut docs = documents();
    docs.push(Path::new(ROOT).join("CHANGELOG.md"));
    let mut broken = Vec::new();
    for doc in &docs {
        let text = std::fs::read_to_string(doc).expect("read a doc");
        let prose: String = text.split("```").step_by(2).collect::<Vec<_>>().join("\n");
        for (i, _) in prose.match_indices("](") {
            let rest = &prose[i + 2..];
            let Some(end) = rest.find(')') else { continue };
            let target = &rest[..end];
            if target.starts_with("http") || target.contains(' ') {
                continue;
            }
            let (path, fragment) = target.split_once('#').unwrap_or((target, ""));
            let file = if path.is_empty() {
                doc.clone()
            } else {
                doc.parent().expect("a doc's directory").join(path)
            };
            if !file.exists() {
                broken.push(format!("{}: {target}", doc.display()));
            } else if !fragment.is_empty() && file.extension().is_some_and(|e| e == "md") {
                let headings = std::fs::read_to_string(&file).expect("read a linked doc");
                let found = headings
                    .lines()
                    .filter_map(|l| l.strip_prefix('#'))
                    .map(|h| anchor(h.trim_start_matches('#')))
                    .any(|a| a == fragment);
                if !found {
                    broken.push(format!("{}: {target} (no such heading)", doc.display()));
                }
            }
        }
    }
    assert!(broken.is_empty(), "broken links: {broken:#?}");
}
