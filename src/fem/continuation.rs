//! Load stepping (continuation in the load λ) with Newton's method, for any [`NonlinearSystem`].
//!
//! Load path: from λ = 1 outwards in both directions (each direction starts from the λ = 1
//! state), landing exactly on every requested load. Each load step uses a tangent predictor
//! (x ← x_k + Δλ dx/dλ, with dx/dλ from [`NonlinearSystem::load_rate`] at the last converged
//! state), relaxed where it overshoots in a few cells ([`NonlinearSystem::relax_predictor`]),
//! then Newton with backtracking line search on the system's scaled residual norm. A
//! rejected step (no convergence, material error at a trial state, failed line search, singular
//! tangent) is halved; after two easy steps in a row the step doubles again. Below the minimum
//! step the direction stops with [`FemError::TargetNotReached`]; after [`Stepping::max_steps`]
//! load steps with [`FemError::StepLimit`]. Every loop is capped: Newton by
//! [`Stepping::max_iterations`], the line search by [`Stepping::max_backtracks`], the step
//! cutting by [`Stepping::min_step`], the load steps of a direction by [`Stepping::max_steps`].
//!
//! Convergence of a Newton solve (both required): the system's scaled residual norm and the
//! scaled norm of the next Newton increment, estimated from the last one and the residual's
//! contraction (`next_increment`), are at most [`Stepping::tolerance`].
//!
//! A [`Cancel`] flag is read before every load step and every Newton iteration: once it is set,
//! the sweep stops and reports [`FemError::Cancelled`]; the loads solved before are kept.

use super::error::{FemError, FemResult, StepFailure};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// A discretised nonlinear problem R(x) = 0 whose prescribed unknowns follow a load λ.
///
/// The unknowns x = (x_f, x_c): the first [`Self::free`] entries are solved for, the others are
/// set by [`Self::apply_load`]. The norms and solves refer to the last [`Self::evaluate`].
pub trait NonlinearSystem {
    /// Number of unknowns (free and prescribed).
    fn unknowns(&self) -> usize;
    /// Number of free unknowns (the first entries of x).
    fn free(&self) -> usize;
    /// Sets the prescribed unknowns of `x` for the load λ.
    fn apply_load(&self, x: &mut [f64], load: f64);
    /// The start of the reference solve, `x` all zero on entry: by default the zero state (no
    /// displacement, no pressure).
    fn initial_guess(&self, _x: &mut [f64]) {}
    /// Evaluates the residual R(x) and, if `tangent`, the tangent K = ∂R_f/∂x_f and ∂R_f/∂λ.
    fn evaluate(&mut self, x: &[f64], tangent: bool) -> crate::Result<()>;
    /// The scale of the last evaluation (e.g. its largest stress) that makes the norms below
    /// dimensionless; the driver holds it fixed over a line search.
    fn scale(&self) -> f64;
    /// Scaled norm of the residual of the last evaluation.
    fn residual_norm(&self, scale: f64) -> f64;
    /// Scaled norm of the increment `step` · `dx` (free unknowns).
    fn increment_norm(&self, dx: &[f64], step: f64, scale: f64) -> f64;
    /// The Newton direction dx = −K⁻¹ R on the free unknowns, with the tangent of the last
    /// evaluation that had one. `refactorise`: factorise that tangent first; otherwise the
    /// factorisation held (of an earlier iterate's tangent) may serve, as long as the
    /// direction is still K⁻¹'s to the solver's accuracy.
    fn newton_direction(&mut self, dx: &mut [f64], refactorise: bool) -> Result<(), StepFailure>;
    /// dx/dλ, all unknowns: K v_f = −∂R_f/∂λ and the prescribed part from the load, with K and
    /// ∂R_f/∂λ of the last evaluation that had the tangent (at a converged state, that state's
    /// or the last iterate's before it: see `Continuation::newton`).
    fn load_rate(&mut self, rate: &mut [f64]) -> Result<(), StepFailure>;
    /// Relaxes, in place, the part of a predicted state `x` (just evaluated) whose stresses
    /// overshoot those of the last converged state, of largest stress `converged_scale`;
    /// returns whether `x` changed. By default nothing is relaxed.
    fn relax_predictor(&mut self, _x: &mut [f64], _converged_scale: f64) -> bool {
        false
    }
}

/// A discrete solution: all unknowns at a load (the stretch of the cylinder).
#[derive(Debug, Clone, PartialEq)]
pub struct State {
    /// Applied stretch λ.
    pub stretch: f64,
    /// Unknowns (dof values).
    pub x: Vec<f64>,
}

/// One Newton iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IterationRecord {
    /// Scaled residual norm after the iteration.
    pub residual: f64,
    /// Scaled increment norm of the iteration (step length included).
    pub increment: f64,
    /// Line-search step length.
    pub step_length: f64,
}

/// One attempted load step.
#[derive(Debug, Clone, PartialEq)]
pub struct StepRecord {
    /// Load the step started from.
    pub from: f64,
    /// Load the step aimed at.
    pub to: f64,
    /// Scaled residual of the predictor.
    pub initial_residual: f64,
    /// Newton iterations.
    pub iterations: Vec<IterationRecord>,
    /// `None` if converged, else why it was rejected.
    pub failure: Option<StepFailure>,
}

/// A flag that stops a running sweep (from another thread, a signal handler or a progress
/// observer). Clones share the flag.
#[derive(Debug, Clone, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// A new, unset flag.
    pub fn new() -> Self {
        Self::default()
    }

    /// Asks every sweep holding this flag to stop.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether the flag is set.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }

    /// The shared atomic (e.g. for `signal_hook::flag::register`).
    pub fn flag(&self) -> Arc<AtomicBool> {
        Arc::clone(&self.0)
    }
}

impl From<Arc<AtomicBool>> for Cancel {
    fn from(flag: Arc<AtomicBool>) -> Self {
        Self(flag)
    }
}

/// Two flags are equal when they are the same flag.
impl PartialEq for Cancel {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// Tolerance, load-stepping and Newton controls of the driver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stepping {
    /// Tolerance on the scaled residual and increment norms.
    pub tolerance: f64,
    /// Newton iterations per load step before the step is cut.
    pub max_iterations: usize,
    /// First load step |Δλ|.
    pub initial_step: f64,
    /// Largest load step |Δλ|.
    pub max_step: f64,
    /// Smallest load step |Δλ| before giving up.
    pub min_step: f64,
    /// A step that converged in at most this many iterations is easy; two in a row double the step.
    pub easy_iterations: usize,
    /// Backtracking halvings in the line search (0: full Newton steps only).
    pub max_backtracks: usize,
    /// Load steps (accepted and rejected) allowed in one direction of a sweep.
    pub max_steps: usize,
}

impl Default for Stepping {
    /// The FE solver's defaults: tolerance 1e-10, 25 Newton iterations per step, first step
    /// 0.05, steps between 1e-4 and 0.1, doubled after two steps of at most 5 iterations, 8
    /// line-search halvings, 10 000 load steps per direction.
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            max_iterations: 25,
            initial_step: 0.05,
            max_step: 0.1,
            min_step: 1e-4,
            easy_iterations: 5,
            max_backtracks: 8,
            max_steps: 10_000,
        }
    }
}

/// What the driver reports to its caller while it runs.
pub trait Observer<S: ?Sized> {
    /// A target load was reached; `x` is the converged state, and the system still holds its
    /// evaluation. `steps`: the load steps since the previous target.
    fn reached(
        &mut self,
        system: &mut S,
        load: f64,
        x: &[f64],
        steps: Vec<StepRecord>,
    ) -> FemResult<()>;
    /// A load step converged.
    fn step_accepted(&mut self, _record: &StepRecord) {}
}

/// A failure of one direction of a sweep, with the last rejected trial state for diagnostics.
pub type DirectionFailure = (FemError, Option<State>);

/// A converged state with its rate dx/dλ: where a load step starts.
#[derive(Debug, Clone)]
struct Converged {
    load: f64,
    x: Vec<f64>,
    rate: Vec<f64>,
    /// Its largest stress ([`NonlinearSystem::scale`]).
    scale: f64,
}

/// The load-stepping Newton driver, with its work vectors (allocated once).
#[derive(Debug, Clone)]
pub struct Continuation {
    stepping: Stepping,
    cancel: Option<Cancel>,
    trial: Vec<f64>,
    delta: Vec<f64>,
    newton_iterations: usize,
    failed_trial: Option<State>,
}

impl Continuation {
    /// A driver for systems with `unknowns` unknowns.
    pub fn new(unknowns: usize, stepping: Stepping, cancel: Option<Cancel>) -> Self {
        Self {
            stepping,
            cancel,
            trial: vec![0.0; unknowns],
            delta: vec![0.0; unknowns],
            newton_iterations: 0,
            failed_trial: None,
        }
    }

    /// Newton iterations performed so far.
    pub fn newton_iterations(&self) -> usize {
        self.newton_iterations
    }

    /// Resets the Newton iteration count.
    pub fn reset_count(&mut self) {
        self.newton_iterations = 0;
    }

    /// The trial state at which the last rejected Newton step failed, kept for diagnostics.
    pub fn failed_trial(&self) -> Option<&State> {
        self.failed_trial.as_ref()
    }

    fn cancelled(&self) -> bool {
        self.cancel.as_ref().is_some_and(Cancel::is_cancelled)
    }

    /// Runs the load path through every target (λ = 1 outwards in both directions, upwards
    /// first), reporting each reached target to `observer`. Targets must be finite and > 0
    /// (checked by the caller). Returns the failure of each direction that stopped; an error
    /// only if the observer fails at λ = 1.
    pub fn sweep<S: NonlinearSystem>(
        &mut self,
        system: &mut S,
        targets: &[f64],
        observer: &mut dyn Observer<S>,
    ) -> FemResult<Vec<DirectionFailure>> {
        let mut up: Vec<f64> = targets.iter().copied().filter(|&t| t > 1.0).collect();
        let mut down: Vec<f64> = targets.iter().copied().filter(|&t| t < 1.0).collect();
        up.sort_by(f64::total_cmp);
        up.dedup();
        down.sort_by(|a, b| b.total_cmp(a));
        down.dedup();
        let (reference, record) = match self.reference(system) {
            Ok(v) => v,
            Err(StepFailure::Cancelled) => {
                return Ok(vec![(FemError::Cancelled { target: 1.0 }, None)]);
            }
            Err(cause) => return Ok(vec![(FemError::ReferenceState { cause }, None)]),
        };
        if targets.contains(&1.0) {
            observer.reached(system, 1.0, &reference.x, vec![record])?;
        }
        let mut failures = Vec::new();
        for list in [&up, &down] {
            if list.is_empty() {
                continue;
            }
            if let Err(e) = self.path(system, reference.clone(), list, observer) {
                let cancelled = matches!(e, FemError::Cancelled { .. });
                failures.push((e, self.failed_trial.clone()));
                if cancelled {
                    break;
                }
            }
        }
        Ok(failures)
    }

    /// Solves the reference state λ = 1 from the system's initial guess and its rate.
    fn reference<S: NonlinearSystem>(
        &mut self,
        system: &mut S,
    ) -> Result<(Converged, StepRecord), StepFailure> {
        let mut x = vec![0.0; system.unknowns()];
        system.initial_guess(&mut x);
        system.apply_load(&mut x, 1.0);
        let mut record = StepRecord {
            from: 1.0,
            to: 1.0,
            initial_residual: 0.0,
            iterations: Vec::new(),
            failure: None,
        };
        self.newton(system, &mut x, &mut record, None)?;
        let scale = system.scale();
        let rate = rate(system)?;
        let reference = Converged {
            load: 1.0,
            x,
            rate,
            scale,
        };
        Ok((reference, record))
    }

    /// Steps from `cur` through `targets` (sorted away from λ = 1), reporting each.
    fn path<S: NonlinearSystem>(
        &mut self,
        system: &mut S,
        mut cur: Converged,
        targets: &[f64],
        observer: &mut dyn Observer<S>,
    ) -> FemResult<()> {
        let o = self.stepping;
        let mut h = o.initial_step.min(o.max_step);
        let mut easy = 0usize;
        let mut taken = 0usize;
        let mut x = vec![0.0; system.unknowns()];
        for &target in targets {
            let mut steps = Vec::new();
            while cur.load != target {
                if self.cancelled() {
                    return Err(FemError::Cancelled { target });
                }
                if taken == o.max_steps {
                    return Err(FemError::StepLimit {
                        target,
                        reached: cur.load,
                        steps: taken,
                    });
                }
                taken += 1;
                let remaining = target - cur.load;
                let next = if remaining.abs() <= h * (1.0 + 1e-9) {
                    target
                } else {
                    cur.load + h * remaining.signum()
                };
                let dl = next - cur.load;
                let (record, outcome) = self.step(system, &cur, next, &mut x);
                match outcome {
                    Ok(rate) => {
                        // The system holds the converged state's evaluation (see `newton`).
                        let scale = system.scale();
                        observer.step_accepted(&record);
                        let n_it = record.iterations.len();
                        steps.push(record);
                        cur = Converged {
                            load: next,
                            x: x.clone(),
                            rate,
                            scale,
                        };
                        if n_it <= o.easy_iterations {
                            easy += 1;
                            if easy >= 2 {
                                h = (2.0 * h).min(o.max_step);
                                easy = 0;
                            }
                        } else {
                            easy = 0;
                        }
                    }
                    Err(StepFailure::Cancelled) => return Err(FemError::Cancelled { target }),
                    Err(cause) => {
                        steps.push(record);
                        easy = 0;
                        h = 0.5 * dl.abs();
                        if h < o.min_step {
                            return Err(FemError::TargetNotReached {
                                target,
                                reached: cur.load,
                                attempted: next,
                                step: dl.abs(),
                                cause,
                            });
                        }
                    }
                }
            }
            // The system holds the converged state's evaluation (see `newton`).
            observer.reached(system, target, &cur.x, steps)?;
        }
        Ok(())
    }

    /// One load step from `cur` to the load `next`: tangent predictor, Newton, rate. On success
    /// `x` holds the converged state.
    ///
    /// Predictors of higher order, from the previous converged state as well, cost more Newton
    /// iterations on the frozen explicit sweep, 16 × 64, d = 0 (95 with this one): quadratic
    /// from the two rates 100, quadratic through the two states 98, cubic Hermite 111. Through
    /// the two states, the predictor's residual halves on the steps 0.90 → 0.80, but is 3 and
    /// 2 times the tangent predictor's on the steps 1.20 → 1.30, each then taking 7 iterations.
    /// Nor does the first direction of a step serve on the held factorisation (the converged
    /// state's): GMRES on the predictor's tangent needs more than its 8 iterations every time.
    fn step<S: NonlinearSystem>(
        &mut self,
        system: &mut S,
        cur: &Converged,
        next: f64,
        x: &mut Vec<f64>,
    ) -> (StepRecord, Result<Vec<f64>, StepFailure>) {
        let dl = next - cur.load;
        for ((xi, c), v) in x.iter_mut().zip(&cur.x).zip(&cur.rate) {
            *xi = c + dl * v;
        }
        system.apply_load(x, next);
        let mut record = StepRecord {
            from: cur.load,
            to: next,
            initial_residual: f64::NAN,
            iterations: Vec::new(),
            failure: None,
        };
        let outcome = self
            .newton(system, x, &mut record, Some(cur.scale))
            .and_then(|_| rate(system));
        if let Err(cause) = &outcome {
            record.failure = Some(cause.clone());
        }
        (record, outcome)
    }

    fn keep_failed_trial(&mut self, load: f64, x: &[f64]) {
        self.failed_trial = Some(State {
            stretch: load,
            x: x.to_vec(),
        });
    }

    /// Newton's method at the load already set in `x` (prescribed unknowns included); a load
    /// step's predictor (`converged_scale`: the largest stress of the state it started from) is
    /// first relaxed where it overshoots ([`NonlinearSystem::relax_predictor`]).
    ///
    /// Each iteration solves K Δx = −R on the free unknowns, then backtracks
    /// ([`Self::line_search`]). On success `x` holds the converged state and the system holds
    /// its residual there; its tangent is of the converged state or, when the last step was
    /// evaluated without one ([`LIKELY_LAST`]), of the iterate before, whose factorisation it
    /// also holds: the rate dx/dλ solved with it is the previous iterate's, as good a
    /// predictor (the two states differ by the last increment, ≤ 1e-4 of the load step's).
    fn newton<S: NonlinearSystem>(
        &mut self,
        system: &mut S,
        x: &mut Vec<f64>,
        record: &mut StepRecord,
        converged_scale: Option<f64>,
    ) -> Result<(), StepFailure> {
        let tol = self.stepping.tolerance;
        let nf = system.free();
        let mut evaluated = system.evaluate(x, true);
        // A predictor that overshoots in a few cells is relaxed there first.
        if let (Ok(()), Some(scale)) = (&evaluated, converged_scale) {
            if system.relax_predictor(x, scale) {
                evaluated = system.evaluate(x, true);
            }
        }
        if let Err(e) = evaluated {
            self.keep_failed_trial(record.to, x);
            return Err(StepFailure::Material(e));
        }
        let mut have_tangent = true;
        let mut factorised = false;
        let mut phi = system.residual_norm(system.scale());
        let mut last_increment = f64::INFINITY;
        record.initial_residual = phi;
        for _ in 0..self.stepping.max_iterations {
            if self.cancelled() {
                return Err(StepFailure::Cancelled);
            }
            self.newton_iterations += 1;
            if !have_tangent {
                if let Err(e) = system.evaluate(x, true) {
                    self.keep_failed_trial(record.to, x);
                    return Err(StepFailure::Material(e));
                }
            }
            // Near the solution this step's last factorisation serves (see `REUSE_BELOW`).
            let refactorise = !(factorised && phi <= REUSE_BELOW * tol);
            system.newton_direction(&mut self.delta[..nf], refactorise)?;
            factorised = true;
            // Near the solution the step is most likely the last: its state without the tangent.
            let tangent = phi > LIKELY_LAST * tol;
            let alpha = self.line_search(system, x, phi, record.to, tangent)?;
            have_tangent = tangent && alpha == 1.0;
            std::mem::swap(x, &mut self.trial);
            let scale = system.scale();
            let increment = system.increment_norm(&self.delta[..nf], alpha, scale);
            let residual = system.residual_norm(scale);
            record.iterations.push(IterationRecord {
                residual,
                increment,
                step_length: alpha,
            });
            let next = next_increment(increment, residual, phi);
            (phi, last_increment) = (residual, increment);
            if residual <= tol && next <= tol {
                return Ok(());
            }
        }
        self.keep_failed_trial(record.to, x);
        Err(StepFailure::MaxIterations {
            iterations: self.stepping.max_iterations,
            residual: phi,
            increment: last_increment,
        })
    }

    /// Backtracking line search from `x` along the direction held in `delta`: the trial
    /// x + α Δx (α = 1, ½, …, at most [`Stepping::max_backtracks`] halvings) is accepted when
    /// the scaled residual (scale frozen at `x`) decreases, φ(α) ≤ (1 − 10⁻⁴ α) φ(0) (Armijo),
    /// or at α = 1 when φ(0) is already at the tolerance (round-off floor). The full step is
    /// evaluated with its tangent if `tangent`. Returns α; the trial is left in `trial`.
    fn line_search<S: NonlinearSystem>(
        &mut self,
        system: &mut S,
        x: &[f64],
        phi: f64,
        load: f64,
        tangent: bool,
    ) -> Result<f64, StepFailure> {
        let nf = system.free();
        let scale = system.scale();
        let mut alpha = 1.0;
        let mut last_error = None;
        for k in 0..=self.stepping.max_backtracks {
            let full = k == 0;
            let with_tangent = full && tangent;
            self.trial.copy_from_slice(x);
            for (t, d) in self.trial[..nf].iter_mut().zip(&self.delta[..nf]) {
                *t += alpha * d;
            }
            match system.evaluate(&self.trial, with_tangent) {
                Ok(()) => {
                    let phi_trial = system.residual_norm(scale);
                    if phi_trial <= (1.0 - 1e-4 * alpha) * phi
                        || (full && phi <= self.stepping.tolerance)
                    {
                        return Ok(alpha);
                    }
                    last_error = None;
                }
                Err(e) => last_error = Some(e),
            }
            alpha *= 0.5;
        }
        self.failed_trial = Some(State {
            stretch: load,
            x: self.trial.clone(),
        });
        Err(match last_error {
            Some(e) => StepFailure::Material(e),
            None => StepFailure::LineSearch { residual: phi },
        })
    }
}

/// Below `LIKELY_LAST` × the tolerance, the scaled residual is in Newton's quadratic phase and
/// the next step is most likely the last: its trial state is evaluated without the tangent,
/// which only a further iteration would need (it is then evaluated again, with it). On the
/// 16 × 64 frozen explicit sweeps (d = 0 and 0.5), 10⁴ catches 34 of the 40 last iterations
/// and costs 5 extra residual evaluations (10⁵: 38 and 22; 10³: 25 and 2).
const LIKELY_LAST: f64 = 1e4;

/// From a scaled residual at most `REUSE_BELOW` × the tolerance, the Newton direction is solved
/// with the factorisation of an earlier iterate of the same load step, GMRES iterating on the
/// current tangent: the direction is the same (to the linear solver's 10⁻¹² backward error), so
/// are the iterates, and a factorisation is saved for 3–5 Krylov iterations (the linear solver
/// refactorises past 8). Frozen explicit sweep, d = 0 (`examples/cylinder_sweep`), with 10⁶:
/// 32 × 128: factorisations 117 → 81, Krylov iterations 144 → 292, sweep 5.82 → 5.45 s
/// (median of 3, alternated); 16 × 64: 102 → 66 and 131 → 286, 0.99 → 0.97 s. 10⁵: 86
/// factorisations, 5.79 s; 10⁷: 64 factorisations but 549 Krylov iterations. The same Newton
/// iterations (117, 102), P within 9e-12 relative. With GMRES stopping at its backward-error
/// bound, 16 × 64, five alternated runs under load 6.5 (factorisations, Krylov iterations,
/// median sweep): 10⁶ 60, 237, 2.69 s; 3·10⁶ 55, 279, 3.23 s; 10⁷ 46, 359, 3.05 s; 3·10⁷ 44,
/// 374, 3.35 s: the factorisations saved are paid back in Krylov iterations.
const REUSE_BELOW: f64 = 1e6;

/// The scaled norm of the next Newton increment, estimated from the last one, `increment`, and
/// the residual's contraction over the last iteration, r_k / r_{k−1} (`residual` / `before`):
/// ‖δ_{k+1}‖ ≈ ‖δ_k‖ · min(1, r_k / r_{k−1}). Near the solution δ_{k+1} = −K⁻¹ R_k and
/// δ_k = −K⁻¹ R_{k−1} with nearly the same K, so their norms shrink as the residual does; the
/// estimate is never above ‖δ_k‖, and at the round-off floor (r_k ≈ r_{k−1}) it is ‖δ_k‖. It
/// saves the iteration that only confirmed a state already converged: 142 → 122 Newton
/// iterations for the frozen explicit sweep on 16 × 64, P changed by ≤ 1.7e-10 relative.
fn next_increment(increment: f64, residual: f64, before: f64) -> f64 {
    if before > 0.0 {
        increment * (residual / before).min(1.0)
    } else {
        increment
    }
}

/// dx/dλ at the state the system holds.
fn rate<S: NonlinearSystem>(system: &mut S) -> Result<Vec<f64>, StepFailure> {
    let mut v = vec![0.0; system.unknowns()];
    system.load_rate(&mut v)?;
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// R(y; λ) = sinh(y) − (λ − 1) on one free unknown y, with x = (y, c), c = λ − 1
    /// prescribed: the solution is y = asinh(λ − 1). Trial states with y above `limit` are
    /// refused, as a material would refuse an overflowing state.
    struct Sinh {
        residual: f64,
        tangent: f64,
        rate_force: f64,
        limit: f64,
        /// Evaluations without and with the tangent.
        evaluations: [usize; 2],
        /// Each Newton direction's |R| and whether it was to refactorise.
        directions: Vec<(f64, bool)>,
    }

    impl NonlinearSystem for Sinh {
        fn unknowns(&self) -> usize {
            2
        }
        fn free(&self) -> usize {
            1
        }
        fn apply_load(&self, x: &mut [f64], load: f64) {
            x[1] = load - 1.0;
        }
        fn evaluate(&mut self, x: &[f64], tangent: bool) -> crate::Result<()> {
            if x[0] > self.limit {
                return Err(crate::Error::NonFinite {
                    quantity: "test residual",
                    value: f64::INFINITY,
                    context: format!("y = {}", x[0]),
                });
            }
            self.residual = x[0].sinh() - x[1];
            self.evaluations[usize::from(tangent)] += 1;
            if tangent {
                self.tangent = x[0].cosh();
                self.rate_force = -1.0;
            }
            Ok(())
        }
        fn scale(&self) -> f64 {
            1.0
        }
        fn residual_norm(&self, scale: f64) -> f64 {
            self.residual.abs() / scale
        }
        fn increment_norm(&self, dx: &[f64], step: f64, _scale: f64) -> f64 {
            (dx[0] * step).abs()
        }
        fn newton_direction(
            &mut self,
            dx: &mut [f64],
            refactorise: bool,
        ) -> Result<(), StepFailure> {
            self.directions.push((self.residual.abs(), refactorise));
            dx[0] = -self.residual / self.tangent;
            Ok(())
        }
        fn load_rate(&mut self, rate: &mut [f64]) -> Result<(), StepFailure> {
            rate[0] = -self.rate_force / self.tangent;
            rate[1] = 1.0;
            Ok(())
        }
    }

    #[derive(Default)]
    struct Collect {
        reached: Vec<(f64, f64, Vec<StepRecord>)>,
        accepted: usize,
    }

    impl Observer<Sinh> for Collect {
        fn reached(
            &mut self,
            _system: &mut Sinh,
            load: f64,
            x: &[f64],
            steps: Vec<StepRecord>,
        ) -> FemResult<()> {
            self.reached.push((load, x[0], steps));
            Ok(())
        }
        fn step_accepted(&mut self, _record: &StepRecord) {
            self.accepted += 1;
        }
    }

    fn stepping() -> Stepping {
        Stepping {
            tolerance: 1e-13,
            max_step: 0.5,
            max_steps: 1000,
            ..Stepping::default()
        }
    }

    fn system(limit: f64) -> Sinh {
        Sinh {
            residual: 0.0,
            tangent: 1.0,
            rate_force: 0.0,
            limit,
            evaluations: [0, 0],
            directions: Vec::new(),
        }
    }

    #[test]
    fn the_driver_follows_the_closed_form_path_in_both_directions() {
        let mut driver = Continuation::new(2, stepping(), None);
        let mut observer = Collect::default();
        let failures = driver
            .sweep(
                &mut system(f64::INFINITY),
                &[0.2, 1.0, 3.0, 6.0],
                &mut observer,
            )
            .unwrap();
        assert!(failures.is_empty());
        let loads: Vec<f64> = observer.reached.iter().map(|r| r.0).collect();
        assert_eq!(loads, [1.0, 3.0, 6.0, 0.2]);
        for (load, y, steps) in &observer.reached {
            assert!((y - (load - 1.0).asinh()).abs() < 1e-13, "λ = {load}: {y}");
            assert!(steps.iter().all(|s| s.failure.is_none()));
        }
        let accepted: usize = observer.reached.iter().map(|r| r.2.len()).sum();
        // λ = 1 is its own (reference) record, not a load step.
        assert_eq!(observer.accepted, accepted - 1);
        // Steps grow from 0.05 to max_step along the easy path.
        let up = &observer.reached[2].2;
        assert!((up.last().unwrap().to - up.last().unwrap().from - 0.5).abs() < 1e-12);
    }

    #[test]
    fn a_refused_trial_cuts_the_step_down_to_the_last_admissible_load() {
        let limit = 1.0;
        let mut driver = Continuation::new(2, stepping(), None);
        let mut observer = Collect::default();
        let failures = driver
            .sweep(&mut system(limit), &[1.5, 3.0], &mut observer)
            .unwrap();
        match failures.as_slice() {
            [(
                FemError::TargetNotReached {
                    target,
                    reached,
                    attempted,
                    cause: StepFailure::Material(_),
                    ..
                },
                Some(trial),
            )] => {
                // y ≤ 1 holds up to λ = 1 + sinh(1): the path stops within one minimum step.
                let edge = 1.0 + limit.sinh();
                assert_eq!(*target, 3.0);
                assert!(*reached <= edge && *reached > edge - 2e-4, "{reached}");
                assert!(*attempted > edge);
                assert!(trial.x[0] > limit);
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(observer.reached.len(), 1);
    }

    /// The sinh path through `targets`, unbounded, checked against the closed form at every
    /// target: the driver, what it reported, and the system with its counts.
    fn closed_form_sweep(targets: &[f64]) -> (Continuation, Collect, Sinh) {
        let mut driver = Continuation::new(2, stepping(), None);
        let mut observer = Collect::default();
        let mut sinh = system(f64::INFINITY);
        let failures = driver.sweep(&mut sinh, targets, &mut observer).unwrap();
        assert!(failures.is_empty());
        for (load, y, _) in &observer.reached {
            assert!((y - (load - 1.0).asinh()).abs() < 1e-13, "λ = {load}: {y}");
        }
        (driver, observer, sinh)
    }

    /// A step taken from a residual in Newton's quadratic phase is evaluated without its
    /// tangent (only a further iteration would need it), and the path is the closed form all the
    /// same: the rate at such a state is solved with the iterate's before it.
    #[test]
    fn a_likely_last_step_is_evaluated_without_its_tangent() {
        let (driver, observer, sinh) = closed_form_sweep(&[0.2, 3.0, 6.0]);
        // Without the rule, every step evaluates its predictor and each iteration's trial with
        // the tangent.
        let steps: usize = observer.reached.iter().map(|r| r.2.len()).sum();
        let [without, with] = sinh.evaluations;
        assert!(without > 0, "{:?}", sinh.evaluations);
        assert!(
            with < steps + driver.newton_iterations(),
            "{with} with the tangent for {steps} steps and {} iterations",
            driver.newton_iterations()
        );
    }

    /// Only near convergence, and only after a factorisation in the same load step, is a
    /// Newton direction solved without refactorising; the path is the closed form all the same.
    #[test]
    fn an_earlier_factorisation_serves_only_near_convergence_within_a_step() {
        let (_, observer, sinh) = closed_form_sweep(&[0.2, 1.0, 3.0, 6.0]);
        // Each step's directions, in the order solved: the first factorises, every later one
        // from a residual at most REUSE_BELOW × tol does not, every other one does.
        let below = REUSE_BELOW * stepping().tolerance;
        let mut directions = sinh.directions.iter();
        let mut reused = 0;
        for step in observer.reached.iter().flat_map(|r| &r.2) {
            for k in 0..step.iterations.len() {
                let &(residual, refactorise) = directions.next().unwrap();
                assert_eq!(
                    refactorise,
                    k == 0 || residual > below,
                    "{residual}, iteration {k}"
                );
                reused += usize::from(!refactorise);
            }
        }
        assert!(directions.next().is_none());
        assert!(reused > 0, "{:?}", sinh.directions);
    }

    #[test]
    fn the_load_steps_of_a_direction_are_capped() {
        let mut driver = Continuation::new(
            2,
            Stepping {
                max_steps: 4,
                ..stepping()
            },
            None,
        );
        let failures = driver
            .sweep(&mut system(f64::INFINITY), &[6.0], &mut Collect::default())
            .unwrap();
        assert!(matches!(
            failures.as_slice(),
            [(FemError::StepLimit { steps: 4, .. }, _)]
        ));
    }
}
