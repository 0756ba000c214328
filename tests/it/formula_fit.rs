//! Fits a user can trust on their own energy: a formula energy's parameters come back from
//! synthetic data; a minimum beyond a bound is a result held at the bound, the others fitted as
//! without the parameter; weights (relative, or each datum's σ) give standard errors that cover
//! the truth on proportional noise, and a datum of huge σ weighs nothing; a scene's fit writes
//! each datum with the fitted model and its residual to fit_points.csv.

const POSITIVE: (f64, f64) = (0.0, f64::INFINITY);

/// A neo-Hookean matrix with Holzapfel-type fibres, c10 in `range`.
fn fibres(c10: f64, range: (f64, f64)) -> FormulaEnergy {
    let declared =
        |name: &str, unit: &str, value: f64, range| Parameter::declared(name, unit, value, range);
    FormulaEnergy::new(
        "c10*(I1 - 3) + k1/(2*k2)*expm1(k2*(I4 - 1)^2)",
        vec![
            declared("c10", "kPa", c10, range),
            declared("k1", "kPa", 0.4, POSITIVE),
            declared("k2", "-", 6.0, POSITIVE),
        ],
    )
    .unwrap()
}
use crate::scratch::scratch;
use activemuscle::energy::{FormulaEnergy, Parameter, Parametric};
use activemuscle::fit::{fit_passive, Data, Direction, FitReport, FitSetup, Weights};
use activemuscle::testing::Sampler;
use activemuscle::uniaxial::along_fibres;
use activemuscle::Muscle;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_activemuscle");

fn grid(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .collect()
}

/// The passive stress of `energy` along the fibres at `lambda`.
fn along(energy: &FormulaEnergy, lambda: Vec<f64>) -> Data {
    let m = Muscle::passive(energy.clone());
    Data::sampled(lambda, |l| Ok(along_fibres(&m, l)?.stress)).unwrap()
}

fn fit(energy: &FormulaEnergy, data: &Data, setup: &FitSetup) -> FitReport {
    let f =
        fit_passive(energy, &[(Direction::Along, data)], setup).unwrap_or_else(|e| panic!("{e}"));
    println!("{}", f.report);
    f.report
}

#[test]
fn a_formula_energys_parameters_come_back_from_its_own_curve() {
    let truth = fibres(0.12, POSITIVE);
    let data = along(&truth, grid(1.02, 1.35, 25));
    let start = truth.rebuilt(&[0.3, 1.0, 3.0]).unwrap();
    let r = fit(&start, &data, &FitSetup::new());
    assert!(r.converged);
    for (v, t) in r.values.iter().zip(truth.parameter_values()) {
        assert!((v - t).abs() < 1e-7 * t, "{v} vs {t}");
    }
}

/// The curve of [`fibres`] with c10 = −0.01: a fit with c10 > 0 has its minimum beyond c10 = 0.
fn negative_c10_data() -> Data {
    along(&fibres(-0.01, (-1.0, 1.0)), grid(1.02, 1.35, 25))
}

#[test]
fn a_minimum_beyond_a_bound_is_a_result_held_at_the_bound() {
    let data = negative_c10_data();
    let r = fit(&fibres(0.12, POSITIVE), &data, &FitSetup::new());
    assert!(r.converged, "{}", r.termination);
    let held = r.at_bound[0].expect("c10 at its bound");
    assert_eq!(held.bound, 0.0);
    assert!(held.beyond < 0.0, "the minimum lies below 0: {held:?}");
    assert!(
        r.values[0] >= 0.0 && r.values[0] < 1e-6,
        "c10 = {}",
        r.values[0]
    );
    assert!(r.standard_errors[0].is_nan());
    assert!(r.at_bound[1..].iter().all(Option::is_none));
    // The others are those of the fit of the fibre term alone (c10 = 0), fitted here.
    let without = FormulaEnergy::new(
        "k1/(2*k2)*expm1(k2*(I4 - 1)^2)",
        vec![
            Parameter::declared("k1", "kPa", 0.4, POSITIVE),
            Parameter::declared("k2", "-", 6.0, POSITIVE),
        ],
    )
    .unwrap();
    let other = fit(&without, &data, &FitSetup::new());
    for (a, b) in r.values[1..].iter().zip(&other.values) {
        assert!((a - b).abs() < 1e-6 * b.abs(), "{a} vs {b}");
    }
    // The standard errors of the others are those of that fit.
    for (a, b) in r.standard_errors[1..].iter().zip(&other.standard_errors) {
        assert!((a - b).abs() < 1e-3 * b.abs(), "{a} vs {b}");
    }
}

/// `data` with noise of `fraction` of each datum (Gaussian, seeded).
fn proportional_noise(data: &Data, fraction: f64, seed: u64) -> Data {
    let mut rng = Sampler::new(seed);
    let noisy = data
        .stress()
        .iter()
        .map(|p| p * (1.0 + fraction * rng.normal()))
        .collect();
    Data::new(data.lambda().to_vec(), noisy).unwrap()
}

#[test]
fn relative_weights_give_standard_errors_that_cover_the_truth_on_proportional_noise() {
    let truth = fibres(0.12, POSITIVE);
    let exact = along(&truth, grid(1.02, 1.35, 40));
    let mut worst_weighted: f64 = 0.0;
    for seed in 1..=4 {
        let data = proportional_noise(&exact, 0.03, seed);
        for (weights, name) in [(Weights::Equal, "equal"), (Weights::Relative, "relative")] {
            let r = fit(&truth, &data, &FitSetup::new().weights(weights.clone()));
            let distance = r
                .values
                .iter()
                .zip(&r.standard_errors)
                .zip(truth.parameter_values())
                .fold(0.0f64, |m, ((v, se), t)| m.max((v - t).abs() / se));
            println!(
                "seed {seed}, {name} weights: truth at most {distance:.2} standard errors away"
            );
            if weights == Weights::Relative {
                worst_weighted = worst_weighted.max(distance);
                assert_eq!(
                    r.sigma.as_deref(),
                    Some(&data.stress().iter().map(|p| p.abs()).collect::<Vec<_>>()[..])
                );
                // Residuals are reported in kPa, model − datum.
                assert!(
                    (r.residual_norm - r.residuals.iter().map(|x| x * x).sum::<f64>().sqrt()).abs()
                        < 1e-12
                );
            }
        }
    }
    assert!(worst_weighted < 3.5, "{worst_weighted}");
}

#[test]
fn a_datum_of_huge_sigma_weighs_nothing() {
    let truth = fibres(0.12, POSITIVE);
    let exact = along(&truth, grid(1.02, 1.35, 20));
    let mut stress = exact.stress().to_vec();
    stress[10] += 5.0; // an outlier
    let mut sigma = vec![0.01; stress.len()];
    sigma[10] = 1e12;
    let data = Data::new(exact.lambda().to_vec(), stress.clone())
        .unwrap()
        .with_sigma(sigma.clone())
        .unwrap();
    let start = truth.rebuilt(&[0.2, 0.5, 5.0]).unwrap();
    let weighted = fit(
        &start,
        &data,
        &FitSetup::new().weights(Weights::Sigma(sigma)),
    );
    // Independently: the same fit without the outlier.
    let (mut lambda, mut kept) = (exact.lambda().to_vec(), stress);
    lambda.remove(10);
    kept.remove(10);
    let without = fit(&start, &Data::new(lambda, kept).unwrap(), &FitSetup::new());
    for (a, b) in weighted.values.iter().zip(&without.values) {
        assert!((a - b).abs() < 1e-8 * b.abs(), "{a} vs {b}");
    }
}

/// The example scene's data file and scene, run through the binary.
#[test]
fn the_example_scene_fits_its_energy_and_writes_the_residuals() {
    let d = scratch("formula-fit-example");
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/examples/user_energy_fit.toml"
    );
    let out_dir = d.join("out");
    let out = Command::new(BIN)
        .args([
            "run".as_ref(),
            scene.as_ref(),
            "--out".as_ref(),
            out_dir.as_os_str(),
            "--quiet".as_ref(),
        ])
        .output()
        .expect("run");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(out.status.code(), Some(0), "{text}");
    let fits = std::fs::read_to_string(out_dir.join("fits.csv")).expect("fits.csv");
    println!("{fits}");
    let header: Vec<&str> = fits.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<&str>> = fits
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    // The truth the data file was drawn from (3 % noise, σ = 3 % of the datum), within three
    // standard errors.
    for (name, truth) in [("c10", 0.12), ("k1", 0.4), ("k2", 6.0)] {
        let row = rows
            .iter()
            .find(|r| r[col("parameter")] == name)
            .expect(name);
        let value: f64 = row[col("value")].parse().unwrap();
        let se: f64 = row[col("standard_error")].parse().unwrap();
        assert_eq!(row[col("converged")], "true");
        assert_eq!(row[col("weights")], "sigma");
        assert!(
            (value - truth).abs() < 3.0 * se,
            "{name} = {value} ± {se}, truth {truth}"
        );
    }
    // fit_points.csv: each datum with the fitted model there and the residual, model − datum;
    // the model is the fitted energy's stress, computed here from fits.csv's values.
    let points = std::fs::read_to_string(out_dir.join("fit_points.csv")).expect("fit_points.csv");
    let header: Vec<&str> = points.lines().next().unwrap().split(',').collect();
    let at = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let fitted: Vec<f64> = ["c10", "k1", "k2"]
        .iter()
        .map(|n| {
            rows.iter().find(|r| r[col("parameter")] == *n).unwrap()[col("value")]
                .parse()
                .unwrap()
        })
        .collect();
    let energy = fibres(0.12, POSITIVE).rebuilt(&fitted).unwrap();
    let m = Muscle::passive(energy);
    let mut data_rows = 0;
    for line in points.lines().skip(1) {
        let cells: Vec<&str> = line.split(',').collect();
        if cells[at("row")] != "data" {
            continue;
        }
        data_rows += 1;
        let number = |name: &str| cells[at(name)].parse::<f64>().unwrap();
        let model = along_fibres(&m, number("lambda")).unwrap().stress;
        assert!(
            (number("model") - model).abs() < 1e-9 * (1.0 + model.abs()),
            "{line}"
        );
        assert!(
            (number("residual") - (number("model") - number("data"))).abs()
                < 1e-12 * (1.0 + model.abs())
        );
        assert!(number("sigma") > 0.0);
    }
    assert_eq!(data_rows, 25);
    let report = std::fs::read_to_string(out_dir.join("report.html")).expect("report");
    assert!(
        report.contains("c10*(I1 - 3)"),
        "the report prints the formula"
    );
}

#[test]
fn a_scene_fit_on_a_bound_is_a_result_not_a_failure() {
    let d = scratch("formula-fit-bound");
    let data = negative_c10_data();
    std::fs::write(d.join("p.csv"), data.to_csv()).unwrap();
    let scene = d.join("bound.toml");
    std::fs::write(
        &scene,
        "[material]\nenergy = \"formula\"\nW = \"c10*(I1 - 3) + k1/(2*k2)*expm1(k2*(I4 - 1)^2)\"\n\
         [material.parameters]\nc10 = { value = 0.12, unit = \"kPa\", range = [0, inf] }\n\
         k1 = { value = 0.4, unit = \"kPa\", range = [0, inf] }\nk2 = { value = 6, range = [0, inf] }\n\
         [[study]]\nkind = \"fit\"\nname = \"bound\"\nfit = \"passive\"\ndata = \"p.csv\"\n",
    )
    .unwrap();
    let out_dir = d.join("out");
    let out = Command::new(BIN)
        .args([
            "run".as_ref(),
            scene.as_os_str(),
            "--out".as_ref(),
            out_dir.as_os_str(),
        ])
        .output()
        .expect("run");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(!stdout.contains("FAILED"), "{stdout}");
    let fits = std::fs::read_to_string(out_dir.join("fits.csv")).unwrap();
    let c10 = fits.lines().find(|l| l.contains(",c10,")).unwrap();
    assert!(c10.contains(",true,") && c10.ends_with(",0,equal"), "{c10}");
    let report = std::fs::read_to_string(out_dir.join("report.html")).unwrap();
    assert!(
        report.contains("<b>at its bound</b> 0"),
        "the report says so"
    );
}
