//! The law representation a scene chooses (`[activation] representation = "tabulated"`) and the
//! trade-off option group that measures it (`law-representation`): the tabulated models give the
//! exactly solved models' curves within the tables' checked tolerances (|Δγ| ≤ 1e-12, stress
//! ≤ 1e-9 kPa + 1e-13 |P|), outside the table too (the exact solve there); the trade-off rows
//! report the errors that the exact and the tabulated muscles, built here, actually have.

use activemuscle::active::{Coupling, FrozenTangent, LawRepresentation, TableSpec};
use activemuscle::models::{LawKind, Models};
use activemuscle::scene::{RunOptions, Scene};
use activemuscle::studies::tradeoff::{run, Geometry, OptionGroup, TradeoffOptions};
use activemuscle::studies::uniaxial::CurveModel;
use activemuscle::studies::{Silent, StudyResult};
use activemuscle::uniaxial::along_fibres;
use activemuscle::Muscle;

/// Uniaxial curves along the fibres of both solved laws, each with its coupling, at two damages;
/// 0.55 is below λ_min, 1.7 beyond the table (λ_hi = 1.6).
fn scene(activation: &str) -> String {
    format!(
        r#"
title = "law representation"
[activation]
{activation}
[[study]]
kind = "uniaxial"
stretch = [0.55, 0.62, 0.7, 0.9, 1.0, 1.17, 1.4, 1.6, 1.7]
laws = ["implicit", "energy"]
couplings = ["frozen", "consistent"]
damage = [0.0, 0.3]
"#
    )
}

/// A curve's label and its points (λ, γ, P [kPa]).
type Labelled = (String, Vec<(f64, f64, f64)>);

/// The active curves of the scene's one uniaxial study.
fn active_curves(text: &str) -> Vec<Labelled> {
    let scene = Scene::parse(text, "representation.toml").expect("valid scene");
    let results = scene.run(&RunOptions::default());
    assert!(results.failures().next().is_none(), "every model computed");
    let StudyResult::Uniaxial(u) = &results.studies[0].result else {
        panic!("a uniaxial result");
    };
    u.curves
        .iter()
        .filter_map(|c| match c.model {
            CurveModel::Active(m) => Some((
                scene.models.label(&m),
                c.points
                    .iter()
                    .map(|p| (p.lambda, p.gamma, p.stress))
                    .collect(),
            )),
            _ => None,
        })
        .collect()
}

#[test]
fn a_tabulated_scene_gives_the_exact_curves_within_the_table_tolerances() {
    let exact = active_curves(&scene(""));
    let tabulated = active_curves(&scene("representation = \"tabulated\""));
    assert_eq!(exact.len(), 8, "2 laws × 2 couplings × 2 damages");
    assert_eq!(tabulated.len(), exact.len());
    for ((label_e, e), (label_t, t)) in exact.iter().zip(&tabulated) {
        assert!(!label_e.contains("tabulated"), "{label_e}");
        assert_eq!(
            label_t,
            &label_e.replace(" law,", " law (tabulated),"),
            "the label says which representation"
        );
        assert_eq!(e.len(), 9, "{label_e}: every stretch computed");
        for (&(l, ge, pe), &(lt, gt, pt)) in e.iter().zip(t) {
            assert_eq!(l, lt);
            assert!(
                (ge - gt).abs() <= 1e-12,
                "{label_t} at λ = {l}: γ {ge} vs {gt}"
            );
            assert!(
                (pe - pt).abs() <= 1e-9 + 1e-13 * pe.abs(),
                "{label_t} at λ = {l}: P {pe} vs {pt} kPa"
            );
        }
    }
}

#[test]
fn the_representation_is_printed_and_read_back() {
    let text = scene("representation = \"tabulated\"\ntable_stretches = [0.6, 1.5]");
    let scene = Scene::parse(&text, "representation.toml").expect("valid scene");
    let LawRepresentation::Tabulated(spec) = scene.models.representation else {
        panic!("tabulated");
    };
    assert_eq!((spec.lambda_lo, spec.lambda_hi), (0.6, 1.5));
    let printed = scene.resolved_toml().expect("printable");
    assert!(
        printed.contains("representation = \"tabulated\""),
        "{printed}"
    );
    let again = Scene::parse(&printed, "printed.toml").expect("the printed scene is valid");
    assert_eq!(again.models, scene.models);
    assert_eq!(
        Scene::paper().expect("paper").models.representation,
        LawRepresentation::Exact
    );
}

#[test]
fn a_table_range_without_tables_or_an_empty_range_is_refused_with_its_key() {
    for (activation, rule) in [
        (
            "table_stretches = [0.6, 1.5]",
            "applies only with activation.representation = \"tabulated\"",
        ),
        (
            "representation = \"tabulated\"\ntable_stretches = [1.5, 0.6]",
            "0 < λ_lo < λ_hi",
        ),
        (
            "representation = \"tabulated\"\ntable_stretches = [0.0, 1.5]",
            "0 < λ_lo < λ_hi",
        ),
        (
            "representation = \"chebyshev\"",
            "unknown variant `chebyshev`",
        ),
    ] {
        let e = match Scene::parse(&scene(activation), "bad.toml") {
            Ok(_) => panic!("accepted {activation}"),
            Err(e) => e.to_string(),
        };
        assert!(e.starts_with("bad.toml:"), "{e}");
        assert!(e.contains("activation."), "{e}");
        assert!(e.contains(rule), "{activation}: {e}");
    }
}

const EXACT: Coupling = Coupling::Frozen(FrozenTangent::Exact);

/// The largest |a − b| over a curve.
fn largest(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn the_tradeoff_group_reports_the_errors_the_tabulated_laws_have() {
    let stretches: Vec<f64> = (0..=20).map(|i| 0.6 + 0.05 * i as f64).collect();
    let options = TradeoffOptions {
        groups: vec![OptionGroup::LawRepresentation],
        geometry: Some(Geometry {
            radius: 1.0,
            length: 4.0,
            grading: 1.0,
        }),
        fe_mesh: Some((1, 4)),
        fe_stretches: vec![0.8, 1.17],
        curve_stretches: Some(stretches.clone()),
        ..TradeoffOptions::default()
    };
    let models = Models::paper();
    let results = run(&models, &options, &Silent).expect("runs");
    let shown: Vec<(&str, &str)> = results
        .rows
        .iter()
        .map(|r| (r.option.as_str(), r.variant.as_str()))
        .collect();
    assert_eq!(
        shown,
        [
            ("implicit law representation (0D)", "exact"),
            ("implicit law representation (0D)", "tabulated"),
            ("energy law representation (0D)", "exact"),
            ("energy law representation (0D)", "tabulated"),
            ("implicit law representation (FE)", "exact"),
            ("implicit law representation (FE)", "tabulated"),
        ]
    );
    assert_eq!(results.findings.len(), 3);
    // The 0D errors, recomputed from muscles built here: exact solve against a table.
    for (row, law, coupling) in [
        (&results.rows[1], LawKind::Implicit, EXACT),
        (&results.rows[3], LawKind::Energy, Coupling::Consistent),
    ] {
        let exact = Muscle::new(
            models.energy.clone(),
            models.law(law, models.map).unwrap(),
            0.0,
            coupling,
        )
        .unwrap();
        let table = models
            .law(law, models.map)
            .unwrap()
            .represented(LawRepresentation::Tabulated(TableSpec::default()), &[0.0])
            .unwrap();
        let table = Muscle::new(models.energy.clone(), table, 0.0, coupling).unwrap();
        let curve = |m: &Muscle<_>| -> (Vec<f64>, Vec<f64>) {
            stretches
                .iter()
                .map(|&l| {
                    let p = along_fibres(m, l).unwrap();
                    (p.stress, p.gamma)
                })
                .unzip()
        };
        let ((pe, ge), (pt, gt)) = (curve(&exact), curve(&table));
        let (dp, dg) = (largest(&pe, &pt), largest(&ge, &gt));
        assert_eq!(row.error.max_abs, dp, "{}", row.option);
        assert_eq!(row.gamma_error, Some(dg), "{}", row.option);
        assert!(dp <= 1e-9 + 1e-13 * pe.iter().fold(0.0, |m: f64, p| m.max(p.abs())));
        assert!(dg <= 1e-12);
        assert!(row.note.contains("pieces"), "{}", row.note);
    }
    // In the cylinder both solves stop at the Newton tolerance (1e-10 relative to the first
    // residual): the tabulated law's stress agrees to that order, not to the table's 1e-9 kPa.
    let fe = &results.rows[5];
    assert!(fe.iterations.is_some());
    assert!(
        fe.error.max_rel <= 1e-8,
        "FE stress relative error {:e}",
        fe.error.max_rel
    );
}

#[test]
fn the_tradeoff_measures_the_explicit_law_on_the_scene_s_active_strain_map() {
    use activemuscle::active::ActivationMap;
    let mut models = Models::paper();
    models.map = ActivationMap::VolumePreserving;
    let stretches = vec![0.8, 1.0, 1.2, 1.4];
    let options = TradeoffOptions {
        groups: vec![OptionGroup::ActivationLaw],
        curve_stretches: Some(stretches.clone()),
        ..TradeoffOptions::default()
    };
    let results = run(&models, &options, &Silent).expect("runs");
    let explicit_row = results
        .rows
        .iter()
        .find(|r| r.variant == "explicit (frozen)")
        .expect("an explicit row");
    // Built here: both laws on the volume-preserving map, the explicit one by `with_map`.
    let on_map = |law: LawKind| {
        Muscle::new(
            models.energy.clone(),
            models.law(law, models.map).unwrap(),
            0.0,
            EXACT,
        )
        .unwrap()
        .with_map(ActivationMap::VolumePreserving)
        .unwrap()
    };
    let curve = |m: &Muscle<_>| -> Vec<f64> {
        stretches
            .iter()
            .map(|&l| along_fibres(m, l).unwrap().stress)
            .collect()
    };
    let expected = largest(
        &curve(&on_map(LawKind::Implicit)),
        &curve(&on_map(LawKind::Explicit)),
    );
    assert_eq!(explicit_row.error.max_abs, expected);
    // On the chapter's map the explicit law would be another model: its error would differ.
    let chapter = Muscle::new(
        models.energy.clone(),
        models.law(LawKind::Explicit, models.map).unwrap(),
        0.0,
        EXACT,
    )
    .unwrap();
    let other = largest(&curve(&on_map(LawKind::Implicit)), &curve(&chapter));
    assert!(
        (other - expected).abs() > 1e-3 * expected,
        "{other} vs {expected}"
    );
}
