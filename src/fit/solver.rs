//! The least-squares engine shared by every fit: residuals written once for any scalar, their
//! Jacobian from dual numbers, a Levenberg–Marquardt search run by argmin (optionally preceded by
//! argmin's Nelder–Mead), and the statistics of the solution.
//!
//! Given residuals r(θ) ∈ ℝᵐ of p free parameters θ, the fit minimises S(θ) = ‖r(θ)‖². With the
//! Jacobian J = ∂r/∂θ (m × p, exact: column j is the ε-part of r evaluated with θ_j seeded as a
//! dual number), the Gauss–Newton step is δ = −(JᵀJ)⁻¹ Jᵀ r; the search damps it
//! (Levenberg–Marquardt, [`super::levenberg`]) until it lowers S, on residuals and variables scaled
//! to O(1) so that data of any magnitude (up to S overflowing at the start) are handled alike.
//!
//! **Bounds** lower_j ≤ θ_j ≤ upper_j: a step that would cross a bound goes 9/10 of the way to it
//! (Nelder–Mead: a vertex outside them has infinite cost, as has any point where the model cannot
//! be evaluated, e.g. exp overflow). A minimum beyond a bound is therefore approached, not
//! reached: the search stalls there ([`NotConverged::BeyondBound`]), and
//! [`least_squares`](super::least_squares) then holds the parameter at the bound and fits the
//! others ([`super::bounded`]): a minimum on a bound is a result.
//!
//! **Convergence** is decided at the best point θ* found: the Gauss–Newton step there must be
//! negligible, |δ_j| ≤ step_tolerance (1 + |θ*_j|) for every j, or small next to the standard
//! errors, δᵀ Σ⁻¹ δ ≤ 10⁻⁶ p (10⁻³ standard errors in the covariance's metric; for uncorrelated
//! parameters |δ_j| ≲ 10⁻³ σ_j). Otherwise the fit is [`FitError::NotConverged`] with the reason ([`NotConverged`]: the
//! iteration cap, no decrease after [`MAX_TRIES`](super::MAX_TRIES) ever shorter steps, a non-finite cost at every
//! trial, a Jacobian that cannot be computed, a minimum beyond a bound) and the best point.
//!
//! **Statistics** at θ*: s² = S/(m − p), covariance Σ = s² (JᵀJ)⁻¹, standard errors σ_j = √Σ_jj,
//! correlation ρ_ij = (JᵀJ)⁻¹_ij / √((JᵀJ)⁻¹_ii (JᵀJ)⁻¹_jj) (defined also for exact data),
//! RMS error √(S/m); all computed in the scaled variables, so none overflows where S would.

use super::levenberg::{
    norm, power_of_two_below, GaussNewton, LevenbergMarquardt, Linearisation, Scaled, Stop,
};
use super::problem::{residuals_and_jacobian, Bounds, Residuals};
use super::{FitError, FitReport, NotConverged};
use argmin::core::{Executor, Jacobian, State, TerminationReason};
use argmin::solver::neldermead::NelderMead;

/// The search strategy (in a scene: `method = "gauss-newton" | "nelder-mead"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Gauss–Newton damped by Levenberg–Marquardt ([`super::levenberg`], run by argmin).
    #[default]
    GaussNewton,
    /// A derivative-free Nelder–Mead simplex search (argmin `NelderMead`, at most 2000
    /// iterations) from the start, then Levenberg–Marquardt from its best point. For poor
    /// starting values.
    NelderMead,
}

/// Solver settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitOptions {
    /// Search strategy.
    pub method: Method,
    /// Maximum Levenberg–Marquardt iterations (each at most [`MAX_TRIES`](super::MAX_TRIES) trial steps).
    pub max_iterations: u64,
    /// Relative size of the Gauss–Newton step below which the fit has converged.
    pub step_tolerance: f64,
}

impl Default for FitOptions {
    /// Gauss–Newton (damped), 1000 iterations, step tolerance 1e-9.
    fn default() -> Self {
        Self {
            method: Method::GaussNewton,
            max_iterations: 1000,
            step_tolerance: 1e-9,
        }
    }
}

/// Minimises ‖r(θ)‖² over the free parameters named `names`, from `start`, within `bounds`:
/// one search, which stalls at a bound beyond which the minimum lies
/// ([`NotConverged::BeyondBound`]; [`least_squares`](super::least_squares) goes on from there).
///
/// Returns the report at a converged point, or [`FitError::NotConverged`] carrying the reason and
/// the best point found. Errors before the search: [`FitError::NoFreeParameter`],
/// [`FitError::TooFewPoints`] (m ≤ p), [`FitError::StartOutOfBounds`] (also NaN starts and bounds),
/// [`FitError::BadStart`] (the model or the residual norm not finite at the start); after it,
/// [`FitError::Unidentifiable`] (JᵀJ singular at the best point).
pub(super) fn search<R: Residuals>(
    problem: &R,
    names: &[String],
    start: &[f64],
    bounds: &[Bounds],
    options: &FitOptions,
) -> Result<FitReport, FitError> {
    let scaled = Scaled {
        problem,
        bounds,
        scale: start_scale(problem, names, start, bounds)?,
    };
    let mut stages = Vec::new();
    let mut iterations = 0;
    let mut theta = start.to_vec();
    if options.method == Method::NelderMead {
        let (best, its, note) = nelder_mead(&scaled, start);
        theta = best;
        iterations += its;
        stages.push(note);
    }
    let (stop, its) = levenberg_marquardt(&scaled, options, &mut theta);
    iterations += its;
    let (mut report, gauss_newton) = statistics(&scaled, names, &theta, iterations)?;
    let gn = match gauss_newton {
        Ok(Some(gn)) => gn,
        Ok(None) => {
            return Err(FitError::Unidentifiable {
                names: names.to_vec(),
                values: theta,
            })
        }
        Err(reason) => {
            let reason = NotConverged::Jacobian { at: theta, reason };
            report.termination = format!("Levenberg-Marquardt: {reason}");
            return Err(FitError::NotConverged {
                reason,
                step: vec![],
                best: Box::new(report),
            });
        }
    };
    if gn.negligible(&theta, options.step_tolerance) {
        stages.push(format!(
            "Levenberg-Marquardt: Gauss-Newton step negligible after {} iterations",
            report.iterations
        ));
        report.termination = stages.join("; ");
        report.converged = true;
        return Ok(report);
    }
    let reason = unconverged_reason(&gn, &theta, bounds, names, stop);
    stages.push(format!("Levenberg-Marquardt: {reason}"));
    report.termination = stages.join("; ");
    Err(FitError::NotConverged {
        reason,
        step: gn.step,
        best: Box::new(report),
    })
}

/// The Levenberg–Marquardt search from `theta` (argmin): why it stopped, and the iterations it
/// took; `theta` becomes the best point it found.
fn levenberg_marquardt<R: Residuals>(
    scaled: &Scaled<R>,
    options: &FitOptions,
    theta: &mut Vec<f64>,
) -> (Result<Stop, NotConverged>, u64) {
    let search = Executor::new(
        scaled.clone(),
        LevenbergMarquardt::new(scaled.bounds, scaled.scale, options.step_tolerance),
    )
    .configure(|s| s.param(theta.clone()).max_iters(options.max_iterations))
    .ctrlc(false)
    .run();
    match search {
        Ok(mut res) => {
            let iterations = res.state().get_iter();
            if let Some(best) = res.state.take_param() {
                *theta = best;
            }
            let stop = match res.solver.stop {
                Some(stop) => Ok(stop),
                None => Err(NotConverged::IterationCap {
                    iterations: options.max_iterations,
                }),
            };
            (stop, iterations)
        }
        Err(e) => (
            Err(NotConverged::Solver {
                message: e.to_string(),
            }),
            0,
        ),
    }
}

/// Why the search did not converge at `theta`, where the Gauss–Newton step `gn` is not
/// negligible, given how it stopped.
fn unconverged_reason(
    gn: &GaussNewton,
    theta: &[f64],
    bounds: &[Bounds],
    names: &[String],
    stop: Result<Stop, NotConverged>,
) -> NotConverged {
    let stalled = matches!(stop, Ok(Stop::NoDecrease { .. }));
    match (gn.beyond(theta, bounds), stop) {
        // Stuck because the step that would lower the cost leaves the bounds.
        (Some((j, target, bound)), _) if stalled => NotConverged::BeyondBound {
            name: names[j].clone(),
            value: theta[j],
            target,
            bound,
        },
        (
            _,
            Ok(Stop::NoDecrease {
                tries,
                infeasible,
                last,
            }),
        ) if infeasible == tries => NotConverged::NonFiniteCost {
            at: theta.to_vec(),
            last,
            tries,
        },
        (
            _,
            Ok(Stop::NoDecrease {
                tries, infeasible, ..
            }),
        ) => NotConverged::NoDecrease {
            at: theta.to_vec(),
            tries,
            infeasible,
        },
        (_, Ok(Stop::Jacobian(reason))) => NotConverged::Jacobian {
            at: theta.to_vec(),
            reason,
        },
        (_, Ok(Stop::Converged)) => NotConverged::Solver {
            message: "the search stopped as converged at a point where the check fails".into(),
        },
        (_, Err(reason)) => reason,
    }
}

/// Checks the request and the start; returns the residual scale s, the power of two at or
/// below ‖r(start)‖ (1 if that is 0).
fn start_scale<R: Residuals>(
    problem: &R,
    names: &[String],
    start: &[f64],
    bounds: &[Bounds],
) -> Result<f64, FitError> {
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
    let bad = |reason: String| FitError::BadStart {
        start: start.to_vec(),
        reason,
    };
    let r = problem.residuals(start).map_err(|e| bad(e.to_string()))?;
    if let Some(x) = r.iter().find(|x| !x.is_finite()) {
        return Err(bad(format!("a residual is {x}")));
    }
    let size = norm(&r);
    if !size.is_finite() {
        let largest = r.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        return Err(bad(format!(
            "the residual norm overflows f64 (largest |residual| {largest:e})"
        )));
    }
    Ok(power_of_two_below(size))
}

/// Nelder–Mead from `start` (at most 2000 iterations): its best point, iterations and a note.
fn nelder_mead<R: Residuals>(scaled: &Scaled<R>, start: &[f64]) -> (Vec<f64>, u64, String) {
    let outcome = NelderMead::new(initial_simplex(start, scaled.bounds))
        .with_sd_tolerance(1e-14)
        .and_then(|nm| {
            Executor::new(scaled.clone(), nm)
                .configure(|s| s.max_iters(2000))
                .ctrlc(false)
                .run()
        });
    match outcome {
        Ok(mut res) => {
            let its = res.state().get_iter();
            let why = match res.state().get_termination_reason() {
                Some(TerminationReason::SolverConverged) => {
                    "cost spread of the simplex below 1e-14"
                }
                Some(TerminationReason::MaxItersReached) => "iteration cap reached",
                _ => "stopped",
            };
            let best = res
                .state
                .take_best_param()
                .unwrap_or_else(|| start.to_vec());
            (
                best,
                its,
                format!("Nelder-Mead: {why} after {its} iterations"),
            )
        }
        Err(e) => (start.to_vec(), 0, format!("Nelder-Mead failed: {e}")),
    }
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

/// The report at θ (residuals, norms, standard errors and correlations; NaN where JᵀJ is
/// singular or the Jacobian cannot be computed) and the Gauss–Newton step there: `None` if JᵀJ
/// is singular, an error if the Jacobian cannot be computed.
fn statistics<R: Residuals>(
    scaled: &Scaled<R>,
    names: &[String],
    theta: &[f64],
    iterations: u64,
) -> Result<(FitReport, Result<Option<GaussNewton>, String>), FitError> {
    let residuals = scaled.problem.residuals(theta)?;
    let (m, p) = (residuals.len(), theta.len());
    let reduced: Vec<f64> = residuals.iter().map(|r| r / scaled.scale).collect();
    let gauss_newton = scaled
        .jacobian(&theta.to_vec())
        .map(|j| Linearisation::new(&reduced, j, scaled.scale).gauss_newton())
        .map_err(|e| e.to_string());
    let residual_norm = scaled.scale * norm(&reduced);
    let (standard_errors, correlation) = match &gauss_newton {
        Ok(Some(gn)) => (gn.standard_errors.clone(), gn.correlation.clone()),
        _ => (vec![f64::NAN; p], vec![vec![f64::NAN; p]; p]),
    };
    let report = FitReport {
        names: names.to_vec(),
        values: theta.to_vec(),
        standard_errors,
        correlation,
        residual_norm,
        rms: residual_norm / (m as f64).sqrt(),
        residuals,
        iterations,
        converged: false,
        termination: String::new(),
        at_bound: vec![None; p],
        sigma: None,
    };
    Ok((report, gauss_newton))
}

/// The residuals at θ and, where JᵀJ is regular there, the standard errors and correlations
/// (see [`statistics`]; none for no parameter).
pub(super) fn statistics_at<R: Residuals>(
    problem: &R,
    theta: &[f64],
) -> Result<(Vec<f64>, Option<Errors>), FitError> {
    let (residuals, jacobian) = residuals_and_jacobian(problem, theta)?;
    if theta.is_empty() {
        return Ok((residuals, None));
    }
    let scale = power_of_two_below(norm(&residuals));
    let reduced: Vec<f64> = residuals.iter().map(|r| r / scale).collect();
    let gn = Linearisation::new(&reduced, jacobian, scale).gauss_newton();
    Ok((residuals, gn.map(|g| (g.standard_errors, g.correlation))))
}

/// Standard errors and the correlation matrix of the estimates.
pub(super) type Errors = (Vec<f64>, Vec<Vec<f64>>);
