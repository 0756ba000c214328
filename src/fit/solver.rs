//! The least-squares engine shared by every fit: residuals written once for any scalar, their
//! Jacobian from dual numbers, Gauss–Newton with a backtracking (Armijo) line search from argmin,
//! optionally preceded by a Nelder–Mead search, and the statistics of the solution.
//!
//! Given residuals r(θ) ∈ ℝᵐ of p free parameters θ, the fit minimises S(θ) = ‖r(θ)‖². With the
//! Jacobian J = ∂r/∂θ (m × p, exact: column j is the ε-part of r evaluated with θ_j seeded as a
//! dual number), Gauss–Newton steps δ = −(JᵀJ)⁻¹ Jᵀ r along which a backtracking line search
//! looks for sufficient decrease.
//!
//! **Bounds** lower_j ≤ θ_j ≤ upper_j act as a barrier: a trial point outside them (or one where
//! the model cannot be evaluated, e.g. exp overflow) has infinite cost, so the line search
//! shortens the step. A minimum on a bound is therefore not reached and reported as not converged.
//!
//! **Convergence** is decided at the best point θ* found, independently of the solver's own
//! stopping rule: the Gauss–Newton step there must be negligible,
//! |δ_j| ≤ step_tolerance (1 + |θ*_j|) or |δ_j| ≤ 10⁻³ σ_j (small next to its standard error).
//!
//! **Statistics** at θ*: s² = S/(m − p), covariance Σ = s² (JᵀJ)⁻¹, standard errors σ_j = √Σ_jj,
//! correlation ρ_ij = (JᵀJ)⁻¹_ij / √((JᵀJ)⁻¹_ii (JᵀJ)⁻¹_jj) (defined also for exact data),
//! RMS error √(S/m).

use super::{FitError, FitReport};
use crate::Scalar;
use argmin::core::{
    CostFunction, Error as ArgminError, Executor, Jacobian, Operator, State, TerminationReason,
};
use argmin::solver::gaussnewton::GaussNewtonLS;
use argmin::solver::linesearch::condition::ArmijoCondition;
use argmin::solver::linesearch::BacktrackingLineSearch;
use argmin::solver::neldermead::NelderMead;
use argmin_math::{ArgminDot, ArgminInv, ArgminTranspose};
use nalgebra::{DMatrix, DVector};
use num_dual::Dual64;
use std::cell::RefCell;
use std::rc::Rc;

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

/// The search strategy (in a scene: `method = "gauss-newton" | "nelder-mead"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Gauss–Newton with a backtracking line search (argmin `GaussNewtonLS`).
    #[default]
    GaussNewton,
    /// A derivative-free Nelder–Mead simplex search (argmin `NelderMead`) from the start, then
    /// Gauss–Newton from its best point. For poor starting values.
    NelderMead,
}

/// Solver settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitOptions {
    /// Search strategy.
    pub method: Method,
    /// Maximum Gauss–Newton iterations.
    pub max_iterations: u64,
    /// Relative size of the final Gauss–Newton step below which the fit has converged.
    pub step_tolerance: f64,
}

impl Default for FitOptions {
    /// Gauss–Newton, 100 iterations, step tolerance 1e-9.
    fn default() -> Self {
        Self {
            method: Method::GaussNewton,
            max_iterations: 100,
            step_tolerance: 1e-9,
        }
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

/// The Jacobian as a thin argmin-compatible matrix type (argmin-math's `vec` backend has no
/// inverse).
#[derive(Debug, Clone)]
struct Jac(DMatrix<f64>);

impl ArgminTranspose<Jac> for Jac {
    fn t(self) -> Jac {
        Jac(self.0.transpose())
    }
}

impl ArgminInv<Jac> for Jac {
    fn inv(&self) -> Result<Jac, ArgminError> {
        self.0.clone().try_inverse().map(Jac).ok_or_else(|| {
            argmin::core::ArgminError::InvalidParameter {
                text: "JᵀJ is singular".into(),
            }
            .into()
        })
    }
}

impl ArgminDot<Jac, Jac> for Jac {
    fn dot(&self, other: &Jac) -> Jac {
        Jac(&self.0 * &other.0)
    }
}

impl ArgminDot<Vec<f64>, Vec<f64>> for Jac {
    fn dot(&self, other: &Vec<f64>) -> Vec<f64> {
        (&self.0 * DVector::from_column_slice(other))
            .as_slice()
            .to_vec()
    }
}

/// The problem as argmin sees it: infeasible points have infinite residuals; the best feasible
/// point ever evaluated is remembered, so a failure still reports it.
struct Wrapped<'a, R> {
    problem: &'a R,
    bounds: &'a [Bounds],
    best: Rc<RefCell<(f64, Vec<f64>)>>,
}

impl<R> Clone for Wrapped<'_, R> {
    fn clone(&self) -> Self {
        Self {
            problem: self.problem,
            bounds: self.bounds,
            best: Rc::clone(&self.best),
        }
    }
}

impl<R: Residuals> Wrapped<'_, R> {
    fn evaluate(&self, theta: &[f64]) -> Option<Vec<f64>> {
        if !theta.iter().zip(self.bounds).all(|(t, b)| b.contains(*t)) {
            return None;
        }
        let r = self.problem.residuals(theta).ok()?;
        if !r.iter().all(|x| x.is_finite()) {
            return None;
        }
        let cost: f64 = r.iter().map(|x| x * x).sum();
        let mut best = self.best.borrow_mut();
        if cost < best.0 {
            *best = (cost, theta.to_vec());
        }
        Some(r)
    }
}

impl<R: Residuals> Operator for Wrapped<'_, R> {
    type Param = Vec<f64>;
    type Output = Vec<f64>;

    fn apply(&self, theta: &Vec<f64>) -> Result<Vec<f64>, ArgminError> {
        Ok(self
            .evaluate(theta)
            .unwrap_or_else(|| vec![f64::INFINITY; self.problem.count()]))
    }
}

impl<R: Residuals> Jacobian for Wrapped<'_, R> {
    type Param = Vec<f64>;
    type Jacobian = Jac;

    fn jacobian(&self, theta: &Vec<f64>) -> Result<Jac, ArgminError> {
        residuals_and_jacobian(self.problem, theta)
            .map(|(_, j)| Jac(j))
            .map_err(|e| {
                argmin::core::ArgminError::InvalidParameter {
                    text: e.to_string(),
                }
                .into()
            })
    }
}

impl<R: Residuals> CostFunction for Wrapped<'_, R> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, theta: &Vec<f64>) -> Result<f64, ArgminError> {
        Ok(self
            .evaluate(theta)
            .map_or(f64::INFINITY, |r| r.iter().map(|x| x * x).sum()))
    }
}

/// Minimises ‖r(θ)‖² over the free parameters named `names`, from `start`, within `bounds`.
///
/// Returns the report at a converged point, or [`FitError::NotConverged`] carrying the best point
/// found. Errors before the search: [`FitError::TooFewPoints`] (m ≤ p),
/// [`FitError::StartOutOfBounds`], [`FitError::BadStart`].
pub fn least_squares<R: Residuals>(
    problem: &R,
    names: &[String],
    start: &[f64],
    bounds: &[Bounds],
    options: &FitOptions,
) -> Result<FitReport, FitError> {
    let (m, p) = (problem.count(), start.len());
    if p == 0 {
        return Err(FitError::NoFreeParameter);
    }
    if m <= p {
        return Err(FitError::TooFewPoints {
            points: m,
            parameters: p,
        });
    }
    for ((name, &s), b) in names.iter().zip(start).zip(bounds) {
        let ordered = b.lower < b.upper; // false for NaN bounds too
        if !ordered || !b.contains(s) {
            return Err(FitError::StartOutOfBounds {
                name: name.clone(),
                start: s,
                lower: b.lower,
                upper: b.upper,
            });
        }
    }
    let wrapped = Wrapped {
        problem,
        bounds,
        best: Rc::new(RefCell::new((f64::INFINITY, start.to_vec()))),
    };
    match problem.residuals(start) {
        Ok(r) if r.iter().all(|x| x.is_finite()) => {}
        Ok(r) => {
            return Err(FitError::BadStart {
                start: start.to_vec(),
                reason: format!("non-finite residuals {r:?}"),
            })
        }
        Err(e) => {
            return Err(FitError::BadStart {
                start: start.to_vec(),
                reason: e.to_string(),
            })
        }
    }
    wrapped.evaluate(start);

    let mut notes = Vec::new();
    let mut iterations = 0;
    if options.method == Method::NelderMead {
        let simplex = initial_simplex(start, bounds);
        let outcome = NelderMead::new(simplex)
            .with_sd_tolerance(1e-14)
            .and_then(|nm| {
                Executor::new(wrapped.clone(), nm)
                    .configure(|s| s.max_iters(2000))
                    .ctrlc(false)
                    .run()
            });
        match outcome {
            Ok(res) => {
                iterations += res.state().get_iter();
                notes.push(format!(
                    "Nelder-Mead: {}",
                    reason(res.state().get_termination_reason())
                ));
            }
            Err(e) => notes.push(format!("Nelder-Mead failed: {e}")),
        }
    }

    let gn_start = wrapped.best.borrow().1.clone();
    let outcome = ArmijoCondition::new(1e-4)
        .and_then(|armijo| BacktrackingLineSearch::new(armijo).rho(0.5))
        .and_then(|ls| GaussNewtonLS::new(ls).with_tolerance(1e-14))
        .and_then(|gn| {
            Executor::new(wrapped.clone(), gn)
                .configure(|s| s.param(gn_start).max_iters(options.max_iterations))
                .ctrlc(false)
                .run()
        });
    match outcome {
        Ok(res) => {
            iterations += res.state().get_iter();
            notes.push(format!(
                "Gauss-Newton: {}",
                reason(res.state().get_termination_reason())
            ));
        }
        Err(e) => notes.push(format!("Gauss-Newton failed: {e}")),
    }

    let theta = wrapped.best.borrow().1.clone();
    let mut report = statistics(problem, names, &theta, iterations)?;
    report.termination = notes.join("; ");
    let (step, singular) = gauss_newton_step(problem, &theta)?;
    if singular {
        return Err(FitError::Unidentifiable {
            names: names.to_vec(),
            values: theta,
        });
    }
    let small = step.iter().enumerate().all(|(j, d)| {
        d.abs() <= options.step_tolerance * (1.0 + theta[j].abs())
            || d.abs() <= 1e-3 * report.standard_errors[j]
    });
    if small {
        report.converged = true;
        Ok(report)
    } else {
        Err(FitError::NotConverged {
            reason: format!(
                "{}; the Gauss-Newton step at the best point is still {step:?}",
                report.termination
            ),
            best: Box::new(report),
        })
    }
}

fn reason(r: Option<&TerminationReason>) -> String {
    r.map_or_else(|| "not terminated".to_string(), |r| r.text().to_string())
}

/// Start plus one vertex per parameter, displaced by 5 % (or 0.05 of the bound width, or 0.05)
/// towards the inside of the bounds.
fn initial_simplex(start: &[f64], bounds: &[Bounds]) -> Vec<Vec<f64>> {
    let mut simplex = vec![start.to_vec()];
    for j in 0..start.len() {
        let mut v = start.to_vec();
        let width = bounds[j].upper - bounds[j].lower;
        let mut h = if start[j] != 0.0 {
            0.05 * start[j].abs()
        } else {
            0.05
        };
        if width.is_finite() {
            h = h.min(0.05 * width);
        }
        v[j] = if bounds[j].contains(start[j] + h) {
            start[j] + h
        } else {
            start[j] - h
        };
        simplex.push(v);
    }
    simplex
}

/// The Gauss–Newton step (JᵀJ)⁻¹ Jᵀ r at θ and whether JᵀJ is singular.
fn gauss_newton_step<R: Residuals>(
    problem: &R,
    theta: &[f64],
) -> Result<(Vec<f64>, bool), FitError> {
    let (r, j) = residuals_and_jacobian(problem, theta)?;
    let jtj = j.transpose() * &j;
    let jtr = j.transpose() * DVector::from_vec(r);
    match jtj.cholesky() {
        Some(ch) => Ok((ch.solve(&jtr).as_slice().to_vec(), false)),
        None => Ok((vec![f64::NAN; theta.len()], true)),
    }
}

/// The report at θ: residuals, norms, standard errors and correlations (NaN where JᵀJ is
/// singular).
fn statistics<R: Residuals>(
    problem: &R,
    names: &[String],
    theta: &[f64],
    iterations: u64,
) -> Result<FitReport, FitError> {
    let (r, j) = residuals_and_jacobian(problem, theta)?;
    let (m, p) = (r.len(), theta.len());
    let sum: f64 = r.iter().map(|x| x * x).sum();
    let s2 = sum / (m - p) as f64;
    let inverse = (j.transpose() * &j)
        .cholesky()
        .map(|c| c.inverse())
        .unwrap_or_else(|| DMatrix::from_element(p, p, f64::NAN));
    let standard_errors = (0..p).map(|i| (s2 * inverse[(i, i)]).sqrt()).collect();
    let correlation = (0..p)
        .map(|a| {
            (0..p)
                .map(|b| inverse[(a, b)] / (inverse[(a, a)] * inverse[(b, b)]).sqrt())
                .collect()
        })
        .collect();
    Ok(FitReport {
        names: names.to_vec(),
        values: theta.to_vec(),
        standard_errors,
        correlation,
        residual_norm: sum.sqrt(),
        rms: (sum / m as f64).sqrt(),
        residuals: r,
        iterations,
        converged: false,
        termination: String::new(),
    })
}
