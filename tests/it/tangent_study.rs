//! The tangent study kind through a scene and the `tangent` command: its tables (one row per
//! model, state, direction and step; one per model and state), a state no model can evaluate as
//! a flagged row without a NaN, the FE level's tables, bad input refused at its key.

use crate::binary::{run_args, run_quiet};
use crate::scratch::scratch;
use activemuscle::output::csv::files;
use activemuscle::scene::{RunOptions, Scene};
use activemuscle::studies::StudyResult;

const FILE: &str = "tangent.toml";

const SCENE: &str = r#"
[activation]
law = "explicit"
coupling = "frozen"
damage = [0.0]

[[study]]
kind = "tangent"
uniaxial_along = [1.1]
deformations = [[1.1, 0.05, 0.0, 0.0, 0.95, 0.02, 0.0, -0.03, 0.96], [10.0, 0, 0, 0, 0.31622776601683794, 0, 0, 0, 0.31622776601683794]]
random_states = 1
near_lambda_min = 1
random_directions = 1
laws = ["explicit"]
couplings = ["frozen"]
h = { largest = 0.015625, smallest = 6.103515625e-5 }
"#;

/// The rows of a CSV file's text, header included.
fn rows(text: &str) -> Vec<Vec<String>> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(text.as_bytes());
    reader
        .records()
        .map(|r| r.unwrap().iter().map(str::to_string).collect())
        .collect()
}

#[test]
fn a_tangent_study_writes_its_tables_and_flags_what_it_cannot_evaluate() {
    let scene = Scene::parse(SCENE, FILE).unwrap();
    let results = scene.run(&RunOptions::default());
    let outcome = &results.studies[0];
    assert!(outcome.failures.is_empty(), "{:?}", outcome.failures);
    let StudyResult::Tangent(r) = &outcome.result else {
        panic!("not a tangent result")
    };
    // Passive and one active model; 5 states; 1 direction; h = 2⁻⁶ … 2⁻¹⁴.
    assert_eq!(
        (
            r.models.len(),
            r.states.len(),
            r.directions.len(),
            r.h.len()
        ),
        (2, 5, 1, 9)
    );
    let files = files(&results);
    let text = |name: &str| {
        let file = files
            .iter()
            .find(|f| f.file == name)
            .unwrap_or_else(|| panic!("{name}"));
        String::from_utf8(file.bytes().unwrap()).unwrap()
    };
    let summary = rows(&text("tangent_summary.csv"));
    assert_eq!(summary.len(), 1 + 2 * 5);
    let column = |name: &str| {
        summary[0]
            .iter()
            .position(|c| c == name)
            .unwrap_or_else(|| panic!("{name}"))
    };
    // λ = 10 along the fibres overflows the chapter's exponential: a flagged row, its numbers empty.
    let overflow: Vec<&Vec<String>> = summary
        .iter()
        .filter(|r| r[column("state")] == "given 2")
        .collect();
    assert_eq!(overflow.len(), 2);
    for row in overflow {
        assert_eq!(row[column("flag")], "not-evaluable");
        assert!(row[column("order_1")].is_empty() && row[column("fd_error")].is_empty());
    }
    // Every number written is finite (the words of a reason may say "inf").
    let words = [
        "study",
        "energy",
        "approach",
        "law",
        "coupling",
        "state",
        "asymmetry_reason",
        "flag",
        "reason",
        "note",
    ];
    for row in summary.iter().skip(1) {
        for (name, value) in summary[0].iter().zip(row) {
            if !words.contains(&name.as_str()) && !value.is_empty() {
                let number = value.parse::<f64>();
                assert!(number.is_ok_and(f64::is_finite), "{name} = {value}");
            }
        }
    }
    // Every other state passes with order 2 (no flag) or is flagged with a cause.
    for row in summary
        .iter()
        .skip(1)
        .filter(|r| r[column("state")] != "given 2")
    {
        if row[column("flag")].is_empty() {
            let order: f64 = row[column("order_1")].parse().unwrap_or(2.0);
            assert!(order > 1.5, "{row:?}");
        } else {
            assert!(!row[column("reason")].is_empty(), "{row:?}");
        }
    }
    // tangent.csv: a row per model, evaluable state, direction and step.
    let remainders = rows(&text("tangent.csv"));
    assert_eq!(remainders.len(), 1 + 2 * 4 * 9);
    assert_eq!(&remainders[0][remainders[0].len() - 3..], ["h", "r0", "r1"]);
}

#[test]
fn bad_input_is_refused_at_its_key() {
    let study = |keys: &str| format!("[[study]]\nkind = \"tangent\"\n{keys}\n");
    let many = format!(
        "deformations = [{}]",
        ["[1, 0, 0, 0, 1, 0, 0, 0, 1]"; 201].join(", ")
    );
    for (keys, key) in [
        (many.as_str(), "states"),
        (
            "deformations = [[1, 0, 0, 0, 1, 0, 0, 0, -1]]",
            "deformations[0]",
        ),
        (
            "deformations = [[1, 0, 0, 0, nan, 0, 0, 0, 1]]",
            "deformations[0]",
        ),
        ("deformations = [[1, 0, 0, 0, 1]]", "deformations[0]"),
        ("h = { largest = 2.0, smallest = 1e-6 }", "h.largest"),
        ("h = { largest = 0.01, smallest = 0.0 }", "h.smallest"),
        (
            "deformations = [[1, 0, 0, 0, 0, 0, 0, 0, 1]]",
            "deformations[0]",
        ),
        (
            "deformations = [[1, 0, 0, 0, 1, 0, 0, 0, 1], [1, 0, 0, 0, inf, 0, 0, 0, 1]]",
            "deformations[1]",
        ),
        ("h = { largest = 1.0, smallest = 1e-6 }", "h.largest"),
        ("h = { largest = 0.01, smallest = -1e-6 }", "h.smallest"),
        ("h = { largest = 0.01, smallest = 0.005 }", "h.smallest"),
        ("random_states = 1000", "random_states"),
        ("random_states = -1", "random_states"),
        ("random_directions = 17", "random_directions"),
        (
            "uniaxial_along = { from = 0.5, to = 1.5, step = 0.004 }",
            "states",
        ),
        (
            "directions = [[0, 0, 0, 0, 0, 0, 0, 0, 0]]",
            "directions[0]",
        ),
        ("stretch_rates = [1.0]", "stretch_rates"),
        ("fe = { nr = 40 }", "fe.nr"),
        ("fe = { elements = [\"Q3\"] }", "fe.elements[0]"),
    ] {
        let e = Scene::parse(&study(keys), FILE).expect_err(keys);
        assert_eq!(e.key, format!("study[0].{key}"), "{keys}: {e}");
    }
}

/// A tangent study with a small FE level: one element, clamped bases, h = 2⁻⁶ … 2⁻¹⁴.
const FE_SCENE: &str = r#"
[activation]
law = "explicit"
coupling = "frozen"
[[study]]
kind = "tangent"
uniaxial_along = [1.1]
random_directions = 1
passive = false
couplings = ["frozen"]
laws = ["explicit"]
h = { largest = 0.015625, smallest = 6.103515625e-5 }
fe = { nr = 2, nz = 2, elements = ["Q1/P0"], bases = ["clamped"], stretch = 1.06 }
"#;

#[test]
fn the_fe_level_tables_hold_newton_with_each_tangent() {
    let scene = Scene::parse(FE_SCENE, FILE).unwrap();
    let results = scene.run(&RunOptions::default());
    let StudyResult::Tangent(r) = &results.studies[0].result else {
        panic!("not a tangent result")
    };
    let fe = r.fe.as_ref().unwrap();
    assert!(fe.failures.is_empty(), "{:?}", fe.failures);
    let c = &fe.configs[0];
    let names: Vec<&str> = c.newton.iter().map(|n| n.tangent).collect();
    assert_eq!(names, ["exact", "symmetric frozen", "finite differences"]);
    let iterations = |name: &str| {
        c.newton
            .iter()
            .find(|n| n.tangent == name)
            .unwrap()
            .residuals
            .len()
    };
    // Linear convergence takes more iterations than quadratic.
    assert!(
        iterations("symmetric frozen") > iterations("exact"),
        "{:?}",
        c.newton
    );
    for t in &c.taylor {
        let a = t.outcome.as_ref().unwrap();
        let last = a.u.orders_1.iter().flatten().last().copied().unwrap();
        let expected = if t.tangent == "symmetric frozen" {
            1.0
        } else {
            2.0
        };
        assert!(
            (last - expected).abs() < 0.2,
            "{} {}: {:?}",
            t.state,
            t.tangent,
            a.u.orders_1
        );
    }
    // What each tangent cost: the iterations are those the residual history takes to 1e-10.
    let costs = fe.costs();
    for n in &c.newton {
        let to_tolerance = n.residuals.iter().position(|&r| r <= 1e-10);
        let cost = costs.iter().find(|k| k.tangent == n.tangent).unwrap();
        assert_eq!(cost.iterations, to_tolerance.map(|k| (k, k)), "{n:?}");
        assert_eq!(cost.converged == 1, to_tolerance.is_some(), "{cost:?}");
        assert!(cost
            .seconds_per_iteration
            .is_some_and(|s| s > 0.0 && s.is_finite()));
    }
    let console = results.studies[0].result.console("t");
    assert!(
        console.iter().any(|l| l
            .starts_with("t: FE level, Newton from the predictor with the exact: ")
            && l.contains("ms to 1e-10")),
        "{console:?}"
    );
    let files = files(&results);
    for name in ["tangent_fe.csv", "tangent_newton.csv"] {
        assert!(files.iter().any(|f| f.file == name), "{name}");
    }
}

#[test]
fn the_tangent_command_checks_a_scenes_own_material() {
    let dir = scratch("tangent-command");
    let scene = dir.join("block.toml");
    std::fs::write(
        &scene,
        "[activation]\nlaw = \"explicit\"\ndamage = [0.0]\n[[study]]\nkind = \"uniaxial\"\nstretch = [1.0, 1.1]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let output = run_args(&[
        "tangent".as_ref(),
        scene.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    for f in [
        "tangent.csv",
        "tangent_summary.csv",
        "report.html",
        "scene.toml",
        "datapackage.json",
    ] {
        assert!(out.join(f).exists(), "{f}");
    }
    assert!(stdout.contains("order of r1"), "{stdout}");
    // What ran is a tangent study a user can run again.
    let ran = std::fs::read_to_string(out.join("scene.toml")).unwrap();
    assert!(Scene::parse(&ran, "scene.toml").is_ok(), "{ran}");
}

#[test]
fn the_example_scene_asks_for_every_approach_with_its_own_laws() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/examples/tangent_check.toml");
    let scene = Scene::load(&path).unwrap();
    let activemuscle::studies::Study::Tangent(t) = &scene.studies[0] else {
        panic!("not a tangent study")
    };
    // passive; active strain and structural: 2 laws × 2 couplings × 2 damages each; active
    // stress, which has no law: one per damage.
    assert_eq!(t.models.len(), 1 + 8 + 2 + 8);
    let active = t.models.iter().filter_map(|m| m.model);
    let active_stress = active.filter(|c| c.activation_law().is_none()).count();
    assert_eq!(active_stress, 2);
    // Its states: 2 given, 4 + 1 + 1 + 1 on paths, 4 + 4 + 2 random.
    assert_eq!(t.sources.len(), 19);
}

/// `tangent_fe.csv` as readers know it: its columns by name, in order, as its schema in
/// `datapackage.json` gives them; a row per configuration, state, tangent and step h = 2⁻⁶ …
/// 2⁻¹⁴; and in r0_u, r1_u the displacement rows' remainders as Taylor's theorem orders them:
/// r₀ falls as h, r₁ as h² with the exact tangent and as h with the symmetric approximation.
#[test]
fn tangent_fe_csv_keeps_its_columns_and_the_remainders_taylor_orders() {
    let dir = scratch("tangent-fe-columns");
    let scene = dir.join("fe.toml");
    std::fs::write(&scene, FE_SCENE).unwrap();
    let out = dir.join("out");
    run_quiet(Some(&scene), &out);
    let resources = crate::datapackage::the_data_obey_their_package(&out);
    assert!(
        resources.iter().any(|r| r == "tangent_fe.csv"),
        "{resources:?}"
    );
    let text = std::fs::read_to_string(out.join("tangent_fe.csv")).unwrap();
    assert_eq!(
        rows(&text)[0],
        [
            "study",
            "model",
            "element",
            "bases",
            "incompressibility",
            "state",
            "tangent",
            "h",
            "r0_u",
            "r1_u",
            "r0_p",
            "r1_p"
        ]
    );
    let rows = crate::datapackage::rows_by_name(&out.join("tangent_fe.csv"));
    let number =
        |r: &std::collections::HashMap<String, String>, k: &str| -> f64 { r[k].parse().unwrap() };
    // Two states × three tangents × nine steps.
    assert_eq!(rows.len(), 2 * 3 * 9);
    for test in rows.chunks(9) {
        let (state, tangent) = (&test[0]["state"], &test[0]["tangent"]);
        assert!(test
            .iter()
            .all(|r| (&r["state"], &r["tangent"]) == (state, tangent)));
        let h: Vec<f64> = test.iter().map(|r| number(r, "h")).collect();
        let expected: Vec<f64> = (6..=14).map(|k| 0.5_f64.powi(k)).collect();
        assert_eq!(h, expected, "{state} {tangent}");
        let order = |k: &str, i: usize| (number(&test[i], k) / number(&test[i + 1], k)).log2();
        assert!(
            (order("r0_u", 7) - 1.0).abs() < 0.05,
            "{state} {tangent}: {}",
            order("r0_u", 7)
        );
        let expected = match tangent.as_str() {
            "exact" => 2.0,
            "symmetric frozen" => 1.0,
            _ => continue,
        };
        // The last pair of steps whose r₁ lies well above the rounding floor.
        let last = (0..8)
            .rev()
            .find(|&i| number(&test[i + 1], "r1_u") > 1e-10)
            .unwrap();
        let o = order("r1_u", last);
        assert!(
            (o - expected).abs() < 0.2,
            "{state} {tangent}: order {o} at pair {last}"
        );
    }
}
