//! The passive fit to planar biaxial data (issue 25): the reduced-energy stresses against the
//! homogeneous state computed from ∂Ψ/∂F with the pressure of σ₃₃ = 0 (a different route),
//! parameters recovered from synthetic equibiaxial and strip data, and the CSV reader's refusals.

use activemuscle::energy::{EhretBolItskov, GiantesioMusesti, Parametric};
use activemuscle::fit::{
    biaxial_stress_with, fit_passive_biaxial, BiaxialData, FitError, FitSetup,
};
use activemuscle::homogeneous::planar_biaxial;
use activemuscle::material::Muscle;
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
