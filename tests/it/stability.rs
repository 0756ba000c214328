//! Strong ellipticity and the uniaxial slope: closed forms, polyconvexity, finite differences.

use activemuscle::active::{ActiveCurve, ConstantLaw, Coupling, FrozenTangent, ImplicitLaw, Law};
use activemuscle::energy::{GiantesioMusesti, NeoHookean};
use activemuscle::invariants::{Kinematics, FULL};
use activemuscle::response::Order;
use activemuscle::stability::{along_fibres_stability, strong_ellipticity};
use activemuscle::uniaxial::along_fibres;
use activemuscle::Muscle;
use nalgebra::{Matrix3, SMatrix, Vector3};

use crate::scratch;
use scratch::scratch;

#[test]
fn neo_hookean_acoustic_tensor_is_mu_in_every_direction() {
    let muscle = Muscle::passive(NeoHookean::new(3.0).unwrap());
    let mut s = activemuscle::testing::Sampler::new(31);
    for _ in 0..10 {
        let f = s.deformation(0.3);
        let k = muscle
            .respond(
                &Kinematics::new(&f, &s.unit_vector()).unwrap(),
                Order::Tangent,
                &FULL,
            )
            .unwrap()
            .tangent
            .unwrap();
        let e = strong_ellipticity(&k, &f, 200).unwrap();
        assert!((e.least - 3.0).abs() < 1e-12, "least {}", e.least);
        assert!(e.holds());
    }
}

#[test]
fn a_negative_definite_tangent_is_not_elliptic() {
    let f = Matrix3::from_diagonal(&Vector3::new(1.2, 1.0, 1.0 / 1.2));
    let e = strong_ellipticity(&(-SMatrix::<f64, 9, 9>::identity()), &f, 50).unwrap();
    assert!((e.least + 1.0).abs() < 1e-12 && !e.holds());
    // The direction found is tangent to the incompressibility constraint: a ⊥ F⁻ᵀN.
    let n = f.try_inverse().unwrap().transpose() * e.normal;
    assert!(n.dot(&e.direction).abs() < 1e-12);
}

#[test]
fn polyconvex_energies_are_strongly_elliptic_along_the_fibres() {
    let gm = GiantesioMusesti::paper();
    for gamma in [0.0, 0.2, 0.4] {
        let muscle = Muscle::new(
            gm,
            Law::Constant(ConstantLaw::new(gamma).unwrap()),
            0.0,
            Coupling::Consistent,
        )
        .unwrap();
        for i in 0..=95 {
            let l = 0.65 + 0.01 * i as f64;
            let s = along_fibres_stability(&muscle, l, 300).unwrap();
            assert!(
                s.ellipticity.holds(),
                "gamma {gamma}, lambda {l}: {:?}",
                s.ellipticity
            );
        }
    }
}

#[test]
fn uniaxial_slope_matches_finite_differences() {
    let (gm, curve) = (GiantesioMusesti::paper(), ActiveCurve::paper());
    for coupling in [Coupling::Frozen(FrozenTangent::Exact), Coupling::Consistent] {
        let muscle = Muscle::new(
            gm,
            Law::Implicit(ImplicitLaw::new(gm, curve)),
            0.2,
            coupling,
        )
        .unwrap();
        for i in 0..=18 {
            let l = 0.7 + 0.05 * i as f64;
            let h = 1e-6;
            let fd = (along_fibres(&muscle, l + h).unwrap().stress
                - along_fibres(&muscle, l - h).unwrap().stress)
                / (2.0 * h);
            let s = along_fibres_stability(&muscle, l, 50).unwrap().slope;
            assert!(
                (fd - s).abs() < 1e-6 * s.abs().max(1.0),
                "{coupling:?} at {l}: slope {s} vs fd {fd}"
            );
        }
    }
}

#[test]
fn diagnosis_finds_the_energy_law_jump_and_passive_stability() {
    use activemuscle::active::{BelowMinimum, EnergyLaw};
    use activemuscle::stability::diagnose_axisymmetric;
    use nalgebra::SVector;
    let gm = GiantesioMusesti::paper();
    // Uniaxial-like states along the axis with fibre stretches 0.60 … 0.70 (λ_min = 0.6243).
    let points: Vec<SVector<f64, 5>> = (0..11)
        .map(|i| {
            let l = 0.60 + 0.01 * i as f64;
            SVector::from([l.powf(-0.5), 0.0, 0.0, l, l.powf(-0.5)])
        })
        .collect();
    let energy = Muscle::new(
        gm,
        Law::Energy(EnergyLaw::new(gm, ActiveCurve::paper()).below_minimum(BelowMinimum::Inactive)),
        0.0,
        Coupling::Consistent,
    )
    .unwrap();
    let d = diagnose_axisymmetric(&energy, &points, 100);
    assert_eq!(d.points, 11);
    assert_eq!(
        d.jump,
        Some((0.6243, 3)),
        "0.60, 0.61, 0.62 lie below lambda_min"
    );
    assert!((d.fibre_stretch.0 - 0.60).abs() < 1e-12 && (d.fibre_stretch.1 - 0.70).abs() < 1e-12);
    assert!(d.to_string().contains("discontinuous"));
    let passive = diagnose_axisymmetric(&Muscle::passive(gm), &points, 100);
    assert_eq!(
        (passive.not_elliptic, passive.jump, passive.refused),
        (0, None, 0)
    );
}

#[test]
fn the_vtk_writer_refuses_non_finite_values() {
    use activemuscle::fem::{vtk::write_vtu, Mesh};
    let mesh = Mesh::structured(1.0, 2.0, 1, 1, 1.0).unwrap();
    let dir = scratch("vtk-non-finite");
    let path = dir.join("bad.vtu");
    let n = mesh.nodes.len();
    let mut u = vec![[0.0, 0.0]; n];
    u[3][1] = f64::NAN;
    let err = write_vtu(&path, &mesh, &u, &vec![0.0; n], &[[1.0, 0.0, 1.0, 0.0]]).unwrap_err();
    assert!(
        err.to_string().contains("u_z") && err.to_string().contains("node 3"),
        "{err}"
    );
    assert!(!path.exists(), "nothing written");
    let err = write_vtu(
        &path,
        &mesh,
        &vec![[0.0, 0.0]; n],
        &vec![0.0; n],
        &[[1.0, f64::INFINITY, 1.0, 0.0]],
    )
    .unwrap_err();
    assert!(err.to_string().contains("gamma"), "{err}");
}
