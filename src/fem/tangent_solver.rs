//! The Newton system K Δx = −R: which factorisation preconditions it.
//!
//! Every solve is exact to the caller's tolerance: GMRES ([`super::gmres`]) iterates on the
//! current tangent K until the normwise backward error ‖b − K x‖ / (‖K‖_F ‖x‖ + ‖b‖) is below
//! it (10⁻¹² for a Newton direction, what a direct solve with partial pivoting attains; see
//! [`super::problem`]), and a factorisation of K only preconditions it. The
//! factorisations, one per Newton iteration:
//!
//! - LDLᵀ of the symmetric part (K + Kᵀ)/2 ([`super::ldlt`]): pattern of K, no pivoting; for a
//!   symmetric tangent GMRES converges in one iteration; on two or more threads and from
//!   [`PATTERN_LU_UNKNOWNS`] unknowns the pattern LU below instead ([`PATTERN_LU_THREADS`]),
//!   whose two cores beat the LDLᵀ's half the flops on one;
//! - once GMRES on it needs more than 10 iterations (a strongly non-symmetric tangent, e.g. the
//!   frozen active-strain model), an LU of K on the LDLᵀ's supernodes ([`super::pattern_lu`]:
//!   same fill as the LDLᵀ, pivoting inside the diagonal blocks), from then on preferred. Ten
//!   GMRES iterations (a matrix product and two triangular solves each) cost about one
//!   factorisation, so past them the LU, with one or two iterations per solve, is cheaper
//!   (the limit was 40 before the centre nodes were condensed; with it, the condensed frozen
//!   tangent stayed on the LDLᵀ: the 8 × 32 frozen sweep at d = 0.5 took 472 GMRES iterations
//!   for 119 solves, against 119 with 10);
//! - faer's LU with partial pivoting ([`super::linear`]), solving directly, for a tangent on
//!   which the pattern LU meets a zero pivot or does not precondition (after three such tangents
//!   in a row, for good), or when
//!   [`LinearSolver::Lu`](super::linear_solver::LinearSolver::Lu) is chosen.
//!
//! The rate dx/dλ at a converged state is solved for its tangent with the factorisation of the
//! last Newton iteration's. Where GMRES on that earlier factor does not converge, the rate's own
//! tangent is factorised the same way (`Timings::refactorisations`); that is no evidence of a
//! non-symmetric tangent, so it does not switch to an LU. (It did until issue 26: with the
//! stopping test that saves the confirming Newton iteration, the converged state lies further
//! from the last factorised one, one such failure put the energy law's symmetric sweep on the
//! pattern LU for good, and its factorisations took 10 instead of 5.5 ms at 9 360 dofs.)
//!
//! An earlier tangent's factorisation also preconditions a Newton iteration near convergence
//! (scaled residual ≤ 10⁻⁴, `continuation::REUSE_BELOW`) within the same load step, for at most
//! [`EARLIER_FACTOR_ITERATIONS`] Krylov iterations before this tangent is factorised: GMRES
//! converges on the current tangent, so the Newton iterates are the same. On the 32 × 128
//! frozen explicit sweep this saves 36 of 117 factorisations for 148 more Krylov iterations.
//! Measured and rejected before, with a factorisation twice as dear against a Krylov
//! iteration: keeping it over the whole quadratic phase or across the iterations of any step
//! (frozen sweep 32 × 128: 24.9 s with reuse against 22.4 s without; energy-law sweep 12 × 48:
//! linear-solve time 0.56 s against 0.55 s; one-step neo-Hookean: 10–20 % slower), because GMRES
//! on a factor far from the current tangent needs 5–10 iterations where a fresh one needs one.
//!
//! faer's factorisations run sequentially (`Par::Seq`): on 2 cores faer's parallel supernodal
//! factorisation was 1.3–1.9× slower at 9k–150k dofs (`cargo run --release --example
//! fem_scaling`). The pattern LU uses the two cores on two independent groups of subtrees of
//! the elimination tree (`pattern_lu::split`): factorisation 7.0 → 5.6 ms at 9 360 dofs and
//! 47 → 34 ms at 37 152 (frozen explicit sweeps, `examples/cylinder_sweep.rs`), and its solves
//! too (`pattern_lu::solve`): GMRES solve (one preconditioner application and one product by K)
//! 1.07 → 0.86 ms and 8.65 → 6.35 ms per call.

use super::assembly::Pattern;
use super::gmres::{Gmres, Preconditioner};
use super::ldlt::SymmetricPartLdlt;
use super::linear::SparseLu;
use super::pattern_lu::PatternLu;
use super::timings::Timings;
use std::time::Instant;

/// GMRES iterations allowed with the LDLᵀ of the symmetric part before switching to an LU
/// (about the cost of one factorisation).
const LDLT_ITERATIONS: usize = 10;
/// GMRES iterations allowed with the pattern LU (exact up to its pivots: one or two).
const PATTERN_LU_ITERATIONS: usize = 20;
/// GMRES iterations allowed on the factorisation of an earlier tangent (a Newton iteration
/// near convergence, see `continuation::REUSE_BELOW`, or the rate at a converged state) before
/// this tangent is factorised: a factorisation costs about as much as 6–7 Krylov iterations
/// (26 ms against 4 ms on the 32 × 128 muscle tangent, 37 152 unknowns, two cores). Most such
/// solves take 3–5 iterations; on the 32 × 128 frozen explicit sweep the cap turns 6 solves of
/// 10–20 iterations into refactorisations (Krylov iterations 345 → 292).
const EARLIER_FACTOR_ITERATIONS: usize = 8;
/// Consecutive failures of the pattern LU after which faer's LU is used for good.
const PATTERN_LU_STRIKES: usize = 3;
/// Threads from which, and unknowns from which, the pattern LU preconditions a symmetric
/// tangent too: on two cores its two groups of subtrees make it faster than faer's sequential
/// LDLᵀ, which does half its flops. Energy law, consistent coupling, `examples/cylinder_sweep`
/// on 2 cores, alternated, factorisations per sweep LDLᵀ → pattern LU: 0.27 → 0.19 s on 12 × 48
/// cells, 0.57 → 0.41 s on 16 × 64 (7 312 unknowns), 4.1 → 3.2 s on 32 × 128 (28 960); on one
/// core the LDLᵀ is the faster (6.4 against 7.6 ms per call on 16 × 64). Below, the gain is at
/// most 0.02 s per sweep (8 × 32, 0.09 → 0.07 s), on 4 × 16 the LDLᵀ is the faster (0.01 against
/// 0.02 s), and on a clamped 2 × 3 mesh at rest the pattern LU, whose pivots stay inside its
/// small diagonal blocks, needed 11 GMRES iterations for 2 solves.
pub const PATTERN_LU_THREADS: usize = 2;
/// See [`PATTERN_LU_THREADS`].
pub const PATTERN_LU_UNKNOWNS: usize = 4000;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Factor {
    None,
    Ldlt,
    PatternLu,
    Lu,
}

/// Factorisations and the Krylov workspace for one tangent pattern.
#[derive(Debug)]
pub struct TangentSolver {
    ldlt: Option<SymmetricPartLdlt>,
    pattern_lu: Option<PatternLu>,
    /// Consecutive factorisations in which the pattern LU met a zero pivot or did not
    /// precondition (each time faer's LU took over for that tangent).
    pattern_lu_strikes: usize,
    /// Use faer's LU for the current tangent (the pattern LU just failed on it).
    skip_pattern_lu: bool,
    lu: Option<SparseLu>,
    gmres: Gmres,
    rhs_copy: Vec<f64>,
    /// The factorisation currently held.
    current: Factor,
    /// GMRES on the LDLᵀ failed once: the tangent is strongly non-symmetric, use an LU.
    prefer_lu: bool,
    /// The held factorisation has not been used yet: it is of the tangent the next solve is
    /// for. A later solve may be for another tangent of the pattern (the rate at a converged
    /// state), on which GMRES failing says nothing about the tangent's symmetry.
    fresh: bool,
}

impl TangentSolver {
    /// `ldlt`: the symbolic LDLᵀ (None: faer's LU only). `symmetric`: whether the tangent may be
    /// symmetric ([`AxisymmetricMaterial::symmetric_tangent`]); if not, the LU from the start
    /// (the pattern LU on the LDLᵀ's supernodes). `threads`: the threads the solve may use; from
    /// [`PATTERN_LU_THREADS`] on and for n ≥ [`PATTERN_LU_UNKNOWNS`], the pattern LU also for a
    /// symmetric tangent.
    ///
    /// [`AxisymmetricMaterial::symmetric_tangent`]: super::material::AxisymmetricMaterial::symmetric_tangent
    pub fn new(n: usize, ldlt: Option<SymmetricPartLdlt>, symmetric: bool, threads: usize) -> Self {
        let two_cores = threads >= PATTERN_LU_THREADS && n >= PATTERN_LU_UNKNOWNS;
        let prefer_lu = ldlt.is_none() || !symmetric || two_cores;
        Self {
            ldlt,
            pattern_lu: None,
            pattern_lu_strikes: 0,
            skip_pattern_lu: false,
            lu: None,
            gmres: Gmres::new(n, 40),
            rhs_copy: vec![0.0; n],
            current: Factor::None,
            prefer_lu,
            fresh: false,
        }
    }

    /// Solves K x = b (b in `rhs`, x returned in it) to the normwise backward error `tolerance`
    /// for the tangent last factorised — or, when a later tangent with the same pattern is
    /// passed (the rate dx/dλ at a converged state), for that one, by GMRES preconditioned with
    /// the held factorisation. `values_norm`: ‖K‖_F. (faer's LU, when it is the one held,
    /// solves directly.)
    pub fn solve(
        &mut self,
        pattern: &Pattern,
        values: &[f64],
        values_norm: f64,
        rhs: &mut [f64],
        tolerance: f64,
        timings: &mut Timings,
    ) -> Result<(), String> {
        for _ in 0..3 {
            let fresh = std::mem::replace(&mut self.fresh, false);
            let max_iter = match self.current {
                Factor::Ldlt => LDLT_ITERATIONS,
                Factor::PatternLu => PATTERN_LU_ITERATIONS,
                _ => break,
            };
            // On an earlier tangent's factorisation, past `EARLIER_FACTOR_ITERATIONS` a
            // factorisation of this tangent is the cheaper.
            let max_iter = if fresh {
                max_iter
            } else {
                max_iter.min(EARLIER_FACTOR_ITERATIONS)
            };
            if self
                .krylov(
                    pattern,
                    values,
                    values_norm,
                    rhs,
                    tolerance,
                    max_iter,
                    timings,
                )
                .is_some()
            {
                if self.current == Factor::PatternLu {
                    self.pattern_lu_strikes = 0;
                }
                return Ok(());
            }
            // GMRES does not converge on a factorisation of an earlier tangent: this tangent's,
            // of the same kind.
            if !fresh {
                timings.refactorisations += 1;
                self.factorise(pattern, values, timings)?;
                continue;
            }
            // GMRES does not converge on this tangent's own factorisation: the pattern LU
            // (after the LDLᵀ) or faer's LU (after the pattern LU) for it, and an LU from now
            // on.
            timings.lu_fallbacks += 1;
            if self.current == Factor::PatternLu {
                self.pattern_lu_strikes += 1;
                self.skip_pattern_lu = true;
            }
            self.prefer_lu = true;
            self.factorise(pattern, values, timings)?;
        }
        let lu = self.lu.as_mut().ok_or("no factorisation")?;
        lu.solve_in_place(rhs)
    }

    /// Whether the factorisation held preconditions GMRES (the LDLᵀ or the pattern LU), which
    /// then converges on whichever tangent is passed to [`Self::solve`]; faer's LU solves
    /// directly, with the tangent it factorised.
    pub fn iterates(&self) -> bool {
        matches!(self.current, Factor::Ldlt | Factor::PatternLu)
    }

    /// Factorises the tangent just assembled (by a Newton iteration whose step has none close enough, see [`Self::iterates`]): LDLᵀ of the symmetric part unless the LU is
    /// preferred or the LDLᵀ breaks down (zero pivot).
    pub fn factorise(
        &mut self,
        pattern: &Pattern,
        values: &[f64],
        timings: &mut Timings,
    ) -> Result<(), String> {
        let t = Instant::now();
        self.current = Factor::None;
        let mut r = Err(String::new());
        if !self.prefer_lu {
            if let Some(ldlt) = self.ldlt.as_mut() {
                r = ldlt.factorise(values);
                if r.is_ok() {
                    self.current = Factor::Ldlt;
                } else {
                    timings.lu_fallbacks += 1;
                }
            }
        }
        let skip = std::mem::take(&mut self.skip_pattern_lu);
        if self.current == Factor::None && !skip && self.pattern_lu_strikes < PATTERN_LU_STRIKES {
            if self.pattern_lu.is_none() {
                if let Some(ldlt) = self.ldlt.as_ref() {
                    self.pattern_lu = PatternLu::new(pattern, ldlt.symbolic(), ldlt.perm()).ok();
                }
            }
            match self.pattern_lu.as_mut().map(|p| p.factorise(values)) {
                Some(Ok(())) => {
                    self.current = Factor::PatternLu;
                    timings.pattern_lu_factorisations += 1;
                    r = Ok(());
                }
                Some(Err(_)) => self.pattern_lu_strikes += 1,
                None => self.pattern_lu_strikes = PATTERN_LU_STRIKES,
            }
        }
        if self.current == Factor::None {
            if self.lu.is_none() {
                self.lu = Some(SparseLu::new(pattern)?);
            }
            if let Some(lu) = self.lu.as_mut() {
                r = lu.factorise(pattern, values);
                if r.is_ok() {
                    self.current = Factor::Lu;
                }
            }
        }
        timings.factorisation += t.elapsed();
        timings.factorisations += 1;
        self.fresh = r.is_ok();
        r
    }

    /// GMRES on K preconditioned by the held factorisation, at most `max_iter` iterations;
    /// restores `rhs` and returns None if it does not converge.
    #[allow(clippy::too_many_arguments)]
    fn krylov(
        &mut self,
        pattern: &Pattern,
        values: &[f64],
        values_norm: f64,
        rhs: &mut [f64],
        tolerance: f64,
        max_iter: usize,
        timings: &mut Timings,
    ) -> Option<usize> {
        self.rhs_copy.copy_from_slice(rhs);
        let pre: Option<&mut dyn Preconditioner> = match self.current {
            Factor::Ldlt => self.ldlt.as_mut().map(|p| p as &mut dyn Preconditioner),
            Factor::PatternLu => self
                .pattern_lu
                .as_mut()
                .map(|p| p as &mut dyn Preconditioner),
            // faer's LU solves directly (see `solve`).
            Factor::Lu | Factor::None => None,
        };
        let its = pre.and_then(|pre| {
            self.gmres
                .solve(pattern, values, values_norm, pre, rhs, tolerance, max_iter)
        });
        match its {
            Some(its) => timings.krylov_iterations += its,
            None => rhs.copy_from_slice(&self.rhs_copy),
        }
        its
    }
}
