//! Homogeneous tests: closed forms for an isotropic energy, lateral equilibrium across the fibres,
//! transverse isotropy of the chapter's energy.

use activemuscle::energy::{GiantesioMusesti, NeoHookean};
use activemuscle::invariants::{Kinematics, FULL};
use activemuscle::response::Order;
use activemuscle::uniaxial::{across_fibres, along_fibres};
use activemuscle::Muscle;
use nalgebra::{Matrix3, Vector3};

#[test]
fn neo_hookean_matches_its_closed_form_in_both_directions() {
    let muscle = Muscle::passive(NeoHookean::new(2.0).unwrap());
    for i in 0..=18 {
        let l = 0.5 + 0.1 * i as f64;
        let exact = 2.0 * (l - 1.0 / (l * l));
        let (a, c) = (
            along_fibres(&muscle, l).unwrap(),
            across_fibres(&muscle, l).unwrap(),
        );
        assert!((a.stress - exact).abs() < 1e-12 * exact.abs().max(1.0));
        assert!(
            (c.stress - exact).abs() < 1e-12 * exact.abs().max(1.0),
            "across at {l}: {} vs {exact}",
            c.stress
        );
        assert!(
            (c.lateral[0] - l.powf(-0.5)).abs() < 1e-12,
            "isotropic: equal lateral stretches"
        );
    }
}

#[test]
fn across_the_fibres_both_lateral_faces_are_traction_free() {
    let muscle = Muscle::passive(GiantesioMusesti::paper());
    for i in 0..=10 {
        let l = 0.7 + 0.08 * i as f64;
        let pt = across_fibres(&muscle, l).unwrap();
        let [a, b] = pt.lateral;
        assert!((a * b * l - 1.0).abs() < 1e-14, "incompressible");
        let kin = Kinematics::new(
            &Matrix3::from_diagonal(&Vector3::new(a, l, b)),
            &Vector3::new(1.0, 0.0, 0.0),
        )
        .unwrap();
        let p = muscle
            .respond(&kin, Order::Stress, &FULL)
            .unwrap()
            .stress
            .unwrap();
        // With the pressure p = F33 ∂Ψ/∂F33, the fibre-direction face is traction free too.
        let pressure = b * p[8];
        let p11 = p[0] - pressure / a;
        assert!(
            p11.abs() < 1e-10 * pt.stress.abs().max(1e-3),
            "lambda {l}: P11 = {p11}"
        );
        assert!(
            (a - b).abs() > 1e-3 || (l - 1.0).abs() < 1e-9,
            "transversely isotropic: lateral stretches differ"
        );
    }
}

#[test]
fn the_chapters_energy_is_stiffer_along_the_fibres() {
    let muscle = Muscle::passive(GiantesioMusesti::paper());
    for l in [1.1, 1.2, 1.3] {
        let (along, across) = (
            along_fibres(&muscle, l).unwrap().stress,
            across_fibres(&muscle, l).unwrap().stress,
        );
        assert!(
            along > across && across > 0.0,
            "lambda {l}: along {along}, across {across}"
        );
    }
}

#[test]
fn invalid_stretch_is_an_error() {
    let muscle = Muscle::passive(GiantesioMusesti::paper());
    for l in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(along_fibres(&muscle, l).is_err());
        assert!(across_fibres(&muscle, l).is_err());
    }
}
