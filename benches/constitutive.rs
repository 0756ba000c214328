//! Per-material-point cost of the constitutive routes, with the chapter's energy and parameters,
//! at a representative F (fibre stretch ≈ 1.1 plus shear, m = e_z) and γ = 0.15.
//!
//! `cargo bench --bench constitutive`; medians land in target/criterion/<group>/<id>/new/estimates.json.
//! Every AD route is timed from F (Kinematics::new included), as the closed form is.
//! See BENCHMARKS.md for the figures and the ratios to the hand-derived closed form.

mod closed_form;
mod point;

use activemuscle::active::active_energy;
use activemuscle::active::{
    ActivationLaw, ActivationMap, ActiveCurve, ConstantLaw, Coupling, EnergyLaw, ExplicitLaw,
    FrozenTangent, ImplicitLaw, Law, LawRepresentation, TableSpec,
};
use activemuscle::energy::{GiantesioMusesti, Invariants, StrainEnergy};
use activemuscle::invariants::{axial_fibre, axisymmetric_f, Kinematics, AXISYMMETRIC, FULL};
use activemuscle::oracle::full_response;
use activemuscle::response::{active_response, invariant_derivatives, Order};
use activemuscle::Muscle;
use closed_form::ClosedForm;
use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::SVector;
use num_dual::{gradient, hessian, Dual2SVec64, DualSVec64};
use point::{axi_entries, full_f, GAMMA};
use std::hint::black_box;
use std::time::Duration;

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

    // Muscle::respond (law + coupling + response), axisymmetric, from the five entries. The
    // tabulated laws: the default table (λ ∈ [0.5, 1.6]) for d = 0, built once here.
    let curve = ActiveCurve::paper();
    let implicit = Law::Implicit(ImplicitLaw::new(energy, curve));
    let energy_law = Law::Energy(EnergyLaw::new(energy, curve));
    let tabulated = |law: &Law<GiantesioMusesti>| {
        law.clone()
            .represented(LawRepresentation::Tabulated(TableSpec::default()), &[0.0])
            .unwrap()
    };
    let exact = Coupling::Frozen(FrozenTangent::Exact);
    let muscles = [
        ("implicit_frozen_exact_axi", implicit.clone(), exact),
        (
            "implicit_tabulated_frozen_exact_axi",
            tabulated(&implicit),
            exact,
        ),
        (
            "explicit_frozen_exact_axi",
            Law::Explicit(ExplicitLaw::paper()),
            exact,
        ),
        (
            "energy_consistent_axi",
            energy_law.clone(),
            Coupling::Consistent,
        ),
        (
            "energy_tabulated_consistent_axi",
            tabulated(&energy_law),
            Coupling::Consistent,
        ),
    ]
    .map(|(name, law, coupling)| (name, Muscle::new(energy, law, 0.0, coupling).unwrap()));
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
    for (_, muscle) in &muscles {
        let law = muscle.law();
        g.bench_function(law.name(), |b| {
            b.iter(|| law.evaluate(black_box(lambda), black_box(0.0)).unwrap())
        });
    }
    g.finish();

    // The active-strain map: the same muscle at constant γ with the chapter's and the
    // volume-preserving map (P + tangent + dP/dγ from F), axisymmetric and 3D.
    let mut g = group_config(c, "map");
    for map in [ActivationMap::Chapter, ActivationMap::VolumePreserving] {
        let muscle = Muscle::new(
            energy,
            Law::Constant(ConstantLaw::new(GAMMA).unwrap()),
            0.0,
            Coupling::Consistent,
        )
        .and_then(|m| m.with_map(map))
        .unwrap();
        g.bench_function(format!("{}_axi", map.name()), |b| {
            b.iter(|| {
                let kin = Kinematics::new(&axisymmetric_f(black_box(&f5)), &m).unwrap();
                muscle.respond(&kin, Order::Tangent, &AXISYMMETRIC).unwrap()
            })
        });
        g.bench_function(format!("{}_3d", map.name()), |b| {
            b.iter(|| {
                let kin = Kinematics::new(black_box(&f3), &m).unwrap();
                muscle.respond(&kin, Order::Tangent, &FULL).unwrap()
            })
        });
    }
    g.finish();

    // Building one table (d = 0, default spec): the cost a scene pays once.
    let mut g = c.benchmark_group("table");
    g.sample_size(10);
    g.warm_up_time(Duration::from_millis(200));
    g.measurement_time(Duration::from_secs(2));
    for law in [&implicit, &energy_law] {
        g.bench_function(format!("build_{}", law.name()), |b| {
            b.iter(|| tabulated(black_box(law)))
        });
    }
    g.finish();
}

criterion_group!(benches, constitutive);
criterion_main!(benches);
