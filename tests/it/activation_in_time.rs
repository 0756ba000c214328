//! Activation in time (issue 15, item 4): the twitch superposition against closed forms summed
//! by hand, the activation level as one scale with the damage, and the activation-in-time study
//! against the uniaxial study, the passive material and the free-contraction equation; the nearly
//! incompressible block against its own equilibrium equations, finite differences and the exact
//! block as κ → ∞.

use activemuscle::active::time::{
    ActivationInTime, Interpolation, MotorUnit, MotorUnits, Schedule,
};
use activemuscle::active::{
    ActivationLaw, ActivationMap, ActiveCurve, Coupling, Drive, FrozenTangent, ImplicitLaw, Law,
};
use activemuscle::energy::GiantesioMusesti;
use activemuscle::invariants::{Kinematics, FULL};
use activemuscle::models::{CouplingKind, LawKind, ModelChoice, Models};
use activemuscle::response::Order;
use activemuscle::scene::{RunOptions, Scene};
use activemuscle::studies::history::HistoryResult;
use activemuscle::studies::{Stop, StudyResult};
use activemuscle::uniaxial::{
    along_fibres, free_contraction, nearly_incompressible, nearly_incompressible_free_contraction,
    nearly_incompressible_with_slope, Direction,
};
use activemuscle::volumetric::{Volumetric, VolumetricForm};
use activemuscle::Muscle;
use nalgebra::{Matrix3, Vector3};

const FILE: &str = "time.toml";

fn one_type(force: f64, t_c: f64, i: f64) -> MotorUnits {
    MotorUnits::new(vec![MotorUnit::new(1.0, force, t_c, i).unwrap()]).unwrap()
}

/// G = (1 − e^{−2x³})/x, x = T/I, with 1 − e^{−y} as −expm1(−y) (no cancellation for small x).
fn gain(t_c: f64, i: f64) -> f64 {
    let x = t_c / i;
    -(-2.0 * x * x * x).exp_m1() / x
}

#[test]
fn one_stimulus_gives_one_twitch_peaking_at_the_contraction_time() {
    // One stimulus at 0.1 s (the next would come at 10.1 s): a(t) = a_s G F (s/T) e^{1 − s/T}.
    let (f, t_c, i, a_s) = (0.3, 0.05, 10.0, 0.8);
    let act = ActivationInTime::new(
        Schedule::new(vec![(0.1, a_s)], Interpolation::Constant).unwrap(),
        Some(one_type(f, t_c, i)),
    );
    let g = gain(t_c, i);
    // At the peak s = T: a_s G F exactly (e^0 = 1).
    let peak = act.level(0.1 + t_c);
    assert!((peak - a_s * g * f).abs() <= 1e-15 * peak, "{peak}");
    for s in [0.01, 0.07, 0.2, 1.0] {
        let by_hand = a_s * g * f * (s / t_c) * (1.0 - s / t_c).exp();
        let a = act.level(0.1 + s);
        assert!(
            (a - by_hand).abs() <= 1e-15 * by_hand,
            "s = {s}: {a} vs {by_hand}"
        );
    }
    assert_eq!(act.level(0.1), 0.0, "no twitch before or at its stimulus");
}

#[test]
fn a_train_of_stimuli_sums_to_its_geometric_series() {
    // Stimuli at t_j = j I, j = 0 … n−1 (t_{n−1} < t): Σ_j (t − jI)/T e^{1 − (t − jI)/T}
    //   = (e/T) e^{−t/T} [t S0 − I S1], S0 = Σ q^j = (q^n − 1)/(q − 1),
    //   S1 = Σ j q^j = q (1 − n q^{n−1} + (n − 1) q^n)/(1 − q)², q = e^{I/T}.
    let (f, t_c, i) = (0.35, 0.08, 0.025);
    let act = ActivationInTime::new(Schedule::constant(1.0).unwrap(), Some(one_type(f, t_c, i)));
    for (t, n) in [(0.06, 3), (0.2, 8), (0.4125, 17)] {
        let q: f64 = (i / t_c).exp();
        let s0 = (q.powi(n) - 1.0) / (q - 1.0);
        let s1 = q * (1.0 - n as f64 * q.powi(n - 1) + (n - 1) as f64 * q.powi(n))
            / ((1.0 - q) * (1.0 - q));
        let sum = std::f64::consts::E / t_c * (-t / t_c).exp() * (t * s0 - i * s1);
        let by_hand = gain(t_c, i) * f * sum;
        let a = act.level(t);
        assert!(
            (a - by_hand).abs() <= 1e-13 * by_hand,
            "t = {t}: {a} vs {by_hand}"
        );
    }
}

#[test]
fn each_schedule_interval_restarts_its_train_weighted_by_its_value() {
    // 4C's intervals: [0, 0.05) at 1 fires t = 0, 0.03; [0.05, ∞) at 0.5 fires 0.05, 0.08, ….
    let (f, t_c, i) = (0.3, 0.04, 0.03);
    let act = ActivationInTime::new(
        Schedule::new(vec![(0.0, 1.0), (0.05, 0.5)], Interpolation::Constant).unwrap(),
        Some(one_type(f, t_c, i)),
    );
    let tw = |s: f64| f * (s / t_c) * (1.0 - s / t_c).exp();
    let t = 0.1;
    let by_hand = gain(t_c, i) * (tw(t) + tw(t - 0.03) + 0.5 * (tw(t - 0.05) + tw(t - 0.08)));
    assert!((act.level(t) - by_hand).abs() <= 1e-15 * by_hand);
}

#[test]
fn two_motor_unit_types_add_by_their_fractions() {
    let (slow, fast) = (
        MotorUnit::new(0.3, 0.3, 0.1, 0.05).unwrap(),
        MotorUnit::new(0.7, 0.3, 0.04, 0.02).unwrap(),
    );
    let both = ActivationInTime::new(
        Schedule::constant(1.0).unwrap(),
        Some(MotorUnits::new(vec![slow, fast]).unwrap()),
    );
    let alone = |u: MotorUnit| {
        let u = MotorUnit::new(1.0, u.twitch_force, u.contraction_time, u.interstimulus).unwrap();
        ActivationInTime::new(
            Schedule::constant(1.0).unwrap(),
            Some(MotorUnits::new(vec![u]).unwrap()),
        )
    };
    for t in [0.05, 0.13, 0.5] {
        let sum = 0.3 * alone(slow).level(t) + 0.7 * alone(fast).level(t);
        assert!((both.level(t) - sum).abs() <= 1e-15 * sum);
    }
}

#[test]
fn activation_level_and_damage_are_one_scale_of_the_active_curve() {
    let law = ImplicitLaw::new(GiantesioMusesti::paper(), ActiveCurve::paper());
    // a = 1 leaves the damage as given and a = 0 is full loss, exactly, for any d.
    let effective_damage = |d, a| Drive::new(d, a).map(|drive| drive.effective_damage());
    for d in [0.0, 0.1, 0.3, 0.7, 1.0] {
        assert_eq!(effective_damage(d, 1.0).unwrap(), d);
        assert_eq!(effective_damage(d, 0.0).unwrap(), 1.0);
    }
    // (a, d) = (0.5, 0) is d = 0.5 exactly; (0.8, 0.25) is (1 − d) a = 0.6, d = 0.4, to rounding.
    for lambda in [0.8, 1.0, 1.17, 1.4] {
        let a = law.evaluate(lambda, Drive::new(0.0, 0.5).unwrap()).unwrap();
        let b = law.evaluate(lambda, 0.5).unwrap();
        assert_eq!(a, b);
        let a = law
            .activation(lambda, Drive::new(0.25, 0.8).unwrap())
            .unwrap();
        let b = law.activation(lambda, 0.4).unwrap();
        assert!((a - b).abs() < 1e-14, "lambda = {lambda}: {a} vs {b}");
    }
    // a > 1 (4C's twitch trains with P_opt = N_a) scales the curve beyond P_opt: the law at
    // a = 1.2 is the law of the curve with 1.2 P_opt.
    let paper = activemuscle::active::curve::ChapterCurve::PAPER;
    let strong = ImplicitLaw::new(
        GiantesioMusesti::paper(),
        ActiveCurve::chapter(0.6243, paper.lambda_opt(), paper.k(), 1.2 * paper.p_opt()).unwrap(),
    );
    for lambda in [0.8, 1.0, 1.17] {
        let a = law
            .activation(lambda, Drive::new(0.0, 1.2).unwrap())
            .unwrap();
        let b = strong.activation(lambda, 0.0).unwrap();
        assert!((a - b).abs() < 1e-13, "lambda = {lambda}: {a} vs {b}");
    }
    assert!(Drive::new(0.0, -0.1).is_err());
    assert!(Drive::new(0.0, f64::INFINITY).is_err());
    assert!(Drive::new(1.5, 1.0).is_err());
}

/// A muscle keeps d_eff = 1 − (1 − d)·a with its damage and level (`Muscle::effective`): however it
/// is built or changed, it answers with the law's γ at the d_eff computed here, and a refused level
/// changes nothing.
#[test]
fn a_muscle_answers_at_its_current_activation_level_however_it_was_set() {
    let law = ImplicitLaw::new(GiantesioMusesti::paper(), ActiveCurve::paper());
    let lambda = 1.1;
    let check = |muscle: &Muscle<GiantesioMusesti>, d: f64, a: f64| {
        let d_eff = 1.0 - (1.0 - d) * a;
        assert_eq!((muscle.damage(), muscle.activation_level()), (d, a));
        assert!(
            (muscle.effective_damage() - d_eff).abs() < 1e-15,
            "d = {d}, a = {a}"
        );
        let gamma = muscle.activation(lambda).unwrap().gamma;
        let expected = law.activation(lambda, d_eff).unwrap();
        assert!(
            (gamma - expected).abs() < 1e-13,
            "d = {d}, a = {a}: γ = {gamma} vs {expected}"
        );
    };
    let d = 0.3;
    let frozen = Coupling::Frozen(FrozenTangent::Exact);
    let mut muscle = Muscle::new(
        GiantesioMusesti::paper(),
        Law::Implicit(law.clone()),
        d,
        frozen,
    )
    .unwrap();
    check(&muscle, d, 1.0);
    muscle.set_activation(0.4).unwrap();
    check(&muscle, d, 0.4);
    assert!(muscle.set_activation(-0.5).is_err());
    assert!(muscle.set_activation(f64::NAN).is_err());
    check(&muscle, d, 0.4);
    muscle.set_activation(1.0).unwrap();
    check(&muscle, d, 1.0);
    let muscle = muscle
        .with_activation(0.25)
        .unwrap()
        .with_map(ActivationMap::Chapter)
        .unwrap();
    check(&muscle, d, 0.25);
    check(&muscle.clone(), d, 0.25);
    let passive = Muscle::passive(GiantesioMusesti::paper())
        .with_activation(0.5)
        .unwrap();
    assert_eq!(passive.effective_damage(), 0.5);
    assert_eq!(passive.activation(lambda).unwrap().gamma, 0.0);
}

fn models() -> Models {
    Models::paper()
}

fn choice(damage: f64) -> ModelChoice {
    ModelChoice {
        approach: activemuscle::active::Approach::ActiveStrain,
        law: LawKind::Implicit,
        coupling: CouplingKind::Frozen,
        damage,
    }
}

#[test]
fn free_contraction_has_zero_axial_stress_and_solves_the_target_equation() {
    let m = models();
    let passive = m.passive();
    for (d, a) in [(0.0, 1.0), (0.0, 0.05), (0.3, 0.6), (0.5, 0.001)] {
        let muscle = m.muscle(choice(d)).unwrap().with_activation(a).unwrap();
        let p = free_contraction(&muscle).unwrap();
        assert!(p.stress.abs() < 1e-12, "d = {d}, a = {a}: P = {}", p.stress);
        assert!(p.lambda < 1.0 && p.lambda > m.curve.lambda_min());
        // Independently of the law: P_pas(λ) + (1 − d) a P_act(λ) = 0 (eq. (12) with the scale),
        // whose left side increases on (λ_min, 1), so a sign change pins the root.
        let target =
            |l: f64| along_fibres(&passive, l).unwrap().stress + (1.0 - d) * a * m.curve.value(l);
        let h = 1e-9;
        assert!(
            target(p.lambda - h) < 0.0 && target(p.lambda + h) > 0.0,
            "d = {d}, a = {a}: root {} not bracketed by the target equation",
            p.lambda
        );
    }
    // The passive block does not move.
    let p = free_contraction(&passive).unwrap();
    assert!(
        (p.lambda - 1.0).abs() < 1e-12 && p.stress.abs() < 1e-12,
        "{p:?}"
    );
}

fn run(text: &str) -> (Scene, activemuscle::scene::Results) {
    let scene = Scene::parse(text, FILE).unwrap_or_else(|e| panic!("{e}"));
    let results = scene.run(&RunOptions::default());
    (scene, results)
}

fn history(results: &activemuscle::scene::Results, name: &str) -> HistoryResult {
    results
        .of::<HistoryResult>()
        .find(|(n, _)| *n == name)
        .map(|(_, h)| h.clone())
        .unwrap_or_else(|| panic!("no history {name}"))
}

#[test]
fn at_full_activation_the_history_is_the_uniaxial_curve_and_at_zero_the_passive_one() {
    let (_, results) = run(r#"
[[study]]
kind = "uniaxial"
name = "u"
stretch = [0.9, 1.1, 1.25]
damage = [0.0, 0.3]
laws = ["implicit"]
couplings = ["frozen"]

[[study]]
kind = "activation-in-time"
name = "on-off"
time = [0.0, 1.0, 1.5, 2.0, 2.5]
schedule = [[0.0, 1.0], [1.0, 0.0], [2.0, 1.0]]
stretch = [[0.0, 0.9], [1.0, 1.1], [2.0, 1.25]]
damage = [0.0, 0.3]
law = "implicit"
coupling = "frozen"
"#);
    assert!(
        results.complete(),
        "{:?}",
        results.failures().collect::<Vec<_>>()
    );
    let uni = results
        .of::<activemuscle::studies::uniaxial::UniaxialResult>()
        .next()
        .unwrap()
        .1
        .clone();
    let h = history(&results, "on-off");
    let m = models();
    let passive = m.passive();
    for hist in &h.histories {
        let curve = uni
            .curves
            .iter()
            .find(|c| {
                matches!(c.model, activemuscle::studies::uniaxial::CurveModel::Active(c)
                    if c.damage == hist.model.damage)
            })
            .unwrap();
        for p in &hist.points {
            if p.level == 1.0 {
                let u = curve.points.iter().find(|u| u.lambda == p.lambda).unwrap();
                assert_eq!(
                    p.stress, u.stress,
                    "t = {}: a = 1 must be the uniaxial value",
                    p.t
                );
                assert_eq!(p.gamma, u.gamma);
            } else {
                assert_eq!(p.level, 0.0);
                let pas = along_fibres(&passive, p.lambda).unwrap();
                assert_eq!(p.gamma, 0.0);
                assert_eq!(p.stress, pas.stress, "t = {}: a = 0 must be passive", p.t);
            }
        }
    }
    // The stretch schedule is linear in time: λ(1.5) = 1.175, λ(2.5) = 1.25 (held).
    let pts = &h.histories[0].points;
    assert!((pts[2].lambda - 1.175).abs() < 1e-15);
    assert_eq!(pts[4].lambda, 1.25);
}

#[test]
fn a_free_contraction_history_reports_zero_stress_and_the_shortening() {
    let (_, results) = run(r#"
[[study]]
kind = "activation-in-time"
name = "free"
time = { from = 0.0, to = 0.3, step = 0.01 }
schedule = [[0.0, 1.0], [0.2, 0.0]]
stretch = "free"
damage = [0.0]
motor_units = [{ fraction = 1.0, twitch_force = 0.3, contraction_time = 0.04, interstimulus = 0.02 }]
"#);
    assert!(
        results.complete(),
        "{:?}",
        results.failures().collect::<Vec<_>>()
    );
    let h = history(&results, "free");
    let pts = &h.histories[0].points;
    assert_eq!(pts.len(), 31);
    assert_eq!(pts[0].level, 0.0);
    assert_eq!(pts[0].lambda, 1.0, "no stimulus has fired at t = 0");
    for p in pts {
        assert!(p.stress.abs() < 1e-12, "t = {}: P = {}", p.t, p.stress);
        assert!(p.level <= 1.0 && p.level >= 0.0);
    }
    assert!(pts[10].lambda < 0.9, "activated: the block shortens");
}

#[test]
fn a_stop_request_ends_the_history_with_what_was_solved() {
    let scene = Scene::parse(
        "[[study]]\nkind = \"activation-in-time\"\ntime = [0.0, 1.0]\n",
        FILE,
    )
    .unwrap();
    let stop = Stop::new();
    stop.stop("time limit of 1 s (--max-seconds) reached");
    let ctx = activemuscle::studies::RunContext {
        progress: &activemuscle::studies::Silent,
        vtk_dir: None,
        stop: Some(&stop),
    };
    let study = &scene.studies[0];
    let outcome = study.run(&scene.models, &ctx).expect("runs");
    assert_eq!(outcome.points, 0);
    assert!(outcome.failures[0].message.contains("time limit"));
    assert!(matches!(outcome.result, StudyResult::ActivationInTime(_)));
}

/// U′(J) of the volumetric forms written out here (the chapter's energy is stress free at F = I,
/// so no linear term): quadratic κ(J − 1); 4C's −(μ/2) J^(−2κ−1) + μ/2.
fn du(form: VolumetricForm, j: f64) -> f64 {
    match form {
        VolumetricForm::Quadratic { kappa } => kappa * (j - 1.0),
        VolumetricForm::Giantesio4C { kappa, mu } => {
            -0.5 * mu * j.powf(-2.0 * kappa - 1.0) + 0.5 * mu
        }
        VolumetricForm::Logarithmic { kappa } => 0.5 * kappa * (j - 1.0 / j),
    }
}

const FORMS: [VolumetricForm; 4] = [
    VolumetricForm::Quadratic { kappa: 1e3 },
    VolumetricForm::Quadratic { kappa: 1e6 },
    VolumetricForm::Logarithmic { kappa: 1e4 },
    VolumetricForm::Giantesio4C {
        kappa: 50.0,
        mu: 0.033,
    },
];

#[test]
fn nearly_incompressible_free_contraction_has_zero_traction_on_every_face() {
    let m = models();
    for form in FORMS {
        let v = Volumetric::new(form, 0.0).unwrap();
        for (d, a) in [(0.0, 1.0), (0.3, 0.6), (0.5, 0.01)] {
            let muscle = m.muscle(choice(d)).unwrap().with_activation(a).unwrap();
            let p = nearly_incompressible_free_contraction(&muscle, &v).unwrap();
            let exact = free_contraction(&muscle).unwrap();
            // Independently: P = ∂Ŵ/∂F + U′(J) J F⁻ᵀ at F = diag(λ, λ₂, λ₃), every diagonal entry 0.
            let f = Vector3::new(p.lambda, p.lateral[0], p.lateral[1]);
            let j = f.product();
            let kin = Kinematics::new(&Matrix3::from_diagonal(&f), &Vector3::x()).unwrap();
            let r = muscle.respond(&kin, Order::Stress, &FULL).unwrap();
            let dw = r.stress.unwrap();
            // The scale the tractions balance: the active and passive stresses at that stretch.
            let scale = 1.0 + m.curve.value(p.lambda).abs() + dw[0].abs();
            for i in 0..3 {
                let traction = dw[4 * i] + du(form, j) * j / f[i];
                assert!(
                    traction.abs() < 1e-10 * scale,
                    "{form:?}, d = {d}, a = {a}: P_{i}{i} = {traction} kPa at {f:?}"
                );
            }
            assert!(p.stress.abs() < 1e-10 * scale, "{form:?}: P = {}", p.stress);
            assert!(
                j < 1.0 + 1e-3 && j > 0.5,
                "{form:?}, d = {d}, a = {a}: J = {j}"
            );
            // It shortens like the exact block, by nearly as much.
            assert!(
                p.lambda < 1.0 && (p.lambda - exact.lambda).abs() < 0.05,
                "{form:?}, d = {d}, a = {a}: λ = {} against {} exactly incompressible",
                p.lambda,
                exact.lambda
            );
        }
    }
}

#[test]
fn the_slope_of_the_nearly_incompressible_curve_passes_a_taylor_test() {
    let m = models();
    let muscle = m.muscle(choice(0.2)).unwrap().with_activation(0.7).unwrap();
    for form in FORMS {
        let v = Volumetric::new(form, 0.0).unwrap();
        for lambda in [0.8, 0.95, 1.1] {
            let (p, slope) =
                nearly_incompressible_with_slope(&muscle, &v, Direction::Along, lambda, true)
                    .unwrap();
            // |P(λ + h) − P(λ) − h P′(λ)| = O(h²): halving h quarters the remainder.
            let remainder = |h: f64| {
                let q = nearly_incompressible(&muscle, &v, Direction::Along, lambda + h).unwrap();
                (q.stress - p.stress - h * slope).abs()
            };
            let (r1, r2) = (remainder(1e-3), remainder(5e-4));
            assert!(
                r2 < 0.3 * r1 && r1 < 1e-3 * slope.abs().max(1.0),
                "{form:?}, λ = {lambda}: remainders {r1}, {r2} (slope {slope} kPa)"
            );
        }
    }
}

#[test]
fn the_nearly_incompressible_history_tends_to_the_exact_one_as_kappa_grows() {
    let scene = |incompressibility: &str, loading: &str| {
        format!(
            r#"{incompressibility}
[[study]]
kind = "activation-in-time"
name = "h"
time = {{ from = 0.0, to = 0.2, step = 0.02 }}
schedule = [[0.0, 1.0], [0.1, 0.3]]
{loading}
damage = [0.0, 0.4]
motor_units = [{{ fraction = 1.0, twitch_force = 0.3, contraction_time = 0.04, interstimulus = 0.02 }}]
"#
        )
    };
    for loading in ["stretch = \"free\"", "stretch = [[0.0, 0.9], [0.2, 1.2]]"] {
        let (_, exact) = run(&scene("", loading));
        assert!(exact.complete());
        let exact = history(&exact, "h");
        let mut previous = f64::INFINITY;
        for kappa in [1e4, 1e6, 1e8] {
            let (_, near) = run(&scene(
                &format!("[incompressibility]\nkind = \"quadratic\"\nkappa = {kappa}\n"),
                loading,
            ));
            assert!(near.complete(), "{:?}", near.failures().collect::<Vec<_>>());
            let near = history(&near, "h");
            // max over steps of |Δλ| + |ΔP|/μ-scale and |J − 1|: both O(1/κ).
            let mut gap: f64 = 0.0;
            for (he, hn) in exact.histories.iter().zip(&near.histories) {
                for (e, n) in he.points.iter().zip(&hn.points) {
                    assert_eq!((e.t, e.level), (n.t, n.level));
                    assert!((e.volume - 1.0).abs() < 1e-14, "exact J = {}", e.volume);
                    assert!(
                        (e.cauchy - e.stress * e.lambda).abs() <= 1e-12 * e.stress.abs().max(1.0),
                        "exact: σ = P λ"
                    );
                    assert!(
                        (n.cauchy * n.volume - n.stress * n.lambda).abs()
                            <= 1e-12 * n.stress.abs().max(1.0),
                        "σ J = P λ"
                    );
                    gap = gap
                        .max((e.lambda - n.lambda).abs())
                        .max((e.stress - n.stress).abs() / 100.0)
                        .max((n.volume - 1.0).abs());
                }
            }
            assert!(
                gap < 0.05 * previous,
                "{loading}, κ = {kappa} kPa: gap {gap} against {previous} at κ/100"
            );
            previous = gap;
        }
        assert!(previous < 1e-5, "{loading}: gap {previous} at κ = 1e8 kPa");
    }
}
