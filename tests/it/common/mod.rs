//! Test materials shared by the FE tests.

use activemuscle::fem::material::axial_stretch;
use activemuscle::fem::{
    AxiF, AxisymmetricMaterial, AxisymmetricSolver, Bases, Element, Mesh, SolverOptions,
    StepRecord, Stepping,
};
use nalgebra::{SMatrix, SVector};

/// Neo-Hookean plus a stress that is not the gradient of any energy: P_rr += c F_zz².
/// Its exact tangent has ∂P_rr/∂F_zz = 2c F_zz but ∂P_zz/∂F_rr = 0: non-symmetric.
pub struct NonSymmetric {
    pub mu: f64,
    pub c: f64,
    /// If true, `stress_tangent` drops the non-symmetric part (an approximated tangent).
    pub approximate: bool,
}

impl AxisymmetricMaterial for NonSymmetric {
    fn stress(&self, f: &AxiF) -> activemuscle::Result<SVector<f64, 5>> {
        let mut p = f * self.mu;
        p[0] += self.c * f[3] * f[3];
        Ok(p)
    }
    fn stress_tangent(
        &self,
        f: &AxiF,
    ) -> activemuscle::Result<(SVector<f64, 5>, SMatrix<f64, 5, 5>)> {
        let mut a = SMatrix::<f64, 5, 5>::identity() * self.mu;
        if !self.approximate {
            a[(0, 3)] += 2.0 * self.c * f[3];
        }
        Ok((self.stress(f)?, a))
    }
    fn point_fields(&self, f: &AxiF) -> activemuscle::Result<(f64, f64)> {
        Ok((0.0, axial_stretch(f)))
    }
}

/// Load steps of `step` (the first and the largest), up to 60 Newton iterations each, to
/// tolerance 1e-11: a large step that Newton must take whole.
pub fn large_steps(step: f64) -> Stepping {
    Stepping {
        initial_step: step,
        max_step: step,
        max_iterations: 60,
        tolerance: 1e-11,
        ..Stepping::default()
    }
}

/// One large load step 1 → 1.3 on a clamped cylinder (R = 1, L = 3) of `nr × nz` cells of
/// `element`; returns the step's record.
pub fn one_step(material: &NonSymmetric, element: Element, nr: usize, nz: usize) -> StepRecord {
    let mesh = Mesh::structured(1.0, 3.0, nr, nz, 1.0).unwrap();
    let options = SolverOptions {
        stepping: large_steps(0.3),
        element,
        ..SolverOptions::default()
    };
    let mut solver = AxisymmetricSolver::new(mesh, Bases::Clamped, material, options).unwrap();
    let sweep = solver.sweep(&[1.3]).unwrap();
    if let Some(e) = sweep.failures.first() {
        panic!("{e}");
    }
    let steps = &sweep.results[0].steps;
    assert_eq!(steps.len(), 1, "the step must not be cut");
    steps[0].clone()
}

/// The scaled residuals of a load step: the initial one, then one per Newton iteration.
pub fn residuals(step: &StepRecord) -> Vec<f64> {
    std::iter::once(step.initial_residual)
        .chain(step.iterations.iter().map(|i| i.residual))
        .collect()
}

/// Numbers in short scientific notation, for printing residual histories.
pub fn sci(v: &[f64]) -> Vec<String> {
    v.iter().map(|x| format!("{x:.3e}")).collect()
}

/// Asserts that Newton converged quadratically in `step` (last observed order ≥ 1.8) with full
/// steps; prints the residuals and the orders after `label`.
pub fn assert_quadratic(step: &StepRecord, label: &str) {
    let r = residuals(step);
    println!("{label}, scaled residuals: {:?}", sci(&r));
    let orders = observed_orders(&r);
    println!("observed orders: {orders:.3?}");
    let last = *orders
        .last()
        .expect("at least three iterates above the floor");
    assert!(last >= 1.8, "observed order {last} < 1.8 (residuals {r:?})");
    assert!(step.iterations.iter().all(|i| i.step_length == 1.0));
}

/// Observed orders of convergence p_k = ln(r_{k+1}/r_k) / ln(r_k/r_{k-1}) of a residual history,
/// over the iterations above the round-off floor (1e-13).
pub fn observed_orders(r: &[f64]) -> Vec<f64> {
    r.windows(3)
        .filter(|w| w[2] > 1e-13 && w.iter().all(|v| *v > 0.0))
        .map(|w| (w[2] / w[1]).ln() / (w[1] / w[0]).ln())
        .collect()
}

/// Asserts that every cell of a VTU file's text holds the neo-Hookean uniaxial state of stretch λ:
/// P_zz = μ(λ − λ⁻²) and p = μ/λ \[kPa\], to 1e-9 relative.
pub fn assert_uniaxial_neo_hookean_cells(text: &str, mu: f64, lambda: f64) {
    let exact = mu * (lambda - lambda.powi(-2));
    let pzz = vtu_data_array(text, "P_zz");
    assert!(
        pzz.iter().all(|v| (v - exact).abs() < 1e-9 * exact),
        "{pzz:?} vs {exact}"
    );
    let p = vtu_data_array(text, "p");
    assert!(
        p.iter().all(|v| (v - mu / lambda).abs() < 1e-9 * mu),
        "{p:?} vs {}",
        mu / lambda
    );
}

/// The numbers of the `<DataArray Name="name">` of a VTU file's text.
pub fn vtu_data_array(text: &str, name: &str) -> Vec<f64> {
    let start = text.find(&format!("Name=\"{name}\"")).unwrap();
    let body = &text[start..];
    let body = &body[body.find('>').unwrap() + 1..body.find("</DataArray>").unwrap()];
    body.split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect()
}
