//! Tangents: Taylor tests against the stress, symmetry where it must hold, the measured asymmetry
//! of the frozen model's exact tangent, and the fast axisymmetric route against the 9-entry route; the
//! Taylor test and the full-AD consistent tangent for both active-strain maps.

use activemuscle::active::{
    ActivationLaw, ActivationMap, ActiveCurve, ConstantLaw, Coupling, EnergyLaw, ExplicitLaw,
    FrozenTangent, ImplicitLaw, Law,
};
use activemuscle::energy::{EhretBolItskov, GiantesioMusesti, StrainEnergy};
use activemuscle::invariants::{
    axial_fibre, axisymmetric_f, Entries, Kinematics, AXISYMMETRIC, FULL,
};
use activemuscle::oracle::active_energy_by_matrices;
use activemuscle::response::{active_response, Order};
use activemuscle::Muscle;
use nalgebra::{Matrix3, SVector, Vector3};
use num_dual::DualNum;
use num_dual::{hessian, Dual2SVec64};

fn laws() -> Vec<(&'static str, Law<GiantesioMusesti>)> {
    laws_with(ActivationMap::Chapter)
}

/// The laws solved with `map` (the explicit law only with the chapter's map, which it is fitted for).
fn laws_with(map: ActivationMap) -> Vec<(&'static str, Law<GiantesioMusesti>)> {
    let (gm, curve) = (GiantesioMusesti::paper(), ActiveCurve::paper());
    let mut laws = vec![
        ("constant", Law::Constant(ConstantLaw::new(0.2).unwrap())),
        (
            "implicit",
            Law::Implicit(ImplicitLaw::new(gm, curve).with_map(map)),
        ),
        (
            "energy",
            Law::Energy(EnergyLaw::new(gm, curve).with_map(map)),
        ),
    ];
    if map == ActivationMap::Chapter {
        laws.insert(2, ("explicit", Law::Explicit(ExplicitLaw::paper())));
    }
    laws
}

const MAPS: [ActivationMap; 2] = [ActivationMap::Chapter, ActivationMap::VolumePreserving];

const COUPLINGS: [Coupling; 3] = [
    Coupling::Frozen(FrozenTangent::Exact),
    Coupling::Frozen(FrozenTangent::Symmetric),
    Coupling::Consistent,
];

/// A sheared stretch of about 1.1 along the fibre m = e₁ (active region).
fn sample_f() -> Matrix3<f64> {
    Matrix3::new(1.1, 0.05, -0.02, 0.03, 0.96, 0.04, -0.01, 0.02, 0.94)
}
fn fibre() -> Vector3<f64> {
    Vector3::new(1.0, 0.0, 0.0)
}

/// Observed orders of the Taylor remainder r(h) = |P(F + h dF) − P(F) − h K dF| for h = 1e-1 … 1e-5.
fn taylor_orders<const N: usize>(
    muscle: &Muscle<GiantesioMusesti>,
    f: &Matrix3<f64>,
    m: &Vector3<f64>,
    entries: &Entries<N>,
) -> Vec<f64> {
    let at = |f: &Matrix3<f64>, order| {
        muscle
            .respond(&Kinematics::new(f, m).unwrap(), order, entries)
            .unwrap()
    };
    let base = at(f, Order::Tangent);
    let (p0, k) = (base.stress.unwrap(), base.tangent.unwrap());
    let dir = SVector::<f64, N>::from_fn(|i, _| {
        0.3 + 0.1 * i as f64 * if i % 2 == 0 { 1.0 } else { -1.0 }
    });
    let mut remainders = vec![];
    for e in 1..=5 {
        let h = 10f64.powi(-e);
        let mut fh = *f;
        for (a, &(i, j)) in entries.index.iter().enumerate() {
            fh[(i, j)] += h * dir[a];
        }
        let p = at(&fh, Order::Stress).stress.unwrap();
        remainders.push((p - p0 - k * dir * h).norm());
    }
    remainders
        .windows(2)
        .map(|w| (w[0] / w[1]).log10())
        .collect()
}

#[test]
fn exact_tangents_pass_the_taylor_test_and_the_symmetric_approximation_does_not() {
    for (map, (name, law)) in MAPS
        .into_iter()
        .flat_map(|map| laws_with(map).into_iter().map(move |l| (map, l)))
    {
        for coupling in COUPLINGS {
            let muscle = Muscle::new(GiantesioMusesti::paper(), law.clone(), 0.1, coupling)
                .and_then(|m| m.with_map(map))
                .unwrap();
            let full = taylor_orders(&muscle, &sample_f(), &fibre(), &FULL);
            let axi_f = axisymmetric_f(&SVector::from([0.97, 0.04, -0.03, 1.12, 0.95]));
            let axi = taylor_orders(&muscle, &axi_f, &axial_fibre(), &AXISYMMETRIC);
            for orders in [&full, &axi] {
                let exact =
                    coupling != Coupling::Frozen(FrozenTangent::Symmetric) || name == "constant";
                // Three decades (1e-2 … 1e-5) of second-order decay for an exact tangent.
                let observed = &orders[1..];
                if exact {
                    assert!(
                        observed.iter().all(|o| *o > 1.9 && *o < 2.1),
                        "{} {name} {coupling:?}: orders {orders:?}",
                        map.name()
                    );
                } else {
                    // First order once the dropped term dominates (last decade, 1e-4 → 1e-5).
                    let last = orders[orders.len() - 1];
                    assert!(
                        last > 0.9 && last < 1.1,
                        "{name} symmetric approximation: orders {orders:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn stress_derivative_in_gamma_passes_the_taylor_test() {
    let gm = GiantesioMusesti::paper();
    let kin = Kinematics::new(&sample_f(), &fibre()).unwrap();
    let g0 = 0.25;
    let base = active_response(&gm, &kin, g0, Order::Tangent, &FULL).unwrap();
    let (p0, dp) = (base.stress.unwrap(), base.dstress_dgamma.unwrap());
    let r: Vec<f64> = (1..=5)
        .map(|e| {
            let h = 10f64.powi(-e);
            (active_response(&gm, &kin, g0 + h, Order::Stress, &FULL)
                .unwrap()
                .stress
                .unwrap()
                - p0
                - dp * h)
                .norm()
        })
        .collect();
    for w in r[1..].windows(2) {
        let order = (w[0] / w[1]).log10();
        assert!(order > 1.9 && order < 2.1, "remainders {r:?}");
    }
}

/// The muscle's dP/dγ is the held-γ rate ∂²Ŵ/∂F∂γ at the law's γ for every law and coupling, and
/// that rate passes the Taylor test above.
#[test]
fn muscle_stress_rate_in_gamma_is_the_held_gamma_rate_at_the_laws_gamma() {
    let gm = GiantesioMusesti::paper();
    let kin = Kinematics::new(&sample_f(), &fibre()).unwrap();
    for (name, law) in laws() {
        for coupling in COUPLINGS {
            let muscle = Muscle::new(gm, law.clone(), 0.1, coupling).unwrap();
            let r = muscle.respond(&kin, Order::Tangent, &FULL).unwrap();
            let held = active_response(&gm, &kin, r.gamma, Order::Tangent, &FULL).unwrap();
            let (dp, expected) = (r.dstress_dgamma.unwrap(), held.dstress_dgamma.unwrap());
            assert!(
                (dp - expected).norm() <= 1e-13 * expected.norm(),
                "{name} {coupling:?}: {dp} vs {expected}"
            );
            let stress_only = muscle.respond(&kin, Order::Stress, &FULL).unwrap();
            assert!(stress_only.dstress_dgamma.is_none());
        }
    }
}

#[test]
fn consistent_tangent_is_symmetric_and_frozen_exact_tangent_is_not() {
    for (name, law) in laws().into_iter().skip(1) {
        let asymmetry = |coupling| {
            let muscle =
                Muscle::new(GiantesioMusesti::paper(), law.clone(), 0.0, coupling).unwrap();
            let k = muscle
                .respond(
                    &Kinematics::new(&sample_f(), &fibre()).unwrap(),
                    Order::Tangent,
                    &FULL,
                )
                .unwrap()
                .tangent
                .unwrap();
            (k - k.transpose()).norm() / k.norm()
        };
        let (consistent, frozen) = (
            asymmetry(Coupling::Consistent),
            asymmetry(Coupling::Frozen(FrozenTangent::Exact)),
        );
        println!("{name}: relative asymmetry ‖K − Kᵀ‖/‖K‖: consistent {consistent:.1e}, frozen exact {frozen:.3e}");
        assert!(consistent < 1e-13, "{name}");
        assert!(
            frozen > 1e-2,
            "{name}: the frozen model is not a gradient, its tangent cannot be symmetric"
        );
    }
}

/// Ψ(F) = Ŵ(F, g(λ_f(F))) differentiated as one function of F's nine entries: independent of
/// the coupling's chain rule.
fn consistent_by_full_ad<E: StrainEnergy>(
    energy: &E,
    map: ActivationMap,
    law: &Law<E>,
    f: &Matrix3<f64>,
    m: &Vector3<f64>,
) -> (SVector<f64, 9>, nalgebra::SMatrix<f64, 9, 9>) {
    let x = SVector::<f64, 9>::from_fn(|a, _| f[(a / 3, a % 3)]);
    let (_, g, h) = hessian(
        |v: SVector<Dual2SVec64<9>, 9>| {
            let f = [[v[0], v[1], v[2]], [v[3], v[4], v[5]], [v[6], v[7], v[8]]];
            let mut fm = [v[0] * 0.0; 3];
            for i in 0..3 {
                fm[i] = f[i][0] * m[0] + f[i][1] * m[1] + f[i][2] * m[2];
            }
            let lambda = (fm[0] * fm[0] + fm[1] * fm[1] + fm[2] * fm[2]).sqrt();
            let gamma = law.gamma(lambda, 0.2).unwrap();
            active_energy_by_matrices(energy, map, &f, m, gamma)
        },
        &x,
    );
    (g, h)
}

#[test]
fn consistent_coupling_equals_full_ad_of_the_composed_energy() {
    for (map, (name, law)) in MAPS
        .into_iter()
        .flat_map(|map| laws_with(map).into_iter().map(move |l| (map, l)))
    {
        let muscle = Muscle::new(
            GiantesioMusesti::paper(),
            law.clone(),
            0.2,
            Coupling::Consistent,
        )
        .and_then(|m| m.with_map(map))
        .unwrap();
        let r = muscle
            .respond(
                &Kinematics::new(&sample_f(), &fibre()).unwrap(),
                Order::Tangent,
                &FULL,
            )
            .unwrap();
        let (p, k) = consistent_by_full_ad(muscle.energy(), map, &law, &sample_f(), &fibre());
        assert!(
            (r.stress.unwrap() - p).norm() < 1e-12 * p.norm(),
            "{} {name} stress",
            map.name()
        );
        assert!(
            (r.tangent.unwrap() - k).norm() < 1e-12 * k.norm(),
            "{} {name} tangent",
            map.name()
        );
    }
}

#[test]
fn axisymmetric_route_equals_the_nine_entry_route() {
    let energies = [GiantesioMusesti::paper()];
    let ebi = Muscle::new(
        EhretBolItskov::paper(),
        Law::Constant(ConstantLaw::new(0.3).unwrap()),
        0.0,
        Coupling::Consistent,
    )
    .unwrap();
    let mut s = activemuscle::testing::Sampler::new(21);
    for _ in 0..50 {
        let axi = SVector::from([
            s.range(0.7, 1.3),
            s.range(-0.2, 0.2),
            s.range(-0.2, 0.2),
            s.range(0.7, 1.5),
            s.range(0.7, 1.3),
        ]);
        let f = axisymmetric_f(&axi);
        let kin = Kinematics::new(&f, &axial_fibre()).unwrap();
        for (_, law) in laws() {
            for coupling in COUPLINGS {
                let muscle = Muscle::new(energies[0], law.clone(), 0.3, coupling).unwrap();
                let (a, b) = (
                    muscle.respond(&kin, Order::Tangent, &AXISYMMETRIC).unwrap(),
                    muscle.respond(&kin, Order::Tangent, &FULL).unwrap(),
                );
                let (pa, ka, pb, kb) = (
                    a.stress.unwrap(),
                    a.tangent.unwrap(),
                    b.stress.unwrap(),
                    b.tangent.unwrap(),
                );
                for (x, &(i, j)) in AXISYMMETRIC.index.iter().enumerate() {
                    let bx = 3 * i + j;
                    assert!((pa[x] - pb[bx]).abs() <= 1e-12 * pb.norm());
                    for (y, &(k, l)) in AXISYMMETRIC.index.iter().enumerate() {
                        assert!((ka[(x, y)] - kb[(bx, 3 * k + l)]).abs() <= 1e-12 * kb.norm());
                    }
                }
            }
        }
        let (a, b) = (
            ebi.respond(&kin, Order::Tangent, &AXISYMMETRIC).unwrap(),
            ebi.respond(&kin, Order::Tangent, &FULL).unwrap(),
        );
        assert!((a.energy - b.energy).abs() <= 1e-14 * b.energy.abs().max(1.0));
        let _ = ActivationLaw::evaluate(&ConstantLaw::new(0.1).unwrap(), 1.0, 0.0).unwrap();
    }
}
