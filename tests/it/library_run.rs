//! A scene runs from a string through the library alone (no CLI, no terminal) and returns typed
//! results: each study's outcome with its curves, their models as values; the numbers are the
//! model's (the implicit law reproduces P_pas + (1 − d) P_act), and the CSV the binary writes is
//! their projection.

use activemuscle::models::{CouplingKind, LawKind};
use activemuscle::output::csv::files;
use activemuscle::scene::{RunOptions, Scene};
use activemuscle::studies::uniaxial::CurveModel;
use activemuscle::studies::{StudyKind, StudyResult};
use activemuscle::uniaxial::{along_fibres, Direction};

use crate::binary;
use crate::scratch;
use scratch::scratch;

const SCENE: &str = r#"
title = "library run"
[[study]]
kind = "uniaxial"
name = "along"
stretch = [0.8, 1.0, 1.17, 1.4]
laws = ["implicit"]
couplings = ["frozen"]
damage = [0.0, 0.3]
constant_gamma = [0.2]
[[study]]
kind = "fit"
name = "damage"
fit = "damage"
true_damage = [0.3]
stretch = { from = 0.8, to = 1.4, step = 0.05 }
[[study]]
kind = "stability"
laws = []
stretch = [1.0, 1.1]
normals = 20
"#;

#[test]
fn a_scene_from_a_string_runs_without_a_terminal_into_typed_results() {
    let scene = Scene::parse(SCENE, "library.toml").expect("valid scene");
    let results = scene.run(&RunOptions::default());
    let kinds: Vec<StudyKind> = results.studies.iter().map(|s| s.kind).collect();
    assert_eq!(
        kinds,
        [StudyKind::Uniaxial, StudyKind::Fit, StudyKind::Stability]
    );
    assert!(results.failures().next().is_none());

    let StudyResult::Uniaxial(u) = &results.studies[0].result else {
        panic!("a uniaxial result");
    };
    assert_eq!(u.direction, Direction::Along);
    // Passive, constant γ, then the two implicit models, each with its model as values.
    assert_eq!(u.curves.len(), 4);
    assert_eq!(u.curves[0].model, CurveModel::Passive);
    assert_eq!(u.curves[1].model, CurveModel::Constant(0.2));
    let passive = scene.models.passive();
    let curve = scene.models.curve;
    for (c, d) in u.curves[2..].iter().zip([0.0, 0.3]) {
        let CurveModel::Active(m) = c.model else {
            panic!("an active curve");
        };
        assert_eq!(
            (m.law, m.coupling, m.damage),
            (LawKind::Implicit, CouplingKind::Frozen, d)
        );
        assert_eq!(c.points.len(), 4);
        for p in &c.points {
            // The implicit law reproduces the target P_pas + (1 − d) P_act (its definition).
            let target = along_fibres(&passive, p.lambda).expect("passive").stress
                + (1.0 - d) * curve.value(p.lambda);
            assert!(
                (p.stress - target).abs() <= 1e-9 * target.abs().max(1.0),
                "λ = {}: {} vs {target}",
                p.lambda,
                p.stress
            );
            assert_eq!(
                p.passive.zip(p.active_target).map(|(a, b)| a + b),
                Some(target)
            );
        }
    }
    // The fit recovers the damage of exact synthetic data.
    let fits: Vec<(&str, &Vec<activemuscle::studies::fit::FitOutcome>)> = results.of().collect();
    let (name, fit) = fits[0];
    assert_eq!(name, "damage");
    assert!(
        fit[0].converged && (fit[0].values[0] - 0.3).abs() < 1e-9,
        "{:?}",
        fit[0]
    );
    // The stability study computed the passive curve only.
    let stability: Vec<(&str, &Vec<activemuscle::studies::stability::StabilityCurve>)> =
        results.of().collect();
    assert_eq!(stability[0].1.len(), 1);
    assert_eq!(stability[0].1[0].model, None);
}

#[test]
fn the_csv_the_binary_writes_is_the_projection_of_the_typed_results() {
    let dir = scratch("library");
    let path = dir.join("library.toml");
    std::fs::write(&path, SCENE).expect("scene");
    binary::run_quiet(Some(&path), &dir.join("out"));
    let scene = Scene::load(&path).expect("valid scene");
    let results = scene.run(&RunOptions::default());
    let tables = files(&results);
    assert!(
        tables.len() >= 3,
        "{:?}",
        tables.iter().map(|t| &t.file).collect::<Vec<_>>()
    );
    for t in tables {
        let written = std::fs::read(dir.join("out").join(&t.file)).expect("the file");
        assert_eq!(t.bytes().expect("csv"), written, "{}", t.file);
    }
}
