//! The Newton system K Δx = −R: which factorisation to compute, when to reuse an old one.
//!
//! Every solve is exact to round-off: GMRES iterates on the current tangent K until the
//! normwise backward error ‖b − K x‖ / (‖K‖_F ‖x‖ + ‖b‖) ≤ 10⁻¹² (what a direct solve with
//! partial pivoting attains), and a factorisation only preconditions it. The factorisations:
//!
//! - LDLᵀ of the symmetric part (K + Kᵀ)/2 ([`super::ldlt`]): pattern of K, no pivoting; for a
//!   symmetric tangent GMRES converges in one iteration;
//! - once GMRES on it needs more than 40 iterations (a strongly non-symmetric tangent, e.g. the
//!   frozen active-strain model), an LU of K on the LDLᵀ's supernodes ([`super::pattern_lu`]:
//!   same fill as the LDLᵀ, pivoting inside the diagonal blocks), from then on preferred;
//! - faer's LU with partial pivoting ([`super::linear`]) for a tangent on which the pattern
//!   LU meets a zero pivot or does not precondition (after three such tangents in a row, for
//!   good), or when `LinearSolver::Lu` is chosen.
//!
//! Reuse (`SolverOptions::reuse_factorisation`): between Newton iterations and load steps the
//! tangent changes little, so the last LDLᵀ or pattern LU is kept and GMRES preconditioned by
//! it usually converges in a few iterations. The iteration budget of such a solve is
//! k_fresh + t_factorise / t_iteration (at least 2, at most the restart length 40), where
//! k_fresh is the iteration count of the last solve with a fresh factorisation, all measured on
//! this problem; a failed attempt factorises the current tangent. Renewal rule: once a solve
//! with the kept factorisation costs more than the average cost per solve since that
//! factorisation (factorisation included), the next tangent is factorised afresh — with solve
//! costs that grow as the tangent drifts away, this minimises the average cost per solve.
//! faer's LU is never reused: applying it costs 1/8–1/20 of factorising it (its fill is bounded
//! by the Cholesky factor of KᵀK, not of K), so GMRES on an earlier one is dearer than a fresh one.
//!
//! Factorisations run sequentially (`Par::Seq`): on 2 cores faer's parallel supernodal
//! factorisation was 1.3–1.9× slower at 9k–150k dofs (`cargo run --release --example
//! fem_scaling`), and the cores are better spent on the element loop.

use super::assembly::Pattern;
use super::ldlt::{Gmres, SymmetricPartLdlt};
use super::linear::SparseLu;
use super::pattern_lu::PatternLu;
use super::solver::Timings;
use std::time::Instant;

/// Normwise backward error to which every linear solve is converged.
const TOLERANCE: f64 = 1e-12;
/// GMRES iterations allowed with a fresh LDLᵀ of the symmetric part before switching to an LU.
const FRESH_LDLT_ITERATIONS: usize = 40;
/// GMRES iterations allowed with a fresh pattern LU (exact up to its pivots: one or two).
const FRESH_PATTERN_LU_ITERATIONS: usize = 20;
/// Consecutive failures of the pattern LU after which faer's LU is used for good.
const PATTERN_LU_STRIKES: usize = 3;
/// Bounds of the iteration budget with a reused factorisation.
const REUSE_BUDGET: (usize, usize) = (2, 40);

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Factor {
    None,
    Ldlt,
    PatternLu,
    Lu,
}

/// Factorisations, the Krylov workspace and the reuse policy for one tangent pattern.
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
    /// The held factorisation is of an earlier tangent.
    stale: bool,
    /// GMRES on the LDLᵀ failed once: the tangent is strongly non-symmetric, use the LU.
    prefer_lu: bool,
    /// Keep factorisations across Newton iterations and load steps.
    reuse: bool,
    /// Factorise the next tangent afresh (renewal rule).
    refresh: bool,
    /// Seconds spent since the last fresh factorisation (it included) and solves since it.
    cycle_seconds: f64,
    cycle_solves: usize,
    /// Seconds of the last fresh factorisation and of one GMRES iteration with it, and the
    /// iterations its solve needed.
    factor_seconds: f64,
    iteration_seconds: f64,
    fresh_iterations: usize,
}

impl TangentSolver {
    /// `ldlt`: the symbolic LDLᵀ (None: LU only). `reuse`: keep factorisations of earlier tangents.
    pub fn new(n: usize, ldlt: Option<SymmetricPartLdlt>, reuse: bool) -> Self {
        let prefer_lu = ldlt.is_none();
        Self {
            ldlt,
            pattern_lu: None,
            pattern_lu_strikes: 0,
            skip_pattern_lu: false,
            lu: None,
            gmres: Gmres::new(n, 40),
            rhs_copy: vec![0.0; n],
            current: Factor::None,
            stale: false,
            prefer_lu,
            reuse,
            refresh: false,
            cycle_seconds: 0.0,
            cycle_solves: 0,
            factor_seconds: 0.0,
            iteration_seconds: f64::INFINITY,
            fresh_iterations: 1,
        }
    }

    /// A new tangent (pattern, values) has been assembled. With reuse the held factorisation
    /// is kept (and becomes stale); otherwise the tangent is factorised now.
    pub fn update(
        &mut self,
        pattern: &Pattern,
        values: &[f64],
        timings: &mut Timings,
    ) -> Result<(), String> {
        let cheap = matches!(self.current, Factor::Ldlt | Factor::PatternLu);
        if self.reuse && cheap && !self.refresh {
            self.stale = true;
            return Ok(());
        }
        self.factorise(pattern, values, timings)
    }

    /// Solves K x = b for the tangent last passed to `update` (b in `rhs`, x returned in it).
    pub fn solve(
        &mut self,
        pattern: &Pattern,
        values: &[f64],
        rhs: &mut [f64],
        timings: &mut Timings,
    ) -> Result<(), String> {
        if self.stale {
            let budget =
                (self.fresh_iterations as f64 + self.factor_seconds / self.iteration_seconds)
                    .clamp(REUSE_BUDGET.0 as f64, REUSE_BUDGET.1 as f64) as usize;
            let t = Instant::now();
            if self.krylov(pattern, values, rhs, budget, timings).is_some() {
                let cost = t.elapsed().as_secs_f64();
                self.cycle_seconds += cost;
                self.cycle_solves += 1;
                self.refresh = cost > self.cycle_seconds / self.cycle_solves as f64;
                return Ok(());
            }
            self.factorise(pattern, values, timings)?;
        }
        for _ in 0..2 {
            let max_iter = match self.current {
                Factor::Ldlt => FRESH_LDLT_ITERATIONS,
                Factor::PatternLu => FRESH_PATTERN_LU_ITERATIONS,
                _ => break,
            };
            let t = Instant::now();
            if let Some(its) = self.krylov(pattern, values, rhs, max_iter, timings) {
                self.iteration_seconds = t.elapsed().as_secs_f64() / its.max(1) as f64;
                if self.current == Factor::PatternLu {
                    self.pattern_lu_strikes = 0;
                }
                self.fresh_iterations = its;
                self.cycle_seconds += t.elapsed().as_secs_f64();
                self.cycle_solves += 1;
                return Ok(());
            }
            // GMRES on the symmetric part does not converge: LU from now on (the pattern
            // LU first; faer's pivoting LU if that does not precondition either).
            timings.lu_fallbacks += 1;
            if self.current == Factor::PatternLu {
                self.pattern_lu_strikes += 1;
                self.skip_pattern_lu = true;
            }
            self.prefer_lu = true;
            self.factorise(pattern, values, timings)?;
        }
        let t = Instant::now();
        let lu = self.lu.as_mut().ok_or("no factorisation")?;
        let r = lu.solve_in_place(rhs);
        self.iteration_seconds = t.elapsed().as_secs_f64();
        self.fresh_iterations = 1;
        self.cycle_seconds += self.iteration_seconds;
        self.cycle_solves += 1;
        r
    }

    /// Fresh factorisation of the current tangent: LDLᵀ of the symmetric part unless the LU is
    /// preferred or the LDLᵀ breaks down (zero pivot).
    fn factorise(
        &mut self,
        pattern: &Pattern,
        values: &[f64],
        timings: &mut Timings,
    ) -> Result<(), String> {
        let t = Instant::now();
        self.current = Factor::None;
        self.stale = false;
        self.refresh = false;
        let mut r = Err(String::new());
        if !self.prefer_lu {
            if let Some(ldlt) = self.ldlt.as_mut() {
                r = ldlt.factorise(pattern, values);
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
                    self.pattern_lu = PatternLu::new(pattern, ldlt.symbolic()).ok();
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
        self.factor_seconds = t.elapsed().as_secs_f64();
        self.cycle_seconds = self.factor_seconds;
        self.cycle_solves = 0;
        timings.factorisation += t.elapsed();
        timings.factorisations += 1;
        r
    }

    /// GMRES on K preconditioned by the held factorisation, at most `max_iter` iterations;
    /// restores `rhs` and returns None if it does not converge.
    fn krylov(
        &mut self,
        pattern: &Pattern,
        values: &[f64],
        rhs: &mut [f64],
        max_iter: usize,
        timings: &mut Timings,
    ) -> Option<usize> {
        self.rhs_copy.copy_from_slice(rhs);
        let its = match self.current {
            Factor::Ldlt => self.ldlt.as_mut().and_then(|ldlt| {
                self.gmres
                    .solve(pattern, values, ldlt, rhs, TOLERANCE, max_iter)
            }),
            Factor::PatternLu => self.pattern_lu.as_mut().and_then(|lu| {
                self.gmres
                    .solve(pattern, values, lu, rhs, TOLERANCE, max_iter)
            }),
            Factor::Lu => self.lu.as_mut().and_then(|lu| {
                self.gmres
                    .solve(pattern, values, lu, rhs, TOLERANCE, max_iter)
            }),
            Factor::None => None,
        };
        match its {
            Some(its) => timings.krylov_iterations += its,
            None => rhs.copy_from_slice(&self.rhs_copy),
        }
        its
    }
}
