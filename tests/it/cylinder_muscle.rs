//! The muscle on the FE solver. Sliding bases: the exact solution is the homogeneous uniaxial
//! state, so the FE nominal stress must equal the 0D result of the constitutive core to solver
//! tolerance, for every law and coupling, with and without damage.

use activemuscle::active::{
    ActiveCurve, Coupling, EnergyLaw, ExplicitLaw, FrozenTangent, ImplicitLaw, Law,
};
use activemuscle::energy::GiantesioMusesti;
use activemuscle::fem::{
    AxiF, AxisymmetricMaterial, AxisymmetricSolver, Bases, Mesh, SolverOptions, Stepping,
};
use activemuscle::uniaxial::along_fibres;
use activemuscle::Muscle;
use nalgebra::{SMatrix, SVector};

fn models() -> Vec<(&'static str, Law<GiantesioMusesti>, Coupling)> {
    let (gm, curve) = (GiantesioMusesti::paper(), ActiveCurve::paper());
    let frozen = Coupling::Frozen(FrozenTangent::Exact);
    vec![
        ("passive", Law::Passive, Coupling::Consistent),
        (
            "implicit/frozen",
            Law::Implicit(ImplicitLaw::new(gm, curve)),
            frozen,
        ),
        (
            "explicit/frozen",
            Law::Explicit(ExplicitLaw::paper()),
            frozen,
        ),
        (
            "energy/consistent",
            Law::Energy(EnergyLaw::new(gm, curve)),
            Coupling::Consistent,
        ),
    ]
}

#[test]
fn sliding_bases_reproduce_the_homogeneous_curve() {
    let targets: Vec<f64> = (7..=16).map(|k| k as f64 / 10.0).collect();
    for (name, law, coupling) in models() {
        for d in [0.0, 0.5] {
            if name == "passive" && d > 0.0 {
                continue;
            }
            let muscle = Muscle::new(GiantesioMusesti::paper(), law.clone(), d, coupling).unwrap();
            let mesh = Mesh::structured(1.0, 4.0, 2, 4, 1.0).unwrap();
            let mut solver =
                AxisymmetricSolver::new(mesh, Bases::Sliding, &muscle, SolverOptions::default())
                    .unwrap();
            let results = solver.sweep(&targets).unwrap().into_result().unwrap();
            assert_eq!(results.len(), targets.len(), "{name}, d = {d}");
            for r in &results {
                let exact = along_fibres(&muscle, r.stretch).unwrap();
                let rel = (r.nominal_stress - exact.stress).abs() / exact.stress.abs().max(1e-3);
                assert!(
                    rel < 1e-9,
                    "{name}, d = {d}, lambda = {}: FE {} vs 0D {} (rel {rel:e})",
                    r.stretch,
                    r.nominal_stress,
                    exact.stress
                );
                assert!(
                    (r.gamma_centre - exact.gamma).abs() < 1e-9,
                    "{name}: gamma at the centre"
                );
                assert!(
                    r.max_volume_error < 1e-9,
                    "det F = 1 at the quadrature points"
                );
            }
        }
    }
}

/// The consistent energy-law model on the clamped cylinder: with the continuous branch below
/// λ_min the chapter's sweep completes; with the jumping variant it stops where the fibres reach
/// λ_min, and says so.
#[test]
fn clamped_consistent_energy_law_completes_the_sweep_and_the_jumping_variant_explains_its_stop() {
    use activemuscle::active::BelowMinimum;
    use activemuscle::stability::diagnose_axisymmetric;
    let gm = GiantesioMusesti::paper();
    let mut targets: Vec<f64> = (0..=18).map(|k| 0.70 + 0.05 * k as f64).collect();
    targets.push(1.17);
    let run = |below: BelowMinimum| {
        let law = Law::Energy(EnergyLaw::new(gm, ActiveCurve::paper()).below_minimum(below));
        let muscle = Muscle::new(gm, law, 0.0, Coupling::Consistent).unwrap();
        let mesh = Mesh::structured(1.0, 4.0, 3, 12, 3.0).unwrap();
        let mut solver =
            AxisymmetricSolver::new(mesh, Bases::Clamped, &muscle, SolverOptions::default())
                .unwrap();
        let sweep = solver.sweep(&targets).unwrap();
        let diagnosis = sweep
            .failed_trials
            .first()
            .cloned()
            .flatten()
            .map(|points| {
                let f: Vec<_> = points.iter().map(|q| q.f).collect();
                diagnose_axisymmetric(&muscle, &f, 60).to_string()
            });
        (sweep.results.len(), diagnosis)
    };
    let (reached, _) = run(BelowMinimum::ZeroWork);
    assert_eq!(
        reached,
        targets.len(),
        "the continuous law completes the sweep"
    );
    let (reached, diagnosis) = run(BelowMinimum::Inactive);
    assert!(reached < targets.len(), "the jumping law cannot reach 0.70");
    let diagnosis = diagnosis.expect("a diagnosis of the failed trial");
    assert!(diagnosis.contains("lambda_min"), "{diagnosis}");
}

/// Solver extremes with the muscle: the coarsest mesh (1 × 4 cells) still follows the clamped
/// sweep, and a target beyond what f64 can represent (exp overflow of the passive energy near
/// λ ≈ 8.5) stops with a typed error naming the largest stretch reached and why.
#[test]
fn coarsest_mesh_runs_and_unreachable_targets_stop_with_the_largest_stretch_reached() {
    use activemuscle::fem::{FemError, StepFailure};
    let gm = GiantesioMusesti::paper();
    let muscle = Muscle::new(
        gm,
        Law::Explicit(ExplicitLaw::paper()),
        0.2,
        Coupling::Frozen(FrozenTangent::Exact),
    )
    .unwrap();
    let mesh = Mesh::structured(1.0, 4.0, 1, 4, 1.0).unwrap();
    let mut solver =
        AxisymmetricSolver::new(mesh, Bases::Clamped, &muscle, SolverOptions::default()).unwrap();
    let sweep = solver.sweep(&[0.7, 0.9, 1.17, 1.4]).unwrap();
    assert_eq!(sweep.results.len(), 4, "{:?}", sweep.failures);
    assert!(sweep.results.iter().all(|r| r.nominal_stress.is_finite()));

    let passive = Muscle::passive(gm);
    let mesh = Mesh::structured(1.0, 4.0, 1, 2, 1.0).unwrap();
    let options = SolverOptions {
        stepping: Stepping {
            max_step: 0.5,
            ..Stepping::default()
        },
        ..SolverOptions::default()
    };
    let mut solver = AxisymmetricSolver::new(mesh, Bases::Sliding, &passive, options).unwrap();
    let sweep = solver.sweep(&[2.0, 12.0]).unwrap();
    assert_eq!(sweep.results.len(), 1, "lambda = 2 is reached");
    match &sweep.failures[..] {
        [FemError::TargetNotReached {
            target,
            reached,
            cause,
            ..
        }] => {
            assert_eq!(*target, 12.0);
            // The material itself is representable up to λ ≈ 8.56 (stability::representable_stretch);
            // the solver stops earlier, where Newton iterates of the trial steps overflow.
            println!("stopped: {}", sweep.failures[0]);
            assert!(
                *reached > 2.0 && *reached < 8.6,
                "largest stretch reached {reached}"
            );
            assert!(
                matches!(
                    cause,
                    StepFailure::Material(activemuscle::Error::NonFinite { .. })
                        | StepFailure::LineSearch { .. }
                        | StepFailure::MaxIterations { .. }
                ),
                "{cause}"
            );
        }
        other => panic!("expected one TargetNotReached, got {other:?}"),
    }
}

/// A material that answers as the one it holds but keeps the default
/// [`AxisymmetricMaterial::symmetric_tangent`] (true).
struct Unsaid<'a, M>(&'a M);

impl<M: AxisymmetricMaterial> AxisymmetricMaterial for Unsaid<'_, M> {
    fn stress(&self, f: &AxiF) -> activemuscle::Result<SVector<f64, 5>> {
        self.0.stress(f)
    }
    fn stress_tangent(
        &self,
        f: &AxiF,
    ) -> activemuscle::Result<(SVector<f64, 5>, SMatrix<f64, 5, 5>)> {
        self.0.stress_tangent(f)
    }
    fn point_fields(&self, f: &AxiF) -> activemuscle::Result<(f64, f64)> {
        self.0.point_fields(f)
    }
}

/// The frozen model's non-symmetric tangent on the clamped cylinder: the default solver (the
/// LU on the LDLᵀ's pattern as GMRES's preconditioner from the first iteration, since the
/// muscle says its tangent is not symmetric; or, for a material that does not say so, GMRES on
/// the LDLᵀ until it fails, then that LU) and faer's partial-pivoting LU alone give the same
/// stresses.
#[test]
fn pattern_lu_path_matches_the_pivoting_lu_on_the_frozen_model() {
    let gm = GiantesioMusesti::paper();
    let muscle = Muscle::new(
        gm,
        Law::Explicit(ExplicitLaw::paper()),
        0.5,
        Coupling::Frozen(FrozenTangent::Exact),
    )
    .unwrap();
    let targets = [0.8, 1.17, 1.4];
    let run = |material: &dyn AxisymmetricMaterial, options: SolverOptions| {
        let mesh = Mesh::structured(1.0, 4.0, 6, 24, 3.0).unwrap();
        let mut solver = AxisymmetricSolver::new(mesh, Bases::Clamped, material, options).unwrap();
        let results = solver.sweep(&targets).unwrap().into_result().unwrap();
        let stresses: Vec<f64> = results.iter().map(|r| r.nominal_stress).collect();
        (stresses, solver.timings())
    };
    assert!(!muscle.symmetric_tangent());
    let (default, t) = run(&muscle, SolverOptions::default());
    let (lu, t_lu) = run(
        &muscle,
        SolverOptions {
            linear_solver: activemuscle::fem::LinearSolver::Lu,
            ..SolverOptions::default()
        },
    );
    // The same muscle behind a wrapper that does not say its tangent is non-symmetric, on one
    // thread (on two, a tangent of 4 000 unknowns or more starts on the pattern LU).
    let (switched, t_switched) = on_threads(1, || run(&Unsaid(&muscle), SolverOptions::default()));
    println!("default: {default:?} {t:?}\nLU: {lu:?} {t_lu:?}\nswitched: {t_switched:?}");
    // Every factorisation a pattern LU, none wasted on the LDLᵀ; a pattern LU that failed to
    // precondition would add an LU fallback.
    assert_eq!(t.pattern_lu_factorisations, t.factorisations, "{t:?}");
    assert_eq!(t.lu_fallbacks, 0, "{t:?}");
    // Without the declaration: one switch from the LDLᵀ to the LU.
    assert_eq!(t_switched.lu_fallbacks, 1, "{t_switched:?}");
    assert_eq!(t_lu.pattern_lu_factorisations, 0);
    for (a, b) in default.iter().chain(&switched).zip(lu.iter().chain(&lu)) {
        assert!((a - b).abs() <= 1e-9 * b.abs(), "{a} vs {b}");
    }
}

/// The energy law with consistent coupling is hyperelastic, so its tangent is symmetric: on one
/// thread a whole sweep stays on the LDLᵀ (one GMRES iteration per solve on a fresh factor),
/// never on an LU, also where the rate at a converged state meets the factor of an earlier
/// tangent.
#[test]
fn the_hyperelastic_sweep_stays_on_the_ldlt_on_one_thread() {
    let muscle = hyperelastic_muscle();
    let mesh = Mesh::structured(1.0, 4.0, 8, 32, 1.0).unwrap();
    let targets: Vec<f64> = (0..=18).map(|k| 0.70 + 0.05 * k as f64).collect();
    let (solver, results) = on_threads(1, || {
        let mut solver =
            AxisymmetricSolver::new(mesh, Bases::Clamped, &muscle, SolverOptions::default())
                .unwrap();
        let results = solver.sweep(&targets).unwrap().into_result().unwrap();
        (solver, results)
    });
    assert_eq!(results.len(), targets.len());
    let t = solver.timings();
    println!("{t:?}");
    assert_eq!(t.lu_fallbacks, 0, "{t:?}");
    assert_eq!(t.pattern_lu_factorisations, 0, "{t:?}");
}

/// The chapter's energy law with consistent coupling, d = 0: a symmetric tangent.
fn hyperelastic_muscle() -> Muscle<GiantesioMusesti> {
    let gm = GiantesioMusesti::paper();
    Muscle::new(
        gm,
        Law::Energy(EnergyLaw::new(gm, ActiveCurve::paper())),
        0.0,
        Coupling::Consistent,
    )
    .unwrap()
}

/// `f` on a rayon pool of `threads` threads (the solver picks its factorisation by them).
fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

/// On two threads and from `PATTERN_LU_UNKNOWNS` unknowns, the symmetric tangent of the energy
/// law is factorised by the pattern LU (two cores) instead of the LDLᵀ (one core), and the two
/// give the same stresses: every solve is converged to the same backward error. Below, on two
/// threads too, the LDLᵀ.
#[test]
fn a_symmetric_tangent_on_two_threads_takes_the_pattern_lu() {
    let muscle = hyperelastic_muscle();
    assert!(muscle.symmetric_tangent());
    let targets = [0.95, 1.17];
    let run = |nr, nz| {
        let mesh = Mesh::structured(1.0, 4.0, nr, nz, 1.0).unwrap();
        let mut solver =
            AxisymmetricSolver::new(mesh, Bases::Clamped, &muscle, SolverOptions::default())
                .unwrap();
        let results = solver.sweep(&targets).unwrap().into_result().unwrap();
        let stresses: Vec<f64> = results.iter().map(|r| r.nominal_stress).collect();
        (stresses, solver.timings())
    };
    // 16 × 64 Q2/Q1: 7 312 unknowns after condensation; 8 × 32: about 1 900.
    let (one, t_one) = on_threads(1, || run(16, 64));
    let (two, t_two) = on_threads(2, || run(16, 64));
    let (_, t_small) = on_threads(2, || run(8, 32));
    assert_eq!(t_small.pattern_lu_factorisations, 0, "{t_small:?}");
    println!("one thread: {one:?} {t_one:?}\ntwo threads: {two:?} {t_two:?}");
    assert_eq!(t_one.pattern_lu_factorisations, 0, "{t_one:?}");
    assert_eq!(t_one.lu_fallbacks, 0, "{t_one:?}");
    assert_eq!(
        t_two.pattern_lu_factorisations, t_two.factorisations,
        "{t_two:?}"
    );
    assert_eq!(t_two.lu_fallbacks, 0, "{t_two:?}");
    assert_eq!(one.len(), targets.len());
    for (a, b) in two.iter().zip(&one) {
        assert!((a - b).abs() <= 1e-9 * b.abs(), "{a} vs {b}");
    }
}
