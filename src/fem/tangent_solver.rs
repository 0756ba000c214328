//! The Newton system K Δx = −R: which factorisation to compute, when to reuse an old one.
//!
//! Every solve is exact to round-off: GMRES iterates on the current tangent K until
//! ‖b − K x‖ ≤ 10⁻¹² ‖b‖, and a factorisation only preconditions it. Three factorisations serve:
//!
//! - LDLᵀ of the symmetric part (K + Kᵀ)/2 (`ldlt`), cheap (pattern of K, no pivoting); for a
//!   symmetric tangent GMRES converges in one iteration;
//! - sparse LU of K (`linear`), used once GMRES on the LDLᵀ has failed (a strongly
//!   non-symmetric tangent, e.g. the frozen active-strain model), and from then on preferred;
//! - the LDLᵀ of an **earlier** tangent (`reuse`): between Newton iterations and load
//!   steps the tangent changes little, so the last factorisation is kept and GMRES preconditioned
//!   by it usually converges in a few iterations. It is replaced by a fresh factorisation as soon
//!   as GMRES would cost more than factorising afresh: the iteration budget is
//!   k_fresh + t_factorise / t_iteration (at least 2, at most the restart length 40), where
//!   k_fresh is the iteration count of the last solve with a fresh factorisation (1 for the
//!   direct LU), all measured on this problem. A failed attempt factorises the current tangent.
//!   Renewal rule: once a solve with the kept factorisation costs more than the average cost
//!   per solve since that factorisation (factorisation included), the next tangent is
//!   factorised afresh — with solve costs that grow as the tangent drifts away, this minimises
//!   the average cost per solve.
//!
//!   Only the LDLᵀ is reused. Applying faer's LU costs 1/8–1/20 of factorising it, several
//!   times an LDLᵀ application (its fill is bounded by the Cholesky factor of KᵀK, not of K),
//!   so GMRES on an earlier LU is
//!   dearer than a fresh LU: the frozen explicit-law sweep on 16 × 64 cells (d = 0.5, `cargo run
//!   --release --example cylinder_sweep -- 16 64 explicit`) took 13.8 s with LU reuse against
//!   7.2 s without. LDLᵀ reuse cut the linear-solve time of the energy-law sweep on 12 × 48
//!   cells from 1.19 s to 0.92 s (same stresses to the printed digits).
//!
//! Factorisations run sequentially (`Par::Seq`): on 2 cores faer's parallel supernodal
//! factorisation was 1.3–1.9× slower at 9k–150k dofs (`cargo run --release --example
//! fem_scaling`), and the cores are better spent on the element loop.

use super::assembly::Pattern;
use super::ldlt::{Gmres, SymmetricPartLdlt};
use super::linear::SparseLu;
use super::solver::Timings;
use std::time::Instant;

/// Relative residual to which every linear solve is converged.
const TOLERANCE: f64 = 1e-12;
/// GMRES iterations allowed with a fresh LDLᵀ of the symmetric part before switching to the LU.
const FRESH_LDLT_ITERATIONS: usize = 200;
/// Bounds of the iteration budget with a reused factorisation.
const REUSE_BUDGET: (usize, usize) = (2, 40);

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Factor {
    None,
    Ldlt,
    Lu,
}

/// Factorisations, the Krylov workspace and the reuse policy for one tangent pattern.
#[derive(Debug)]
pub struct TangentSolver {
    ldlt: Option<SymmetricPartLdlt>,
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
        if self.reuse && self.current == Factor::Ldlt && !self.refresh {
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
        if self.current == Factor::Ldlt {
            let t = Instant::now();
            if let Some(its) = self.krylov(pattern, values, rhs, FRESH_LDLT_ITERATIONS, timings) {
                self.iteration_seconds = t.elapsed().as_secs_f64() / its.max(1) as f64;
                self.fresh_iterations = its;
                self.cycle_seconds += t.elapsed().as_secs_f64();
                self.cycle_solves += 1;
                return Ok(());
            }
            // GMRES on the symmetric part does not converge: LU from now on.
            timings.lu_fallbacks += 1;
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
