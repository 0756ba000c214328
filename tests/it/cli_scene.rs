//! Every kind of bad scene input gives a non-zero exit and a message naming the file, the key,
//! the value and the rule; the binary is run as a user runs it.

use std::ffi::OsStr;
use std::path::PathBuf;
use std::process::Command;

use crate::scratch;
use scratch::{scratch, Scratch};

const BIN: &str = env!("CARGO_BIN_EXE_activemuscle");

const STUDY: &str = "[[study]]\nkind = \"uniaxial\"\nstretch = [1.0, 1.1]\n";

/// Writes `text` to `NAME.toml` in a fresh scratch directory; returns the directory (removed
/// when dropped) and the file.
fn scene_file(name: &str, text: &str) -> (Scratch, PathBuf) {
    let dir = scratch(&format!("cli-scene-{name}"));
    let p = dir.join(format!("{name}.toml"));
    std::fs::write(&p, text).expect("write scene");
    (dir, p)
}

/// Runs the binary with `args`; asserts success and returns its standard output.
fn succeeds(args: &[&OsStr]) -> String {
    let out = Command::new(BIN).args(args).output().expect("run binary");
    assert!(
        out.status.success(),
        "{:?}: {}",
        args,
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Runs `check` on `text`; asserts failure and that stderr names the file and every `needle`.
fn rejected(name: &str, text: &str, needles: &[&str]) {
    let (_dir, path) = scene_file(name, text);
    let out = Command::new(BIN)
        .arg("check")
        .arg(&path)
        .output()
        .expect("run binary");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success(),
        "{name}: accepted a bad scene; stderr: {err}"
    );
    assert!(
        err.contains(&format!("{name}.toml")),
        "{name}: message does not name the file: {err}"
    );
    for n in needles {
        assert!(err.contains(n), "{name}: message lacks {n:?}: {err}");
    }
}

#[test]
fn a_valid_scene_is_accepted_and_printed_resolved() {
    let (_dir, path) = scene_file("valid", STUDY);
    let text = succeeds(&["check".as_ref(), path.as_ref()]);
    // Defaults are the chapter's values.
    for v in [
        "mu = 0.1599",
        "alpha = 19.35",
        "w0 = 0.7335",
        "lambda_min = 0.6243",
        "p_opt = 73.52",
        "a = 1.0133",
    ] {
        assert!(text.contains(v), "resolved scene lacks {v}: {text}");
    }
}

#[test]
fn the_shipped_paper_scene_is_valid() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/paper.toml");
    succeeds(&["check".as_ref(), path.as_ref()]);
}

#[test]
fn unknown_keys_are_named_with_their_path() {
    rejected(
        "unknown_key",
        &format!("[material]\nmuu = 1.0\n{STUDY}"),
        &["material.muu", "unknown field"],
    );
    rejected(
        "unknown_study_key",
        "[[study]]\nkind = \"uniaxial\"\nstretch = [1.0]\nnz_typo = 3\n",
        &["study[0].nz_typo"],
    );
    rejected(
        "unknown_range_key",
        "[[study]]\nkind = \"uniaxial\"\nstretch = { from = 0.8, to = 1.2, stepp = 0.1 }\n",
        &["study[0].stretch.stepp"],
    );
}

#[test]
fn wrong_types_are_named_with_key_and_value() {
    rejected(
        "wrong_type",
        "[[study]]\nkind = \"cylinder\"\nstretch = [1.1]\nnr = \"six\"\n",
        &["study[0].nr", "\"six\""],
    );
    rejected(
        "unknown_law",
        &format!("[activation]\nlaw = \"magic\"\n{STUDY}"),
        &["activation.law", "magic"],
    );
}

#[test]
fn activation_of_one_or_more_is_rejected() {
    rejected(
        "gamma_one",
        "[[study]]\nkind = \"uniaxial\"\nstretch = [1.0]\nconstant_gamma = [0.2, 1.0]\n",
        &["study[0].constant_gamma[1]", "= 1", "[0, 1)"],
    );
}

#[test]
fn damage_outside_the_unit_interval_is_rejected() {
    rejected(
        "damage",
        "[[study]]\nkind = \"uniaxial\"\nstretch = [1.0]\nlaws = [\"implicit\"]\ndamage = [0.0, 1.5]\n",
        &["study[0].damage[1]", "1.5", "[0, 1]"],
    );
    rejected(
        "damage_default",
        &format!("[activation]\ndamage = [-0.1]\n{STUDY}"),
        &["activation.damage[0]", "-0.1"],
    );
}

#[test]
fn inconsistent_active_curve_is_rejected() {
    rejected(
        "lambda_min",
        &format!("[activation]\nlambda_min = 1.2\n{STUDY}"),
        &["activation.lambda_opt", "1.1704", "lambda_min"],
    );
}

#[test]
fn energy_parameters_out_of_range_are_rejected() {
    rejected(
        "w0",
        &format!("[material]\nw0 = 1.0\n{STUDY}"),
        &["material.w0", "= 1", "(0, 1)"],
    );
    rejected(
        "mu",
        &format!("[material]\nmu = -2\n{STUDY}"),
        &["material.mu", "-2", "> 0"],
    );
    rejected(
        "beta_on_gm",
        &format!("[material]\nbeta = 1.0\n{STUDY}"),
        &["material.beta", "giantesio-musesti"],
    );
}

#[test]
fn empty_or_broken_stretch_lists_are_rejected() {
    rejected(
        "empty_stretch",
        "[[study]]\nkind = \"uniaxial\"\nstretch = []\n",
        &["study[0].stretch", "empty"],
    );
    rejected(
        "negative_stretch",
        "[[study]]\nkind = \"uniaxial\"\nstretch = [1.0, -0.5]\n",
        &["study[0].stretch", "-0.5"],
    );
    rejected(
        "range_step",
        "[[study]]\nkind = \"uniaxial\"\nstretch = { from = 0.8, to = 1.25, step = 0.1 }\n",
        &["study[0].stretch.step", "0.1", "whole steps"],
    );
    rejected(
        "missing_stretch",
        "[[study]]\nkind = \"uniaxial\"\n",
        &["study[0].stretch", "missing"],
    );
}

#[test]
fn cylinder_rules_are_enforced() {
    let cyl = "[[study]]\nkind = \"cylinder\"\nstretch = [0.9, 1.1]\n";
    rejected(
        "nr_zero",
        &format!("{cyl}nr = 0\n"),
        &["study[0].nr", "= 0", "[1, 10000]"],
    );
    rejected(
        "grading",
        &format!("{cyl}grading = 0.5\n"),
        &["study[0].grading", "0.5", "≥ 1"],
    );
    rejected(
        "radius",
        &format!("{cyl}radius = 0\n"),
        &["study[0].radius", "> 0"],
    );
    rejected(
        "vtk",
        &format!("{cyl}vtk = [1.17]\n"),
        &["study[0].vtk[0]", "1.17", "computed stretches"],
    );
    rejected(
        "laws_on_cylinder",
        &format!("{cyl}laws = [\"explicit\"]\n"),
        &["study[0].laws", "cylinder"],
    );
    rejected(
        "explicit_needs_gm",
        &format!("[material]\nenergy = \"ehret-bol-itskov\"\n{cyl}law = \"explicit\"\n"),
        &["study[0].law", "explicit", "giantesio-musesti"],
    );
}

#[test]
fn a_scene_without_studies_or_file_is_rejected() {
    rejected(
        "no_study",
        "title = \"nothing\"\n",
        &["study", "at least one"],
    );
    let out = Command::new(BIN)
        .args(["check", "/nonexistent/scene.toml"])
        .output()
        .expect("run binary");
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("/nonexistent/scene.toml"));
}

#[test]
fn a_failed_run_leaves_no_outputs() {
    let (tmp, path) = scene_file("run_bad", "[[study]]\nkind = \"uniaxial\"\nstretch = []\n");
    let dir = tmp.join("out");
    let out = Command::new(BIN)
        .arg("run")
        .arg(&path)
        .arg("--out")
        .arg(&dir)
        .arg("--quiet")
        .output()
        .expect("run binary");
    assert!(!out.status.success());
    assert!(!dir.join("curves.csv").exists() && !dir.join("report.html").exists());
}

const TRADEOFF: &str =
    "[[study]]\nkind = \"tradeoff\"\noptions = [\"activation-law\"]\nstretch = [1.0, 1.1, 1.2]\n";

#[test]
fn tradeoff_takes_a_scene_and_measures_only_its_options() {
    let (tmp, path) = scene_file("tradeoff", TRADEOFF);
    let dir = tmp.join("out");
    succeeds(&[
        "tradeoff".as_ref(),
        path.as_ref(),
        "--out".as_ref(),
        dir.as_ref(),
        "--quiet".as_ref(),
    ]);
    let csv = std::fs::read_to_string(dir.join("tradeoff.csv")).expect("tradeoff.csv");
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(rows.len(), 3, "{csv}");
    assert!(rows.iter().all(|r| r.starts_with("activation law (0D),")));
    assert!(rows[0].contains("3 stretches"), "{csv}");
    for f in [
        "tradeoff.md",
        "tradeoff.html",
        "tradeoff_activation_law_0d.png",
        "tradeoff_activation_law_0d.svg",
    ] {
        assert!(dir.join(f).exists(), "{f} missing");
    }
    assert!(!dir.join("tradeoff_mesh_clamped.png").exists());
}

#[test]
fn a_tradeoff_study_writes_its_table_and_figures_into_the_run_and_its_report() {
    let (tmp, path) = scene_file(
        "tradeoff_run",
        &format!("{TRADEOFF}\n[[study]]\nkind = \"uniaxial\"\nstretch = [1.0, 1.1]\n"),
    );
    let dir = tmp.join("out");
    succeeds(&[
        "run".as_ref(),
        path.as_ref(),
        "--out".as_ref(),
        dir.as_ref(),
        "--quiet".as_ref(),
    ]);
    for f in [
        "tradeoff.csv",
        "tradeoff.md",
        "tradeoff_activation_law_0d.png",
        "curves.csv",
    ] {
        assert!(dir.join(f).exists(), "{f} missing");
    }
    let report = std::fs::read_to_string(dir.join("report.html")).expect("report.html");
    for needle in [
        "Speed versus accuracy: activation law (0D)",
        "activation law (0D) · explicit (frozen)",
        "Explicit law (0D, 3 stretches)",
        "tradeoff.csv",
    ] {
        assert!(report.contains(needle), "report lacks {needle:?}");
    }
}

/// The shipped trade-off scene checks, and its comment names every option group a user can ask
/// for ([`OptionGroup::ALL`]), each on a line of its own.
#[test]
fn the_shipped_tradeoff_scene_is_valid_and_names_every_option_group() {
    use activemuscle::studies::tradeoff::OptionGroup;
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/tradeoff.toml");
    succeeds(&["check".as_ref(), path.as_ref()]);
    let text = std::fs::read_to_string(path).unwrap();
    for group in OptionGroup::ALL {
        let line = format!("#   \"{}\" ", group.key());
        assert!(
            text.contains(&line),
            "scenes/tradeoff.toml does not describe {line:?}"
        );
    }
}

#[test]
fn check_prints_the_parameters_of_the_energies_that_run() {
    use activemuscle::energy::{EhretBolItskov, GiantesioMusesti};
    use activemuscle::models::EnergySpec;
    use activemuscle::scene::SceneSpec;
    use activemuscle::studies::StudySpec;
    let (_dir, path) = scene_file(
        "energies",
        "[material]\nenergy = \"ehret-bol-itskov\"\nmu = 0.2\nalpha = 15.0\nbeta = 2.0\nw0 = 0.6\n\
         [[study]]\nkind = \"uniaxial\"\nstretch = [1.0, 1.1]\n\
         compare = [{ energy = \"ehret-bol-itskov\", alpha = 10.0 }, { energy = \"giantesio-musesti\" }]\n\
         [[study]]\nkind = \"fit\"\nfit = \"passive\"\nstretch = [1.0, 1.1, 1.2, 1.3]\n\
         reference = { energy = \"ehret-bol-itskov\", beta = 3.0 }\n",
    );
    let stdout = succeeds(&["check".as_ref(), path.as_ref()]);
    // The printout is a scene the reader reads back.
    let printed: SceneSpec = activemuscle::scene::Scene::parse(&stdout, "printed.toml")
        .expect("check prints a scene")
        .resolved;
    // Every parameter, by name (a TOML table has no order).
    let sorted = |mut p: Vec<(String, f64)>| {
        p.sort_by(|a, b| a.0.cmp(&b.0));
        p
    };
    let values = |e: &EnergySpec| (e.energy.clone(), sorted(e.parameters.clone()));
    let named = |name: &str, v: &[(&str, f64)]| {
        let p = v.iter().map(|(n, x)| (n.to_string(), *x)).collect();
        (name.to_string(), sorted(p))
    };
    assert_eq!(
        values(&printed.material.energy),
        named(
            "ehret-bol-itskov",
            &[("mu", 0.2), ("alpha", 15.0), ("beta", 2.0), ("w0", 0.6)]
        )
    );
    // What is left out is the chapter's value, as the library states it.
    let (ebi, gm) = (EhretBolItskov::paper(), GiantesioMusesti::paper());
    let StudySpec::Uniaxial(uniaxial) = &printed.studies[0] else {
        panic!("study 0 is uniaxial: {:?}", printed.studies[0]);
    };
    let compare = uniaxial.compare.as_ref().expect("compare printed");
    assert_eq!(
        values(&compare[0]),
        named(
            "ehret-bol-itskov",
            &[
                ("mu", ebi.mu()),
                ("alpha", 10.0),
                ("beta", ebi.beta()),
                ("w0", ebi.w0())
            ]
        )
    );
    assert_eq!(
        values(&compare[1]),
        named(
            "giantesio-musesti",
            &[("mu", gm.mu()), ("alpha", gm.alpha()), ("w0", gm.w0())]
        )
    );
    let StudySpec::Fit(fit) = &printed.studies[1] else {
        panic!("study 1 is a fit: {:?}", printed.studies[1]);
    };
    let reference = fit.reference.as_ref().expect("reference");
    assert_eq!(
        values(reference),
        named(
            "ehret-bol-itskov",
            &[
                ("mu", ebi.mu()),
                ("alpha", ebi.alpha()),
                ("beta", 3.0),
                ("w0", ebi.w0())
            ]
        )
    );
}

#[test]
fn a_bad_tradeoff_study_is_named_with_file_line_key_value_and_rule() {
    rejected(
        "tradeoff_meshes",
        "[[study]]\nkind = \"tradeoff\"\nmeshes = [[4, 16], [2, 8]]\n",
        &[
            "tradeoff_meshes.toml:3: study[0].meshes[1] = [2, 8]",
            "coarse to fine",
        ],
    );
    rejected(
        "tradeoff_option",
        "[[study]]\nkind = \"tradeoff\"\noptions = [\"mesh\", \"quadrature\"]\n",
        &[
            "tradeoff_option.toml:3: study[0].options",
            "quadrature",
            "activation-law-fe",
        ],
    );
}

/// `element = "Q1/P0"` reaches the solver: on sliding bases the FE reproduces the 0D curve (the
/// run's own verification line) with the Q1/P0 dof count; an unknown element is named.
#[test]
fn a_cylinder_study_chooses_its_element() {
    let (tmp, path) = scene_file(
        "q1p0",
        "[[study]]\nkind = \"cylinder\"\nbases = \"sliding\"\nelement = \"Q1/P0\"\nnr = 3\nnz = 6\nlaw = \"explicit\"\nstretch = [0.9, 1.0, 1.17]\n",
    );
    let dir = tmp.join("out");
    let stdout = succeeds(&[
        OsStr::new("run"),
        path.as_os_str(),
        OsStr::new("--out"),
        dir.as_os_str(),
        OsStr::new("--quiet"),
    ]);
    let line = stdout
        .lines()
        .find(|l| l.contains("max |P_FE − P_0D| = "))
        .expect("verification line");
    let err: f64 = line
        .split("max |P_FE − P_0D| = ")
        .nth(1)
        .and_then(|t| t.split_whitespace().next())
        .and_then(|t| t.parse().ok())
        .expect("a number");
    assert!(err < 1e-8, "{line}");
    let report = std::fs::read_to_string(dir.join("report.html")).expect("report");
    assert!(
        report.contains("3 × 6 Q1/P0 cells"),
        "element named in the report"
    );
    // Q1/P0 on 3 × 6 cells, sliding: 4 × 7 nodes, u_r fixed on the axis (7), u_z on both bases
    // (8), 18 cell pressures → 56 − 15 + 18 = 59 free dofs.
    assert!(report.contains("59 dofs"), "Q1/P0 dof count");
    rejected(
        "element",
        "[[study]]\nkind = \"cylinder\"\nstretch = [0.9, 1.0]\nelement = \"Q3\"\n",
        &["element.toml:4", "study[0].element", "Q3", "Q1/P0"],
    );
}

/// `activemuscle check scene.toml | head -1`: the reader goes away, the command does not panic
/// on the broken pipe (it used to, exit 101).
#[test]
fn a_closed_standard_output_is_no_panic() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/paper.toml");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_activemuscle"))
        .args(["check", path])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("runs");
    drop(child.stdout.take());
    let out = child.wait_with_output().expect("waits");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(out.status.code(), Some(0), "{stderr}");
}
