//! The 4C muscle passive energy (`4c-passive`) against closed forms derived by hand: the nominal
//! stress along the fibres, a dilatation (where det C enters), the Ehret–Böl–Itskov energy where
//! det C = 1, and its parameters by name in a scene.

use activemuscle::energy::{EhretBolItskov, FourCPassive, Invariants, StrainEnergy};
use activemuscle::invariants::Kinematics;
use activemuscle::scene::Scene;
use activemuscle::uniaxial::along_fibres;
use activemuscle::{Error, Muscle};
use nalgebra::{Matrix3, Vector3};

fn energy_at(w: &FourCPassive, f: &Matrix3<f64>, m: &Vector3<f64>) -> f64 {
    let kin = Kinematics::new(f, m).unwrap();
    w.energy(&Invariants::from_array(kin.invariants))
}

/// Along the fibres, F = diag(λ, λ^-½, λ^-½), m = e₁, det C = 1:
/// I = (w0/3)(λ² + 2/λ) + (1 − w0)λ², J = (w0/3)(λ⁻² + 2λ) + (1 − w0)λ⁻², and the nominal
/// stress is P = dW/dλ = μ/4 [e^{α(I−1)} I′ + e^{β(J−1)} J′] with
/// I′ = (w0/3)(2λ − 2λ⁻²) + 2(1 − w0)λ, J′ = (w0/3)(2 − 2λ⁻³) − 2(1 − w0)λ⁻³.
#[test]
fn fibre_path_stress_matches_the_hand_derived_closed_form() {
    let (mu, alpha, beta, w0) = (0.1599, 19.69, 1.190, 0.7388);
    let w = FourCPassive::new(mu, alpha, beta, w0).unwrap();
    let muscle = Muscle::passive(w);
    for lambda in [0.7, 0.9, 1.0, 1.1, 1.3, 1.5] {
        let l: f64 = lambda;
        let (a, b) = (w0 / 3.0, 1.0 - w0);
        let i = a * (l * l + 2.0 / l) + b * l * l;
        let j = a * (l.powi(-2) + 2.0 * l) + b * l.powi(-2);
        let di = a * (2.0 * l - 2.0 * l.powi(-2)) + 2.0 * b * l;
        let dj = a * (2.0 - 2.0 * l.powi(-3)) - 2.0 * b * l.powi(-3);
        let p = mu / 4.0 * ((alpha * (i - 1.0)).exp() * di + (beta * (j - 1.0)).exp() * dj);
        let got = along_fibres(&muscle, l).unwrap().stress;
        assert!(
            (got - p).abs() <= 1e-12 * p.abs().max(1e-3),
            "lambda {l}: {got} vs {p} kPa"
        );
    }
}

/// Under a dilatation F = s I: I = s², J = s⁶ · s⁻² = s⁴, so
/// W = μ/4 {[e^{α(s² − 1)} − 1]/α + [e^{β(s⁴ − 1)} − 1]/β} — det C enters J.
#[test]
fn dilatation_energy_carries_det_c() {
    let w = FourCPassive::paper();
    let p = w.parameters();
    let m = Vector3::new(0.0, 0.6, 0.8);
    for s in [0.9, 1.05, 1.2] {
        let f = Matrix3::identity() * s;
        let s2: f64 = s * s;
        let expected = p.mu() / 4.0
            * ((p.alpha() * (s2 - 1.0)).exp_m1() / p.alpha()
                + (p.beta() * (s2 * s2 - 1.0)).exp_m1() / p.beta());
        let got = energy_at(&w, &f, &m);
        assert!(
            (got - expected).abs() <= 1e-14 * expected.abs(),
            "{got} vs {expected}"
        );
    }
}

/// Where det C = 1, J = K_p and the energy is the Ehret–Böl–Itskov one with the same parameters.
#[test]
fn isochoric_deformations_give_the_ehret_bol_itskov_energy() {
    let w = FourCPassive::paper();
    let ebi = EhretBolItskov::paper();
    let mut s = activemuscle::testing::Sampler::new(0x4c);
    for _ in 0..20 {
        let f = s.deformation(0.3);
        let f = f / f.determinant().cbrt();
        let m = s.unit_vector();
        let kin = Kinematics::new(&f, &m).unwrap();
        let inv = Invariants::from_array(kin.invariants);
        let (a, b) = (w.energy(&inv), ebi.energy(&inv));
        assert!((a - b).abs() <= 1e-12 * b.abs().max(1e-6), "{a} vs {b}");
    }
}

#[test]
fn scenes_name_it_and_its_parameters_are_validated() {
    let study = "[[study]]\nkind = \"uniaxial\"\nstretch = [1.0]\nlaws = [\"implicit\"]\n";
    let text = format!(
        "[material]\nenergy = \"4c-passive\"\nmu = 0.2\nalpha = 10.0\nbeta = 1.5\nw0 = 0.5\n{study}"
    );
    let scene = Scene::parse(&text, "s.toml").unwrap();
    assert_eq!(
        scene.models.energy,
        activemuscle::Energy::FourCPassive(FourCPassive::new(0.2, 10.0, 1.5, 0.5).unwrap())
    );
    let bad = format!("[material]\nenergy = \"4c-passive\"\nbeta = -1.0\n{study}");
    let e = Scene::parse(&bad, "s.toml").unwrap_err().to_string();
    assert!(e.contains("s.toml:3") && e.contains("beta"), "{e}");
    assert_eq!(
        FourCPassive::new(0.2, 10.0, 1.5, 1.0),
        Err(Error::InvalidParameter {
            name: "w0",
            value: 1.0,
            rule: "must lie in (0, 1)"
        })
    );
}
