//! A study's name names its output files (issue 24, items 3 and 9): a name of any script's
//! letters and digits is a name, a name too long to be a file name is refused when the scene is
//! read (it used to cost a finished run: exit 1 and nothing written), and the longest name
//! allowed writes every file of its study.

use crate::binary::run_args;
use crate::scratch::scratch;
use activemuscle::scene::Scene;
use activemuscle::studies::slug;

const FILE: &str = "names.toml";

/// A fit study named `name` and a stability study named `other` (both small).
fn fit_and_stability(name: &str, other: &str) -> String {
    format!(
        "[[study]]\nkind = \"fit\"\nname = \"{name}\"\nfit = \"passive\"\n\
         reference = {{ energy = \"ehret-bol-itskov\" }}\nstretch = {{ from = 1.0, to = 1.5, step = 0.1 }}\n\
         free = [\"alpha\", \"w0\"]\n\n\
         [[study]]\nkind = \"stability\"\nname = \"{other}\"\nstretch = [1.0, 1.1]\n\
         laws = [\"implicit\"]\nnormals = 10\n"
    )
}

#[test]
fn a_name_too_long_for_a_file_name_is_refused_when_the_scene_is_read() {
    let name = "a".repeat(250);
    let e = Scene::parse(&fit_and_stability(&name, "stability"), FILE)
        .expect_err("a 250-character name");
    let shown = e.to_string();
    assert!(
        shown.starts_with(&format!("{FILE}:3: study[0].name")),
        "{shown}"
    );
    assert!(
        shown.contains("250 characters") && shown.contains("at most 100") && shown.contains("255"),
        "{shown}"
    );
    assert!(shown.len() < 600, "the name is not repeated whole: {shown}");
    // `check` says so too, and `run` computes nothing and writes nothing.
    let dir = scratch("long-name");
    let scene = dir.join("long.toml");
    std::fs::write(&scene, fit_and_stability(&name, "stability")).expect("write scene");
    let check = run_args(&["check".as_ref(), scene.as_os_str()]);
    assert_eq!(check.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&check.stderr).contains("study[0].name"));
    let out = dir.join("out");
    let run = run_args(&[
        "run".as_ref(),
        scene.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert_eq!(run.status.code(), Some(1));
    assert!(run.stdout.is_empty(), "computed before refusing");
    assert!(!out.exists());
}

/// The cap is in bytes of the file name: 100 ASCII letters pass, 34 Cyrillic letters
/// (68 bytes) pass, 51 (102 bytes) do not.
#[test]
fn the_cap_counts_the_bytes_of_the_file_name() {
    assert!(Scene::parse(&fit_and_stability(&"b".repeat(100), &"c".repeat(100)), FILE).is_ok());
    assert!(Scene::parse(&fit_and_stability(&"б".repeat(34), "s"), FILE).is_ok());
    let e = Scene::parse(&fit_and_stability(&"б".repeat(51), "s"), FILE).expect_err("102 bytes");
    assert!(e.to_string().contains("102 bytes"), "{e}");
}

/// The longest name allowed writes every file of a fit and a stability study: no file name
/// reaches 255 bytes.
#[test]
fn the_longest_name_allowed_runs_and_writes_its_files() {
    let name = "n".repeat(100);
    let other = "s".repeat(100);
    let dir = scratch("longest-name");
    let scene = dir.join("longest.toml");
    std::fs::write(&scene, fit_and_stability(&name, &other)).expect("write scene");
    let out = dir.join("out");
    let run = run_args(&[
        "run".as_ref(),
        scene.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert_eq!(
        run.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let files: Vec<String> = std::fs::read_dir(&out)
        .expect("list")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    for stem in [format!("fig_fit_{name}"), format!("fig_stability_{other}")] {
        for ext in ["png", "svg"] {
            let file = format!("{stem}.{ext}");
            assert!(files.contains(&file), "{file} missing: {files:?}");
        }
    }
}

/// Letters and digits of any script make a name (they were refused: "needs at least one letter
/// or digit"); ASCII names keep the file names they had.
#[test]
fn names_in_any_script_are_names() {
    for (name, file) in [
        ("Мышца", "мышца"),
        ("筋肉", "筋肉"),
        ("μ", "μ"),
        ("Muskel ß 2", "muskel_ß_2"),
    ] {
        assert_eq!(slug(name), file, "{name}");
        let text =
            format!("[[study]]\nkind = \"uniaxial\"\nname = \"{name}\"\nstretch = [1.0, 1.1]\n");
        let scene = Scene::parse(&text, FILE).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(scene.studies[0].name(), name);
    }
    for (name, file) in [
        ("cyl A", "cyl_a"),
        ("  Fit: damage (d = 0.5)  ", "fit_damage_d_0_5"),
        ("stability along fibres", "stability_along_fibres"),
    ] {
        assert_eq!(slug(name), file, "{name}");
    }
    // Nothing but letters, digits and single inner `_`: no separator, control character or
    // leading dot survives.
    assert_eq!(slug("../μ/x\\y\u{0}\n.z"), "μ_x_y_z");
    assert_eq!(slug(".hidden"), "hidden");
    assert_eq!(slug("---"), "");
    // Case is ignored in any script (one file on a case-insensitive file system): refused.
    let e = Scene::parse(
        "[[study]]\nkind = \"uniaxial\"\nname = \"Мышца\"\nstretch = [1.0]\n\
         [[study]]\nkind = \"uniaxial\"\nname = \"мышца\"\nstretch = [1.0]\n",
        FILE,
    )
    .expect_err("one output name");
    assert!(e.to_string().contains("both give the output name"), "{e}");
}

/// A run of studies named in three scripts writes their figures under those names.
#[test]
fn studies_named_in_other_scripts_run_and_name_their_figures() {
    let dir = scratch("unicode-names");
    let scene = dir.join("names.toml");
    let mut text = String::new();
    for name in ["Мышца", "筋肉", "μ"] {
        text.push_str(&format!(
            "[[study]]\nkind = \"stability\"\nname = \"{name}\"\nstretch = [1.0, 1.1]\nlaws = [\"implicit\"]\nnormals = 10\n"
        ));
    }
    std::fs::write(&scene, text).expect("write scene");
    let out = dir.join("out");
    let run = run_args(&[
        "run".as_ref(),
        scene.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert_eq!(
        run.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    for file in ["мышца", "筋肉", "μ"] {
        let png = out.join(format!("fig_stability_{file}.png"));
        assert!(png.is_file(), "{}", png.display());
    }
}
