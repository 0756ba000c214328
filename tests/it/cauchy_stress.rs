//! 0D studies report the Cauchy stress σ = J⁻¹ P Fᵀ next to the nominal stress P: along the
//! fibres (incompressible, lateral faces traction free) σ₁₁ = λ P₁₁; across the fibres against
//! the full tensor assembled here from the material's ∂Ψ/∂F and the lateral equilibrium; and the
//! `cauchy` column of curves.csv.

use activemuscle::active::{ActiveCurve, Coupling, EnergyLaw, FrozenTangent, ImplicitLaw, Law};
use activemuscle::energy::GiantesioMusesti;
use activemuscle::invariants::{Kinematics, FULL};
use activemuscle::output::csv::files;
use activemuscle::response::Order;
use activemuscle::scene::{RunOptions, Scene};
use activemuscle::uniaxial::{across_fibres, along_fibres};
use activemuscle::Muscle;
use nalgebra::{Matrix3, Vector3};

fn muscles() -> Vec<Muscle<GiantesioMusesti>> {
    let (gm, curve) = (GiantesioMusesti::paper(), ActiveCurve::paper());
    vec![
        Muscle::passive(gm),
        Muscle::new(
            gm,
            Law::Implicit(ImplicitLaw::new(gm, curve)),
            0.2,
            Coupling::Frozen(FrozenTangent::Exact),
        )
        .unwrap(),
        Muscle::new(
            gm,
            Law::Energy(EnergyLaw::new(gm, curve)),
            0.0,
            Coupling::Consistent,
        )
        .unwrap(),
    ]
}

#[test]
fn along_the_fibres_cauchy_stress_is_lambda_times_the_nominal_stress() {
    for muscle in muscles() {
        for lambda in [0.7, 0.9, 1.0, 1.17, 1.4] {
            let p = along_fibres(&muscle, lambda).unwrap();
            let expected = lambda * p.stress;
            assert!(
                (p.cauchy - expected).abs() <= 1e-12 * expected.abs().max(1.0),
                "lambda {lambda}: sigma {} vs lambda P {expected}",
                p.cauchy
            );
        }
    }
}

/// Across the fibres (stretch along e₂, fibres along e₁), F = diag(a, λ, 1/(aλ)) with the fibre
/// stretch a from the lateral equilibrium. Here: P = ∂Ψ/∂F − p F⁻ᵀ with p from σ₃₃ = 0, then
/// σ = J⁻¹ P Fᵀ as a full 3×3 product; σ₂₂ is the reported value, σ₁₁ and σ₃₃ vanish (traction
/// free), and σ₂₂ = λ P₂₂.
#[test]
fn across_the_fibres_cauchy_stress_matches_the_full_tensor() {
    let m = Vector3::new(1.0, 0.0, 0.0);
    for muscle in muscles() {
        for lambda in [0.8, 1.1, 1.3] {
            let point = across_fibres(&muscle, lambda).unwrap();
            let [a, f33] = point.lateral;
            let f = Matrix3::from_diagonal(&Vector3::new(a, lambda, f33));
            let kin = Kinematics::new(&f, &m).unwrap();
            let dpsi = muscle
                .respond(&kin, Order::Stress, &FULL)
                .unwrap()
                .stress
                .unwrap();
            let dpsi = Matrix3::from_row_slice(dpsi.as_slice());
            let f_inv_t = f.try_inverse().unwrap().transpose();
            let pressure = dpsi[(2, 2)] / f_inv_t[(2, 2)];
            let p = dpsi - f_inv_t * pressure;
            let sigma = p * f.transpose() / f.determinant();
            let scale = sigma[(1, 1)].abs().max(1.0);
            assert!(
                (point.cauchy - sigma[(1, 1)]).abs() <= 1e-12 * scale,
                "lambda {lambda}: {} vs {}",
                point.cauchy,
                sigma[(1, 1)]
            );
            assert!(
                sigma[(0, 0)].abs() <= 1e-10 * scale,
                "sigma11 = {}",
                sigma[(0, 0)]
            );
            assert!(sigma[(2, 2)].abs() <= 1e-12 * scale);
            assert!((point.cauchy - lambda * point.stress).abs() <= 1e-12 * scale);
        }
    }
}

#[test]
fn curves_csv_has_a_cauchy_column() {
    let text = "[[study]]\nkind = \"uniaxial\"\nstretch = [0.9, 1.0, 1.2]\nlaws = [\"implicit\"]\n\
                \n[[study]]\nkind = \"uniaxial\"\ndirection = \"across\"\nstretch = [1.1]\nlaws = []\n";
    let scene = Scene::parse(text, "c.toml").unwrap();
    let results = scene.run(&RunOptions::default());
    let csv = String::from_utf8(files(&results)[0].bytes().unwrap()).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let (l, p, s) = ["lambda", "P", "cauchy"]
        .map(|c| header.iter().position(|h| *h == c).unwrap())
        .into();
    let mut n = 0;
    for line in lines {
        let cells: Vec<&str> = line.split(',').collect();
        let [lambda, nominal, cauchy]: [f64; 3] = [l, p, s].map(|k| cells[k].parse().unwrap());
        assert!(
            (cauchy - lambda * nominal).abs() <= 1e-12 * cauchy.abs().max(1.0),
            "{line}"
        );
        n += 1;
    }
    assert_eq!(n, 3 * 2 + 1, "{csv}");
}

#[test]
fn stability_points_carry_the_cauchy_stress() {
    for muscle in muscles() {
        for lambda in [0.8, 1.0, 1.25] {
            let s = activemuscle::stability::along_fibres_stability(&muscle, lambda, 8).unwrap();
            let p = along_fibres(&muscle, lambda).unwrap();
            assert!((s.cauchy - lambda * s.stress).abs() <= 1e-12 * s.cauchy.abs().max(1.0));
            assert!((s.cauchy - p.cauchy).abs() <= 1e-12 * s.cauchy.abs().max(1.0));
        }
    }
}
