//! The activation approaches (issue 23, item 2) against independent derivations: active stress
//! and the structural activation I = C:(L + ωM) against dual numbers over F's nine entries
//! (energies written here by matrices), finite differences of the energy and symmetry of the
//! hyperelastic tangents; the structural implicit law against 4C's Lambert W closed form; each
//! approach on the sliding FE cylinder against its homogeneous (0D) curve; and the refusals.

use activemuscle::active::{
    ActivationLaw, ActivationMap, ActiveCurve, ConstantLaw, Coupling, Drive, FrozenTangent,
    ImplicitLaw, Law,
};
use activemuscle::energy::{EhretBolItskov, FourCPassive, GiantesioMusesti, NeoHookean};
use activemuscle::fem::{AxisymmetricSolver, Bases, Mesh, SolverOptions};
use activemuscle::invariants::{Kinematics, FULL};
use activemuscle::models::Models;
use activemuscle::oracle::{active_energy_by_matrices, full_response_with};
use activemuscle::response::Order;
use activemuscle::uniaxial::along_fibres;
use activemuscle::{Energy, Muscle, StrainEnergy};
use nalgebra::{Matrix3, SVector, Vector3};
use num_dual::{hessian, Dual2SVec64, DualNum};

/// A general F (stretch near 1.1 along e₃ with shear) and a fibre off the axes.
fn state() -> (Matrix3<f64>, Vector3<f64>) {
    let f = Matrix3::new(0.93, 0.08, -0.05, 0.04, 0.97, 0.11, -0.06, 0.09, 1.12);
    let m = Vector3::new(0.2, -0.3, 0.93).normalize();
    (f, m)
}

fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |a, v| a.max(v.abs()))
}

/// Ψ = W(C) + E(λ_f) by dual numbers over F's nine entries: W by matrices (the oracle's
/// route at γ = 0), E lifted from its value and its derivatives dE/dλ = T, d²E/dλ² = T′ at
/// λ_f's real part (the target of the drive, differentiated by dual numbers here).
fn active_stress_oracle<E: StrainEnergy>(
    energy: &E,
    curve: &ActiveCurve,
    drive: Drive,
    f: &Matrix3<f64>,
    m: &Vector3<f64>,
) -> (SVector<f64, 9>, nalgebra::SMatrix<f64, 9, 9>) {
    let lambda0 = (f * m).norm();
    let (t, t1) = num_dual::first_derivative(|l| drive.target(curve, l), lambda0);
    let x = SVector::<f64, 9>::from_iterator(f.transpose().iter().copied());
    let (_, g, h) = hessian(
        |v: SVector<Dual2SVec64<9>, 9>| {
            let ff = [[v[0], v[1], v[2]], [v[3], v[4], v[5]], [v[6], v[7], v[8]]];
            let w = active_energy_by_matrices(
                energy,
                ActivationMap::Chapter,
                &ff,
                m,
                Dual2SVec64::from_re(0.0),
            );
            let mut fm = [Dual2SVec64::from_re(0.0); 3];
            for (i, row) in ff.iter().enumerate() {
                for (j, x) in row.iter().enumerate() {
                    fm[i] += *x * m[j];
                }
            }
            let lambda = (fm[0] * fm[0] + fm[1] * fm[1] + fm[2] * fm[2]).sqrt();
            let dl = lambda - lambda0;
            w + dl * t + dl * dl * (0.5 * t1)
        },
        &x,
    );
    (g, h)
}

#[test]
fn active_stress_stress_and_tangent_match_the_nine_entry_oracle_and_are_symmetric() {
    let (f, m) = state();
    let kin = Kinematics::new(&f, &m).unwrap();
    for (energy, curve) in [
        (
            Energy::GiantesioMusesti(GiantesioMusesti::paper()),
            ActiveCurve::paper(),
        ),
        (
            Energy::EhretBolItskov(EhretBolItskov::paper()),
            ActiveCurve::ehret_bol_itskov(0.682, 1.192, 50.0).unwrap(),
        ),
    ] {
        for d in [0.0, 0.3] {
            let muscle = Muscle::active_stress(energy.clone(), curve, d).unwrap();
            let r = muscle.respond(&kin, Order::Tangent, &FULL).unwrap();
            let (p, a) = (r.stress.unwrap(), r.tangent.unwrap());
            let (g, h) = active_stress_oracle(&energy, &curve, Drive::from(d), &f, &m);
            let scale = max_abs(g.as_slice());
            assert!(
                max_abs((p - g).as_slice()) < 1e-11 * scale,
                "{}: stress {p} vs {g}",
                energy.name()
            );
            let scale = max_abs(h.as_slice());
            assert!(
                max_abs((a - h).as_slice()) < 1e-10 * scale,
                "{}: tangent",
                energy.name()
            );
            assert!(
                max_abs((a - a.transpose()).as_slice()) < 1e-12 * scale,
                "not symmetric"
            );
            assert_eq!(r.gamma, 0.0);
        }
    }
}

/// Active stress adds exactly T(λ_f) F M/λ_f to the passive stress (the formula of FEBio and
/// Blemker), at a general F.
#[test]
fn active_stress_is_the_passive_stress_plus_the_target_along_the_fibre() {
    let (f, m) = state();
    let kin = Kinematics::new(&f, &m).unwrap();
    let gm = GiantesioMusesti::paper();
    let curve = ActiveCurve::paper();
    let d = 0.2;
    let active = Muscle::active_stress(gm, curve, d).unwrap();
    let passive = Muscle::passive(gm);
    let p = active
        .respond(&kin, Order::Stress, &FULL)
        .unwrap()
        .stress
        .unwrap();
    let p0 = passive
        .respond(&kin, Order::Stress, &FULL)
        .unwrap()
        .stress
        .unwrap();
    let fm = f * m;
    let lambda = fm.norm();
    let t = (1.0 - d) * curve.value(lambda);
    for i in 0..3 {
        for j in 0..3 {
            let expected = p0[3 * i + j] + t * fm[i] * m[j] / lambda;
            assert!(
                (p[3 * i + j] - expected).abs() < 1e-12 * (1.0 + t),
                "{i}{j}"
            );
        }
    }
}

/// 4C's MAT_Muscle_Weickenmeier activation level in closed form (the Lambert W function): the
/// structural implicit law's root for 4C's energy and Ehret–Böl–Itskov's.
#[test]
fn structural_implicit_law_is_4c_s_lambert_w_closed_form() {
    let lambert = |x: f64| {
        let mut w: f64 = x.ln_1p();
        for _ in 0..200 {
            let step = (w * w.exp() - x) / (w.exp() * (w + 1.0));
            w -= step;
            if step.abs() < 1e-16 * w.abs().max(1e-300) {
                break;
            }
        }
        w
    };
    let curve = ActiveCurve::ehret_bol_itskov(0.682, 1.192, 0.5).unwrap();
    for energy in [
        Energy::FourCPassive(FourCPassive::paper()),
        Energy::EhretBolItskov(EhretBolItskov::paper()),
    ] {
        let (mu, alpha, w0) = (0.1599, 19.69, 0.7388);
        let map = ActivationMap::structural(&energy).unwrap();
        let law = ImplicitLaw::new(energy.clone(), curve).with_map(map);
        for lambda in [0.75, 0.9, 1.0, 1.2, 1.35] {
            for d in [0.0, 0.6] {
                let pa = (1.0 - d) * curve.value(lambda);
                let l = lambda;
                let ip1 = w0 / 3.0 * (2.0 * l - 2.0 / (l * l)) + 2.0 * (1.0 - w0) * l;
                let ip = w0 / 3.0 * (l * l + 2.0 / l) + (1.0 - w0) * l * l;
                let xi =
                    pa * (2.0 * alpha * l / mu) * (0.5 * alpha * (2.0 - 2.0 * ip + l * ip1)).exp()
                        + 0.5 * alpha * l * ip1 * (0.5 * alpha * l * ip1).exp();
                let closed = lambert(xi) / (alpha * l * l) - ip1 / (2.0 * l);
                let omega = law.activation(lambda, d).unwrap();
                assert!(
                    (omega - closed).abs() < 1e-12,
                    "{}, λ = {lambda}, d = {d}: ω = {omega} vs {closed}",
                    energy.name()
                );
            }
        }
    }
}

/// The structural map's stress, tangent and dP/dω at a held ω against dual numbers over F's
/// nine entries and ω (the oracle with C:(L + ωM) formed by matrices).
#[test]
fn structural_response_matches_the_nine_entry_oracle() {
    let (f, m) = state();
    let kin = Kinematics::new(&f, &m).unwrap();
    let energy = Energy::FourCPassive(FourCPassive::paper());
    let map = ActivationMap::structural(&energy).unwrap();
    for omega in [0.0, 0.2, 0.45] {
        let muscle = Muscle::new(
            energy.clone(),
            Law::Constant(ConstantLaw::new(omega).unwrap()),
            0.0,
            Coupling::Consistent,
        )
        .unwrap()
        .with_map(map)
        .unwrap();
        let r = muscle.respond(&kin, Order::Tangent, &FULL).unwrap();
        let o = full_response_with(&energy, map, &f, &m, omega).unwrap();
        let rel = |a: &[f64], b: &[f64]| {
            max_abs(&a.iter().zip(b).map(|(x, y)| x - y).collect::<Vec<_>>()) / max_abs(b)
        };
        assert!((r.energy - o.energy).abs() < 1e-13 * o.energy.abs().max(1.0));
        assert!(
            rel(r.stress.unwrap().as_slice(), o.stress.as_slice()) < 1e-12,
            "ω = {omega}"
        );
        assert!(
            rel(r.tangent.unwrap().as_slice(), o.tangent.as_slice()) < 1e-11,
            "ω = {omega}"
        );
        assert!(
            rel(
                r.dstress_dgamma.unwrap().as_slice(),
                o.dstress_dgamma.as_slice()
            ) < 1e-11
        );
    }
}

/// The consistent structural model is hyperelastic: its stress is the gradient of its energy
/// Ψ(F) = Ŵ(F, ω(λ_f(F))) (central differences, a Taylor test) and its tangent is symmetric;
/// the frozen model's exact tangent is not.
#[test]
fn consistent_structural_model_is_hyperelastic_and_frozen_is_not() {
    let (f, m) = state();
    let energy = Energy::EhretBolItskov(EhretBolItskov::paper());
    let map = ActivationMap::structural(&energy).unwrap();
    let curve = ActiveCurve::ehret_bol_itskov(0.682, 1.192, 30.0).unwrap();
    let law = Law::Implicit(ImplicitLaw::new(energy.clone(), curve).with_map(map));
    let muscle = |coupling| {
        Muscle::new(energy.clone(), law.clone(), 0.1, coupling)
            .unwrap()
            .with_map(map)
            .unwrap()
    };
    let consistent = muscle(Coupling::Consistent);
    let psi = |f: &Matrix3<f64>| {
        let kin = Kinematics::new(f, &m).unwrap();
        consistent
            .respond(&kin, Order::Energy, &FULL)
            .unwrap()
            .energy
    };
    let kin = Kinematics::new(&f, &m).unwrap();
    let r = consistent.respond(&kin, Order::Tangent, &FULL).unwrap();
    assert!(r.gamma > 0.05, "ω = {}", r.gamma);
    let p = r.stress.unwrap();
    let mut worst = 0.0f64;
    for k in 0..9 {
        let h = 1e-6;
        let mut e = Matrix3::zeros();
        e[(k / 3, k % 3)] = 1.0;
        let fd = (psi(&(f + e * h)) - psi(&(f - e * h))) / (2.0 * h);
        worst = worst.max((fd - p[k]).abs());
    }
    assert!(
        worst < 1e-6 * max_abs(p.as_slice()),
        "stress vs dΨ/dF: {worst:e}"
    );
    let a = r.tangent.unwrap();
    let scale = max_abs(a.as_slice());
    assert!(max_abs((a - a.transpose()).as_slice()) < 1e-11 * scale);
    let frozen = muscle(Coupling::Frozen(FrozenTangent::Exact));
    let a = frozen
        .respond(&kin, Order::Tangent, &FULL)
        .unwrap()
        .tangent
        .unwrap();
    assert!(max_abs((a - a.transpose()).as_slice()) > 1e-3 * max_abs(a.as_slice()));
}

fn sliding_matches_0d(muscle: &Muscle<Energy>, what: &str) {
    let mesh = Mesh::structured(1.0, 3.0, 2, 4, 1.0).unwrap();
    let mut solver =
        AxisymmetricSolver::new(mesh, Bases::Sliding, muscle, SolverOptions::default()).unwrap();
    let stretches = [0.85, 1.0, 1.12, 1.3];
    let results = solver.sweep(&stretches).unwrap().into_result().unwrap();
    assert_eq!(results.len(), stretches.len());
    for r in &results {
        let p0 = along_fibres(muscle, r.stretch).unwrap().stress;
        let rel = (r.nominal_stress - p0).abs() / p0.abs().max(1e-3);
        println!(
            "{what}: λ = {}: P_FE = {:.12e}, P_0D = {p0:.12e}, rel {rel:.1e}",
            r.stretch, r.nominal_stress
        );
        assert!(
            rel < 1e-9,
            "{what} at λ = {}: {} vs {p0}",
            r.stretch,
            r.nominal_stress
        );
    }
}

#[test]
fn sliding_cylinder_reproduces_the_0d_curve_for_every_approach() {
    let mut models = Models::paper();
    models.fibre = [0.0, 0.0, 1.0];
    use activemuscle::active::{ActivationMap, Approach};
    use activemuscle::models::{CouplingKind, LawKind, ModelChoice};
    let choice = |approach, law, coupling| ModelChoice {
        approach,
        law,
        coupling,
        damage: 0.2,
    };
    sliding_matches_0d(
        &models
            .muscle(ModelChoice::lawless(Approach::ActiveStress, 0.2))
            .unwrap(),
        "active stress",
    );
    for coupling in [CouplingKind::Frozen, CouplingKind::Consistent] {
        let m = models
            .muscle(choice(Approach::Structural, LawKind::Implicit, coupling))
            .unwrap();
        sliding_matches_0d(&m, "structural");
    }
    models.map = ActivationMap::VolumePreserving;
    let m = models
        .muscle(choice(
            Approach::ActiveStrain,
            LawKind::Energy,
            CouplingKind::Consistent,
        ))
        .unwrap();
    sliding_matches_0d(&m, "volume-preserving");
}

#[test]
fn the_structural_approach_is_refused_for_an_energy_without_a_structural_invariant() {
    let mut models = Models::paper();
    models.energy = Energy::NeoHookean(NeoHookean::new(1.0).unwrap());
    let structural = activemuscle::active::Approach::Structural;
    let rule = models.activation_map(structural).unwrap_err();
    assert!(
        rule.contains("C:(L + ωM)") && rule.contains("neo-hookean"),
        "{rule}"
    );
    assert!(models
        .supports(structural, activemuscle::models::LawKind::Implicit)
        .is_err());
    let error = models
        .muscle(activemuscle::models::ModelChoice {
            approach: structural,
            law: activemuscle::models::LawKind::Implicit,
            coupling: activemuscle::models::CouplingKind::Frozen,
            damage: 0.0,
        })
        .unwrap_err();
    assert!(error.to_string().contains("neo-hookean"));
}

/// A structural ω may exceed 1 (it is not a contraction); a negative one is refused.
#[test]
fn structural_activation_range_is_nonnegative_and_unbounded() {
    let map = ActivationMap::structural(&EhretBolItskov::paper()).unwrap();
    assert_eq!(map.check(1.7).unwrap(), 1.7);
    assert!(map.check(-0.1).is_err());
    assert!(ActivationMap::Chapter.check(1.0).is_err());
    assert!(ActivationMap::structural(&NeoHookean::new(1.0).unwrap()).is_none());
    // The structural map changes C:M only: ω C:M is added to I = C:L.
    let j = [3.1, 1.2, 2.9, 0.8, 1.0];
    let ie = map.elastic_invariants(&j, 0.3);
    let w0 = 0.7388;
    let i = |x: &[f64; 5]| w0 / 3.0 * x[0] + (1.0 - w0) * x[1];
    assert!((i(&ie) - (i(&j) + 0.3 * j[1])).abs() < 1e-15);
    assert_eq!([ie[0], ie[2], ie[3], ie[4]], [j[0], j[2], j[3], j[4]]);
}
