//! Böl & Reese's force–velocity factor within its range: its parameters are checked when a
//! scene is read (d_c ∈ [0, 1]: 1 − d_c is the force left at the fastest shortening), the factor
//! is never negative (clamped at 0 beyond the curve's range, where the formula turns negative),
//! and a history that shortens faster than |λ̇_min| says so in a failure line instead of a
//! pushing active stress and a negative target column.

use activemuscle::active::ForceVelocity;
use activemuscle::scene::{RunOptions, Scene};
use activemuscle::studies::StudyResult;

/// The shortening branch as Böl & Reese (2008) write it, r = λ̇/λ̇_min, without any clamp.
fn shortening(fv: &ForceVelocity, rate: f64) -> f64 {
    let r = rate / fv.min_rate;
    (1.0 - fv.dc) + fv.dc * (1.0 - r) / (1.0 + fv.kc * r)
}

fn refused(force_velocity: &str) -> String {
    let text = format!(
        "[activation]\nforce_velocity = {force_velocity}\n[[study]]\nkind = \"activation-in-time\"\n\
         time = [0, 1]\n"
    );
    match Scene::parse(&text, "scene.toml") {
        Ok(_) => panic!("accepted: {force_velocity}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn parameters_outside_their_ranges_are_refused_when_the_scene_is_read() {
    let with = |dc: &str, de: &str| {
        format!("{{ min_rate = -17.0, ke = 5.0, kc = 5.0, de = {de}, dc = {dc} }}")
    };
    for dc in ["5.0", "1e300", "1.0000001", "-0.1"] {
        let e = refused(&with(dc, "0.5"));
        assert!(
            e.contains("activation.force_velocity.dc") && e.contains("[0, 1]"),
            "{e}"
        );
        assert!(!e.contains("00000000000"), "numbers written short: {e}");
    }
    let e = refused(&with("1.0", "-0.5"));
    assert!(e.contains("activation.force_velocity.de"), "{e}");
    let e = refused("{ min_rate = 0.0, ke = 5.0, kc = 5.0, de = 0.5, dc = 1.0 }");
    assert!(e.contains("activation.force_velocity.min_rate"), "{e}");
    for dc in ["0.0", "1.0", "0.5"] {
        let text = format!(
            "[activation]\nforce_velocity = {}\n[[study]]\nkind = \"activation-in-time\"\ntime = [0, 1]\n",
            with(dc, "0.5")
        );
        Scene::parse(&text, "scene.toml").unwrap_or_else(|e| panic!("dc = {dc}: {e}"));
    }
}

#[test]
fn the_factor_is_the_formula_within_its_range_and_never_negative_beyond() {
    for (kc, dc) in [(5.0, 1.0), (0.2, 0.9), (0.0, 0.5), (5.0, 0.3)] {
        let fv = ForceVelocity::new(-17.0, 5.0, kc, 0.5, dc).unwrap();
        assert_eq!(fv.factor(0.0), 1.0);
        assert!((fv.factor(fv.min_rate) - (1.0 - dc)).abs() < 1e-15);
        for i in 0..=400 {
            let rate = -60.0 + 0.3 * f64::from(i);
            let f = fv.factor(rate);
            assert!(f >= 0.0, "kc = {kc}, dc = {dc}: f_v({rate}) = {f}");
            if rate <= 0.0 {
                // Within the range the formula itself, beyond it the formula clamped at 0.
                let exact = shortening(&fv, rate);
                assert_eq!(fv.within_range(rate), rate >= fv.min_rate);
                let expected = if fv.within_range(rate) {
                    exact
                } else {
                    exact.max(0.0)
                };
                assert!((f - expected).abs() < 1e-14, "{rate}: {f} vs {expected}");
            } else {
                assert!(f >= 1.0 && fv.within_range(rate), "lengthening: {f}");
            }
        }
    }
    // With d_c = 1 the formula turns negative right past λ̇_min: the clamp, with zero slope.
    let fv = ForceVelocity::new(-17.0, 5.0, 5.0, 0.5, 1.0).unwrap();
    assert!(shortening(&fv, -20.0) < 0.0);
    let slope = num_dual::first_derivative(|r| fv.factor(r), -20.0).1;
    assert_eq!((fv.factor(-20.0), slope), (0.0, 0.0));
}

/// A history prescribed from λ = 1.2 to 0.8 in 0.2 s (λ̇ = −2 /s over the steps of 0.1 s that
/// follow λ's kinks) with λ̇_min = −1 /s, under `approach`.
fn fast_shortening(approach: &str) -> (Vec<activemuscle::studies::history::HistoryPoint>, String) {
    let text = format!(
        "[activation]\napproach = \"{approach}\"\n\
         force_velocity = {{ min_rate = -1.0, ke = 5.0, kc = 5.0, de = 0.5, dc = 1.0 }}\n\
         [[study]]\nkind = \"activation-in-time\"\ntime = {{ from = 0.0, to = 1.0, step = 0.1 }}\n\
         stretch = [[0, 1.2], [0.2, 0.8]]\n"
    );
    let results = Scene::parse(&text, "scene.toml")
        .unwrap()
        .run(&RunOptions::default());
    let outcome = &results.studies[0];
    let StudyResult::ActivationInTime(h) = &outcome.result else {
        panic!("{:?}", outcome.failures)
    };
    let messages: Vec<String> = outcome.failures.iter().map(|f| f.message.clone()).collect();
    (h.histories[0].points.clone(), messages.join("\n"))
}

#[test]
fn a_history_shortening_faster_than_the_curve_is_flagged_and_its_active_stress_never_pushes() {
    for approach in ["active-stress", "active-strain"] {
        let (points, failures) = fast_shortening(approach);
        assert_eq!(points.len(), 11, "{approach}: every step computed");
        // The steps whose backward rate is below λ̇_min = −1 /s, counted here from the rows.
        let fast = points
            .windows(2)
            .filter(|w| (w[1].lambda - w[0].lambda) / (w[1].t - w[0].t) < -1.0)
            .count();
        assert_eq!(fast, 2);
        assert!(
            failures.contains(&format!(
                "force-velocity beyond its range at {fast} of 11 steps"
            )) && failures.contains("from t = 0.1 s")
                && failures.contains("min_rate = -1"),
            "{approach}: {failures}"
        );
        for p in &points {
            assert!(p.active_target >= 0.0, "{approach}: {p:?}");
            if approach == "active-stress" {
                // P = P_pas + f_v (1 − d) a P_act with f_v ≥ 0: never below the passive stress.
                assert!(p.stress >= p.passive - 1e-9, "{approach}: {p:?}");
            }
        }
    }
}
