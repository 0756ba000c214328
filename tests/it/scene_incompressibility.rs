//! `[incompressibility]` in a scene: exact (default) or a volumetric energy, validated at load
//! time with file, line, key and rule; a nearly incompressible scene runs its uniaxial curves
//! and its sliding cylinder on Ŵ + U(J), and they agree (sliding cylinder = 0D).

use activemuscle::output::report::{html, RunInfo};
use activemuscle::scene::{RunOptions, Scene, SceneError};
use activemuscle::studies::StudyResult;
use activemuscle::uniaxial::{nearly_incompressible, Direction};
use activemuscle::volumetric::VolumetricForm;

const FILE: &str = "inc.toml";

fn rejected(text: &str) -> SceneError {
    match Scene::parse(text, FILE) {
        Ok(_) => panic!("accepted a bad scene:\n{text}"),
        Err(e) => e,
    }
}

const STUDY: &str = "\n[[study]]\nkind = \"uniaxial\"\nstretch = [1.0, 1.1]\n";

#[test]
fn bad_incompressibility_values_are_refused_at_their_line() {
    for (table, line, key, rule) in [
        (
            "kind = \"quadratic\"\nkappa = 0.0",
            3,
            "incompressibility.kappa",
            "> 0",
        ),
        (
            "kind = \"quadratic\"\nkappa = nan",
            3,
            "incompressibility.kappa",
            "finite",
        ),
        (
            "kind = \"quadratic\"",
            1,
            "incompressibility.kappa",
            "needs kappa",
        ),
        (
            "kind = \"squishy\"",
            2,
            "incompressibility.kind",
            "expected",
        ),
        (
            "kind = \"exact\"\nkappa = 3.0",
            3,
            "incompressibility.kappa",
            "no volumetric",
        ),
        (
            "kind = \"logarithmic\"\nkappa = 3.0\nmu = 1.0",
            4,
            "incompressibility.mu",
            "only the 4c",
        ),
        (
            "kind = \"4c-giantesio\"\nkappa = 3.0\nmu = -1.0",
            4,
            "incompressibility.mu",
            "> 0",
        ),
        (
            "kind = \"quadratic\"\nkapa = 3.0",
            3,
            "incompressibility",
            "unknown field",
        ),
    ] {
        let e = rejected(&format!("[incompressibility]\n{table}\n{STUDY}"));
        let shown = e.to_string();
        println!("{shown}");
        assert!(shown.contains(key), "{key} missing: {shown}");
        assert!(shown.contains(rule), "{rule} missing: {shown}");
        if line > 1 {
            assert!(
                shown.starts_with(&format!("{FILE}:{line}:")),
                "line {line}: {shown}"
            );
        }
    }
}

#[test]
fn exact_is_the_default_and_4c_takes_the_energys_mu() {
    let scene = Scene::parse(STUDY, FILE).unwrap();
    assert!(scene.models.volumetric.is_none());
    // `check` writes every default out, this one too.
    assert!(scene
        .resolved_toml()
        .unwrap()
        .contains("[incompressibility]\nkind = \"exact\"\n"));
    let scene = Scene::parse(
        &format!("[incompressibility]\nkind = \"4c-giantesio\"\nkappa = 50.0\n{STUDY}"),
        FILE,
    )
    .unwrap();
    let v = scene.models.volumetric.expect("a volumetric energy");
    assert_eq!(
        v.form(),
        VolumetricForm::Giantesio4C {
            kappa: 50.0,
            mu: 0.1599
        }
    );
    // The chapter's energy is stress free at F = I: the linear term is μ/2.
    assert!((v.shift() - 0.1599 / 2.0).abs() < 1e-15);
    let text = scene.resolved_toml().unwrap();
    assert!(text.contains("kind = \"4c-giantesio\""), "{text}");
    assert_eq!(Scene::parse(&text, FILE).unwrap().models, scene.models);
}

#[test]
fn a_nearly_incompressible_scene_runs_on_the_volumetric_energy() {
    let text = r#"
[incompressibility]
kind = "quadratic"
kappa = 2000.0

[[study]]
kind = "uniaxial"
name = "along"
stretch = [0.9, 1.0, 1.2]
laws = ["explicit"]
couplings = ["frozen"]

[[study]]
kind = "cylinder"
name = "sliding"
bases = "sliding"
nr = 2
nz = 4
stretch = [0.9, 1.0, 1.2]
law = "explicit"
coupling = "frozen"
"#;
    let scene = Scene::parse(text, FILE).unwrap();
    let results = scene.run(&RunOptions::default());
    assert!(results.failures().next().is_none());
    let StudyResult::Uniaxial(u) = &results.studies[0].result else {
        panic!("a uniaxial result");
    };
    let vol = scene.models.volumetric.unwrap();
    let active = u.curves.last().unwrap();
    let activemuscle::studies::uniaxial::CurveModel::Active(model) = active.model else {
        panic!("an active curve");
    };
    let muscle = scene.models.muscle(model).unwrap();
    for p in &active.points {
        let zero_d = nearly_incompressible(&muscle, &vol, Direction::Along, p.lambda).unwrap();
        assert_eq!(p.stress, zero_d.stress);
        let exact = Direction::Along.point(&muscle, p.lambda).unwrap().stress;
        if p.lambda != 1.0 {
            assert!(
                (p.stress - exact).abs() > 1e-4,
                "the penalty must show at {}",
                p.lambda
            );
        }
    }
    let info = RunInfo::default();
    let report = html(&scene, &results, &[], &info).unwrap();
    assert!(
        report.contains("incompressibility: quadratic"),
        "the report names the option"
    );
    assert!(report.contains("κ = 2000 kPa"));
    let StudyResult::Cylinder(c) = &results.studies[1].result else {
        panic!("a cylinder result");
    };
    for pt in &c.sweeps[0].points {
        let zero_d = pt.stress_0d.unwrap();
        assert!(
            (pt.stress - zero_d).abs() < 1e-8 * zero_d.abs().max(1.0),
            "λ = {}: FE {} vs 0D {zero_d}",
            pt.lambda,
            pt.stress
        );
    }
}
