//! Levenberg–Marquardt: the damped Gauss–Newton search every fit takes, as an argmin [`Solver`].
//!
//! **Scaling.** Whatever the units and size of the data, the search sees O(1) numbers: residuals
//! r̃ = r/s with s the power of two at or below ‖r(θ₀)‖ (division by it is exact), and variables
//! x̂_j = c_j θ_j / s with c_j the power of two at or below ‖J_:j‖, so that the Jacobian
//! Ĵ = ∂r̃/∂x̂ = J C⁻¹ (C = diag(c_j)) has columns of norm in [1, 2).
//!
//! **Step.** (ĴᵀĴ + μ I) δ̂ = −Ĵᵀ r̃, δ_j = δ̂_j s / c_j (Marquardt's scaling: μ damps each parameter
//! relative to its own curvature; μ = 0 is the Gauss–Newton step, μ → ∞ a shrinking gradient step).
//! Each iteration tries the Gauss–Newton step itself first (fast in the narrow valleys of strongly
//! correlated parameters, where any damping slows the search), then damped steps with the current
//! μ, growing. A parameter whose step would cross a bound goes only 9/10 of the way to it (so the
//! search slides along a bound instead of stalling there, and never evaluates the bound itself,
//! which the model may exclude). A trial is accepted if it lowers ‖r̃‖; a trial where the model
//! cannot be evaluated counts as infinite cost. The damping follows the gain ratio
//! ρ = [½‖r̃(θ)‖² − ½‖r̃(θ + δ)‖²] / [½ δ̂ᵀ(μ δ̂ − Ĵᵀ r̃)] (actual over predicted decrease):
//! accepted, μ ← μ max(1/3, 1 − (2ρ − 1)³) and ν ← 2; rejected, μ ← μ ν and ν ← 2ν; μ₀ = 10⁻³
//! (Madsen, Nielsen & Tingleff, *Methods for non-linear least squares problems*, 2004, §3.2).
//!
//! **Bounded.** At most [`MAX_TRIES`] trials per iteration (after k rejections μ has grown by
//! 2^{k(k+1)/2}: the last trials are steps ~10⁻⁶³ of a gradient step), and argmin's iteration cap.
//! Every way of stopping is a [`Stop`].

use super::problem::{residuals_and_jacobian, Bounds, Residuals};
use argmin::core::{
    CostFunction, Error as ArgminError, IterState, Jacobian, Operator, Problem, Solver, State,
    TerminationReason, KV,
};
use nalgebra::{DMatrix, DVector};

/// Trials (ever more damped steps) per iteration before the search gives up.
pub const MAX_TRIES: u32 = 20;

/// The fraction of the distance to a bound that a step crossing it goes.
const TO_BOUND: f64 = 0.9;

/// Initial damping μ₀ (relative to the unit diagonal of ĴᵀĴ).
const INITIAL_DAMPING: f64 = 1e-3;

/// ‖v‖₂ computed without overflow or underflow of the squares (scaled by the largest |v_i|);
/// infinite if an entry is not finite.
pub(crate) fn norm(v: &[f64]) -> f64 {
    if v.iter().any(|x| !x.is_finite()) {
        return f64::INFINITY;
    }
    let big = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    if big == 0.0 {
        return 0.0;
    }
    big * v.iter().map(|x| (x / big) * (x / big)).sum::<f64>().sqrt()
}

/// The power of two at or below x (x finite and normal), else 1: a scale that divides exactly.
pub(crate) fn power_of_two_below(x: f64) -> f64 {
    let p = f64::from_bits(x.abs().to_bits() & 0x7FF0_0000_0000_0000);
    if p.is_normal() {
        p
    } else {
        1.0
    }
}

/// The least-squares problem as argmin sees it: r̃(θ) = r(θ)/s, infinite outside the bounds or
/// where the model cannot be evaluated; the Jacobian J = ∂r/∂θ unscaled (exact, dual numbers).
pub(crate) struct Scaled<'a, R> {
    pub problem: &'a R,
    pub bounds: &'a [Bounds],
    /// s, a power of two.
    pub scale: f64,
}

impl<R> Clone for Scaled<'_, R> {
    fn clone(&self) -> Self {
        Self { ..*self }
    }
}

impl<R: Residuals> Scaled<'_, R> {
    /// r̃(θ), or `None` outside the bounds, where the model fails or a residual is not finite.
    pub fn residuals(&self, theta: &[f64]) -> Option<Vec<f64>> {
        if !theta.iter().zip(self.bounds).all(|(t, b)| b.contains(*t)) {
            return None;
        }
        let r = self.problem.residuals(theta).ok()?;
        r.iter()
            .all(|x| x.is_finite())
            .then(|| r.iter().map(|x| x / self.scale).collect())
    }
}

impl<R: Residuals> Operator for Scaled<'_, R> {
    type Param = Vec<f64>;
    type Output = Vec<f64>;

    fn apply(&self, theta: &Vec<f64>) -> Result<Vec<f64>, ArgminError> {
        Ok(self
            .residuals(theta)
            .unwrap_or_else(|| vec![f64::INFINITY; self.problem.count()]))
    }
}

impl<R: Residuals> CostFunction for Scaled<'_, R> {
    type Param = Vec<f64>;
    type Output = f64;

    /// ‖r̃(θ)‖ (infinite where the model cannot be evaluated).
    fn cost(&self, theta: &Vec<f64>) -> Result<f64, ArgminError> {
        Ok(self.residuals(theta).map_or(f64::INFINITY, |r| norm(&r)))
    }
}

impl<R: Residuals> Jacobian for Scaled<'_, R> {
    type Param = Vec<f64>;
    type Jacobian = DMatrix<f64>;

    fn jacobian(&self, theta: &Vec<f64>) -> Result<DMatrix<f64>, ArgminError> {
        let fail =
            |text: String| ArgminError::from(argmin::core::ArgminError::InvalidParameter { text });
        let (_, j) =
            residuals_and_jacobian(self.problem, theta).map_err(|e| fail(e.to_string()))?;
        match j.iter().find(|x| !x.is_finite()) {
            Some(x) => Err(fail(format!("an entry is {x}"))),
            None => Ok(j),
        }
    }
}

/// The problem linearised at θ in scaled variables: r̃ and Ĵ = J C⁻¹, with δ_j = δ̂_j s/c_j.
pub(crate) struct Linearisation {
    residuals: DVector<f64>,
    jacobian: DMatrix<f64>,
    /// s / c_j.
    units: Vec<f64>,
}

/// The Gauss–Newton step at a point and what the statistics need.
pub(crate) struct GaussNewton {
    /// δ = −(JᵀJ)⁻¹ Jᵀ r in the parameters' own units.
    pub step: Vec<f64>,
    /// Standard errors σ_j = √(s² (JᵀJ)⁻¹_jj), s² = ‖r‖²/(m − p).
    pub standard_errors: Vec<f64>,
    /// ρ_ij = (JᵀJ)⁻¹_ij / √((JᵀJ)⁻¹_ii (JᵀJ)⁻¹_jj) (invariant under the column scaling).
    pub correlation: Vec<Vec<f64>>,
    /// The step's size in standard errors, δᵀ Σ⁻¹ δ = ‖J δ‖² / s² (Σ = s² (JᵀJ)⁻¹): the
    /// fraction (m − p) ‖J δ‖²/‖r‖² of the cost the linear model can still remove, times m − p.
    pub mahalanobis: f64,
}

impl Linearisation {
    /// From the scaled residuals r̃, the unscaled Jacobian J and the residual scale s.
    pub fn new(residuals: &[f64], jacobian: DMatrix<f64>, scale: f64) -> Self {
        let mut jacobian = jacobian;
        let mut units = Vec::with_capacity(jacobian.ncols());
        for mut column in jacobian.column_iter_mut() {
            let c = power_of_two_below(norm(column.as_slice()));
            column /= c;
            units.push(scale / c);
        }
        Self {
            residuals: DVector::from_column_slice(residuals),
            jacobian,
            units,
        }
    }

    /// ĴᵀĴ and Ĵᵀr̃.
    fn normal(&self) -> (DMatrix<f64>, DVector<f64>) {
        let jt = self.jacobian.transpose();
        (&jt * &self.jacobian, jt * &self.residuals)
    }

    /// δ_j = δ̂_j s / c_j.
    fn unscaled(&self, scaled: &DVector<f64>) -> Vec<f64> {
        scaled.iter().zip(&self.units).map(|(d, u)| d * u).collect()
    }

    /// The Gauss–Newton step and the statistics, or `None` if ĴᵀĴ is singular (not positive
    /// definite in floating point).
    pub fn gauss_newton(&self) -> Option<GaussNewton> {
        let (a, g) = self.normal();
        let inverse = a.cholesky()?.inverse();
        let scaled = -(&inverse * g);
        let step = self.unscaled(&scaled);
        let (m, p) = (self.jacobian.nrows(), self.jacobian.ncols());
        let spread = norm(self.residuals.as_slice()) / ((m - p) as f64).sqrt();
        let predicted = norm((&self.jacobian * &scaled).as_slice());
        let mahalanobis = if predicted == 0.0 {
            0.0
        } else {
            (predicted / spread).powi(2)
        };
        let standard_errors = (0..p)
            .map(|j| self.units[j] * spread * inverse[(j, j)].sqrt())
            .collect();
        let correlation = (0..p)
            .map(|a| {
                (0..p)
                    .map(|b| inverse[(a, b)] / (inverse[(a, a)] * inverse[(b, b)]).sqrt())
                    .collect()
            })
            .collect();
        Some(GaussNewton {
            step,
            standard_errors,
            correlation,
            mahalanobis,
        })
    }
}

impl GaussNewton {
    /// The step is negligible: |δ_j| ≤ tolerance (1 + |θ_j|) for every j, or the step is below
    /// 10⁻³ standard errors in the covariance's own metric, δᵀ Σ⁻¹ δ ≤ 10⁻⁶ p. (Not
    /// |δ_j| ≤ 10⁻³ σ_j coordinate by coordinate: with strongly correlated parameters every σ_j
    /// is huge while the step still removes most of the cost.)
    pub fn negligible(&self, theta: &[f64], tolerance: f64) -> bool {
        let small = self
            .step
            .iter()
            .zip(theta)
            .all(|(d, t)| d.abs() <= tolerance * (1.0 + t.abs()));
        small || self.mahalanobis <= 1e-6 * self.step.len() as f64
    }

    /// The first parameter that the step takes out of its bounds: (index, target, bound).
    pub fn beyond(&self, theta: &[f64], bounds: &[Bounds]) -> Option<(usize, f64, f64)> {
        (0..theta.len()).find_map(|j| {
            let target = theta[j] + self.step[j];
            if target < bounds[j].lower {
                Some((j, target, bounds[j].lower))
            } else if target > bounds[j].upper {
                Some((j, target, bounds[j].upper))
            } else {
                None
            }
        })
    }
}

/// θ + δ, except that a parameter whose step crosses a bound goes only [`TO_BOUND`] of the way
/// to it, or nowhere once that rounds to the bound (the bound itself may be outside the model,
/// e.g. w0 = 1).
fn within_bounds(theta: &[f64], step: &[f64], bounds: &[Bounds]) -> Vec<f64> {
    theta
        .iter()
        .zip(step)
        .zip(bounds)
        .map(|((&t, &d), b)| {
            let x = t + d;
            let bound = if x < b.lower {
                b.lower
            } else if x > b.upper {
                b.upper
            } else {
                return x;
            };
            // Within rounding of the bound, the parameter stays where it is.
            let y = t + TO_BOUND * (bound - t);
            if y == bound {
                t
            } else {
                y
            }
        })
        .collect()
}

/// How the search stopped (besides argmin's iteration cap).
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Stop {
    /// The Gauss–Newton step at the current point is negligible.
    Converged,
    /// [`MAX_TRIES`] trials did not lower the cost; `infeasible` of them had infinite cost.
    NoDecrease {
        /// Trials.
        tries: u32,
        /// Trials outside the bounds or not computable.
        infeasible: u32,
        /// The last (shortest) trial point.
        last: Vec<f64>,
    },
    /// The Jacobian at the current point could not be computed.
    Jacobian(String),
}

/// The Levenberg–Marquardt search (see the module docs). Param `Vec<f64>`, cost ‖r̃‖.
pub(crate) struct LevenbergMarquardt {
    bounds: Vec<Bounds>,
    scale: f64,
    tolerance: f64,
    damping: f64,
    growth: f64,
    /// r̃ at the current point.
    residuals: Vec<f64>,
    /// Why it stopped, if not at the iteration cap.
    pub stop: Option<Stop>,
}

impl LevenbergMarquardt {
    /// A search within `bounds` on residuals scaled by `scale`, stopping when the Gauss–Newton
    /// step is negligible at relative `tolerance` (see [`GaussNewton::negligible`]).
    pub fn new(bounds: &[Bounds], scale: f64, tolerance: f64) -> Self {
        Self {
            bounds: bounds.to_vec(),
            scale,
            tolerance,
            damping: INITIAL_DAMPING,
            growth: 2.0,
            residuals: Vec::new(),
            stop: None,
        }
    }

    fn reject(&mut self) {
        self.damping *= self.growth;
        self.growth *= 2.0;
    }
}

type LmState = IterState<Vec<f64>, (), (), (), (), f64>;

impl<O> Solver<O, LmState> for LevenbergMarquardt
where
    O: Operator<Param = Vec<f64>, Output = Vec<f64>>
        + Jacobian<Param = Vec<f64>, Jacobian = DMatrix<f64>>,
{
    fn name(&self) -> &str {
        "Levenberg-Marquardt"
    }

    fn init(
        &mut self,
        problem: &mut Problem<O>,
        state: LmState,
    ) -> Result<(LmState, Option<KV>), ArgminError> {
        let theta = state.get_param().cloned().unwrap_or_default();
        self.residuals = problem.apply(&theta)?;
        let cost = norm(&self.residuals);
        Ok((state.cost(cost), None))
    }

    fn next_iter(
        &mut self,
        problem: &mut Problem<O>,
        mut state: LmState,
    ) -> Result<(LmState, Option<KV>), ArgminError> {
        let theta = state.take_param().unwrap_or_default();
        let lin = match problem.jacobian(&theta) {
            Ok(j) => Linearisation::new(&self.residuals, j, self.scale),
            Err(e) => {
                self.stop = Some(Stop::Jacobian(e.to_string()));
                let exit = TerminationReason::SolverExit("Jacobian failed".into());
                return Ok((state.param(theta).terminate_with(exit), None));
            }
        };
        let mut gauss_newton = lin.gauss_newton();
        if gauss_newton
            .as_ref()
            .is_some_and(|gn| gn.negligible(&theta, self.tolerance))
        {
            self.stop = Some(Stop::Converged);
            let done = TerminationReason::SolverConverged;
            return Ok((state.param(theta).terminate_with(done), None));
        }
        let (a, g) = lin.normal();
        let cost = norm(&self.residuals);
        let (mut infeasible, mut last) = (0, theta.clone());
        for _ in 0..MAX_TRIES {
            // The Gauss–Newton step first, then ever more damped ones.
            let (step, damped) = match gauss_newton.take() {
                Some(gn) => (gn.step, None),
                None => {
                    let system = &a + DMatrix::identity(a.nrows(), a.ncols()) * self.damping;
                    match system.cholesky() {
                        Some(c) => {
                            let scaled = c.solve(&-&g);
                            (lin.unscaled(&scaled), Some(scaled))
                        }
                        None => {
                            self.reject();
                            continue;
                        }
                    }
                }
            };
            let trial = within_bounds(&theta, &step, &self.bounds);
            let residuals = problem.apply(&trial)?;
            let trial_cost = norm(&residuals);
            last = trial.clone();
            let actual = 0.5 * (cost - trial_cost) * (cost + trial_cost);
            if actual > 0.0 {
                if let Some(scaled) = damped {
                    let predicted = 0.5 * scaled.dot(&(&scaled * self.damping - &g));
                    let rho = actual / predicted;
                    self.damping *= (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
                }
                self.growth = 2.0;
                self.residuals = residuals;
                return Ok((state.param(trial).cost(trial_cost), None));
            }
            if !trial_cost.is_finite() {
                infeasible += 1;
            }
            if damped.is_some() {
                self.reject();
            }
        }
        self.stop = Some(Stop::NoDecrease {
            tries: MAX_TRIES,
            infeasible,
            last,
        });
        let exit = TerminationReason::SolverExit("no decrease".into());
        Ok((state.param(theta).terminate_with(exit), None))
    }
}
