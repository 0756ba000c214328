//! Work bounded before it starts and long work followed: the memory estimate and its limit, the
//! cap on load steps, progress per stretch and cancellation keeping what was solved, and quick,
//! typed failures (never a NaN) of cylinders no solver can do.

use activemuscle::active::{ActiveCurve, Coupling, ExplicitLaw, FrozenTangent, Law};
use activemuscle::energy::GiantesioMusesti;
use activemuscle::fem::{
    AxisymmetricSolver, Bases, Cancel, Element, FemError, LinearSolver, MemoryEstimate, Mesh,
    NeoHookean, Progress, SolverOptions, StepFailure, Stepping, StretchResult,
};
use activemuscle::Muscle;

const MIB: u64 = 1 << 20;

#[test]
fn the_solver_refuses_a_mesh_above_its_memory_limit_and_names_both() {
    let material = NeoHookean::new(5.0).unwrap();
    let solver = |limit| {
        let mesh = Mesh::structured(1.0, 4.0, 8, 32, 1.0).unwrap();
        let options = SolverOptions {
            memory_limit: Some(limit),
            ..SolverOptions::default()
        };
        AxisymmetricSolver::new(mesh, Bases::Clamped, &material, options)
    };
    let accepted = solver(1 << 30).unwrap();
    let needed = accepted.memory_estimate().bytes;
    assert!(
        needed > MIB as f64 && needed < (100 * MIB) as f64,
        "{needed}"
    );
    let error = solver(MIB).unwrap_err();
    println!("{error}");
    assert!(matches!(error, FemError::MemoryLimit { limit, .. } if limit == MIB));
    assert!(error.to_string().contains("1.0 MiB"));
}

/// The fill model used before the symbolic factorisation against the factor's real size
/// (faer's symbolic Cholesky on the solver's ordering).
#[test]
fn the_fill_model_bounds_the_factor_from_above_within_a_factor_two() {
    let material = NeoHookean::new(5.0).unwrap();
    for element in Element::ALL {
        for (nr, nz) in [(8, 32), (16, 64)] {
            let model =
                MemoryEstimate::structured(nr, nz, element, LinearSolver::SymmetricPartGmres);
            let mesh = Mesh::structured(1.0, 4.0, nr, nz, 1.0).unwrap();
            let options = SolverOptions {
                element,
                ..SolverOptions::default()
            };
            let solver = AxisymmetricSolver::new(mesh, Bases::Clamped, &material, options).unwrap();
            let exact = solver.memory_estimate();
            let ratio = model.factor_values / exact.factor_values;
            println!(
                "{element} {nr} × {nz}: factor values {} exact, {:.0} modelled ({ratio:.2}); \
                 estimate {:.1} MiB from the counts, {:.1} MiB exact",
                exact.factor_values,
                model.factor_values,
                model.bytes / MIB as f64,
                exact.bytes / MIB as f64
            );
            assert!((1.0..2.0).contains(&ratio), "{ratio}");
            assert_eq!(exact.dofs, solver.n_free_dofs() as f64);
        }
    }
}

/// One load step 1 → 1.05, 1.1, 1.2 (the step doubles after two easy steps), then the cap.
#[test]
fn load_steps_are_capped_and_an_unreachable_target_is_refused_up_front() {
    let material = NeoHookean::new(5.0).unwrap();
    let options = SolverOptions {
        stepping: Stepping {
            max_steps: 3,
            ..Stepping::default()
        },
        ..SolverOptions::default()
    };
    let mesh = Mesh::structured(1.0, 4.0, 2, 8, 1.0).unwrap();
    let mut solver = AxisymmetricSolver::new(mesh, Bases::Clamped, &material, options).unwrap();
    let sweep = solver.sweep(&[1.25]).unwrap();
    assert!(sweep.results.is_empty());
    match sweep.failures.as_slice() {
        [FemError::StepLimit {
            target,
            reached,
            steps,
        }] => {
            assert_eq!((*target, *steps), (1.25, 3));
            assert!((reached - 1.2).abs() < 1e-12, "{reached}");
        }
        other => panic!("{other:?}"),
    }
    // 1 → 1.5 needs at least 5 steps of max_step = 0.1.
    assert!(matches!(
        solver.sweep(&[1.5]),
        Err(FemError::InvalidInput {
            name: "target stretch",
            ..
        })
    ));
}

/// A clamped neo-Hookean cylinder on 3 × 12 cells.
fn neo_hookean_solver(cancel: Option<Cancel>) -> AxisymmetricSolver<'static, NeoHookean> {
    static MATERIAL: NeoHookean = NeoHookean { mu: 5.0 };
    let mesh = Mesh::structured(1.0, 4.0, 3, 12, 1.0).unwrap();
    let options = SolverOptions {
        cancel,
        ..SolverOptions::default()
    };
    AxisymmetricSolver::new(mesh, Bases::Clamped, &MATERIAL, options).unwrap()
}

#[test]
fn progress_comes_per_stretch_and_a_cancelled_sweep_keeps_what_it_solved() {
    let targets = [0.9, 1.05, 1.1, 1.15, 1.2, 1.25];
    let full = neo_hookean_solver(None)
        .sweep(&targets)
        .unwrap()
        .into_result()
        .unwrap();
    let cancel = Cancel::new();
    let mut solver = neo_hookean_solver(Some(cancel.clone()));
    let (mut solved, mut steps) = (Vec::new(), 0);
    let sweep = solver
        .sweep_with(&targets, &mut |progress| match progress {
            Progress::Stretch(r) => {
                solved.push(r.stretch);
                if solved.len() == 2 {
                    cancel.cancel();
                }
            }
            Progress::Step(record) => {
                assert!(record.failure.is_none());
                steps += 1;
            }
        })
        .unwrap();
    // Upwards first: 1.05 and 1.1 solved, then the sweep stops (the downward direction too).
    assert_eq!(solved, [1.05, 1.1]);
    let upwards: Vec<&StretchResult> = full.iter().filter(|r| r.stretch > 1.0).collect();
    assert_eq!(sweep.results.len(), 2);
    for (kept, uncancelled) in sweep.results.iter().zip(&upwards) {
        assert_eq!(kept, *uncancelled);
    }
    let accepted: usize = sweep
        .results
        .iter()
        .flat_map(|r| &r.steps)
        .filter(|s| s.failure.is_none())
        .count();
    assert_eq!(steps, accepted);
    match sweep.failures.as_slice() {
        [FemError::Cancelled { target }] => assert_eq!(*target, 1.15),
        other => panic!("{other:?}"),
    }
    assert_eq!(sweep.failed_trials.len(), 1);
    // Cancelled before it starts: nothing solved, a typed reason.
    let sweep = solver.sweep(&targets).unwrap();
    assert!(sweep.results.is_empty());
    assert!(matches!(
        sweep.failures.as_slice(),
        [FemError::Cancelled { target }] if *target == 1.0
    ));
}

fn muscle(law: Law<GiantesioMusesti>) -> Muscle<GiantesioMusesti> {
    Muscle::new(
        GiantesioMusesti::paper(),
        law,
        0.0,
        Coupling::Frozen(FrozenTangent::Exact),
    )
    .unwrap()
}

fn clamped(
    material: &Muscle<GiantesioMusesti>,
    radius: f64,
    length: f64,
    cells: (usize, usize),
    targets: &[f64],
) -> Vec<FemError> {
    let mesh = Mesh::structured(radius, length, cells.0, cells.1, 1.0).unwrap();
    let mut solver =
        AxisymmetricSolver::new(mesh, Bases::Clamped, material, SolverOptions::default()).unwrap();
    let sweep = solver.sweep(targets).unwrap();
    for r in &sweep.results {
        for v in [r.nominal_stress, r.gamma_centre, r.fibre_stretch_centre] {
            assert!(v.is_finite(), "{r:?}");
        }
    }
    sweep.failures
}

/// The cylinder reproducers of issue 11 through the library: each ends in a fraction of a
/// second (measured: 0.007–0.3 s) with a typed error, and nothing non-finite is reported.
#[test]
fn unreasonable_cylinders_end_with_typed_errors_and_no_nan() {
    let explicit = muscle(Law::Explicit(ExplicitLaw::paper()));
    // λ = 9 on 2 × 8 cells: the corner cells invert long before (det F ≤ 0).
    match clamped(&explicit, 1.0, 4.0, (2, 8), &[9.0]).as_slice() {
        [FemError::TargetNotReached {
            target,
            reached,
            cause: StepFailure::Material(activemuscle::Error::NonPositiveJacobian { .. }),
            ..
        }] => assert!(*target == 9.0 && *reached > 1.5 && *reached < 9.0),
        other => panic!("{other:?}"),
    }
    // R = 1e-6, L = 1e6: cells of aspect ratio 2.5e11, a tangent no f64 solve resolves.
    assert!(matches!(
        clamped(&explicit, 1e-6, 1e6, (6, 24), &[1.17]).as_slice(),
        [FemError::ReferenceState { .. }]
    ));
    // A tolerance below round-off is refused before anything runs.
    let mesh = Mesh::structured(1.0, 4.0, 6, 24, 1.0).unwrap();
    let options = SolverOptions {
        stepping: Stepping {
            tolerance: 1e-300,
            ..Stepping::default()
        },
        ..SolverOptions::default()
    };
    assert!(matches!(
        AxisymmetricSolver::new(mesh, Bases::Clamped, &explicit, options),
        Err(FemError::InvalidInput {
            name: "tolerance",
            ..
        })
    ));
    // The explicit law with b = 1e6 leaves its domain at λ = 1: the reference state says so.
    let gm = GiantesioMusesti::paper();
    let law = ExplicitLaw::new(1.0133, 1e6, gm, ActiveCurve::paper()).unwrap();
    match clamped(&muscle(Law::Explicit(law)), 1.0, 4.0, (6, 24), &[1.17]).as_slice() {
        [FemError::ReferenceState {
            cause: StepFailure::Material(_),
        }] => {}
        other => panic!("{other:?}"),
    }
}
