//! Newton's method: quadratic convergence with the exact (non-symmetric) tangent, linear
//! convergence with an approximated one, and typed errors instead of panics.

use activemuscle::fem::material::axial_stretch;
use activemuscle::fem::{
    AxiF, AxisymmetricMaterial, AxisymmetricSolver, Bases, Element, FemError, Mesh, NeoHookean,
    SolverOptions, StepFailure, StepRecord, Stepping,
};
use nalgebra::{SMatrix, SVector};

const MU: f64 = 10.0;
/// Strength of the non-gradient stress term.
const C: f64 = 0.15 * MU;

use crate::common;
use common::{residuals, sci, NonSymmetric};

/// One large load step 1 → 1.3 on a clamped cylinder of 4 × 8 Q2/Q1 cells.
fn one_step(material: &NonSymmetric) -> StepRecord {
    common::one_step(material, Element::Q2Q1, 4, 8)
}

#[test]
fn exact_nonsymmetric_tangent_converges_quadratically() {
    let exact = one_step(&NonSymmetric {
        mu: MU,
        c: C,
        approximate: false,
    });
    common::assert_quadratic(&exact, "exact tangent");
}

#[test]
fn dropping_the_nonsymmetric_part_of_the_tangent_converges_only_linearly() {
    let exact = one_step(&NonSymmetric {
        mu: MU,
        c: C,
        approximate: false,
    });
    let approx = one_step(&NonSymmetric {
        mu: MU,
        c: C,
        approximate: true,
    });
    let r = residuals(&approx);
    println!("approximated tangent, scaled residuals: {:?}", sci(&r));
    let ratios: Vec<f64> = r
        .windows(2)
        .filter(|w| w[1] > 1e-13)
        .map(|w| w[1] / w[0])
        .collect();
    println!("contraction ratios: {ratios:.3?}");
    println!(
        "iterations: exact tangent {}, approximated tangent {}",
        exact.iterations.len(),
        approx.iterations.len()
    );
    assert!(approx.iterations.len() >= exact.iterations.len() + 3);
    // Linear convergence: the contraction ratio settles at a constant, it does not go to zero.
    let tail = &ratios[ratios.len().saturating_sub(4)..];
    assert!(tail.len() >= 3);
    for q in tail {
        assert!(
            *q > 1e-3 && *q < 0.9,
            "ratio {q} is not a linear-convergence ratio"
        );
    }
    let spread =
        tail.iter().cloned().fold(0.0, f64::max) / tail.iter().cloned().fold(1.0, f64::min);
    assert!(spread < 3.0, "ratios {tail:?} do not settle");
}

/// Neo-Hookean that refuses (as an overflow would) any fibre stretch above `limit`.
struct Breaks {
    inner: NeoHookean,
    limit: f64,
}

impl Breaks {
    fn check(&self, f: &AxiF) -> activemuscle::Result<()> {
        let lf = axial_stretch(f);
        if lf > self.limit {
            Err(activemuscle::Error::NonFinite {
                quantity: "test stress",
                value: f64::INFINITY,
                context: format!("fibre stretch {lf}"),
            })
        } else {
            Ok(())
        }
    }
}

impl AxisymmetricMaterial for Breaks {
    fn stress(&self, f: &AxiF) -> activemuscle::Result<SVector<f64, 5>> {
        self.check(f)?;
        self.inner.stress(f)
    }
    fn stress_tangent(
        &self,
        f: &AxiF,
    ) -> activemuscle::Result<(SVector<f64, 5>, SMatrix<f64, 5, 5>)> {
        self.check(f)?;
        self.inner.stress_tangent(f)
    }
    fn point_fields(&self, f: &AxiF) -> activemuscle::Result<(f64, f64)> {
        self.inner.point_fields(f)
    }
}

#[test]
fn unreachable_target_is_a_typed_error_naming_the_largest_stretch_reached() {
    let material = Breaks {
        inner: NeoHookean::new(MU).unwrap(),
        limit: 1.237,
    };
    let mesh = Mesh::structured(1.0, 2.0, 2, 4, 1.0).unwrap();
    let mut solver =
        AxisymmetricSolver::new(mesh, Bases::Sliding, &material, SolverOptions::default()).unwrap();
    let sweep = solver.sweep(&[0.8, 1.1, 1.2, 1.5]).unwrap();
    // The downward direction is unaffected; upward reaches 1.1 and 1.2 only.
    let reached: Vec<f64> = sweep.results.iter().map(|r| r.stretch).collect();
    assert_eq!(reached, vec![0.8, 1.1, 1.2]);
    assert_eq!(sweep.failures.len(), 1);
    let message = sweep.failures[0].to_string();
    println!("{message}");
    match &sweep.failures[0] {
        FemError::TargetNotReached {
            target,
            reached,
            attempted,
            step,
            cause,
        } => {
            assert_eq!(*target, 1.5);
            // Sliding bases are homogeneous: the largest admissible stretch is the limit itself.
            assert!(
                *reached <= 1.237 && *reached > 1.237 - 2e-4,
                "reached {reached}"
            );
            assert!(*attempted > 1.237);
            assert!(*step < 2.0 * SolverOptions::default().stepping.min_step);
            assert!(matches!(
                cause,
                StepFailure::Material(activemuscle::Error::NonFinite { .. })
            ));
        }
        other => panic!("unexpected error {other:?}"),
    }
    // The failed trial's quadrature-point deformations are available for a stability check.
    let qps = solver
        .failed_trial_quadrature_points()
        .expect("a failed trial is kept");
    assert!(qps.iter().any(|q| axial_stretch(&q.f) > 1.237));
    assert!(message.contains("1.5") && message.contains("largest converged stretch"));
}

#[test]
fn invalid_inputs_are_typed_errors() {
    let material = NeoHookean::new(MU).unwrap();
    assert!(matches!(
        Mesh::structured(1.0, 1.0, 0, 2, 1.0),
        Err(FemError::InvalidInput { .. })
    ));
    assert!(matches!(
        Mesh::structured(-1.0, 1.0, 1, 2, 1.0),
        Err(FemError::InvalidInput { .. })
    ));
    assert!(matches!(
        Mesh::structured(1.0, f64::NAN, 1, 2, 1.0),
        Err(FemError::InvalidInput { .. })
    ));
    assert!(matches!(
        Mesh::structured(1.0, 1.0, 1, 2, 0.5),
        Err(FemError::InvalidInput { .. })
    ));
    let mesh = Mesh::structured(1.0, 1.0, 1, 2, 1.0).unwrap();
    let mut solver =
        AxisymmetricSolver::new(mesh, Bases::Clamped, &material, SolverOptions::default()).unwrap();
    for bad in [
        vec![],
        vec![1.2, 0.0],
        vec![f64::INFINITY],
        vec![-0.5],
        vec![f64::NAN],
    ] {
        assert!(
            matches!(solver.sweep(&bad), Err(FemError::InvalidInput { .. })),
            "targets {bad:?} accepted"
        );
    }
    let bad_options = SolverOptions {
        stepping: Stepping {
            min_step: 0.0,
            ..Stepping::default()
        },
        ..SolverOptions::default()
    };
    let mesh = Mesh::structured(1.0, 1.0, 1, 2, 1.0).unwrap();
    assert!(matches!(
        AxisymmetricSolver::new(mesh, Bases::Clamped, &material, bad_options),
        Err(FemError::InvalidInput { .. })
    ));
}
