//! A minimum on a bound, as a result: the least-squares fit of every kind.
//!
//! The search ([`super::solver`]) never evaluates a bound (a step that would cross one goes
//! 9/10 of the way), so a minimum beyond a bound (EBI's β → 0, a Yeoh c₁₀ → 0, a damage d → 0)
//! ends with the search stalled against it ([`NotConverged::BeyondBound`]). Then the parameter
//! is held there — at the bound itself if the model can be evaluated there, else at the closest
//! point the search reached — and the others are fitted again, from where the search stopped;
//! a further bound is held the same way. At the end the Karush–Kuhn–Tucker condition of every
//! held parameter is checked: moving it back inside must not lower S = ‖r‖², i.e.
//! ∂S/∂θ_j = 2 Σ r_i ∂r_i/∂θ_j ≥ 0 at a lower bound (≤ 0 at an upper), to a rounding tolerance.
//! If it holds, the fit converged with the parameter [`AtBound`] (no standard error: it is not
//! estimated; the others' statistics are those of the fit with it held); if not, the stalled
//! search's error stands.

use super::problem::{residuals_and_jacobian, Bounds, Residuals};
use super::solver::{search, FitOptions};
use super::{FitError, FitReport, NotConverged};
use crate::Scalar;

/// A parameter held at a bound: the bound and where the search's Gauss–Newton step would have
/// taken it (the unconstrained minimum's side).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AtBound {
    /// The bound.
    pub bound: f64,
    /// Where the Gauss–Newton step pointed when the parameter was held, beyond the bound.
    pub beyond: f64,
}

/// The problem with some parameters held: residuals of the free ones (`free`, indices into the
/// full parameter vector `at`).
struct Held<'a, R> {
    problem: &'a R,
    at: Vec<f64>,
    free: Vec<usize>,
}

impl<R: Residuals> Residuals for Held<'_, R> {
    fn count(&self) -> usize {
        self.problem.count()
    }

    fn residuals<T: Scalar>(&self, theta: &[T]) -> crate::Result<Vec<T>> {
        let mut all: Vec<T> = self.at.iter().map(|&v| T::from(v)).collect();
        for (k, &i) in self.free.iter().enumerate() {
            all[i] = theta[k];
        }
        self.problem.residuals(&all)
    }
}

/// The most searches of one fit: each holds a parameter at a bound or releases one.
fn max_rounds(p: usize) -> usize {
    2 * p + 2
}

/// The state of an active-set fit: where it is, which parameters are held at which bound.
struct ActiveSet<'a, R> {
    problem: &'a R,
    names: &'a [String],
    bounds: &'a [Bounds],
    options: &'a FitOptions,
    at: Vec<f64>,
    held: Vec<Option<AtBound>>,
    iterations: u64,
    notes: Vec<String>,
}

impl<R: Residuals> ActiveSet<'_, R> {
    fn free(&self) -> Vec<usize> {
        (0..self.at.len())
            .filter(|&k| self.held[k].is_none())
            .collect()
    }

    /// One search over the parameters not held, from where the fit is (none if all are held).
    fn search(&self, free: &[usize]) -> Option<Result<FitReport, FitError>> {
        if free.is_empty() {
            return None;
        }
        let sub = Held {
            problem: self.problem,
            at: self.at.clone(),
            free: free.to_vec(),
        };
        let start: Vec<f64> = free.iter().map(|&k| self.at[k]).collect();
        let names: Vec<String> = free.iter().map(|&k| self.names[k].clone()).collect();
        let bounds: Vec<Bounds> = free.iter().map(|&k| self.bounds[k]).collect();
        let budget = FitOptions {
            max_iterations: self
                .options
                .max_iterations
                .saturating_sub(self.iterations)
                .max(1),
            ..*self.options
        };
        Some(search(&sub, &names, &start, &bounds, &budget))
    }

    /// Moves to the free parameters' `values` after a search of `iterations`.
    fn moved(&mut self, free: &[usize], values: &[f64], iterations: u64) {
        for (i, &f) in free.iter().enumerate() {
            self.at[f] = values[i];
        }
        self.iterations += iterations;
    }

    /// Holds parameter `j` at its bound (or where it is, if the model cannot be evaluated there).
    fn hold(&mut self, j: usize, hold: AtBound) {
        if evaluable(self.problem, &self.at, j, hold.bound) {
            self.at[j] = hold.bound;
        }
        self.held[j] = Some(hold);
        self.notes.push(format!(
            "{} held at its bound {} (the Gauss-Newton step points beyond, to {})",
            self.names[j],
            crate::text::shortest(hold.bound),
            crate::text::significant(hold.beyond, 6)
        ));
    }

    /// Releases the held parameters whose minimum has moved inside; whether there were any.
    fn release_misplaced(&mut self) -> Result<bool, FitError> {
        let inside = misplaced(self.problem, &self.at, &self.held)?;
        for &j in &inside {
            self.notes.push(format!(
                "{} released from its bound (the minimum moved inside)",
                self.names[j]
            ));
            self.held[j] = None;
        }
        Ok(!inside.is_empty())
    }

    /// After a search over `free` that ended in `e`: a parameter stalled at its bound is held;
    /// stalled elsewhere with a held parameter that belongs inside, that one is released; else
    /// the error stands (its best point expanded to every parameter).
    fn stalled(&mut self, free: &[usize], e: FitError) -> Result<(), FitError> {
        let FitError::NotConverged { best, .. } = &e else {
            return Err(expanded(e, self.names, &self.at, free, &self.held));
        };
        let names: Vec<String> = free.iter().map(|&k| self.names[k].clone()).collect();
        let before = self.at.clone();
        self.moved(free, &best.values.clone(), best.iterations);
        if let Some((k, hold)) = stalled_at_bound(&e, &names) {
            self.hold(free[k], hold);
            return Ok(());
        }
        if self.release_misplaced()? {
            return Ok(());
        }
        Err(expanded(e, self.names, &before, free, &self.held))
    }
}

/// Minimises ‖r(θ)‖² over the free parameters named `names`, from `start`, within `bounds`
/// (see [`super::solver`]); a minimum beyond a bound is held there and reported [`AtBound`].
///
/// An active-set iteration: search over the parameters not held; a search that stalls against a
/// bound, with the parameter there (within 10⁻⁶ of how far beyond it the Gauss–Newton step
/// points), holds it; a search that converges releases every held parameter whose KKT condition
/// fails (the minimum has moved inside) and searches again, or finishes. A search that stalls
/// with the parameter away from the bound (a poor direction, not a minimum beyond it) ends the
/// fit as before: not converged.
pub fn least_squares<R: Residuals>(
    problem: &R,
    names: &[String],
    start: &[f64],
    bounds: &[Bounds],
    options: &FitOptions,
) -> Result<FitReport, FitError> {
    let p = start.len();
    let mut fit = ActiveSet {
        problem,
        names,
        bounds,
        options,
        at: start.to_vec(),
        held: vec![None; p],
        iterations: 0,
        notes: Vec::new(),
    };
    for _ in 0..max_rounds(p) {
        let free = fit.free();
        let last = match fit.search(&free) {
            None => String::new(),
            Some(Ok(report)) => {
                fit.moved(&free, &report.values, report.iterations);
                report.termination
            }
            Some(Err(e)) => {
                fit.stalled(&free, e)?;
                continue;
            }
        };
        if !fit.release_misplaced()? {
            fit.notes.push(last);
            return finish(problem, names, &fit.at, fit.held, fit.iterations, fit.notes);
        }
    }
    let report = finish(problem, names, &fit.at, fit.held, fit.iterations, fit.notes)?;
    Err(FitError::NotConverged {
        reason: NotConverged::Solver {
            message: format!(
                "holding parameters at their bounds and releasing them did not settle in {} searches",
                max_rounds(p)
            ),
        },
        step: vec![],
        best: Box::new(FitReport {
            converged: false,
            ..report
        }),
    })
}

/// The parameter (index into `names`) of a search that stalled against its bound, and the bound,
/// if the error says so and the parameter is there: within 10⁻⁶ of the distance beyond the
/// bound that the Gauss–Newton step points to.
fn stalled_at_bound(e: &FitError, names: &[String]) -> Option<(usize, AtBound)> {
    let FitError::NotConverged {
        reason:
            NotConverged::BeyondBound {
                name,
                value,
                target,
                bound,
            },
        ..
    } = e
    else {
        return None;
    };
    let k = names.iter().position(|n| n == name)?;
    ((value - bound).abs() <= 1e-6 * (target - bound).abs()).then_some((
        k,
        AtBound {
            bound: *bound,
            beyond: *target,
        },
    ))
}

/// Whether the model can be evaluated with parameter `j` of `at` at `bound`.
fn evaluable<R: Residuals>(problem: &R, at: &[f64], j: usize, bound: f64) -> bool {
    let mut x = at.to_vec();
    x[j] = bound;
    bound.is_finite()
        && problem
            .residuals(&x)
            .is_ok_and(|r| r.iter().all(|v| v.is_finite()))
}

/// The held parameters (indices) at which moving inside lowers S = ‖r‖²: their KKT condition
/// ∂S/∂θ_j ≥ 0 at a lower bound (≤ 0 at an upper) fails beyond rounding.
fn misplaced<R: Residuals>(
    problem: &R,
    at: &[f64],
    held: &[Option<AtBound>],
) -> Result<Vec<usize>, FitError> {
    if held.iter().all(Option::is_none) {
        return Ok(Vec::new());
    }
    let (r, jacobian) = residuals_and_jacobian(problem, at)?;
    let mut inside = Vec::new();
    for (j, h) in held.iter().enumerate() {
        let Some(h) = h else { continue };
        let column = jacobian.column(j);
        // ∂S/∂θ_j / 2 and its rounding scale.
        let slope: f64 = r.iter().zip(column.iter()).map(|(r, d)| r * d).sum();
        let size: f64 = r
            .iter()
            .zip(column.iter())
            .map(|(r, d)| (r * d).abs())
            .sum();
        let outward = if h.beyond < h.bound { slope } else { -slope };
        if outward < -1e-10 * size {
            inside.push(j);
        }
    }
    Ok(inside)
}

/// The full report at `at`, the `held` parameters at their bounds and the others free: the
/// statistics of the free ones from the Jacobian there (as a fit of them alone would give).
fn finish<R: Residuals>(
    problem: &R,
    names: &[String],
    at: &[f64],
    held: Vec<Option<AtBound>>,
    iterations: u64,
    notes: Vec<String>,
) -> Result<FitReport, FitError> {
    let p = at.len();
    let free: Vec<usize> = (0..p).filter(|&k| held[k].is_none()).collect();
    let sub = Held {
        problem,
        at: at.to_vec(),
        free: free.clone(),
    };
    let pick: Vec<f64> = free.iter().map(|&k| at[k]).collect();
    let (residuals, statistics) = super::solver::statistics_at(&sub, &pick)?;
    let m = residuals.len();
    let residual_norm = super::levenberg::norm(&residuals);
    let mut standard_errors = vec![f64::NAN; p];
    let mut correlation = vec![vec![f64::NAN; p]; p];
    if let Some((se, rho)) = statistics {
        for (a, &i) in free.iter().enumerate() {
            standard_errors[i] = se[a];
            for (b, &k) in free.iter().enumerate() {
                correlation[i][k] = rho[a][b];
            }
        }
    }
    let notes: Vec<String> = notes.into_iter().filter(|n| !n.is_empty()).collect();
    Ok(FitReport {
        names: names.to_vec(),
        values: at.to_vec(),
        standard_errors,
        correlation,
        residuals,
        residual_norm,
        rms: residual_norm / (m as f64).sqrt(),
        iterations,
        converged: true,
        termination: notes.join("; "),
        at_bound: held,
        sigma: None,
    })
}

/// An error of the fit of the `free` parameters, its best point (if it has one) expanded to all
/// parameters.
fn expanded(
    e: FitError,
    names: &[String],
    at: &[f64],
    free: &[usize],
    held: &[Option<AtBound>],
) -> FitError {
    if held.iter().all(Option::is_none) {
        // Every parameter was free: the search's own error, its Gauss–Newton step included.
        return e;
    }
    match e {
        FitError::NotConverged { reason, best, .. } => {
            expanded_best(&best, names, at, free, held, reason)
        }
        other => other,
    }
}

fn expanded_best(
    best: &FitReport,
    names: &[String],
    at: &[f64],
    free: &[usize],
    held: &[Option<AtBound>],
    reason: NotConverged,
) -> FitError {
    let p = at.len();
    let mut report = FitReport {
        names: names.to_vec(),
        values: at.to_vec(),
        standard_errors: vec![f64::NAN; p],
        correlation: vec![vec![f64::NAN; p]; p],
        at_bound: held.to_vec(),
        ..best.clone()
    };
    for (a, &i) in free.iter().enumerate() {
        report.values[i] = best.values[a];
        report.standard_errors[i] = best.standard_errors[a];
        for (b, &k) in free.iter().enumerate() {
            report.correlation[i][k] = best.correlation[a][b];
        }
    }
    FitError::NotConverged {
        reason,
        step: vec![],
        best: Box::new(report),
    }
}
