//! Every iterative loop outside the FE solver ends, with a typed error naming what did not
//! converge, for any input (issue 11, defect 2): the root finder, the activation laws' solves,
//! the active curve's integral and the lateral equilibrium across the fibres. Each case runs on
//! its own thread under a generous deadline, so a regression to an unbounded loop fails the test
//! instead of hanging CI.

use crate::deadline;
use activemuscle::active::{ActivationLaw, ActiveCurve, EnergyLaw, ImplicitLaw};
use activemuscle::energy::GiantesioMusesti;
use activemuscle::roots::{newton_bisection, MAX_ITERATIONS};
use activemuscle::text::shortest;
use activemuscle::uniaxial::{across_fibres, along_fibres};
use activemuscle::{Error, Muscle};
use deadline::within;
use std::cell::Cell;

#[test]
fn the_root_finder_stops_at_its_cap_and_says_where_it_was() {
    // A step function (never exactly 0, no usable derivative) and a NaN tolerance that can never
    // be met: only the cap ends the search.
    let calls = Cell::new(0);
    let a = std::f64::consts::PI / 10.0;
    let r = newton_bisection(
        |x| {
            calls.set(calls.get() + 1);
            (if x < a { -1.0 } else { 1.0 }, 0.0)
        },
        0.0,
        1.0,
        f64::NAN,
    );
    assert_eq!(calls.get(), MAX_ITERATIONS);
    let message = r.expect_err("a NaN tolerance cannot converge");
    assert!(
        message.contains("200 iterations") && message.contains("bracket"),
        "{message}"
    );
    // The same root with a tolerance: found, and equal to the closed form.
    let x = newton_bisection(|x| (x * x - 2.0, 2.0 * x), 0.0, 2.0, 1e-15).unwrap();
    assert!((x - 2f64.sqrt()).abs() < 1e-15);
}

/// The exact laws at stretches from λ_min to far beyond where P_tot overflows: a root whose
/// residual (computed by the law's own residual function, not the solver) vanishes, or a typed
/// error naming the equation and the stretch.
#[test]
fn the_exact_laws_end_at_any_stretch_with_a_root_or_a_typed_error() {
    within(120, || {
        let (energy, curve) = (GiantesioMusesti::paper(), ActiveCurve::paper());
        let implicit = ImplicitLaw::new(energy, curve);
        let law = EnergyLaw::new(energy, curve);
        let passive = Muscle::passive(energy);
        let lambda_min = curve.lambda_min();
        for lambda in [
            lambda_min * (1.0 + 1e-15),
            lambda_min + 1e-9,
            0.65,
            1.9,
            2.0,
            3.0,
            5.0,
            8.0,
            50.0,
            1e6,
            1e300,
        ] {
            for d in [0.0, 0.5] {
                match implicit.activation(lambda, d) {
                    Ok(g) => {
                        // Relative to the stresses it balances, P_pas + (1 − d) P_act (where
                        // P_pas overflows, P_act = 0 and γ = 0 by definition).
                        if let Ok(p) = along_fibres(&passive, lambda) {
                            let scale = p.stress.abs() + (1.0 - d) * curve.value(lambda);
                            let r = implicit.residual(lambda, g, d);
                            assert!(r.abs() <= 1e-12 * scale, "{lambda}: {r} of {scale}");
                        } else {
                            assert_eq!((g, curve.value(lambda)), (0.0, 0.0));
                        }
                    }
                    Err(Error::NoSolution { equation, reason }) => {
                        // The stretch as messages write numbers: short (1e300, not 301 digits).
                        assert!(
                            equation.contains(&format!("lambda = {}", shortest(lambda)))
                                && equation.len() < 120,
                            "{equation}"
                        );
                        println!("implicit, {lambda}: {reason}");
                    }
                    Err(e) => println!("implicit, {lambda}: {e}"),
                }
                match law.activation(lambda, d) {
                    Ok(g) => {
                        let r = law.residual(lambda, g, d);
                        assert!(r.is_finite(), "{lambda}: {r}");
                    }
                    Err(Error::NoSolution { equation, reason }) => {
                        // The stretch as messages write numbers: short (1e300, not 301 digits).
                        assert!(
                            equation.contains(&format!("lambda = {}", shortest(lambda)))
                                && equation.len() < 120,
                            "{equation}"
                        );
                        println!("energy, {lambda}: {reason}");
                    }
                    Err(e) => println!("energy, {lambda}: {e}"),
                }
            }
        }
    });
}

/// P_act is exactly 0 past λ ≈ 12.6 for the chapter's curve, so ∫ P_act is the same to any
/// larger stretch; the integral to 1e12 once took 2·10¹³ panels.
#[test]
fn the_active_work_to_a_huge_stretch_is_the_work_to_where_p_act_vanishes() {
    let curve = ActiveCurve::paper();
    for l in [13.0, 20.0, 1e3, 1e9] {
        assert_eq!(curve.value(l), 0.0);
    }
    let (near, far) = within(60, move || (curve.integral(14.0), curve.integral(1e12)));
    assert!(
        near > 0.0 && (far - near).abs() <= 1e-13 * near,
        "{far} vs {near}"
    );
    // dW/dλ = P_act at 1.2 by central differences of the same integral (no shortcut there).
    let h = 1e-4;
    let slope = (curve.integral(1.2 + h) - curve.integral(1.2 - h)) / (2.0 * h);
    assert!((slope - curve.value(1.2)).abs() <= 1e-6 * curve.value(1.2));
}

#[test]
fn the_lateral_equilibrium_across_the_fibres_ends_at_any_stretch() {
    within(60, || {
        let m = Muscle::passive(GiantesioMusesti::paper());
        for lambda in [1e-300, 1e-6, 0.05, 8.0, 50.0, 1e6, 1e300] {
            match across_fibres(&m, lambda) {
                Ok(p) => assert!(p.stress.is_finite() && p.lateral[0] > 0.0, "{lambda}"),
                Err(e) => println!("across, {lambda}: {e}"),
            }
        }
    });
}
