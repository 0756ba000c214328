//! Recovery: synthetic data from known parameters give them back — to 1e-8 from exact data, and
//! within the reported standard errors from data with 1 % seeded noise.

use activemuscle::active::ActiveCurve;
use activemuscle::energy::{EhretBolItskov, GiantesioMusesti};
use activemuscle::fit::{
    fit_active_curve, fit_passive, Data, Direction, FitOptions, FitSetup, Method,
};
use activemuscle::material::Muscle;
use activemuscle::uniaxial::{across_fibres, along_fibres};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

fn grid(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .collect()
}

/// Adds 0.01 max|P| ε to each value, ε standard normal (Box–Muller), seeded: 1 % noise of the
/// data's scale, the same at every point (the model of the standard errors s² (JᵀJ)⁻¹; noise
/// proportional to P would call for weights).
fn with_noise(data: &Data, seed: u64) -> Data {
    let mut rng = StdRng::seed_from_u64(seed);
    let scale = data.stress().iter().fold(0.0f64, |a, p| a.max(p.abs()));
    let noisy = data
        .stress()
        .iter()
        .map(|&p| {
            let (u1, u2): (f64, f64) = (rng.random::<f64>().max(1e-300), rng.random());
            let eps = (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos();
            p + 0.01 * scale * eps
        })
        .collect();
    Data::new(data.lambda().to_vec(), noisy).unwrap()
}

fn along(energy: GiantesioMusesti, lambda: Vec<f64>) -> Data {
    let m = Muscle::passive(energy);
    Data::sampled(lambda, |l| Ok(along_fibres(&m, l)?.stress)).unwrap()
}

const TRUE_ALPHA: f64 = 19.35;
const TRUE_W0: f64 = 0.7335;

#[test]
fn passive_parameters_are_recovered_to_1e_8_from_exact_data() {
    let data = along(GiantesioMusesti::paper(), grid(1.0, 1.5, 26));
    let start = GiantesioMusesti::new(0.1599, 15.0, 0.6).unwrap();
    let fit = fit_passive(&start, &[(Direction::Along, &data)], &FitSetup::new()).unwrap();
    println!("{}", fit.report);
    assert!(fit.report.converged);
    assert!((fit.energy.alpha() - TRUE_ALPHA).abs() < 1e-8 * TRUE_ALPHA);
    assert!((fit.energy.w0() - TRUE_W0).abs() < 1e-8);
}

#[test]
fn passive_parameters_are_recovered_within_their_standard_errors_from_noisy_data() {
    let data = with_noise(&along(GiantesioMusesti::paper(), grid(1.0, 1.5, 26)), 7);
    let start = GiantesioMusesti::new(0.1599, 15.0, 0.6).unwrap();
    let fit = fit_passive(&start, &[(Direction::Along, &data)], &FitSetup::new()).unwrap();
    let r = &fit.report;
    println!("{r}");
    for (name, truth) in [("alpha", TRUE_ALPHA), ("w0", TRUE_W0)] {
        let (v, se) = (r.value(name).unwrap(), r.standard_error(name).unwrap());
        assert!(se > 0.0 && se < 0.1 * truth, "{name}: se {se}");
        println!(
            "{name}: |error| = {:.2} standard errors",
            (v - truth).abs() / se
        );
        assert!(
            (v - truth).abs() < 3.0 * se,
            "{name}: {v} vs {truth} ± {se}"
        );
    }
}

#[test]
fn all_four_parameters_of_the_ebi_energy_come_back_from_tests_along_and_across() {
    let truth = EhretBolItskov::paper();
    let m = Muscle::passive(truth);
    let along = Data::sampled(grid(0.8, 1.5, 15), |l| Ok(along_fibres(&m, l)?.stress)).unwrap();
    let across = Data::sampled(grid(0.8, 1.5, 15), |l| Ok(across_fibres(&m, l)?.stress)).unwrap();
    let start = EhretBolItskov::new(0.12, 17.0, 1.5, 0.7).unwrap();
    let setup = FitSetup::new().free(&["mu", "alpha", "beta", "w0"]);
    let fit = fit_passive(
        &start,
        &[(Direction::Along, &along), (Direction::Across, &across)],
        &setup,
    )
    .unwrap();
    println!("{}", fit.report);
    for (got, want) in [
        (fit.energy.mu(), truth.mu()),
        (fit.energy.alpha(), truth.alpha()),
        (fit.energy.beta(), truth.beta()),
        (fit.energy.w0(), truth.w0()),
    ] {
        assert!((got - want).abs() < 1e-8 * want, "{got} vs {want}");
    }
}

#[test]
fn active_curve_is_recovered_from_exact_and_noisy_data() {
    let truth = ActiveCurve::paper();
    let data = Data::sampled(grid(0.7, 1.7, 41), |l| Ok(truth.value(l))).unwrap();
    let start = ActiveCurve::chapter(0.55, 1.1, 0.6, truth.parameter("p_opt").unwrap()).unwrap();
    let fit = fit_active_curve(&start, &data, &FitSetup::new()).unwrap();
    println!("{}", fit.report);
    let c = fit.curve;
    assert!((c.lambda_min() - truth.lambda_min()).abs() < 1e-8);
    assert!(
        (c.parameter("lambda_opt").unwrap() - truth.parameter("lambda_opt").unwrap()).abs() < 1e-8
    );
    assert!((c.parameter("k").unwrap() - truth.parameter("k").unwrap()).abs() < 1e-8);

    let noisy = with_noise(&data, 11);
    let fit = fit_active_curve(&start, &noisy, &FitSetup::new()).unwrap();
    println!("{}", fit.report);
    let r = &fit.report;
    for (name, t) in [
        ("lambda_min", truth.lambda_min()),
        ("lambda_opt", truth.parameter("lambda_opt").unwrap()),
        ("k", truth.parameter("k").unwrap()),
    ] {
        let (v, se) = (r.value(name).unwrap(), r.standard_error(name).unwrap());
        println!(
            "{name}: |error| = {:.2} standard errors",
            (v - t).abs() / se
        );
        assert!((v - t).abs() < 3.0 * se, "{name}: {v} vs {t} ± {se}");
    }
}

#[test]
fn nelder_mead_then_gauss_newton_recovers_from_a_poor_start() {
    let data = along(GiantesioMusesti::paper(), grid(1.0, 1.5, 26));
    let start = GiantesioMusesti::new(0.1599, 8.0, 0.4).unwrap();
    let options = FitOptions {
        method: Method::NelderMead,
        ..FitOptions::default()
    };
    let fit = fit_passive(
        &start,
        &[(Direction::Along, &data)],
        &FitSetup::new().options(options),
    )
    .unwrap();
    println!("{}", fit.report);
    assert!((fit.energy.alpha() - TRUE_ALPHA).abs() < 1e-8 * TRUE_ALPHA);
    assert!((fit.energy.w0() - TRUE_W0).abs() < 1e-8);
}
