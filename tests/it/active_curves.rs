//! The battery every shipped active curve passes (issue 23, item 1), run over the registry
//! (`CURVES`), so that a new curve gets it without a line here: its dual-number derivatives
//! against finite differences (a Taylor test), its integral against its derivative and against
//! an independent quadrature, zero at and below its support, and every law reproducing the
//! target P_pas + (1 − d) P_act along the fibres to 1e-10. Ehret–Böl–Itskov's curve is also
//! checked against the formula as 4C prints it.

use activemuscle::active::{
    ActivationLaw, ActiveCurve, Coupling, CurveEntry, Drive, EnergyLaw, FrozenTangent, ImplicitLaw,
    Law, CURVES,
};
use activemuscle::energy::{EhretBolItskov, GiantesioMusesti};
use activemuscle::uniaxial::along_fibres;
use activemuscle::{Muscle, StrainEnergy};
use num_dual::{first_derivative, second_derivative};

/// Every shipped curve with its default parameters.
fn shipped() -> Vec<ActiveCurve> {
    CURVES
        .iter()
        .map(|c| c.default_curve().expect("every shipped curve has defaults"))
        .collect()
}

/// Stretches above the support, up to where the curves have decayed.
fn stretches(curve: &ActiveCurve) -> Vec<f64> {
    let lo = curve.lambda_min();
    (1..=40).map(|i| lo + 1.2 * i as f64 / 40.0).collect()
}

#[test]
fn every_shipped_curve_is_in_the_registry_once_with_defaults_in_range() {
    assert!(CURVES.len() >= 2);
    for (i, c) in CURVES.iter().enumerate() {
        assert!(CURVES[..i].iter().all(|o| o.name != c.name), "{}", c.name);
        let curve = c.default_curve().unwrap();
        assert_eq!(curve.name(), c.name);
        assert_eq!(CurveEntry::find(c.name).unwrap().name, c.name);
        for (p, v) in curve.parameters().iter().zip(curve.parameter_values()) {
            assert!(
                v >= p.range.0 && v <= p.range.1,
                "{}: {} = {v}",
                c.name,
                p.name
            );
        }
        // Rebuilt from its own values it is the same curve; a wrong count is refused.
        assert_eq!(curve.rebuilt(&curve.parameter_values()).unwrap(), curve);
        assert!(c.build(&[1.0]).is_err());
    }
    assert_eq!(CURVES[0].name, "chapter");
    assert_eq!(CURVES[0].default_curve().unwrap(), ActiveCurve::paper());
}

/// Taylor test: the remainder r(h) = P(λ + h) − P(λ) − h P′(λ) − h²/2 P″(λ) with the dual
/// numbers' P′, P″ shrinks like h³ (ratio 8 per halving); with a wrong P′ it would shrink like h.
#[test]
fn dual_number_derivatives_pass_a_taylor_test() {
    for curve in shipped() {
        for lambda in stretches(&curve) {
            let (p, p1, p2) = second_derivative(|l| curve.value(l), lambda);
            assert!((p - curve.value(lambda)).abs() <= 1e-14 * p.abs());
            let remainder = |h: f64| curve.value(lambda + h) - p - h * p1 - 0.5 * h * h * p2;
            // Steps small against the distance to λ_min, where the chapter's curve is flat to all
            // orders and its derivatives grow fast.
            let h = (1e-2f64).min((lambda - curve.lambda_min()) / 20.0);
            let (r1, r2) = (remainder(h).abs(), remainder(0.5 * h).abs());
            let scale = p.abs() + p1.abs() + p2.abs();
            if r1 < 1e-12 * scale {
                continue; // below rounding: nothing to measure
            }
            let ratio = r1 / r2;
            assert!(
                ratio > 6.0 && ratio < 10.0,
                "{} at λ = {lambda}: remainder ratio {ratio} (r = {r1:e}, {r2:e})",
                curve.name()
            );
        }
    }
}

/// The curve and its derivatives vanish at and below λ_min, in f64 and in dual numbers; so does
/// the integral; and the curve is positive just above.
#[test]
fn every_curve_is_zero_at_and_below_its_support() {
    for curve in shipped() {
        let lo = curve.lambda_min();
        for lambda in [0.05, 0.5 * lo, lo - 1e-9, lo] {
            let (p, p1, p2) = second_derivative(|l| curve.value(l), lambda);
            assert_eq!((p, p1, p2), (0.0, 0.0, 0.0), "{} at {lambda}", curve.name());
            assert_eq!(curve.integral(lambda), 0.0);
        }
        assert!(curve.value(lo + 0.05) > 0.0, "{}", curve.name());
        // Far above the peak it decays to 0 without a non-finite value.
        for lambda in [3.0, 20.0, 1e3] {
            let (p, p1, p2): (f64, f64, f64) = second_derivative(|l| curve.value(l), lambda);
            assert!(p.is_finite() && p1.is_finite() && p2.is_finite() && p >= 0.0);
            assert!(curve.integral(lambda).is_finite());
        }
    }
}

/// Composite Simpson on 20 000 panels with compensated summation: an independent quadrature.
fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    let n = 20_000;
    let h = (b - a) / n as f64;
    let (mut sum, mut c) = (0.0_f64, 0.0_f64);
    for i in 0..=n {
        let w = if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        let y = w * f(a + i as f64 * h) - c;
        let t = sum + y;
        c = (t - sum) - y;
        sum = t;
    }
    sum * h / 3.0
}

#[test]
fn the_integral_agrees_with_its_derivative_and_with_an_independent_quadrature() {
    for curve in shipped() {
        let lo = curve.lambda_min();
        for lambda in [lo + 0.01, lo + 0.2, 1.0, 1.17, 1.5, 2.0] {
            let integral = curve.integral(lambda);
            let reference = simpson(|s| curve.value(s), lo, lambda);
            let rel = (integral - reference).abs() / reference.abs();
            assert!(
                rel < 1e-12,
                "{} at {lambda}: {integral} vs {reference} ({rel:e})",
                curve.name()
            );
            // Its derivative is the curve (central differences of the integral).
            let h = 1e-5;
            let slope = (curve.integral(lambda + h) - curve.integral(lambda - h)) / (2.0 * h);
            let p = curve.value(lambda);
            assert!(
                (slope - p).abs() < 1e-7 * (1.0 + p),
                "{} at {lambda}: dI/dλ = {slope} vs P = {p}",
                curve.name()
            );
            // The closed form, where there is one, is the registry's quadrature to 1e-14.
            if curve.has_closed_integral() {
                let q = curve.quadrature(lambda);
                assert!(
                    (integral - q).abs() <= 1e-14 * q.abs(),
                    "{} at {lambda}: closed form {integral} vs quadrature {q}",
                    curve.name()
                );
            }
        }
    }
}

/// Ehret–Böl–Itskov's curve as 4C writes it (`evaluate_force_stretch_dependency_ehret` and its
/// integral), against the crate's rewritten forms.
#[test]
fn ehret_bol_itskov_curve_is_4c_s_formula() {
    let (lmin, lopt, popt) = (0.682, 1.192, 0.005207);
    let curve = ActiveCurve::ehret_bol_itskov(lmin, lopt, popt).unwrap();
    let e = |l: f64| {
        ((2.0 * lmin - l - lopt) * (l - lopt) / (2.0 * (lmin - lopt) * (lmin - lopt))).exp()
    };
    for l in [0.69, 0.8, 1.0, 1.192, 1.4, 2.0] {
        let p = popt * (l - lmin) / (lopt - lmin) * e(l);
        let integral = popt * (lmin - lopt) * (e(l) - 0.5_f64.exp());
        assert!((curve.value(l) - p).abs() <= 1e-15 * p, "{l}");
        assert!(
            (curve.integral(l) - integral).abs() <= 1e-12 * integral,
            "{l}: {} vs {integral}",
            curve.integral(l)
        );
        // 4C's derivative, evaluate_derivative_force_stretch_dependency_ehret.
        let d = popt * ((lmin - l).powi(2) - (lmin - lopt).powi(2)) / (lmin - lopt).powi(3) * e(l);
        let (_, slope) = first_derivative(|x| curve.value(x), l);
        assert!((slope - d).abs() <= 1e-12 * popt, "{l}: {slope} vs {d}");
    }
    assert_eq!(curve.value(lopt), popt);
    assert!(ActiveCurve::ehret_bol_itskov(1.2, 1.1, 1.0).is_err());
}

/// The uniaxial nominal stress along the fibres of `muscle` at λ, minus the passive stress.
fn active_part<E: StrainEnergy>(muscle: &Muscle<E>, passive: &Muscle<E>, lambda: f64) -> f64 {
    along_fibres(muscle, lambda).unwrap().stress - along_fibres(passive, lambda).unwrap().stress
}

/// Along the fibres every law reproduces the target (1 − d) P_act of every curve: the implicit
/// law with the frozen coupling (its equation), the energy law with the consistent coupling
/// (the derivative of its energy equation), and the active-stress approach by construction.
#[test]
fn each_law_reproduces_the_target_of_each_curve_to_1e_10() {
    let frozen = Coupling::Frozen(FrozenTangent::Exact);
    let energies = [
        activemuscle::Energy::GiantesioMusesti(GiantesioMusesti::paper()),
        activemuscle::Energy::EhretBolItskov(EhretBolItskov::paper()),
    ];
    for curve in shipped() {
        for energy in &energies {
            let passive = Muscle::passive(energy.clone());
            for d in [0.0, 0.4] {
                let implicit = Muscle::new(
                    energy.clone(),
                    Law::Implicit(ImplicitLaw::new(energy.clone(), curve)),
                    d,
                    frozen,
                )
                .unwrap();
                let consistent = Muscle::new(
                    energy.clone(),
                    Law::Energy(EnergyLaw::new(energy.clone(), curve)),
                    d,
                    Coupling::Consistent,
                )
                .unwrap();
                let stress = Muscle::active_stress(energy.clone(), curve, d).unwrap();
                for lambda in [0.8, 0.95, 1.1, 1.3] {
                    let target = Drive::from(d).target(&curve, lambda);
                    for (name, m) in [
                        ("implicit/frozen", &implicit),
                        ("energy/consistent", &consistent),
                        ("active stress", &stress),
                    ] {
                        let p = active_part(m, &passive, lambda);
                        assert!(
                            (p - target).abs() <= 1e-10 * (1.0 + target.abs()),
                            "{} curve, {}, {name}, d = {d}, λ = {lambda}: {p} vs {target}",
                            curve.name(),
                            energy.name()
                        );
                    }
                }
            }
        }
    }
}

/// Where the target is 0 (d = 1, a = 0, λ ≤ λ_min), every law gives γ = 0 — the explicit law too,
/// whose formula alone would give its approximation's offset (issue 24, item 1).
#[test]
fn every_law_is_inactive_where_the_target_is_zero() {
    let gm = GiantesioMusesti::paper();
    let curve = ActiveCurve::paper();
    let laws: Vec<Law<GiantesioMusesti>> = vec![
        Law::Implicit(ImplicitLaw::new(gm, curve)),
        Law::Energy(EnergyLaw::new(gm, curve)),
        Law::Explicit(activemuscle::active::ExplicitLaw::paper()),
    ];
    for law in &laws {
        for lambda in [0.5, 0.7, 1.0, 1.2, 1.5] {
            for drive in [
                Drive::from(1.0),
                Drive::new(0.0, 0.0).unwrap(),
                Drive::new(0.3, 0.0).unwrap(),
            ] {
                let v = law.evaluate(lambda, drive).unwrap();
                assert_eq!(
                    (v.gamma, v.slope, v.curvature),
                    (0.0, 0.0, 0.0),
                    "{} law at λ = {lambda}, {drive:?}",
                    law.name()
                );
            }
        }
        // Below λ_min at d = 0 the implicit and explicit laws are 0 (the energy law's default
        // zero-work branch is not: it continues γ so that Ψ stays continuous).
        if law.name() != "energy" {
            assert_eq!(law.activation(0.6, 0.0).unwrap(), 0.0);
        }
    }
}
