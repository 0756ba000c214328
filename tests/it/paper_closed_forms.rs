//! The dual-number stress equals the chapter's closed forms: P_pas (eq. (11)), P_tot
//! (eq. (10)) and the full tensor of eq. (7) with the pressure from
//! traction-free lateral faces, to 1e-12 relative, over λ ∈ [0.65, 1.6] and γ ∈ [0, 0.4].

use activemuscle::active::{ConstantLaw, Coupling, Law};
use activemuscle::energy::GiantesioMusesti;
use activemuscle::invariants::{Kinematics, FULL};
use activemuscle::response::{active_response, Order};
use activemuscle::uniaxial::along_fibres;
use activemuscle::Muscle;
use nalgebra::{Matrix3, Vector3};

const MU: f64 = 0.1599;
const ALPHA: f64 = 19.35;
const W0: f64 = 0.7335;

/// eq. (11).
fn p_pas(l: f64) -> f64 {
    let f = 1.0 - 2.0 / 3.0 * W0;
    MU / 2.0
        * ((f * l - W0 / 3.0 / (l * l)) * (ALPHA * (f * l * l + W0 / 3.0 * 2.0 / l - 1.0)).exp()
            - f / l.powi(3)
            + W0 / 3.0)
}

/// eq. (10) with I_e, K_e and their λ-derivatives as printed.
fn p_tot(l: f64, g: f64) -> f64 {
    let c2 = (1.0 - g).powi(2);
    let ie = W0 / 3.0 * (l * l / c2 + 2.0 / l) + (1.0 - W0) * l * l / c2;
    let ie_d = 2.0 * W0 / 3.0 * (l / c2 - 1.0 / (l * l)) + 2.0 * (1.0 - W0) * l / c2;
    let ke_d = 2.0 * W0 / 3.0 * (-c2 / l.powi(3) + 1.0) - 2.0 * (1.0 - W0) * c2 / l.powi(3);
    (1.0 - g) * MU / 4.0 * (ie_d * (ALPHA * (ie - 1.0)).exp() + ke_d)
}

/// eq. (7) without the pressure term:
/// μ/2 (1−γ) F_e { e^{α(I_e−1)} A − C_e⁻¹ A C_e⁻¹ } F_a⁻¹, A = w0/3 I + (1−w0) M.
fn p_hat(f: &Matrix3<f64>, m: &Vector3<f64>, g: f64) -> Matrix3<f64> {
    let mm = m * m.transpose();
    let fa_inv = Matrix3::identity() + mm * (g / (1.0 - g));
    let fe = f * fa_inv;
    let ce = fe.transpose() * fe;
    let ce_inv = ce.try_inverse().unwrap();
    let a = Matrix3::identity() * (W0 / 3.0) + mm * (1.0 - W0);
    let ie = W0 / 3.0 * ce.trace() + (1.0 - W0) * (ce * mm).trace();
    fe * (a * (ALPHA * (ie - 1.0)).exp() - ce_inv * a * ce_inv) * fa_inv * (MU / 2.0 * (1.0 - g))
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-3)
}

fn stretches() -> impl Iterator<Item = f64> {
    (0..=95).map(|i| 0.65 + 0.01 * i as f64)
}

#[test]
fn passive_stress_matches_eq_ppas() {
    let muscle = Muscle::passive(GiantesioMusesti::paper());
    for l in stretches() {
        let p = along_fibres(&muscle, l).unwrap().stress;
        assert!(
            rel(p, p_pas(l)) < 1e-12,
            "lambda {l}: AD {p} vs closed form {}",
            p_pas(l)
        );
    }
}

#[test]
fn total_stress_matches_eq_ptotcalcolato() {
    let gm = GiantesioMusesti::paper();
    for g in [0.0, 0.1, 0.2, 0.3, 0.4] {
        let muscle = Muscle::new(
            gm,
            Law::Constant(ConstantLaw::new(g).unwrap()),
            0.0,
            Coupling::Consistent,
        )
        .unwrap();
        for l in stretches() {
            let p = along_fibres(&muscle, l).unwrap().stress;
            assert!(
                rel(p, p_tot(l, g)) < 1e-12,
                "lambda {l}, gamma {g}: AD {p} vs {}",
                p_tot(l, g)
            );
        }
    }
}

#[test]
fn full_tensor_matches_eq_stresspktotale_with_lateral_pressure() {
    let gm = GiantesioMusesti::paper();
    let m = Vector3::new(1.0, 0.0, 0.0);
    for g in [0.0, 0.15, 0.4] {
        for l in stretches() {
            let t = 1.0 / l.sqrt();
            let f = Matrix3::from_diagonal(&Vector3::new(l, t, t));
            let kin = Kinematics::new(&f, &m).unwrap();
            let ad = active_response(&gm, &kin, g, Order::Stress, &FULL)
                .unwrap()
                .stress
                .unwrap();
            let ad = Matrix3::from_row_slice(ad.as_slice());
            let closed = p_hat(&f, &m, g);
            // Pressure from P_22 = 0 (traction-free lateral faces), then the full tensor.
            let f_inv_t = f.try_inverse().unwrap().transpose();
            let (pa, pc) = (ad[(1, 1)] * t, closed[(1, 1)] * t);
            let (full_ad, full_closed) = (ad - f_inv_t * pa, closed - f_inv_t * pc);
            let scale = full_closed.norm().max(1e-3);
            assert!(
                (full_ad - full_closed).norm() < 1e-12 * scale,
                "lambda {l}, gamma {g}"
            );
            assert!(
                full_closed[(2, 2)].abs() < 1e-12 * scale,
                "lateral faces are traction free"
            );
            assert!(
                rel(full_closed[(0, 0)], p_tot(l, g)) < 1e-12,
                "P_11 is P_tot"
            );
        }
    }
}

#[test]
fn full_tensor_matches_at_general_deformations() {
    let gm = GiantesioMusesti::paper();
    let mut s = activemuscle::testing::Sampler::new(11);
    for _ in 0..100 {
        let (f, m, g) = (s.deformation(0.25), s.unit_vector(), s.range(0.0, 0.4));
        let kin = Kinematics::new(&f, &m).unwrap();
        let ad = active_response(&gm, &kin, g, Order::Stress, &FULL)
            .unwrap()
            .stress
            .unwrap();
        let closed = p_hat(&f, &m, g);
        let ad = Matrix3::from_row_slice(ad.as_slice());
        assert!(
            (ad - closed).norm() < 1e-12 * closed.norm(),
            "F = {f}, gamma = {g}"
        );
    }
}
