//! Activation laws: the implicit law solves eq. (13), the energy law its energy
//! counterpart; derivatives are exact; the couplings reproduce the active target curve.

use activemuscle::active::{
    ActivationLaw, ActiveCurve, Coupling, EnergyLaw, ExplicitLaw, FrozenTangent, ImplicitLaw, Law,
};
use activemuscle::energy::GiantesioMusesti;
use activemuscle::uniaxial::along_fibres;
use activemuscle::Muscle;
use num_dual::{first_derivative, Dual64};

fn gm() -> GiantesioMusesti {
    GiantesioMusesti::paper()
}
fn implicit() -> ImplicitLaw<GiantesioMusesti> {
    ImplicitLaw::new(gm(), ActiveCurve::paper())
}
fn energy_law() -> EnergyLaw<GiantesioMusesti> {
    EnergyLaw::new(gm(), ActiveCurve::paper())
}
/// 500 stretches in (λ_min, 1.6].
fn stretches() -> impl Iterator<Item = f64> {
    let lmin = ActiveCurve::paper().lambda_min();
    (1..=500).map(move |i| lmin + (1.6 - lmin) * i as f64 / 500.0)
}
/// P_pas + (1 − d) P_act [kPa].
fn target(l: f64, d: f64) -> f64 {
    along_fibres(&Muscle::passive(gm()), l).unwrap().stress
        + (1.0 - d) * ActiveCurve::paper().value(l)
}

#[test]
fn implicit_law_is_exact_to_1e_12() {
    let law = implicit();
    for d in [0.0, 0.3] {
        for l in stretches() {
            let g = law.evaluate(l, d).unwrap().gamma;
            let r = law.residual(l, g, d);
            assert!(
                r.abs() <= 1e-12 * target(l, d).abs().max(1.0),
                "lambda {l}, d {d}: residual {r} kPa"
            );
        }
    }
}

#[test]
fn implicit_law_matches_the_checked_values() {
    let law = implicit();
    for (l, expected, tol) in [
        (0.8, 0.3293, 1e-4),
        (1.0, 0.24326, 1e-5),
        (1.17, 0.14895, 1e-5),
        (1.4, 0.0215, 1e-4),
    ] {
        let g = law.evaluate(l, 0.0).unwrap().gamma;
        assert!(
            (g - expected).abs() < tol,
            "gamma({l}) = {g}, expected {expected}"
        );
    }
    // Ill-conditioned just above λ_min: γ climbs from ≈ 0 to ≈ 0.30 between 0.65 and 0.70.
    assert!(law.evaluate(0.65, 0.0).unwrap().gamma < 1e-3);
    assert!((law.evaluate(0.70, 0.0).unwrap().gamma - 0.30).abs() < 0.01);
}

#[test]
fn energy_law_matches_the_checked_value_and_solves_its_equation() {
    let law = energy_law();
    assert!((law.evaluate(1.17, 0.0).unwrap().gamma - 0.1919).abs() < 1e-4);
    for d in [0.0, 0.5] {
        for l in stretches().step_by(5) {
            let g = law.evaluate(l, d).unwrap().gamma;
            let scale = ActiveCurve::paper().integral(l).max(1e-3);
            assert!(
                law.residual(l, g, d).abs() < 1e-12 * scale.max(1.0),
                "lambda {l}"
            );
        }
    }
}

/// dγ/dλ and d²γ/dλ² against central differences of γ and of dγ/dλ.
fn check_derivatives(law: &impl ActivationLaw, name: &str, range: (f64, f64)) {
    let h = 1e-5;
    for i in 0..=40 {
        let l = range.0 + (range.1 - range.0) * i as f64 / 40.0;
        let v = law.evaluate(l, 0.2).unwrap();
        assert_eq!(
            law.activation(l, 0.2).unwrap(),
            v.gamma,
            "{name}: gamma alone = gamma with derivatives"
        );
        let (gamma, slope) = law.gamma_and_slope(l, 0.2).unwrap();
        assert!(
            gamma == v.gamma && (slope - v.slope).abs() <= 1e-14 * v.slope.abs().max(1.0),
            "{name}: (gamma, slope) alone = ({gamma}, {slope}), with the curvature ({}, {})",
            v.gamma,
            v.slope
        );
        let (up, down) = (
            law.evaluate(l + h, 0.2).unwrap(),
            law.evaluate(l - h, 0.2).unwrap(),
        );
        let slope_fd = (up.gamma - down.gamma) / (2.0 * h);
        let curvature_fd = (up.slope - down.slope) / (2.0 * h);
        assert!(
            (slope_fd - v.slope).abs() < 1e-6 * v.slope.abs().max(1.0),
            "{name} slope at {l}: {} vs fd {slope_fd}",
            v.slope
        );
        assert!(
            (curvature_fd - v.curvature).abs() < 1e-5 * v.curvature.abs().max(1.0),
            "{name} curvature at {l}: {} vs fd {curvature_fd}",
            v.curvature
        );
        // The generic evaluation carries the same slope through a dual number.
        let (_, slope) = first_derivative(|x: Dual64| law.gamma(x, 0.2).unwrap(), l);
        assert!((slope - v.slope).abs() <= 1e-12 * v.slope.abs().max(1.0));
    }
}

#[test]
fn law_derivatives_agree_with_finite_differences() {
    check_derivatives(&implicit(), "implicit", (0.7, 1.6));
    check_derivatives(
        &Law::<GiantesioMusesti>::Explicit(ExplicitLaw::paper()),
        "explicit through Law",
        (0.7, 1.6),
    );
    check_derivatives(&energy_law(), "energy", (0.7, 1.6));
    check_derivatives(&ExplicitLaw::paper(), "explicit", (0.7, 1.6));
}

#[test]
fn explicit_law_approximates_the_implicit_law_and_vanishes_near_1_73() {
    let (ex, im) = (ExplicitLaw::paper(), implicit());
    let mut worst: f64 = 0.0;
    for i in 0..=70 {
        let l = 0.8 + 0.01 * i as f64;
        worst = worst
            .max((ex.evaluate(l, 0.0).unwrap().gamma - im.evaluate(l, 0.0).unwrap().gamma).abs());
    }
    println!("max |gamma_explicit - gamma_implicit| on [0.8, 1.5] = {worst:.3e}");
    assert!(worst < 3e-3 && worst > 1e-5);
    // The chapter says the explicit γ is negative for λ ≥ 1.6; as printed it stays positive to ≈ 1.73.
    let (mut lo, mut hi) = (1.5, 2.0);
    for _ in 0..50 {
        let mid = 0.5 * (lo + hi);
        if ex.evaluate(mid, 0.0).unwrap().gamma > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    println!("explicit gamma reaches 0 at lambda = {lo:.4}");
    assert!(ex.evaluate(1.6, 0.0).unwrap().gamma > 0.0);
    assert!((1.70..1.76).contains(&lo), "zero crossing at {lo}");
}

fn worst_relative_gap(muscle: &Muscle<GiantesioMusesti>, d: f64) -> (f64, f64) {
    let (mut rel, mut abs): (f64, f64) = (0.0, 0.0);
    for l in stretches() {
        let (p, t) = (along_fibres(muscle, l).unwrap().stress, target(l, d));
        abs = abs.max((p - t).abs());
        rel = rel.max((p - t).abs() / t.abs().max(1.0));
    }
    (rel, abs)
}

#[test]
fn energy_law_with_consistent_coupling_reproduces_the_target_curve() {
    for d in [0.0, 0.25, 0.5] {
        let muscle = Muscle::new(gm(), Law::Energy(energy_law()), d, Coupling::Consistent).unwrap();
        let (rel, _) = worst_relative_gap(&muscle, d);
        assert!(rel < 1e-10, "d = {d}: {rel:e}");
    }
}

#[test]
fn implicit_law_with_frozen_coupling_reproduces_the_target_curve() {
    for d in [0.0, 0.25, 0.5] {
        let muscle = Muscle::new(
            gm(),
            Law::Implicit(implicit()),
            d,
            Coupling::Frozen(FrozenTangent::Exact),
        )
        .unwrap();
        let (rel, _) = worst_relative_gap(&muscle, d);
        assert!(rel < 1e-10, "d = {d}: {rel:e}");
    }
}

#[test]
fn mismatched_pairs_miss_the_target_by_kilopascals() {
    let frozen = Coupling::Frozen(FrozenTangent::Exact);
    for d in [0.0, 0.5] {
        let explicit_frozen =
            Muscle::new(gm(), Law::Explicit(ExplicitLaw::paper()), d, frozen).unwrap();
        let implicit_consistent =
            Muscle::new(gm(), Law::Implicit(implicit()), d, Coupling::Consistent).unwrap();
        let (re, ae) = worst_relative_gap(&explicit_frozen, d);
        let (ri, ai) = worst_relative_gap(&implicit_consistent, d);
        println!("d = {d}: explicit/frozen max gap {ae:.3} kPa (rel {re:.2e}); implicit/consistent max gap {ai:.3} kPa (rel {ri:.2e})");
        assert!(
            ae > 0.1 && ai > 0.1,
            "a different model cannot reproduce the target exactly"
        );
    }
}

#[test]
fn the_energy_law_continues_continuously_below_lambda_min() {
    use activemuscle::active::BelowMinimum;
    let lmin = ActiveCurve::paper().lambda_min();
    let (continuous, jumping) = (
        energy_law(),
        energy_law().below_minimum(BelowMinimum::Inactive),
    );
    // A fine grid across λ_min (and across the stretch ≈ λ_min + 6e-4 where ∫P_act leaves 0 in f64).
    let grid: Vec<f64> = (0..=400)
        .map(|i| lmin - 0.002 + 0.00001 * i as f64)
        .collect();
    let gammas: Vec<f64> = grid
        .iter()
        .map(|&l| continuous.evaluate(l, 0.0).unwrap().gamma)
        .collect();
    let worst = gammas
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .fold(0.0, f64::max);
    assert!(
        worst < 1e-5,
        "gamma continuous across lambda_min: largest step {worst:e} over 1e-5 in lambda"
    );
    assert!(gammas.iter().all(|g| *g > 0.2), "on the zero-work branch");
    assert_eq!(jumping.evaluate(lmin - 1e-8, 0.0).unwrap().gamma, 0.0);
    assert!(
        jumping.evaluate(lmin + 0.01, 0.0).unwrap().gamma > 0.2,
        "the inactive variant jumps"
    );
    // At λ_min itself, not where ∫P_act leaves 0 in f64 (≈ 6e-4 above it).
    assert!(jumping.evaluate(lmin + 1e-6, 0.0).unwrap().gamma > 0.2);
    assert_eq!(jumping.evaluate(lmin, 0.0).unwrap().gamma, 0.0);
    // Zero active work below λ_min: Ŵ(λ, γ) = W_pas(λ), and the consistent stress is P_pas.
    for l in [0.5, 0.55, 0.6, 0.62] {
        let g = continuous.evaluate(l, 0.3).unwrap().gamma;
        assert!(continuous.residual(l, g, 0.3).abs() < 1e-13);
        let muscle = Muscle::new(
            gm(),
            Law::Energy(continuous.clone()),
            0.3,
            Coupling::Consistent,
        )
        .unwrap();
        let (p, pas) = (along_fibres(&muscle, l).unwrap().stress, target(l, 0.3));
        assert!(
            (p - pas).abs() < 1e-10 * pas.abs(),
            "lambda {l}: {p} vs {pas}"
        );
    }
    // Full damage: no activation at all.
    assert_eq!(continuous.evaluate(0.6, 1.0).unwrap().gamma, 0.0);
}

/// ∫_{λ_min}^{λ} P_act against composite Simpson on 200 000 intervals (a different rule, step
/// ≤ 6e-6): to 2e-15 kPa + 1e-13 relative (equal 0.05 panels were 4e-15 kPa off at λ = 0.674,
/// where the integral is 2.4e-4 kPa and the integrand flat to all orders at λ_min).
#[test]
fn active_work_integral_matches_a_fine_simpson_rule() {
    let curve = ActiveCurve::paper();
    let lmin = curve.lambda_min();
    let simpson = |l: f64| {
        let n = 200_000;
        let h = (l - lmin) / n as f64;
        let inner: f64 = (1..n)
            .map(|i| curve.value(lmin + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 })
            .sum();
        (inner + curve.value(l)) * h / 3.0
    };
    for i in 1..=60 {
        let l = lmin + 1.1 * i as f64 / 60.0 - 0.004;
        let (quadrature, reference) = (curve.integral(l), simpson(l));
        let allowed = 2e-15 + 1e-13 * reference;
        assert!(
            (quadrature - reference).abs() <= allowed,
            "lambda {l}: {quadrature:e} vs {reference:e}"
        );
    }
    assert_eq!(curve.integral(lmin), 0.0);
}
