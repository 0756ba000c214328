//! The fit Jacobians come from dual numbers; here they are checked against central differences of
//! the same residuals, and the dual-parameter stresses against the library's uniaxial tests.

use activemuscle::active::ActiveCurve;
use activemuscle::energy::{EhretBolItskov, GiantesioMusesti};
use activemuscle::fit::{
    across_stress_with, fibre_stress_with, residuals_and_jacobian, Parametric, Residuals,
};
use activemuscle::material::Muscle;
use activemuscle::uniaxial::{across_fibres, along_fibres};
use activemuscle::Scalar;

/// Worst ratio of |central difference − dual Jacobian| to its allowance 1e-6 |J_ij| plus the
/// rounding error of the difference, 1e-13 (|r_i| + 1) / h_j. Below 1 means they agree.
fn mismatch<R: Residuals>(problem: &R, theta: &[f64]) -> f64 {
    let (r, jac) = residuals_and_jacobian(problem, theta).unwrap();
    let mut worst: f64 = 0.0;
    for j in 0..theta.len() {
        let h = 1e-6 * theta[j].abs().max(1e-3);
        let (mut up, mut down) = (theta.to_vec(), theta.to_vec());
        up[j] += h;
        down[j] -= h;
        let (ru, rd) = (
            problem.residuals(&up).unwrap(),
            problem.residuals(&down).unwrap(),
        );
        for i in 0..ru.len() {
            let fd = (ru[i] - rd[i]) / (2.0 * h);
            let allowance = 1e-6 * jac[(i, j)].abs() + 1e-13 * (r[i].abs() + 1.0) / h;
            worst = worst.max((fd - jac[(i, j)]).abs() / allowance);
        }
    }
    worst
}

struct Along<E>(E, Vec<f64>);
impl<E: Parametric> Residuals for Along<E> {
    fn count(&self) -> usize {
        self.1.len()
    }
    fn residuals<T: Scalar>(&self, theta: &[T]) -> activemuscle::Result<Vec<T>> {
        Ok(self
            .1
            .iter()
            .map(|&l| fibre_stress_with(&self.0, theta, l))
            .collect())
    }
}

struct Curve(Vec<f64>);
impl Residuals for Curve {
    fn count(&self) -> usize {
        self.0.len()
    }
    fn residuals<T: Scalar>(&self, p: &[T]) -> activemuscle::Result<Vec<T>> {
        Ok(self
            .0
            .iter()
            .map(|&l| ActiveCurve::paper().value_with(p, T::from(l)))
            .collect())
    }
}

fn grid(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .collect()
}

#[test]
fn dual_parameter_stress_matches_the_uniaxial_test_along_the_fibres() {
    let e = EhretBolItskov::paper();
    let muscle = Muscle::passive(e);
    for l in grid(0.7, 1.5, 9) {
        let p = fibre_stress_with(&e, &e.parameter_values(), l);
        let reference = along_fibres(&muscle, l).unwrap().stress;
        assert!(
            (p - reference).abs() <= 1e-12 * (1.0 + reference.abs()),
            "{l}: {p} vs {reference}"
        );
    }
}

#[test]
fn passive_jacobian_along_the_fibres_matches_central_differences() {
    let gm = Along(GiantesioMusesti::paper(), grid(0.8, 1.5, 15));
    assert!(mismatch(&gm, &GiantesioMusesti::paper().parameter_values()) < 1.0);
    let ebi = Along(EhretBolItskov::paper(), grid(0.8, 1.5, 15));
    let m = mismatch(&ebi, &EhretBolItskov::paper().parameter_values());
    assert!(m < 1.0, "{m}");
}

#[test]
fn active_curve_jacobian_matches_central_differences() {
    let c = ActiveCurve::paper();
    let theta = [
        c.lambda_min(),
        c.parameter("lambda_opt").unwrap(),
        c.parameter("k").unwrap(),
        c.parameter("p_opt").unwrap(),
    ];
    assert!(mismatch(&Curve(grid(0.65, 1.6, 20)), &theta) < 1.0);
}

/// Across the fibres the stress goes through the lateral equilibrium a*(θ), differentiated by the
/// implicit-function theorem; its value must be the library's across-fibre stress.
#[test]
fn across_fibre_stress_and_jacobian_through_the_lateral_equilibrium() {
    struct Across(GiantesioMusesti, Vec<f64>);
    impl Residuals for Across {
        fn count(&self) -> usize {
            self.1.len()
        }
        fn residuals<T: Scalar>(&self, theta: &[T]) -> activemuscle::Result<Vec<T>> {
            self.1
                .iter()
                .map(|&l| across_stress_with(&self.0, theta, l))
                .collect()
        }
    }
    let e = GiantesioMusesti::paper();
    let muscle = Muscle::passive(e);
    let lambda = grid(0.8, 1.4, 7);
    for &l in &lambda {
        let p = across_stress_with(&e, &e.parameter_values(), l).unwrap();
        let reference = across_fibres(&muscle, l).unwrap().stress;
        assert!(
            (p - reference).abs() <= 1e-10 * (1.0 + reference.abs()),
            "{l}: {p} vs {reference}"
        );
    }
    assert!(mismatch(&Across(e, lambda), &e.parameter_values()) < 1.0);
}
