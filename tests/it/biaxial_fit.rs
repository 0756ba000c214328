//! The passive fit to planar biaxial data (issue 25): the reduced-energy stresses against the
//! homogeneous state computed from ∂Ψ/∂F with the pressure of σ₃₃ = 0 (a different route),
//! parameters recovered from synthetic equibiaxial and strip data, and the CSV reader's refusals.

use activemuscle::energy::{EhretBolItskov, GiantesioMusesti, Parametric};
use activemuscle::fit::{
    biaxial_stress_with, fit_passive_biaxial, BiaxialData, FitError, FitSetup,
};
use activemuscle::homogeneous::planar_biaxial;
use activemuscle::material::Muscle;
use activemuscle::scene::{RunOptions, Scene};
use activemuscle::studies::StudyResult;
use activemuscle::StrainEnergy;

/// Equibiaxial λ₁ = λ₂ ∈ [1, 1.2] and strip (λ₂ = 1) λ₁ ∈ [1, 1.2]: the protocols labs run.
fn protocols() -> Vec<[f64; 2]> {
    let mut rows: Vec<[f64; 2]> = (0..=8)
        .map(|i| 1.0 + 0.025 * i as f64)
        .map(|l| [l, l])
        .collect();
    rows.extend((1..=8).map(|i| [1.0 + 0.025 * i as f64, 1.0]));
    rows.extend((1..=8).map(|i| [1.0, 1.0 + 0.025 * i as f64]));
    rows
}

/// (P₁₁, P₂₂) of `energy` at each row by [`planar_biaxial`] (∂Ψ/∂F − p F⁻ᵀ, σ₃₃ = 0).
fn sampled<E: StrainEnergy + Clone>(energy: &E, rows: &[[f64; 2]]) -> BiaxialData {
    let muscle = Muscle::passive(energy.clone());
    let stresses = rows
        .iter()
        .map(|&[a, b]| {
            let s = planar_biaxial(&muscle, None, a, b).unwrap();
            [s.nominal[(0, 0)], s.nominal[(1, 1)]]
        })
        .collect();
    BiaxialData::new(rows.to_vec(), stresses).unwrap()
}

#[test]
fn reduced_energy_stresses_equal_the_homogeneous_state_with_its_pressure() {
    let energy = GiantesioMusesti::paper();
    let data = sampled(&energy, &protocols());
    let values = energy.parameter_values();
    for (&l, p) in data.stretches().iter().zip(data.stresses()) {
        let [p11, p22] = biaxial_stress_with(&energy, &values, l);
        assert!(
            (p11 - p[0]).abs() < 1e-10 * (1.0 + p[0].abs()),
            "{l:?}: {p11} vs {}",
            p[0]
        );
        assert!(
            (p22 - p[1]).abs() < 1e-10 * (1.0 + p[1].abs()),
            "{l:?}: {p22} vs {}",
            p[1]
        );
    }
}

#[test]
fn all_four_parameters_of_the_ebi_energy_come_back_from_biaxial_data() {
    let truth = EhretBolItskov::paper();
    let data = sampled(&truth, &protocols());
    let start = EhretBolItskov::new(0.12, 17.0, 1.5, 0.7).unwrap();
    let setup = FitSetup::new().free(&["mu", "alpha", "beta", "w0"]);
    let fit = fit_passive_biaxial(&start, &data, &setup).unwrap();
    println!("{}", fit.report);
    assert!(fit.report.converged);
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
fn biaxial_csv_is_read_and_bad_files_are_refused_with_their_line() {
    let good = "lambda1,lambda2,P11,P22\n1.1,1.0,2.5,0.5\n1.1,1.1,3.0,1.0\n";
    let data = BiaxialData::from_csv_reader(good.as_bytes(), "lab.csv").unwrap();
    assert_eq!(data.stretches(), &[[1.1, 1.0], [1.1, 1.1]]);
    assert_eq!(data.stresses(), &[[2.5, 0.5], [3.0, 1.0]]);
    let refused =
        |text: &str| BiaxialData::from_csv_reader(text.as_bytes(), "lab.csv").unwrap_err();
    let header = refused("lambda,P\n1.1,2.0\n").to_string();
    assert!(
        header.contains("lambda1,lambda2,P11,P22") && header.contains("line 1"),
        "{header}"
    );
    let word = refused("lambda1,lambda2,P11,P22\n1.1,x,2.5,0.5\n").to_string();
    assert!(
        word.contains("line 2") && word.contains("lambda2"),
        "{word}"
    );
    assert!(matches!(
        refused("lambda1,lambda2,P11,P22\n1.1,-1.0,2.5,0.5\n"),
        FitError::NonPositiveStretch { .. }
    ));
    assert!(matches!(
        refused("lambda1,lambda2,P11,P22\n1.1,1.0,NaN,0.5\n"),
        FitError::NonFiniteData { column: "P11", .. }
    ));
}

/// (P₁₁, P₂₂) of the incompressible neo-Hookean solid W = μ/2 (I₁ − 3) in planar biaxial
/// stretch with σ₃₃ = 0, in closed form: p = μλ₃², P₁₁ = μ(λ₁ − λ₃²/λ₁), P₂₂ = μ(λ₂ − λ₃²/λ₂),
/// λ₃ = 1/(λ₁λ₂).
fn neo_hookean_rows(mu: f64) -> String {
    let mut csv = String::from("lambda1,lambda2,P11,P22\n");
    for [l1, l2] in protocols().into_iter().skip(1) {
        let l3 = 1.0 / (l1 * l2);
        let p11 = mu * (l1 - l3 * l3 / l1);
        let p22 = mu * (l2 - l3 * l3 / l2);
        csv.push_str(&format!("{l1},{l2},{p11:.17e},{p22:.17e}\n"));
    }
    csv
}

/// A scene of the neo-Hookean material fitting `fit` to `lab.csv` in a fresh directory.
fn fit_scene(name: &str, csv: &str, fit: &str) -> (crate::scratch::Scratch, Scene) {
    let d = crate::scratch::scratch(name);
    std::fs::write(d.join("lab.csv"), csv).unwrap();
    let text = format!(
        "[material]\nenergy = \"neo-hookean\"\nmu = 1.0\n[[study]]\nkind = \"fit\"\nname = \"lab\"\n{fit}"
    );
    let path = d.join("scene.toml");
    std::fs::write(&path, &text).unwrap();
    let scene = Scene::load(&path);
    (d, scene.unwrap_or_else(|e| panic!("{e}")))
}

#[test]
fn a_scene_fits_the_passive_energy_to_a_biaxial_file_and_draws_both_stresses() {
    let (d, scene) = fit_scene(
        "biaxial-scene",
        &neo_hookean_rows(0.37),
        "fit = \"passive\"\ndata = \"lab.csv\"\nfree = [\"mu\"]\n",
    );
    let results = scene.run(&RunOptions::default());
    let StudyResult::Fit(fits) = &results.studies[0].result else {
        panic!("not a fit: {:?}", results.studies[0].result)
    };
    let fit = &fits[0];
    assert!(fit.converged, "{}", fit.termination);
    assert_eq!(fit.names, ["mu"]);
    assert!((fit.values[0] - 0.37).abs() < 1e-9, "{}", fit.values[0]);
    assert_eq!(fit.points, protocols().len() - 1);
    assert!(fit.source.contains("planar biaxial"), "{}", fit.source);
    // Two panels, P₁₁ and P₂₂, each the data and the fitted model at every row.
    assert_eq!(fit.plot.len(), 2);
    for (k, c) in fit.plot.iter().enumerate() {
        assert!(c.at_rows && c.y_label.starts_with(["P₁₁", "P₂₂"][k]));
        assert_eq!(c.data.len(), fit.points);
        for (&(x, p), &(xd, pd)) in c.fitted.iter().zip(&c.data) {
            assert_eq!(x, xd);
            assert!((p - pd).abs() < 1e-8 * (1.0 + pd.abs()), "{p} vs {pd}");
        }
    }
    // The written spec has no direction (biaxial data load both) and reads back the same.
    let written = scene.resolved_toml().unwrap();
    assert!(!written.contains("direction"), "{written}");
    std::fs::write(d.join("again.toml"), &written).unwrap();
    Scene::load(&d.join("again.toml")).unwrap_or_else(|e| panic!("{e}\n{written}"));
}

#[test]
fn biaxial_data_are_refused_where_they_do_not_belong() {
    let rows = neo_hookean_rows(0.37);
    let refused = |name: &str, fit: &str| {
        let d = crate::scratch::scratch(name);
        std::fs::write(d.join("lab.csv"), &rows).unwrap();
        let path = d.join("scene.toml");
        let text = format!(
            "[material]\nenergy = \"neo-hookean\"\nmu = 1.0\n[[study]]\nkind = \"fit\"\n{fit}"
        );
        std::fs::write(&path, text).unwrap();
        match Scene::load(&path) {
            Ok(_) => panic!("{name}: accepted"),
            Err(e) => e.to_string(),
        }
    };
    let direction = refused(
        "biaxial-direction",
        "fit = \"passive\"\ndata = \"lab.csv\"\nfree = [\"mu\"]\ndirection = \"across\"\n",
    );
    assert!(direction.contains("direction"), "{direction}");
    let active = refused(
        "biaxial-active",
        "fit = \"active-curve\"\ndata = \"lab.csv\"\n",
    );
    assert!(
        active.contains("data") && active.contains("passive fits take"),
        "{active}"
    );
    // One row gives two stresses: too few for two free parameters.
    let few = {
        let d = crate::scratch::scratch("biaxial-few");
        std::fs::write(
            d.join("lab.csv"),
            "lambda1,lambda2,P11,P22\n1.1,1.1,1.0,1.0\n",
        )
        .unwrap();
        let path = d.join("scene.toml");
        std::fs::write(
            &path,
            "[[study]]\nkind = \"fit\"\nfit = \"passive\"\ndata = \"lab.csv\"\nfree = [\"mu\", \"alpha\"]\n",
        )
        .unwrap();
        Scene::load(&path).map(|_| ()).unwrap_err().to_string()
    };
    assert!(few.contains("2 stresses (two per row)"), "{few}");
}
