//! The activation approaches as a registry: what each declares is what the models build and
//! what a scene accepts. Every approach meets the uniaxial target along the fibres with every law
//! it lists (an independent closed form: P_pas + (1 − d) P_act); a key that applies to none of a
//! scene's approaches is refused at the key with the approach's reason, never cut or ignored; an
//! approach without a law is never labelled with one; `check`'s printout holds only the keys
//! that apply and reads back to the same scene.

use activemuscle::active::{Approach, ShippedApproach};
use activemuscle::models::{CouplingKind, LawKind, ModelChoice, Models};
use activemuscle::output::figures::figures;
use activemuscle::output::report::{html, RunInfo};
use activemuscle::plot::CurveId;
use activemuscle::scene::{RunOptions, Scene, SceneError};
use activemuscle::studies::curves::{cylinder_rows, uniaxial_rows};
use activemuscle::studies::cylinder::CylinderResult;
use activemuscle::studies::uniaxial::UniaxialResult;
use activemuscle::studies::StudyResult;
use activemuscle::uniaxial::Direction;
use std::collections::BTreeSet;

const FILE: &str = "approaches.toml";

fn rejected(text: &str) -> SceneError {
    match Scene::parse(text, FILE) {
        Ok(_) => panic!("accepted a bad scene:\n{text}"),
        Err(e) => e,
    }
}

/// The error names `key` (after the file and line), the value and a word of the rule.
fn refused_at(text: &str, key: &str, value: &str, rule: &str) {
    let e = rejected(text).to_string();
    assert!(
        e.contains(&format!(": {key} = ")) || e.contains(&format!(": {key}: ")),
        "key {key} expected: {e}"
    );
    assert!(e.contains(value), "value {value:?} expected: {e}");
    assert!(e.contains(rule), "rule {rule:?} expected: {e}");
}

const UNIAXIAL: &str = "[[study]]\nkind = \"uniaxial\"\nstretch = [0.9, 1.1, 1.3]\n";

fn active_stress(extra: &str) -> String {
    format!("[activation]\napproach = \"active-stress\"\n{extra}")
}

fn structural(extra: &str) -> String {
    format!("[activation]\napproach = \"structural\"\n{extra}")
}

/// Along the fibres every approach, with every law it lists in the coupling the law is built
/// for (implicit frozen, energy consistent; none for an approach without a law), gives
/// P_pas + (1 − d) P_act to 1e-8 relative: the target computed here from the passive energy and
/// the active curve alone.
#[test]
fn every_approach_meets_the_target_along_the_fibres_with_every_law_it_lists() {
    let models = Models::paper();
    let passive = models.passive();
    let d = 0.3;
    for &approach in Approach::ALL {
        let mut choices = vec![ModelChoice::lawless(approach, d)];
        let exact = [
            (LawKind::Implicit, CouplingKind::Frozen),
            (LawKind::Energy, CouplingKind::Consistent),
        ];
        if !approach.laws().is_empty() {
            choices = exact
                .iter()
                .filter(|(l, _)| approach.laws().contains(l))
                .map(|&(law, coupling)| ModelChoice {
                    approach,
                    law,
                    coupling,
                    damage: d,
                })
                .collect();
            assert!(!choices.is_empty(), "{}", approach.name());
        }
        for m in choices {
            let muscle = models.muscle(m).unwrap();
            for lambda in [0.8, 1.0, 1.17, 1.4] {
                let p = models.uniaxial(&muscle, Direction::Along, lambda).unwrap();
                let p_pas = models
                    .uniaxial(&passive, Direction::Along, lambda)
                    .unwrap()
                    .stress;
                let target = p_pas + (1.0 - d) * models.curve.value(lambda);
                assert!(
                    (p.stress - target).abs() <= 1e-8 * target.abs(),
                    "{} at λ = {lambda}: {} vs {target}",
                    models.label(&m),
                    p.stress
                );
            }
        }
    }
}

/// A law an approach does not list is refused with its reason; one it lists is built.
#[test]
fn every_approach_refuses_the_laws_it_does_not_list() {
    let models = Models::paper();
    for &approach in Approach::ALL {
        for law in LawKind::ALL {
            let listed = approach.laws().contains(&law);
            match models.supports(approach, law) {
                Ok(()) => assert!(listed, "{} builds {}", approach.name(), law.name()),
                Err(rule) => {
                    assert!(
                        !listed,
                        "{} refuses {}: {rule}",
                        approach.name(),
                        law.name()
                    );
                    assert!(rule.contains(approach.no_law()), "{rule}");
                }
            }
        }
        let named: Approach = toml::from_str::<toml::Table>(&format!("a = {:?}", approach.name()))
            .unwrap()["a"]
            .clone()
            .try_into()
            .unwrap();
        assert_eq!(named, approach);
    }
    // The registry's declarations: active stress has no law, hence no coupling and no map.
    use activemuscle::active::approach::ActiveStress;
    assert!(ActiveStress::LAWS.is_empty() && ActiveStress::COUPLINGS.is_empty());
    assert!(ActiveStress::VARIABLE.is_none());
    let e = rejected(&format!(
        "[activation]\napproach = \"sideways\"\n{UNIAXIAL}"
    ))
    .to_string();
    assert!(
        e.contains("active-strain") && e.contains("structural"),
        "{e}"
    );
}

#[test]
fn active_stress_refuses_an_activation_law_at_its_key() {
    refused_at(
        &active_stress(&format!("law = \"implicit\"\n{UNIAXIAL}")),
        "activation.law",
        "implicit",
        "active stress has no activation variable",
    );
    refused_at(
        &active_stress(&format!("coupling = \"consistent\"\n{UNIAXIAL}")),
        "activation.coupling",
        "consistent",
        "no law and no coupling",
    );
}

/// Today's cut (`laws[..1]`) computed the first law and dropped the others without a word.
#[test]
fn active_stress_refuses_a_study_s_laws_and_couplings_instead_of_cutting_them() {
    let laws = active_stress(&format!("{UNIAXIAL}laws = [\"implicit\", \"explicit\"]\n"));
    refused_at(
        &laws,
        "study[0].laws",
        "explicit",
        "active stress has no activation variable",
    );
    let couplings = active_stress(
        "[[study]]\nkind = \"stability\"\nstretch = [1.0, 1.1]\ncouplings = [\"frozen\", \"consistent\"]\n",
    );
    refused_at(
        &couplings,
        "study[0].couplings",
        "consistent",
        "no law and no coupling",
    );
    let cylinder = active_stress(
        "[[study]]\nkind = \"cylinder\"\nstretch = [1.1]\nnr = 1\nnz = 4\nlaw = \"energy\"\n",
    );
    refused_at(
        &cylinder,
        "study[0].law",
        "energy",
        "active stress has no activation variable",
    );
    // A shear study of active stress alone: its laws apply to no approach of it.
    let shear = "[[study]]\nkind = \"shear\"\nshear = [0.1]\napproaches = [\"active-stress\"]\nlaws = [\"implicit\"]\n";
    refused_at(
        shear,
        "study[0].laws",
        "implicit",
        "active stress has no activation variable",
    );
}

#[test]
fn the_map_is_refused_for_the_approaches_that_do_not_choose_one() {
    let map = format!("map = \"volume-preserving\"\n{UNIAXIAL}");
    refused_at(
        &active_stress(&map),
        "activation.map",
        "volume-preserving",
        "no activation map",
    );
    refused_at(
        &structural(&map),
        "activation.map",
        "volume-preserving",
        "structural invariant",
    );
}

#[test]
fn a_law_s_options_are_refused_without_the_law_they_belong_to() {
    for (key, value, rule) in [
        ("frozen_tangent", "\"symmetric\"", "no law and no coupling"),
        ("below_minimum", "\"inactive\"", "the energy law's"),
        ("representation", "\"tabulated\"", "no law"),
        ("explicit", "{ a = 1.0 }", "the explicit law's"),
    ] {
        let text = active_stress(&format!("{key} = {value}\n{UNIAXIAL}"));
        refused_at(&text, &format!("activation.{key}"), "", rule);
    }
    // The structural approach has the energy law but not the explicit one.
    let explicit = structural(&format!("explicit = {{ a = 1.0 }}\n{UNIAXIAL}"));
    refused_at(
        &explicit,
        "activation.explicit",
        "a = 1",
        "fitted for active strain",
    );
    assert!(Scene::parse(
        &structural(&format!("below_minimum = \"inactive\"\n{UNIAXIAL}")),
        FILE
    )
    .is_ok());
}

/// Quasi-static studies have λ̇ = 0, f_v = 1: force–velocity given to a scene without a study
/// in time would change nothing, and is refused.
#[test]
fn force_velocity_is_refused_without_a_study_driven_in_time() {
    let fv = "force_velocity = { min_rate = -17.0, ke = 5.0, kc = 5.0, de = 0.5, dc = 1.0 }\n";
    let text = format!("[activation]\n{fv}{UNIAXIAL}");
    refused_at(&text, "activation.force_velocity", "", "activation-in-time");
    let in_time = format!(
        "[activation]\n{fv}[[study]]\nkind = \"activation-in-time\"\ntime = {{ from = 0.0, to = 0.2, step = 0.1 }}\nschedule = [[0.0, 1.0]]\n"
    );
    Scene::parse(&in_time, FILE).unwrap();
}

#[test]
fn a_constant_activation_is_refused_for_an_approach_without_a_variable() {
    let text = active_stress(&format!("{UNIAXIAL}constant_gamma = [0.2]\n"));
    refused_at(&text, "study[0].constant_gamma", "0.2", "has none");
}

/// A trade-off measures laws and runs its other options with one; an explicit-law fit is of
/// the chapter's active-strain γ: neither measures active strain in a scene that asks for
/// another approach.
#[test]
fn a_tradeoff_and_an_explicit_law_fit_are_refused_where_the_approach_has_no_such_law() {
    let tradeoff = active_stress("[[study]]\nkind = \"tradeoff\"\noptions = [\"mesh\"]\n");
    refused_at(
        &tradeoff,
        "study[0].kind",
        "tradeoff",
        "active stress has no activation variable",
    );
    let fit = "[[study]]\nkind = \"fit\"\nfit = \"explicit-law\"\nstretch = { from = 0.8, to = 1.4, step = 0.1 }\n";
    refused_at(
        &structural(fit),
        "study[0].fit",
        "explicit-law",
        "fitted for active strain",
    );
    refused_at(
        &active_stress(fit),
        "study[0].fit",
        "explicit-law",
        "no law",
    );
    assert!(Scene::parse(fit, FILE).is_ok());
}

/// The rule quotes what the file says: a structural scene on an energy without a structural
/// invariant is refused at its approach, not at a law it does not name.
#[test]
fn a_refusal_quotes_the_value_the_file_writes() {
    let text = format!(
        "[material]\nenergy = \"neo-hookean\"\nmu = 1.0\n{}",
        structural(&format!("{UNIAXIAL}laws = [\"implicit\"]\n"))
    );
    let e = rejected(&text).to_string();
    assert!(e.contains("activation.approach = \"structural\""), "{e}");
    assert!(!e.contains("explicit"), "{e}");
    let explicit = structural(&format!("{UNIAXIAL}laws = [\"implicit\", \"explicit\"]\n"));
    refused_at(
        &explicit,
        "study[0].laws[1]",
        "\"explicit\"",
        "fitted for active strain",
    );
}

/// The curves a run writes, and the curves its figures draw with a legend entry.
fn written_and_drawn(scene: &Scene) -> (BTreeSet<CurveId>, BTreeSet<CurveId>, String) {
    let results = scene.run(&RunOptions::default());
    assert!(
        results.complete(),
        "{:?}",
        results.failures().collect::<Vec<_>>()
    );
    let mut rows = Vec::new();
    for (study, u) in results.of::<UniaxialResult>() {
        rows.extend(uniaxial_rows(study, u));
    }
    for (study, c) in results.of::<CylinderResult>() {
        rows.extend(cylinder_rows(study, c));
    }
    let written = rows.iter().map(|r| r.curve()).collect();
    let figures = figures(scene, &results);
    let drawn = figures
        .iter()
        .flat_map(|f| f.panels.iter())
        .flat_map(|p| p.series.iter())
        .filter(|s| !s.label.is_empty())
        .filter_map(|s| s.curve.clone())
        .collect();
    let mut text: String = figures
        .iter()
        .map(|f| format!("{}\n{}\n", f.heading, f.caption))
        .collect();
    text.push_str(&html(scene, &results, &[], &RunInfo::default()).unwrap());
    for s in &results.studies {
        if let StudyResult::Stability(curves) = &s.result {
            text.extend(curves.iter().map(|c| format!("\n{}", c.label())));
        }
    }
    (written, drawn, text)
}

/// Not "γ(λ) of the implicit law" over γ ≡ 0: labels, captions and the report's table of models
/// name the approach, and every curve written is still drawn.
#[test]
fn an_active_stress_run_is_never_labelled_with_a_law() {
    let text = active_stress(
        "damage = [0.0, 0.5]\n[[study]]\nkind = \"uniaxial\"\nstretch = [0.9, 1.1, 1.3]\n\
         [[study]]\nkind = \"uniaxial\"\nname = \"one damage\"\nstretch = [0.9, 1.1]\ndamage = [0.2]\n\
         [[study]]\nkind = \"stability\"\nstretch = [1.0, 1.1]\nnormals = 12\n\
         [[study]]\nkind = \"cylinder\"\nstretch = [1.05]\nnr = 1\nnz = 4\ndamage = [0.0]\n",
    );
    let scene = Scene::parse(&text, FILE).unwrap();
    let m = scene.studies.iter().find_map(|s| match s {
        activemuscle::studies::Study::Uniaxial(u) => u.models.first().copied(),
        _ => None,
    });
    assert_eq!(
        scene.models.label(&m.unwrap()),
        "giantesio-musesti, active stress, d = 0"
    );
    let (written, drawn, words) = written_and_drawn(&scene);
    assert!(
        written.is_subset(&drawn),
        "not drawn: {:?}",
        written.difference(&drawn)
    );
    for law in [
        "implicit law",
        "explicit law",
        "energy law",
        "frozen coupling",
        "implicit, frozen",
    ] {
        assert!(!words.contains(law), "{law:?} in:\n{words}");
    }
    assert!(
        words.contains("active stress") && words.contains("active-stress"),
        "{words}"
    );
}

/// `check` writes the keys that apply to the scene's approaches, and its printout is a scene
/// that reads back to the same models.
#[test]
fn check_prints_the_keys_that_apply_and_its_printout_reads_back() {
    for (approach, absent, present) in [
        (
            "active-stress",
            &["law", "coupling", "map", "frozen_tangent", "representation"][..],
            &["damage"][..],
        ),
        (
            "structural",
            &["map", "[activation.explicit]"][..],
            &["law", "below_minimum"][..],
        ),
        (
            "active-strain",
            &[][..],
            &["law", "map", "[activation.explicit]"][..],
        ),
    ] {
        let scene = Scene::parse(
            &format!("[activation]\napproach = {approach:?}\n{UNIAXIAL}"),
            FILE,
        )
        .unwrap();
        let printed = scene.resolved_toml().unwrap();
        let activation = printed
            .split("[activation]")
            .nth(1)
            .and_then(|s| s.split("[incompressibility]").next())
            .unwrap();
        for key in absent {
            let line = |l: &str| l.starts_with(&format!("{key} =")) || l == *key;
            assert!(
                !activation.lines().any(line),
                "{approach}: {key} in\n{activation}"
            );
        }
        for key in present {
            assert!(
                activation.contains(key),
                "{approach}: {key} missing in\n{activation}"
            );
        }
        let again = Scene::parse(&printed, FILE).unwrap();
        assert_eq!(again.models, scene.models, "{approach}");
        assert_eq!(again.defaults, scene.defaults, "{approach}");
        assert_eq!(again.studies, scene.studies, "{approach}");
    }
}

/// A shear study's laws apply to those of its approaches that have one; an approach without a
/// law gives one model per damage, its cells empty of law and coupling.
#[test]
fn a_shear_study_s_laws_apply_to_its_approaches_that_have_one() {
    let text = "[[study]]\nkind = \"shear\"\nshear = [0.1]\napproaches = [\"active-strain\", \"active-stress\"]\n\
                laws = [\"implicit\", \"energy\"]\ncouplings = [\"frozen\"]\ndamage = [0.0, 0.5]\n";
    let scene = Scene::parse(text, FILE).unwrap();
    let activemuscle::studies::Study::Shear(s) = &scene.studies[0] else {
        panic!("a shear study");
    };
    // The passive material, 2 laws × 1 coupling × 2 damages of active strain, 2 of active stress.
    assert_eq!(s.models.len(), 1 + 4 + 2);
    for m in s.models.iter().filter(|m| m.model.is_some()) {
        let [a, l, c] = m.cells();
        match a.as_deref() {
            Some("active-stress") => assert_eq!((l, c), (None, None)),
            Some("active-strain") => assert!(l.is_some() && c.is_some()),
            other => panic!("{other:?}"),
        }
    }
}

/// A trade-off follows the scene's approach: on the structural approach it measures the laws
/// that give ω (the implicit law, the reference, and the energy law) with the structural map,
/// and says why the explicit law is not measured.
#[test]
fn a_structural_tradeoff_measures_the_structural_laws() {
    use activemuscle::studies::tradeoff::{run, OptionGroup, TradeoffOptions};
    let options = TradeoffOptions {
        groups: vec![OptionGroup::ActivationLaw],
        approach: Approach::Structural,
        curve_stretches: Some(vec![0.9, 1.1, 1.3]),
        ..TradeoffOptions::default()
    };
    let results = run(&Models::paper(), &options, &activemuscle::studies::Silent).unwrap();
    let variants: Vec<&str> = results.rows.iter().map(|r| r.variant.as_str()).collect();
    assert_eq!(variants, ["implicit (frozen)", "energy (consistent)"]);
    // The energy law's consistent model meets the same target as the implicit law's frozen one.
    assert!(
        results.rows[1].error.max_rel < 1e-8,
        "{:?}",
        results.rows[1]
    );
    assert!(
        results
            .findings
            .iter()
            .any(|f| f.contains("explicit law") && f.contains("structural")),
        "{:#?}",
        results.findings
    );
}
