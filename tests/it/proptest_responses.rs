//! Random deformations, activations and parameters: every response is finite or a typed error,
//! and where finite the derivative identities hold (energy → stress → tangent, by central
//! differences along a random direction).

use activemuscle::energy::{EhretBolItskov, GiantesioMusesti};
use activemuscle::invariants::{Kinematics, FULL};
use activemuscle::response::{active_response, Order};
use activemuscle::{Error, StrainEnergy};
use nalgebra::{Matrix3, SVector, Vector3};
use proptest::prelude::*;

fn check<E: StrainEnergy>(
    energy: &E,
    f: &Matrix3<f64>,
    m: &Vector3<f64>,
    gamma: f64,
    dir: &Matrix3<f64>,
) -> Result<(), TestCaseError> {
    let kin = match Kinematics::new(f, m) {
        Ok(k) => k,
        Err(e) => {
            prop_assert!(matches!(e, Error::NonPositiveJacobian { .. }), "{}", e);
            return Ok(());
        }
    };
    let r = match active_response(energy, &kin, gamma, Order::Tangent, &FULL) {
        Ok(r) => r,
        Err(e) => {
            prop_assert!(matches!(e, Error::NonFinite { .. }), "{}", e);
            return Ok(());
        }
    };
    let (p, k) = (r.stress.unwrap(), r.tangent.unwrap());
    prop_assert!(
        r.energy.is_finite() && p.iter().all(|x| x.is_finite()) && k.iter().all(|x| x.is_finite())
    );
    if k.norm() > 1e8 {
        return Ok(()); // finite, but central differences lose their meaning this close to overflow
    }
    let d = SVector::<f64, 9>::from_fn(|a, _| dir[(a / 3, a % 3)]);
    let h = 1e-6;
    let at = |s: f64| {
        let kin = Kinematics::new(&(f + dir * s), m).unwrap();
        active_response(energy, &kin, gamma, Order::Stress, &FULL).unwrap()
    };
    let (up, down) = (at(h), at(-h));
    let dw = (up.energy - down.energy) / (2.0 * h);
    prop_assert!(
        (dw - p.dot(&d)).abs() <= 1e-6 * (p.norm() * d.norm() + r.energy.abs() + 1e-3),
        "dW {dw} vs P:D {}",
        p.dot(&d)
    );
    let dp = (up.stress.unwrap() - down.stress.unwrap()) / (2.0 * h);
    prop_assert!(
        (dp - k * d).norm() <= 1e-5 * (k.norm() * d.norm() + 1e-3),
        "dP vs K:D"
    );
    Ok(())
}

fn matrix(e: [f64; 9]) -> Matrix3<f64> {
    Matrix3::from_row_slice(&e)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn chapter_energy_responses_are_finite_or_typed_errors(
        h in prop::array::uniform9(-0.6f64..0.6),
        dir in prop::array::uniform9(-1.0f64..1.0),
        m in prop::array::uniform3(-1.0f64..1.0),
        alpha in 0.1f64..40.0,
        w0 in 0.01f64..0.99,
        gamma in 0.0f64..0.95,
    ) {
        let m = Vector3::from(m);
        prop_assume!(m.norm() > 0.1);
        let energy = GiantesioMusesti::new(0.1599, alpha, w0).unwrap();
        check(&energy, &(Matrix3::identity() + matrix(h)), &m.normalize(), gamma, &matrix(dir))?;
    }

    #[test]
    fn ebi_energy_responses_are_finite_or_typed_errors(
        h in prop::array::uniform9(-0.6f64..0.6),
        dir in prop::array::uniform9(-1.0f64..1.0),
        beta in 0.1f64..10.0,
        gamma in 0.0f64..0.95,
    ) {
        let energy = EhretBolItskov::new(0.1599, 19.69, beta, 0.7388).unwrap();
        check(&energy, &(Matrix3::identity() + matrix(h)), &Vector3::new(0.0, 0.6, 0.8), gamma, &matrix(dir))?;
    }

    #[test]
    fn invalid_parameters_are_typed_errors(mu in -10.0f64..10.0, alpha in -10.0f64..40.0, w0 in -1.0f64..2.0) {
        match GiantesioMusesti::new(mu, alpha, w0) {
            Ok(_) => prop_assert!(mu > 0.0 && alpha > 0.0 && w0 > 0.0 && w0 < 1.0),
            Err(e) => prop_assert!(matches!(e, Error::InvalidParameter { .. }), "{}", e),
        }
    }
}
