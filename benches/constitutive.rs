//! Per-material-point cost of the constitutive routes, with the chapter's energy and parameters,
//! at a representative F (fibre stretch ≈ 1.1 plus shear, m = e_z) and γ = 0.15.
//!
//! `cargo bench --bench constitutive`; medians land in target/criterion/<group>/<id>/new/estimates.json.
//! Every AD route is timed from F (Kinematics::new included), as the closed form is.
//! See BENCHMARKS.md for the figures and the ratios to the hand-derived closed form.

mod closed_form;

use activemuscle::active::active_energy;
use activemuscle::active::{
    ActivationLaw, ActiveCurve, Coupling, EnergyLaw, ExplicitLaw, FrozenTangent, ImplicitLaw, Law,
};
use activemuscle::energy::{GiantesioMusesti, Invariants, StrainEnergy};
use activemuscle::invariants::{axial_fibre, axisymmetric_f, Kinematics, AXISYMMETRIC, FULL};
use activemuscle::oracle::full_response;
use activemuscle::response::{active_response, invariant_derivatives, Order};
use activemuscle::Muscle;
use closed_form::ClosedForm;
use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::{Matrix3, SVector};
use num_dual::{gradient, hessian, Dual2SVec64, DualSVec64};
use std::hint::black_box;
use std::time::Duration;

const GAMMA: f64 = 0.15;

/// Axisymmetric entries [F_rr, F_rz, F_zr, F_zz, F_θθ]: axial stretch 1.1, lateral contraction
/// 1/√1.1, shear 0.05 / 0.02 (det F ≈ 1).
fn axi_entries() -> SVector<f64, 5> {
    let l = 1.0 / 1.1_f64.sqrt();
    SVector::from([l, 0.05, 0.02, 1.1, l])
}

/// 3D F: the axisymmetric point plus an out-of-plane shear, so that no entry is structurally zero.
fn full_f() -> Matrix3<f64> {
    let mut f = axisymmetric_f(&axi_entries());
    f[(0, 1)] = 0.03;
    f[(1, 2)] = -0.02;
    f[(2, 1)] = 0.01;
    f
}

fn group_config<'a>(
    c: &'a mut Criterion,
    name: &str,
) -> criterion::BenchmarkGroup<'a, criterion::measurement::WallTime> {
    let mut g = c.benchmark_group(name);
    g.warm_up_time(Duration::from_millis(500));
    g.measurement_time(Duration::from_millis(1500));
    g.sample_size(30);
    g
}

fn constitutive(c: &mut Criterion) {
    let energy = GiantesioMusesti::paper();
    let cf = ClosedForm::new(energy.mu(), energy.alpha(), energy.w0());
    let m = axial_fibre();
    let f5 = axi_entries();
    let f_axi = axisymmetric_f(&f5);
    let f3 = full_f();

    // Energy only, f64, from the invariants of C (the user's W through the active-strain map).
    let j = Kinematics::new(&f3, &m).unwrap().invariants;
    let mut g = group_config(c, "energy");
    g.bench_function("energy_f64_from_invariants", |b| {
        b.iter(|| active_energy(&energy, black_box(&j), black_box(GAMMA)))
    });
    g.bench_function("energy_f64_from_F_3d", |b| {
        b.iter(|| {
            let kin = Kinematics::new(black_box(&f3), black_box(&m)).unwrap();
            active_energy(&energy, &kin.invariants, black_box(GAMMA))
        })
    });
    g.finish();

    let mut g = group_config(c, "stress");
    g.bench_function("fast_ad_axi", |b| {
        b.iter(|| {
            let kin = Kinematics::new(&axisymmetric_f(black_box(&f5)), &m).unwrap();
            active_response(
                &energy,
                &kin,
                black_box(GAMMA),
                Order::Stress,
                &AXISYMMETRIC,
            )
            .unwrap()
        })
    });
    g.bench_function("fast_ad_3d", |b| {
        b.iter(|| {
            let kin = Kinematics::new(black_box(&f3), black_box(&m)).unwrap();
            active_response(&energy, &kin, black_box(GAMMA), Order::Stress, &FULL).unwrap()
        })
    });
    g.finish();

    let mut g = group_config(c, "tangent");
    g.bench_function("closed_form_axi", |b| {
        b.iter(|| cf.axisymmetric(black_box(&f5), black_box(GAMMA)).unwrap())
    });
    g.bench_function("closed_form_3d", |b| {
        b.iter(|| {
            cf.full(black_box(&f3), black_box(&m), black_box(GAMMA))
                .unwrap()
        })
    });
    g.bench_function("fast_ad_axi", |b| {
        b.iter(|| {
            let kin = Kinematics::new(&axisymmetric_f(black_box(&f5)), &m).unwrap();
            active_response(
                &energy,
                &kin,
                black_box(GAMMA),
                Order::Tangent,
                &AXISYMMETRIC,
            )
            .unwrap()
        })
    });
    g.bench_function("fast_ad_3d", |b| {
        b.iter(|| {
            let kin = Kinematics::new(black_box(&f3), black_box(&m)).unwrap();
            active_response(&energy, &kin, black_box(GAMMA), Order::Tangent, &FULL).unwrap()
        })
    });
    g.bench_function("oracle_3d", |b| {
        b.iter(|| full_response(&energy, black_box(&f3), black_box(&m), black_box(GAMMA)).unwrap())
    });
    g.finish();

    // Where the fast route's time goes (each piece alone, inputs prepared outside the loop).
    let kin3 = Kinematics::new(&f3, &m).unwrap();
    let kina = Kinematics::new(&f_axi, &m).unwrap();
    let j3 = SVector::from(kin3.invariants);
    let d3 = invariant_derivatives(&energy, &j3, GAMMA, Order::Tangent).unwrap();
    let mut g = group_config(c, "parts");
    g.bench_function("kinematics_new", |b| {
        b.iter(|| Kinematics::new(black_box(&f3), black_box(&m)).unwrap())
    });
    g.bench_function("invariant_derivatives_stress", |b| {
        b.iter(|| {
            invariant_derivatives(&energy, black_box(&j3), black_box(GAMMA), Order::Stress).unwrap()
        })
    });
    g.bench_function("invariant_derivatives_tangent", |b| {
        b.iter(|| {
            invariant_derivatives(&energy, black_box(&j3), black_box(GAMMA), Order::Tangent)
                .unwrap()
        })
    });
    // The user's W alone (no active-strain map, no checks): f64, and num-dual over its 5 inputs.
    let ie = SVector::from(activemuscle::active::strain::elastic_invariants(
        &kin3.invariants,
        GAMMA,
    ));
    let inv = |v: &SVector<f64, 5>| Invariants::from_array([v[0], v[1], v[2], v[3], v[4]]);
    g.bench_function("user_energy_f64", |b| {
        b.iter(|| energy.energy(&inv(black_box(&ie))))
    });
    g.bench_function("num_dual_gradient_5", |b| {
        b.iter(|| {
            gradient(
                |v: SVector<DualSVec64<5>, 5>| {
                    energy.energy(&Invariants::from_array([v[0], v[1], v[2], v[3], v[4]]))
                },
                black_box(&ie),
            )
        })
    });
    g.bench_function("num_dual_hessian_5", |b| {
        b.iter(|| {
            hessian(
                |v: SVector<Dual2SVec64<5>, 5>| {
                    energy.energy(&Invariants::from_array([v[0], v[1], v[2], v[3], v[4]]))
                },
                black_box(&ie),
            )
        })
    });
    // The route's own Dᵀ K D (upper triangle over four invariants) is not public: it is the
    // difference between active_response given kinematics and the parts above and below.
    g.bench_function("gradients_axi", |b| {
        b.iter(|| black_box(&kina).gradients(&AXISYMMETRIC))
    });
    g.bench_function("gradients_3d", |b| {
        b.iter(|| black_box(&kin3).gradients(&FULL))
    });
    g.bench_function("curvature_axi", |b| {
        b.iter(|| black_box(&kina).curvature(black_box(&d3.d_j), &AXISYMMETRIC))
    });
    g.bench_function("curvature_3d", |b| {
        b.iter(|| black_box(&kin3).curvature(black_box(&d3.d_j), &FULL))
    });
    g.bench_function("active_response_tangent_axi_given_kinematics", |b| {
        b.iter(|| {
            active_response(
                &energy,
                black_box(&kina),
                black_box(GAMMA),
                Order::Tangent,
                &AXISYMMETRIC,
            )
            .unwrap()
        })
    });
    g.bench_function("active_response_tangent_3d_given_kinematics", |b| {
        b.iter(|| {
            active_response(
                &energy,
                black_box(&kin3),
                black_box(GAMMA),
                Order::Tangent,
                &FULL,
            )
            .unwrap()
        })
    });
    g.finish();

    // Muscle::respond (law + coupling + response), axisymmetric, from the five entries.
    let curve = ActiveCurve::paper();
    let implicit = ImplicitLaw::new(energy, curve);
    let explicit = ExplicitLaw::paper();
    let energy_law = EnergyLaw::new(energy, curve);
    let exact = Coupling::Frozen(FrozenTangent::Exact);
    let muscles = [
        (
            "implicit_frozen_exact_axi",
            Muscle::new(energy, Law::Implicit(implicit.clone()), 0.0, exact).unwrap(),
        ),
        (
            "explicit_frozen_exact_axi",
            Muscle::new(energy, Law::Explicit(explicit), 0.0, exact).unwrap(),
        ),
        (
            "energy_consistent_axi",
            Muscle::new(
                energy,
                Law::Energy(energy_law.clone()),
                0.0,
                Coupling::Consistent,
            )
            .unwrap(),
        ),
    ];
    let mut g = group_config(c, "muscle");
    for (name, muscle) in &muscles {
        g.bench_function(*name, |b| {
            b.iter(|| {
                let kin = Kinematics::new(&axisymmetric_f(black_box(&f5)), &m).unwrap();
                muscle.respond(&kin, Order::Tangent, &AXISYMMETRIC).unwrap()
            })
        });
    }
    g.finish();

    let lambda = 1.1;
    let mut g = group_config(c, "law");
    g.bench_function("implicit", |b| {
        b.iter(|| {
            implicit
                .evaluate(black_box(lambda), black_box(0.0))
                .unwrap()
        })
    });
    g.bench_function("explicit", |b| {
        b.iter(|| {
            explicit
                .evaluate(black_box(lambda), black_box(0.0))
                .unwrap()
        })
    });
    g.bench_function("energy", |b| {
        b.iter(|| {
            energy_law
                .evaluate(black_box(lambda), black_box(0.0))
                .unwrap()
        })
    });
    g.finish();
}

criterion_group!(benches, constitutive);
criterion_main!(benches);
