//! Clamped bases: the solution is not homogeneous; the nominal stress converges under mesh refinement.
//!
//! Where a clamped base meets the traction-free lateral surface (r = R, z ∈ {0, L}) the exact
//! solution is singular, which limits the observed order to about 1 and makes the uniform
//! 2 × 8 → 4 × 16 pair pre-asymptotic; the meshes here are graded towards the bases (middle/base
//! cell-height ratio 4), on which the differences decrease monotonically.

use activemuscle::fem::element::jacobian;
use activemuscle::fem::{AxisymmetricSolver, Bases, Mesh, NeoHookean, SolverOptions};

#[test]
fn clamped_nominal_stress_converges_under_mesh_refinement() {
    let mu = 5.0;
    let (radius, length, lambda) = (1.0, 4.0, 1.17);
    let material = NeoHookean::new(mu).unwrap();
    let mut stress = Vec::new();
    let mut volume_error = Vec::new();
    for (nr, nz) in [(2, 8), (4, 16), (8, 32), (16, 64)] {
        let mesh = Mesh::structured(radius, length, nr, nz, 4.0).unwrap();
        let mut solver =
            AxisymmetricSolver::new(mesh, Bases::Clamped, &material, SolverOptions::default())
                .unwrap();
        let res = solver.sweep(&[lambda]).unwrap().into_result().unwrap();
        let r = &res[0];
        println!(
            "{nr:>3} × {nz:<3} ({:>6} free dofs): P = {:.10} kPa, max |J − 1| = {:.1e}",
            solver.n_free_dofs(),
            r.nominal_stress,
            r.max_volume_error
        );
        // Taylor–Hood enforces J = 1 weakly (∫ q (J − 1) dV = 0 for Q1 q), not pointwise; q = 1
        // is in the pressure space, so the deformed volume equals the reference one.
        let qps = solver.quadrature_points(&r.state);
        let v0: f64 = qps.iter().map(|q| q.dv).sum();
        let v: f64 = qps.iter().map(|q| jacobian(&q.f) * q.dv).sum();
        let exact_volume = std::f64::consts::PI * radius * radius * length;
        assert!((v0 - exact_volume).abs() < 1e-12 * exact_volume);
        assert!((v - v0).abs() < 1e-10 * v0, "volume {v} vs {v0}");
        // Volume-weighted L² norm of J − 1 (the pointwise maximum sits at the singular corner).
        let l2 = (qps
            .iter()
            .map(|q| (jacobian(&q.f) - 1.0).powi(2) * q.dv)
            .sum::<f64>()
            / v0)
            .sqrt();
        volume_error.push(l2);
        stress.push(r.nominal_stress);
    }
    let uniaxial = mu * (lambda - lambda.powi(-2));
    // Clamping stiffens the cylinder: P above the homogeneous value.
    assert!(
        stress.iter().all(|&p| p > uniaxial),
        "{stress:?} vs uniaxial {uniaxial}"
    );
    let diffs: Vec<f64> = stress.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    let orders: Vec<f64> = diffs.windows(2).map(|d| (d[0] / d[1]).log2()).collect();
    println!("differences between successive meshes: {:?}", sci(&diffs));
    println!("observed order of convergence (h halved): {orders:.2?}");
    assert!(
        diffs.windows(2).all(|d| d[1] < d[0]),
        "differences {diffs:?} do not decrease"
    );
    assert!(orders.iter().all(|&p| p > 0.5), "orders {orders:?}");
    println!("L² norm of J − 1: {:?}", sci(&volume_error));
    assert!(
        volume_error.windows(2).all(|w| w[1] < w[0]),
        "‖J − 1‖ does not decrease"
    );
}

fn sci(v: &[f64]) -> Vec<String> {
    v.iter().map(|x| format!("{x:.3e}")).collect()
}
