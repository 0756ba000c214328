//! Fits from a scene, through the binary as a user runs it: unusable data files are named with
//! their line, a fit that does not converge is reported as such and the run goes on, and the
//! writers refuse non-finite numbers.

use activemuscle::active::Approach;
use activemuscle::models::{CouplingKind, LawKind, ModelChoice};
use activemuscle::output::csv::table_csv;
use activemuscle::studies::fit::{FitKind, FitOutcome};
use activemuscle::studies::outputs::KindOutput;
use activemuscle::studies::stability::{StabilityCurve, StabilityPoint};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::scratch;
use scratch::{scratch, Scratch};

const BIN: &str = env!("CARGO_BIN_EXE_activemuscle");

fn dir(name: &str) -> Scratch {
    scratch(&format!("cli-fit-{name}"))
}

/// Writes `data.csv` and a scene that fits the damage to it; returns the scene path.
fn damage_scene(d: &Path, data: &str, extra: &str) -> PathBuf {
    std::fs::write(d.join("weak.csv"), data).expect("write data");
    let scene = d.join("scene.toml");
    std::fs::write(
        &scene,
        format!("[[study]]\nkind = \"fit\"\nfit = \"damage\"\ndata = \"weak.csv\"\n{extra}"),
    )
    .expect("write scene");
    scene
}

fn run(args: &[&std::ffi::OsStr]) -> Output {
    Command::new(BIN).args(args).output().expect("run binary")
}

fn check_fails_naming(name: &str, data: &str, needles: &[&str]) {
    let d = dir(name);
    let scene = damage_scene(&d, data, "");
    let out = run(&["check".as_ref(), scene.as_os_str()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{name}: accepted; stderr {err}");
    for n in ["scene.toml", "study[0].data", "weak.csv"]
        .iter()
        .chain(needles)
    {
        assert!(err.contains(n), "{name}: message lacks {n:?}: {err}");
    }
}

#[test]
fn unusable_data_files_are_named_with_the_line() {
    let head = "lambda,P\n0.9,40.0\n1.0,50.0\n";
    check_fails_naming(
        "nan",
        &format!("{head}1.1,NaN\n1.2,60\n"),
        &["line 4", "not a finite number"],
    );
    check_fails_naming(
        "text",
        &format!("{head}1.1,strong\n"),
        &["line 4", "\"strong\"", "not a number"],
    );
    check_fails_naming(
        "duplicate",
        &format!("{head}1.0,51\n"),
        &["line 4", "repeats"],
    );
    check_fails_naming(
        "decreasing",
        &format!("{head}0.95,51\n"),
        &["line 4", "must increase"],
    );
    check_fails_naming("header", "stretch,stress\n1,2\n", &["line 1", "lambda,P"]);
    check_fails_naming(
        "too_few",
        "lambda,P\n1.0,50\n",
        &["1 points", "need at least 2"],
    );
    // The same message when running, and nothing is written.
    let d = dir("run_nan");
    let scene = damage_scene(&d, &format!("{head}1.1,nan\n1.2,60\n"), "");
    let out_dir = d.join("out");
    let out = run(&[
        "run".as_ref(),
        scene.as_os_str(),
        "--out".as_ref(),
        out_dir.as_os_str(),
        "--quiet".as_ref(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("weak.csv") && err.contains("line 4"),
        "{err}"
    );
    assert!(!out_dir.join("fits.csv").exists());
}

#[test]
fn fit_rules_name_the_key_value_and_rule() {
    let d = dir("rules");
    let data = "lambda,P\n0.9,40\n1.0,50\n1.1,60\n";
    for (extra, needles) in [
        (
            "free = [\"alpha\"]\n",
            vec!["study[0].free[0]", "\"alpha\"", "not a parameter"],
        ),
        (
            "start = { d = 2.0 }\nbounds = { d = [0.0, 1.0] }\n",
            vec!["study[0].start.d", "2", "bounds.d"],
        ),
        (
            "bounds = { d = [1.0, 0.0] }\n",
            vec!["study[0].bounds.d", "lower < upper"],
        ),
        ("noise = -1.0\n", vec!["study[0].noise", "-1", "≥ 0"]),
        (
            "stretch = [1.0, 1.1]\n",
            vec!["study[0].stretch", "remove stretch"],
        ),
        (
            "laws = [\"implicit\"]\n",
            vec!["study[0].laws", "not a key of a fit"],
        ),
    ] {
        let scene = damage_scene(&d, data, extra);
        let out = run(&["check".as_ref(), scene.as_os_str()]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{extra}: accepted");
        for n in needles {
            assert!(err.contains(n), "{extra}: message lacks {n:?}: {err}");
        }
    }
}

#[test]
fn a_fit_from_a_data_file_is_reported_and_one_that_does_not_converge_says_so() {
    let d = dir("ok");
    // P_pas + (1 − 0.3) P_act of the chapter's muscle, read from the library, in a file.
    let muscle = activemuscle::Muscle::passive(activemuscle::energy::GiantesioMusesti::paper());
    let curve = activemuscle::active::ActiveCurve::paper();
    let mut text = String::from("lambda,P\n");
    for i in 0..16 {
        let l = 0.8 + 0.04 * i as f64;
        let p = activemuscle::uniaxial::along_fibres(&muscle, l)
            .expect("passive")
            .stress
            + 0.7 * curve.value(l);
        text.push_str(&format!("{l},{p}\n"));
    }
    // The second study cannot converge in one Gauss–Newton iteration from a far start on the
    // nonlinear active-curve fit.
    let scene = damage_scene(
        &d,
        &text,
        "\n[[study]]\nkind = \"fit\"\nname = \"hopeless\"\nfit = \"active-curve\"\nstretch = { from = 0.7, to = 1.5, step = 0.05 }\n\
         start = { lambda_min = 0.3, lambda_opt = 1.6, k = 3.0 }\nmax_iterations = 1\n",
    );
    let out_dir = d.join("out");
    let out = run(&[
        "run".as_ref(),
        scene.as_os_str(),
        "--out".as_ref(),
        out_dir.as_os_str(),
        "--quiet".as_ref(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    // The run goes on and writes everything, but it did not compute everything: exit 3.
    assert_eq!(
        out.status.code(),
        Some(3),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("FAILED: hopeless") && stdout.contains("NOT a solution"),
        "{stdout}"
    );
    let csv = std::fs::read_to_string(out_dir.join("fits.csv")).expect("fits.csv");
    let rows: Vec<&str> = csv.lines().collect();
    assert!(rows[0].starts_with("study,fit,case,parameter,value,standard_error"));
    let d_row = rows
        .iter()
        .find(|r| r.contains(",damage,"))
        .expect("damage row");
    let cells: Vec<&str> = d_row.split(',').collect();
    let fitted: f64 = cells[4].parse().expect("number");
    assert!((fitted - 0.3).abs() < 1e-8, "{d_row}");
    assert!(d_row.contains(",true,"), "{d_row}");
    assert!(
        rows.iter()
            .filter(|r| r.contains("hopeless"))
            .all(|r| r.contains(",false,")),
        "{csv}"
    );
    let report = std::fs::read_to_string(out_dir.join("report.html")).expect("report");
    assert!(report.contains("NOT converged") && report.contains("<h2>Fits</h2>"));
    assert!(out_dir.join("fig_fit_damage.png").exists());
}

#[test]
fn writers_refuse_non_finite_numbers_and_say_where() {
    let fit = FitOutcome {
        kind: FitKind::Damage,
        case: "true d = 0.3".into(),
        source: String::new(),
        points: 10,
        names: vec!["d".into()],
        values: vec![f64::NAN],
        standard_errors: vec![None],
        reference: vec![None],
        correlation: vec![vec![None]],
        rms: 0.0,
        unit: "kPa",
        residual_norm: 0.0,
        iterations: 1,
        converged: false,
        termination: String::new(),
        extra: vec![],
        plot: Default::default(),
        at_bound: vec![None],
        weights: activemuscle::studies::fit::WeightsKind::Equal,
        sigma: None,
        residuals: vec![],
    };
    let written = |tables: Vec<activemuscle::studies::outputs::OwnTable>| {
        let t = &tables[0];
        table_csv(&t.file, &[&t.table])
    };
    let e = written(vec![fit].tables("my fit"))
        .expect_err("NaN written")
        .to_string();
    assert!(
        e.contains("value = NaN")
            && e.contains("fits.csv, row 1")
            && e.contains("study = my fit")
            && e.contains("parameter = d"),
        "{e}"
    );
    let curve = StabilityCurve {
        approach: Approach::ActiveStrain,
        model: Some(ModelChoice {
            approach: activemuscle::active::Approach::ActiveStrain,
            law: LawKind::Implicit,
            coupling: CouplingKind::Frozen,
            damage: 0.5,
        }),
        points: vec![StabilityPoint {
            lambda: 1.2,
            stress: 10.0,
            cauchy: 12.0,
            slope: f64::INFINITY,
            least: 1.0,
            relative: 1.0,
            elliptic: true,
            outside: None,
        }],
    };
    let e = written(vec![curve].tables("map"))
        .expect_err("inf written")
        .to_string();
    assert!(
        e.contains("dP_dlambda = inf")
            && e.contains("law = implicit, coupling = frozen")
            && e.contains("lambda = 1.2"),
        "{e}"
    );
}

/// Issue 11's reproducer, which hung in argmin's backtracking line search: a passive fit on
/// P = 0.08 λ² for λ in [1, 5]. The run finishes (killed and failed after 120 s otherwise),
/// writes fits.csv with the fit's converged flag, and says in words why the fit did not converge
/// — never that a solver "converged".
#[test]
fn the_fit_that_hung_finishes_and_reports_why_it_did_not_converge() {
    let d = dir("hang");
    let mut data = String::from("lambda,P\n");
    for i in 0..=30 {
        let l = 1.0 + 4.0 * i as f64 / 30.0;
        data.push_str(&format!("{l},{}\n", 0.08 * l * l));
    }
    std::fs::write(d.join("p.csv"), data).expect("write data");
    let scene = d.join("fit.toml");
    std::fs::write(
        &scene,
        "title = \"fit hang\"\n[[study]]\nkind = \"fit\"\nname = \"passive\"\nfit = \"passive\"\ndata = \"p.csv\"\n",
    )
    .expect("write scene");
    let out_dir = d.join("out");
    let mut child = Command::new(BIN)
        .args([
            "run".as_ref(),
            scene.as_os_str(),
            "--out".as_ref(),
            out_dir.as_os_str(),
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run binary");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
    while child.try_wait().expect("wait").is_none() {
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("the run did not finish within 120 s");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let out = child.wait_with_output().expect("output");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(out_dir.join("fits.csv")).expect("fits.csv written");
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(rows.len(), 2, "{csv}");
    let converged = rows.iter().all(|r| r.contains(",true,"));
    if !converged {
        assert!(rows.iter().all(|r| r.contains(",false,")), "{csv}");
        assert!(
            text.contains("did not converge: the least-squares minimum lies beyond the bounds")
                && text.contains("best point found"),
            "{text}"
        );
    }
    assert!(!text.to_lowercase().contains("solver converged"), "{text}");
}
