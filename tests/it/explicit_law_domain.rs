//! The explicit law (eq. (14)) is an approximation of the implicit law on its domain only,
//! 0.7 ≤ λ_f ≤ 1.5 and d_eff = d + (1 − d)(1 − a) ≤ 0.5 (issue 42, item 2; docs/explicit_law.md):
//! a scene bound to leave it is refused at its key, a point that leaves it on the way is computed
//! and flagged (the `in_domain` column, an OUTSIDE line, the report).

use crate::binary;
use crate::datapackage::rows_by_name as rows;
use crate::scratch::scratch;
use activemuscle::active::{
    ActiveCurve, Coupling, Drive, ExplicitLaw, FrozenTangent, ImplicitLaw, Law, OutsideDomain,
};
use activemuscle::energy::GiantesioMusesti;
use activemuscle::uniaxial::{along_fibres, free_contraction};
use activemuscle::Muscle;
use std::path::Path;

fn muscle(law: Law<GiantesioMusesti>) -> Muscle<GiantesioMusesti> {
    let frozen = Coupling::Frozen(FrozenTangent::Exact);
    Muscle::new(GiantesioMusesti::paper(), law, 0.0, frozen).unwrap()
}

fn explicit() -> Muscle<GiantesioMusesti> {
    muscle(Law::Explicit(ExplicitLaw::paper()))
}

fn implicit() -> Muscle<GiantesioMusesti> {
    let law = ImplicitLaw::new(GiantesioMusesti::paper(), ActiveCurve::paper());
    muscle(Law::Implicit(law))
}

/// `activemuscle check` on `scene` (written into a scratch directory `name`): its exit status
/// and stderr.
pub(crate) fn check(name: &str, scene: &str) -> (i32, String) {
    let dir = scratch(name);
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene).unwrap();
    let out = binary::run_args(&[std::ffi::OsStr::new("check"), path.as_os_str()]);
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn near_rest_the_explicit_law_contracts_a_free_block_and_says_it_left_its_domain() {
    // a = 1e-6: the target (1 − d)·a·P_act nearly vanishes, and the implicit law barely moves
    // the block (P_pas(λ) + 1e-6 P_act(λ) = 0 just below 1), while eq. (14) keeps γ ≈ 0.19.
    let e = explicit().with_activation(1e-6).unwrap();
    let i = implicit().with_activation(1e-6).unwrap();
    let (pe, pi) = (free_contraction(&e).unwrap(), free_contraction(&i).unwrap());
    assert!((pi.lambda - 0.9999).abs() < 1e-4, "{}", pi.lambda);
    assert!((pe.lambda - 0.7362).abs() < 1e-4, "{}", pe.lambda);
    let d_eff = Drive::new(0.0, 1e-6).unwrap().effective_damage();
    assert_eq!(
        e.outside_domain(pe.fibre_stretch),
        Some(OutsideDomain::EffectiveDamage(d_eff))
    );
    assert_eq!(i.outside_domain(pi.fibre_stretch), None);
    // Fully active, the same law is inside its domain at 0.8 and 1.2 and outside at 0.65, 1.6;
    // at and below λ_min it gives γ = 0 exactly, as the implicit law does.
    let full = explicit();
    for (l, inside) in [(0.8, true), (1.2, true), (0.65, false), (1.6, false)] {
        assert_eq!(full.outside_domain(l).is_none(), inside, "λ = {l}");
    }
    let lmin = ActiveCurve::paper().lambda_min();
    assert_eq!(full.outside_domain(lmin), None);
    assert_eq!(full.activation(lmin).unwrap().gamma, 0.0);
}

#[test]
fn a_free_contraction_near_rest_with_the_explicit_law_is_refused_at_its_schedule() {
    let (rc, err) = check(
        "explicit-near-rest",
        "[[study]]\nkind = \"activation-in-time\"\nname = \"free\"\ntime = [0.0, 1.0]\n\
         schedule = [[0.0, 1e-6]]\nstretch = \"free\"\nlaw = \"explicit\"\ndamage = [0.0]\n",
    );
    assert_eq!(rc, 1, "{err}");
    assert!(
        err.contains("study[0].schedule = a(0 s) = 1e-6")
            && err.contains("d_eff = d + (1 − d)(1 − a) = 0.999999")
            && err.contains("use the implicit or the energy law"),
        "{err}"
    );
}

#[test]
fn a_ramp_from_rest_with_the_explicit_law_is_refused_at_its_first_active_step() {
    let scene = |law: &str| {
        format!(
            "[[study]]\nkind = \"activation-in-time\"\nname = \"ramp\"\n\
             time = {{ from = 0.0, to = 0.01, step = 0.001 }}\n\
             schedule = [[0.0, 0.0], [1.0, 1.0]]\ninterpolation = \"linear\"\nstretch = \"free\"\n\
             law = \"{law}\"\ndamage = [0.0]\n"
        )
    };
    let (rc, err) = check("explicit-ramp", &scene("explicit"));
    assert_eq!(rc, 1, "{err}");
    // a(0) = 0 is exact (no activation); a(0.001 s) = 0.001 is the first step outside.
    assert!(
        err.contains("schedule = a(0.001 s) = 0.001") && err.contains("= 0.999 there"),
        "{err}"
    );
    // The implicit law holds everywhere: the same ramp is accepted.
    let (rc, err) = check("implicit-ramp", &scene("implicit"));
    assert_eq!(rc, 0, "{err}");
}

#[test]
fn a_damage_between_one_half_and_one_is_refused_for_the_explicit_law_only() {
    let scene = |laws: &str, damage: &str| {
        format!(
            "[[study]]\nkind = \"uniaxial\"\nstretch = [0.9, 1.0, 1.1]\nlaws = {laws}\n\
             damage = {damage}\n"
        )
    };
    let (rc, err) = check(
        "explicit-damage",
        &scene("[\"implicit\", \"explicit\"]", "[0.0, 0.999999]"),
    );
    assert_eq!(rc, 1, "{err}");
    assert!(
        err.contains("study[0].damage[1] = 0.999999")
            && err.contains("the explicit law holds for 0.7 ≤ λ_f ≤ 1.5 and 0 ≤ d_eff ≤ 0.5"),
        "{err}"
    );
    // At d = 0.999999 the explicit law's P(1) is 0.25 kPa where its target, (1 − d) P_act(1),
    // is 6.3e-5 kPa: what the refusal says.
    let d = 0.999999;
    let m = Muscle::new(
        GiantesioMusesti::paper(),
        Law::Explicit(ExplicitLaw::paper()),
        d,
        Coupling::Frozen(FrozenTangent::Exact),
    )
    .unwrap();
    let p = along_fibres(&m, 1.0).unwrap().stress;
    let target = (1.0 - d) * ActiveCurve::paper().value(1.0);
    assert!((p - 0.2475).abs() < 1e-3 && (target - 6.3e-5).abs() < 1e-6);
    for (laws, damage) in [
        ("[\"implicit\"]", "[0.999999]"),
        ("[\"explicit\"]", "[0.0, 0.5, 1.0]"),
    ] {
        let (rc, err) = check("explicit-damage-ok", &scene(laws, damage));
        assert_eq!(rc, 0, "{laws} {damage}: {err}");
    }
}

#[test]
fn a_weakly_recruited_region_is_refused_for_the_explicit_law() {
    let scene = |activation: f64| {
        format!(
            "[activation]\nlaw = \"explicit\"\n[[study]]\nkind = \"cylinder\"\nnr = 2\nnz = 4\n\
             damage = [0.0]\nstretch = [1.0, 1.1]\n[[study.regions]]\nr = [0.0, 0.5]\n\
             activation = {activation}\n"
        )
    };
    let (rc, err) = check("explicit-region", &scene(0.4));
    assert_eq!(rc, 1, "{err}");
    assert!(
        err.contains("study[0].regions[0].activation = 0.4") && err.contains("= 0.6,"),
        "{err}"
    );
    for a in [0.0, 0.5, 1.0] {
        let (rc, err) = check("explicit-region-ok", &scene(a));
        assert_eq!(rc, 0, "a = {a}: {err}");
    }
}

/// The stdout of a run of `scene` into `out`.
fn run(scene: &str, dir: &Path) -> String {
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene).unwrap();
    let out = binary::run_quiet(Some(&path), &dir.join("out"));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
fn a_curve_beyond_the_fitted_stretches_is_computed_flagged_and_measured_against_its_target() {
    let dir = scratch("explicit-flagged");
    let stdout = run(
        "[[study]]\nkind = \"uniaxial\"\nname = \"u\"\nstretch = [0.65, 1.0, 1.6]\n\
         laws = [\"explicit\", \"implicit\"]\ncouplings = [\"frozen\"]\ndamage = [0.0]\n\
         [[study]]\nkind = \"cylinder\"\nname = \"c\"\nnr = 1\nnz = 2\nbases = \"sliding\"\n\
         law = \"explicit\"\ncoupling = \"frozen\"\ndamage = [0.0]\nstretch = [1.2, 1.55]\n",
        &dir,
    );
    let curves = rows(&dir.join("out/curves.csv"));
    for r in &curves {
        let l: f64 = r["lambda"].parse().unwrap();
        let expected = match r["law"].as_str() {
            "explicit" => {
                if (0.7..=1.5).contains(&l) {
                    "true"
                } else {
                    "false"
                }
            }
            _ => "",
        };
        assert_eq!(r["in_domain"], expected, "{r:?}");
    }
    // The distance from the target at λ = 1.6, against the implicit law, which meets it.
    let p = |m: &Muscle<GiantesioMusesti>| along_fibres(m, 1.6).unwrap().stress;
    let distance = (p(&explicit()) - p(&implicit())).abs();
    assert!((distance - 174.4).abs() < 0.05, "{distance}");
    let line = stdout
        .lines()
        .find(|l| l.starts_with("OUTSIDE: u — "))
        .unwrap_or_else(|| panic!("{stdout}"));
    assert!(
        line.contains("2 of 3 points outside the explicit law's domain")
            && line.contains("λ_f below 0.7 at λ = 0.65")
            && line.contains("λ_f above 1.5 at λ = 1.6")
            && line.contains(&format!("reaches {distance:.1} kPa (at λ = 1.6)"))
            && line.contains("in_domain = false in curves.csv"),
        "{line}"
    );
    assert!(
        stdout.contains("OUTSIDE: c — ")
            && stdout.contains("1 of 2 stretches with quadrature points outside"),
        "{stdout}"
    );
    let report = std::fs::read_to_string(dir.join("out/report.html")).unwrap();
    assert!(report.contains("Where a law left its domain") && report.contains("2 of 3 points"));
}

#[test]
fn force_velocity_that_moves_d_eff_out_is_flagged_with_its_rate_and_factor() {
    // λ from 1.2 down to 1.0 in 1 s: λ̇ = −0.2/s, r = λ̇/λ̇_min = 0.5 and, with d_c = 1, k_c = 5,
    // f_v = (1 − r)/(1 + 5 r) = 1/7: d_eff = 1 − f_v = 6/7, outside [0, 0.5].
    let dir = scratch("explicit-velocity");
    let stdout = run(
        "[activation]\nlaw = \"explicit\"\n\
         force_velocity = { min_rate = -0.4, ke = 5.0, kc = 5.0, de = 0.5, dc = 1.0 }\n\
         [[study]]\nkind = \"activation-in-time\"\nname = \"h\"\ntime = [0.0, 0.5, 1.0]\n\
         stretch = [[0.0, 1.2], [1.0, 1.0]]\ndamage = [0.0]\n",
        &dir,
    );
    let history = rows(&dir.join("out/history.csv"));
    let col =
        |r: &std::collections::HashMap<String, String>, c: &str| -> f64 { r[c].parse().unwrap() };
    assert_eq!(history[0]["in_domain"], "true");
    assert_eq!(
        (col(&history[0], "lambda_rate"), col(&history[0], "f_v")),
        (0.0, 1.0)
    );
    for r in &history[1..] {
        assert_eq!(r["in_domain"], "false", "{r:?}");
        assert!((col(r, "lambda_rate") + 0.2).abs() < 1e-12, "{r:?}");
        assert!((col(r, "f_v") - 1.0 / 7.0).abs() < 1e-12, "{r:?}");
    }
    assert!(
        stdout.contains("OUTSIDE: h — ")
            && stdout.contains("2 of 3 time steps")
            && stdout.contains("d_eff = 0.857143 at t = 0.5–1 s"),
        "{stdout}"
    );
    // The history figure's caption names the factor the target was scaled by.
    let report = std::fs::read_to_string(dir.join("out/report.html")).unwrap();
    assert!(report.contains("scaled by (1 − d)·a(t)·f_v(λ̇)"), "{report}");
}

#[test]
fn a_tangent_study_flags_its_states_outside_the_explicit_laws_domain_as_the_other_kinds_do() {
    let dir = scratch("explicit-tangent");
    let stdout = run(
        "[[study]]\nkind = \"tangent\"\nname = \"t\"\nuniaxial_along = [0.65, 1.0, 1.6]\n\
         random_states = 0\nnear_lambda_min = 0\nlarge_fibre_stretch = 0\nrandom_directions = 1\n\
         h = { largest = 0.015625, smallest = 0.001953125 }\n\
         approaches = [\"active-strain\"]\nlaws = [\"explicit\", \"implicit\"]\n\
         couplings = [\"frozen\"]\ndamage = [0.0]\npassive = false\n",
        &dir,
    );
    let summary = rows(&dir.join("out/tangent_summary.csv"));
    let mut outside = 0;
    for r in &summary {
        // λ_f = |F m| with m = e₁, from the state's F as written.
        let f = |k: &str| r[k].parse::<f64>().unwrap();
        let fibre_stretch = (f("F11").powi(2) + f("F21").powi(2) + f("F31").powi(2)).sqrt();
        let expected = match r["law"].as_str() {
            "explicit" if (0.7..=1.5).contains(&fibre_stretch) => "true",
            "explicit" => {
                outside += 1;
                "false"
            }
            _ => "",
        };
        assert_eq!(r["in_domain"], expected, "{r:?}");
    }
    assert_eq!(outside, 2, "{summary:?}");
    let line = stdout
        .lines()
        .find(|l| l.starts_with("OUTSIDE: t — "))
        .unwrap_or_else(|| panic!("{stdout}"));
    assert!(
        line.contains("2 of 3 states outside the explicit law's domain")
            && line.contains("λ_f below 0.7")
            && line.contains("λ_f above 1.5")
            && line.contains("in_domain = false in tangent_summary.csv"),
        "{line}"
    );
    assert_eq!(stdout.matches("OUTSIDE:").count(), 1, "{stdout}");
    let report = std::fs::read_to_string(dir.join("out/report.html")).unwrap();
    assert!(report.contains("Where a law left its domain") && report.contains("2 of 3 states"));
}
