//! Test support shared by the crate's tests and by users testing their own energies: a seeded
//! generator of deformations and rotations, finite-difference helpers, and
//! [`energy_test_battery!`](crate::energy_test_battery), the battery every energy must pass.

use nalgebra::{Matrix3, Unit, UnitQuaternion, Vector3};

pub use crate::random::Sampler;

/// Test geometry drawn from a [`Sampler`].
impl Sampler {
    /// A random unit vector.
    pub fn unit_vector(&mut self) -> Vector3<f64> {
        loop {
            let v = Vector3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            let n = v.norm();
            if n > 0.1 && n <= 1.0 {
                return v / n;
            }
        }
    }

    /// A random rotation.
    pub fn rotation(&mut self) -> Matrix3<f64> {
        let axis = Unit::new_normalize(self.unit_vector());
        UnitQuaternion::from_axis_angle(&axis, self.range(-3.1, 3.1))
            .to_rotation_matrix()
            .into_inner()
    }

    /// F = I + H with entries of H uniform in [−size, size], redrawn until det F > 0.2.
    pub fn deformation(&mut self, size: f64) -> Matrix3<f64> {
        loop {
            let f = Matrix3::identity() + Matrix3::from_fn(|_, _| self.range(-size, size));
            if f.determinant() > 0.2 {
                return f;
            }
        }
    }
}

/// The rotation by `angle` about the unit vector `m`.
pub fn rotation_about(m: &Vector3<f64>, angle: f64) -> Matrix3<f64> {
    UnitQuaternion::from_axis_angle(&Unit::new_normalize(*m), angle)
        .to_rotation_matrix()
        .into_inner()
}

/// Generates the battery of tests every strain energy must pass, in a module named `$name`.
///
/// `energy_test_battery!(my_energy, MyEnergy::new(1.0).unwrap(), gamma = 0.0);` tests, for the
/// active-strain energy Ŵ(F, γ) built on it (γ = 0: the passive energy itself):
/// zero energy and stress at F = I (γ = 0 only), objectivity W(QF) = W(F) and P(QF) = Q P(F),
/// invariance under rotations about m, major symmetry of ∂²Ŵ/∂F², energy versus stress and stress
/// versus tangent by central differences, agreement of the fast route with the 9-entry oracle,
/// and rejection of det F ≤ 0.
#[macro_export]
macro_rules! energy_test_battery {
    ($name:ident, $energy:expr, gamma = $gamma:expr) => {
        mod $name {
            #[allow(unused_imports)]
            use super::*;
            use $crate::invariants::{Kinematics, FULL};
            use $crate::nalgebra::{Matrix3, Vector3};
            use $crate::response::{active_response, Order, Response};
            use $crate::testing::{rotation_about, Sampler};

            const GAMMA: f64 = $gamma;
            const SAMPLES: usize = 20;

            fn at(f: &Matrix3<f64>, m: &Vector3<f64>, order: Order) -> Response<9> {
                let kin = Kinematics::new(f, m).expect("admissible F");
                active_response(&$energy, &kin, GAMMA, order, &FULL).expect("finite response")
            }

            fn stress_matrix(r: &Response<9>) -> Matrix3<f64> {
                let p = r.stress.expect("stress");
                Matrix3::from_row_slice(p.as_slice())
            }

            #[test]
            fn zero_energy_and_stress_at_identity() {
                if GAMMA != 0.0 {
                    return;
                }
                let mut s = Sampler::new(1);
                let r = at(&Matrix3::identity(), &s.unit_vector(), Order::Stress);
                assert!(r.energy.abs() < 1e-14, "W(I) = {}", r.energy);
                let p = stress_matrix(&r);
                // Under incompressibility the stress at I may be a pure pressure: P(I) = c I.
                let c = p.trace() / 3.0;
                assert!((p - Matrix3::identity() * c).norm() < 1e-12, "P(I) = {p}");
            }

            #[test]
            fn objectivity() {
                let mut s = Sampler::new(2);
                for _ in 0..SAMPLES {
                    let (f, m, q) = (s.deformation(0.3), s.unit_vector(), s.rotation());
                    let (a, b) = (at(&f, &m, Order::Stress), at(&(q * f), &m, Order::Stress));
                    let scale = a.energy.abs().max(1e-3);
                    assert!((a.energy - b.energy).abs() < 1e-12 * scale, "W(QF) != W(F)");
                    let (pa, pb) = (stress_matrix(&a), stress_matrix(&b));
                    assert!(
                        (q * pa - pb).norm() < 1e-11 * pa.norm().max(1e-3),
                        "P(QF) != Q P(F)"
                    );
                }
            }

            #[test]
            fn invariant_under_rotations_about_the_fibres() {
                let mut s = Sampler::new(3);
                for _ in 0..SAMPLES {
                    let (f, m) = (s.deformation(0.3), s.unit_vector());
                    let q = rotation_about(&m, s.range(-3.0, 3.0));
                    let (a, b) = (at(&f, &m, Order::Energy), at(&(f * q), &m, Order::Energy));
                    assert!((a.energy - b.energy).abs() < 1e-12 * a.energy.abs().max(1e-3));
                }
            }

            #[test]
            fn tangent_has_major_symmetry() {
                let mut s = Sampler::new(4);
                for _ in 0..SAMPLES {
                    let k = at(&s.deformation(0.3), &s.unit_vector(), Order::Tangent)
                        .tangent
                        .expect("tangent");
                    assert!(
                        (k - k.transpose()).norm() < 1e-12 * k.norm(),
                        "asymmetry {}",
                        (k - k.transpose()).norm()
                    );
                }
            }

            #[test]
            fn stress_is_the_derivative_of_the_energy() {
                let mut s = Sampler::new(5);
                let h = 1e-6;
                for _ in 0..SAMPLES {
                    let (f, m) = (s.deformation(0.3), s.unit_vector());
                    let p = stress_matrix(&at(&f, &m, Order::Stress));
                    for i in 0..3 {
                        for j in 0..3 {
                            let mut d = Matrix3::zeros();
                            d[(i, j)] = h;
                            let fd = (at(&(f + d), &m, Order::Energy).energy
                                - at(&(f - d), &m, Order::Energy).energy)
                                / (2.0 * h);
                            assert!(
                                (fd - p[(i, j)]).abs() < 1e-6 * p.norm().max(1e-2),
                                "dW/dF_{i}{j}: fd {fd} vs {}",
                                p[(i, j)]
                            );
                        }
                    }
                }
            }

            #[test]
            fn tangent_is_the_derivative_of_the_stress() {
                let mut s = Sampler::new(6);
                let h = 1e-6;
                for _ in 0..SAMPLES {
                    let (f, m) = (s.deformation(0.3), s.unit_vector());
                    let k = at(&f, &m, Order::Tangent).tangent.expect("tangent");
                    for b in 0..9 {
                        let mut d = Matrix3::zeros();
                        d[(b / 3, b % 3)] = h;
                        let fd = (at(&(f + d), &m, Order::Stress).stress.expect("P")
                            - at(&(f - d), &m, Order::Stress).stress.expect("P"))
                            / (2.0 * h);
                        assert!((fd - k.column(b)).norm() < 1e-6 * k.norm(), "column {b}");
                    }
                }
            }

            #[test]
            fn fast_route_equals_the_nine_entry_oracle() {
                let mut s = Sampler::new(7);
                for _ in 0..SAMPLES {
                    let (f, m) = (s.deformation(0.3), s.unit_vector());
                    let fast = at(&f, &m, Order::Tangent);
                    let slow =
                        $crate::oracle::full_response(&$energy, &f, &m, GAMMA).expect("oracle");
                    let p = fast.stress.expect("P");
                    assert!((p - slow.stress).norm() <= 1e-12 * slow.stress.norm().max(1e-3));
                    let k = fast.tangent.expect("K");
                    assert!((k - slow.tangent).norm() <= 1e-12 * slow.tangent.norm());
                    let dg = fast.dstress_dgamma.expect("dP/dgamma");
                    assert!(
                        (dg - slow.dstress_dgamma).norm()
                            <= 1e-12 * slow.dstress_dgamma.norm().max(1e-3)
                    );
                    assert!(
                        (fast.denergy_dgamma.expect("") - slow.denergy_dgamma).abs()
                            <= 1e-12 * slow.denergy_dgamma.abs().max(1e-3)
                    );
                    assert!(
                        (fast.d2energy_dgamma2.expect("") - slow.d2energy_dgamma2).abs()
                            <= 1e-12 * slow.d2energy_dgamma2.abs().max(1e-3)
                    );
                }
            }

            #[test]
            fn declared_invariants_are_honest() {
                use $crate::StrainEnergy;
                if ($energy).uses_det_c() {
                    return;
                }
                // An energy that says it ignores det C must have ∂W/∂det C = 0 everywhere.
                let mut s = Sampler::new(8);
                for _ in 0..SAMPLES {
                    let v = $crate::nalgebra::SVector::<f64, 5>::from_fn(|_, _| s.range(0.5, 2.0));
                    let (_, g) = $crate::num_dual::gradient(
                        |x: $crate::nalgebra::SVector<$crate::num_dual::DualSVec64<5>, 5>| {
                            ($energy).energy(&$crate::energy::Invariants::from_array([
                                x[0], x[1], x[2], x[3], x[4],
                            ]))
                        },
                        &v,
                    );
                    assert_eq!(
                        g[4], 0.0,
                        "uses_det_c() is false but dW/d(det C) = {}",
                        g[4]
                    );
                }
            }

            #[test]
            fn rejects_non_positive_jacobian() {
                let m = Vector3::new(1.0, 0.0, 0.0);
                for f in [
                    Matrix3::from_diagonal(&Vector3::new(-1.0, 1.0, 1.0)),
                    Matrix3::zeros(),
                ] {
                    assert!(matches!(
                        Kinematics::new(&f, &m),
                        Err($crate::Error::NonPositiveJacobian { .. })
                    ));
                }
            }
        }
    };
}
