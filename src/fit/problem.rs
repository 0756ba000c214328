//! A least-squares problem as every fit states it: residuals r(θ) written once for any scalar
//! ([`Residuals`]), bounds on the parameters ([`Bounds`]), and the exact Jacobian J = ∂r/∂θ from
//! dual numbers ([`residuals_and_jacobian`]). The search ([`super::levenberg`]) and the driver
//! ([`super::solver`]) both read them.

use crate::Scalar;
use nalgebra::DMatrix;
use num_dual::Dual64;

/// A least-squares problem: residuals r_i(θ) [kPa or dimensionless], written once for any
/// scalar. `f64` gives the values; [`Dual64`] with one θ_j seeded gives column j of the Jacobian.
pub trait Residuals {
    /// Number of residuals m.
    fn count(&self) -> usize;

    /// r(θ) for the free parameters θ (as many as the problem declares).
    fn residuals<T: Scalar>(&self, theta: &[T]) -> crate::Result<Vec<T>>;
}

/// Closed interval lower ≤ θ ≤ upper for one parameter (infinite ends allowed).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// Lower bound.
    pub lower: f64,
    /// Upper bound.
    pub upper: f64,
}

impl Bounds {
    /// [lower, upper].
    pub const fn new(lower: f64, upper: f64) -> Self {
        Self { lower, upper }
    }

    /// (0, ∞): positive parameters.
    pub const POSITIVE: Self = Self::new(0.0, f64::INFINITY);

    /// [0, 1].
    pub const UNIT: Self = Self::new(0.0, 1.0);

    /// No bound.
    pub const FREE: Self = Self::new(f64::NEG_INFINITY, f64::INFINITY);

    /// True if lower ≤ x ≤ upper.
    pub fn contains(&self, x: f64) -> bool {
        x >= self.lower && x <= self.upper
    }
}

/// Residual values and exact Jacobian (m × p) at θ: one dual evaluation per free parameter.
pub fn residuals_and_jacobian<R: Residuals>(
    problem: &R,
    theta: &[f64],
) -> crate::Result<(Vec<f64>, DMatrix<f64>)> {
    let values = problem.residuals(theta)?;
    let mut jac = DMatrix::zeros(values.len(), theta.len());
    for j in 0..theta.len() {
        let seeded: Vec<Dual64> = theta
            .iter()
            .enumerate()
            .map(|(k, &t)| {
                if k == j {
                    Dual64::from_re(t).derivative()
                } else {
                    Dual64::from_re(t)
                }
            })
            .collect();
        for (i, r) in problem.residuals(&seeded)?.iter().enumerate() {
            jac[(i, j)] = r.eps;
        }
    }
    Ok((values, jac))
}
