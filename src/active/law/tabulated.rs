//! Tabulated activation laws: the implicit and the energy-consistent law replaced, for chosen
//! damages and a chosen stretch range, by a piecewise quintic Hermite interpolant built once
//! from the exact solve and checked against it.
//!
//! On each piece [a, b] (width h) the law is the quintic
//!
//! γ(λ) ≈ p(t) = Σ_{k≤5} c_k t^k,  t = (λ − a)/h,
//!
//! that takes the node values γ₀, γ₁ and the exact h γ′, h² γ″ (implicit-function theorem,
//! see [`LawValue`]) at t = 0 and t = 1: with A = γ₁ − γ₀ − hγ₀′ − h²γ₀″/2,
//! B = h(γ₁′ − γ₀′) − h²γ₀″ and C = h²(γ₁″ − γ₀″),
//!
//! c₀ = γ₀, c₁ = hγ₀′, c₂ = h²γ₀″/2, c₃ = 10A − 4B + C/2, c₄ = −15A + 7B − C, c₅ = 6A − 3B + C/2.
//!
//! Neighbouring pieces share their end data, so the table is C² in λ, and γ′ = p′(t)/h,
//! γ″ = p″(t)/h² are the exact derivatives of the table itself: the frozen model's exact tangent
//! and the consistent model's stress and tangent are those of the tabulated law.
//!
//! **Node values.** The solved γ carries ≈ 2e-16 of absolute rounding noise (the rounding of
//! P_tot, amplified by the energy's exponent α(I − 1) ≈ 10–15), and interpolating values puts
//! that noise, divided by the node spacing, into γ′ — which the consistent stress multiplies by
//! ∂Ŵ/∂γ ≈ 1.5e4 kPa at λ = 1.6 (measured: values-only interpolants, Chebyshev or Hermite, miss
//! 1e-9 kPa there). So the node values are built from the slopes: along each chain of adjacent
//! pieces, γ at a node is the running sum of the rises ∫γ′ of the pieces to its left
//! (5-point Gauss–Legendre of the exact slope), plus the straight line that fits the solved
//! values best (least squares weighted by piece width). γ′ then inherits the accuracy of the
//! exact slopes, γ that of the solved values.
//!
//! **Build and check.** Pieces start 0.05 wide. Each is checked at t = ¼, ½, ¾ (points not used
//! to build it) against the exact law: |Δγ|, the fibre stress of the frozen model
//! P_tot(λ, γ) = ∂Ŵ/∂λ and that of the consistent model dΨ/dλ = ∂Ŵ/∂λ + ∂Ŵ/∂γ γ′
//! (eq. D:Ptotcalcolato and its consistent counterpart) must meet half the tolerances of the
//! [`TableSpec`]; a piece that does not is bisected. Where bisecting stops helping (below a width
//! of [`STALL_WIDTH`] the error fell by less than [`STALL_FACTOR`], or the width reached
//! [`MIN_WIDTH`]) the piece is left to the exact solve: there the exact law's own rounding
//! (amplified by the energy's exponential) is above the tolerances, and the table answers only
//! where it meets them. With the node values assembled, every piece is checked again against
//! [`FINAL_MARGIN`] of the tolerances (one that fails is left to the exact solve too), and the
//! largest errors and the intervals left to the exact solve are kept in a [`TableReport`]. The
//! interpolation error is h⁶ |γ⁽⁶⁾| t³(1 − t)³/720, largest at t = ½.
//!
//! **The rule at λ_min.** λ_min is always a piece boundary: no polynomial spans it.
//! - Implicit law: γ = 0 for λ ≤ λ_min exactly, as in the exact law (no table there). Above
//!   λ_min the law is flat to all orders (γ ≈ P_act/∂_γP_tot ∝ e^{−k(λ²−λ_opt²)²/(λ−λ_min)}):
//!   the first piece starts at λ_min from γ = γ′ = γ″ = 0.
//! - Energy law, [`BelowMinimum::Inactive`]: γ = 0 for λ ≤ λ_min exactly; above, the pieces
//!   start from the branch's limit at λ_min (the zero-work root), on the other side of the jump.
//! - Energy law, [`BelowMinimum::ZeroWork`]: γ is continuous across λ_min but the work term
//!   switches from 0 to ∫P_act there; pieces on [λ_lo, λ_min] and on [λ_min, λ_hi] meet there.
//!
//! A negative value of the interpolant (|γ| at rounding level just above λ_min) is returned as
//! γ = 0. Outside [λ_lo, λ_hi] and for a damage without a table, the exact law is solved.

use super::{ActivationLaw, BelowMinimum, EnergyLaw, ImplicitLaw, LawValue};
use crate::active::drive::Drive;
use crate::active::map::ActivationMap;
use crate::energy::StrainEnergy;
use crate::{Error, Result};
use std::fmt;
use std::sync::Arc;
use std::time::Instant;

/// The narrowest piece the build bisects to before it gives up.
pub const MIN_WIDTH: f64 = 1e-6;

/// The partition asks for this fraction of the tolerances, the final check (with the assembled
/// node values) for [`FINAL_MARGIN`]: it sees three points per piece, and the stretches between
/// them must stay within the whole tolerances (on the chapter's energy with a weaker active
/// curve, a piece passing its points at 0.99 reached 1.06 between them).
const PARTITION_MARGIN: f64 = 0.5;
const FINAL_MARGIN: f64 = 0.75;

/// Widest initial piece; the build bisects from there.
const INITIAL_WIDTH: f64 = 0.05;

/// Below this width a piece whose error a bisection did not cut by [`STALL_FACTOR`] is left to
/// the exact solve: a halving divides the interpolation error by 2⁶ = 64, so an error that no
/// longer falls is the exact law's own rounding, which no table can beat.
const STALL_WIDTH: f64 = 1e-3;
/// See [`STALL_WIDTH`].
const STALL_FACTOR: f64 = 4.0;

/// What to tabulate: the stretch range and the tolerances the build checks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TableSpec {
    /// Lower end of the table λ_lo [-] (> 0).
    pub lambda_lo: f64,
    /// Upper end of the table λ_hi [-] (> λ_lo).
    pub lambda_hi: f64,
    /// Largest |γ_table − γ_exact| allowed at the check points [-].
    pub gamma_tolerance: f64,
    /// Absolute part of the largest error allowed at the check points in the fibre stress of
    /// the frozen and of the consistent model \[kPa\].
    pub stress_tolerance: f64,
    /// Relative part [-]: the stress error allowed is `stress_tolerance + relative_stress_tolerance
    /// × |P|`, P the exact fibre stress at the point.
    pub relative_stress_tolerance: f64,
}

impl Default for TableSpec {
    /// λ ∈ [0.5, 1.6], |Δγ| ≤ 1e-12, fibre-stress error ≤ 1e-9 kPa + 1e-13 |P|. The clamped
    /// cylinder's fibres reach down to ≈ 0.58 on the chapter's sweep λ ∈ [0.7, 1.6]. The
    /// relative part matters only where |P| ≳ 1000 kPa (λ ≳ 1.5; at λ = 1.6, P ≈ 8 300 kPa and
    /// it allows 1.8e-9 kPa): there 1e-9 kPa meets the exact solve's own rounding. Its γ carries
    /// ≈ 2e-16 of absolute noise (the rounding of P_tot, amplified by the exponent
    /// α(I − 1) ≈ 10–15 of the energy), which ∂P_tot/∂γ turns into ≈ 1e-10 kPa at λ = 1.6 and
    /// ≈ 2e-9 kPa at 1.7 (∂P_tot/∂γ ≈ 1e7 kPa there), and the consistent stress multiplies the
    /// slope's noise (≈ 1e-14) by ∂Ŵ/∂γ ≈ 1.5e4 kPa at 1.6. Measured at 20 000 random stretches
    /// per table: within 0.61 of these tolerances (with no relative part, the energy law
    /// reaches 1.1× the absolute one near 1.6).
    fn default() -> Self {
        Self {
            lambda_lo: 0.5,
            lambda_hi: 1.6,
            gamma_tolerance: 1e-12,
            stress_tolerance: 1e-9,
            relative_stress_tolerance: 1e-13,
        }
    }
}

impl TableSpec {
    /// Checks every field: a positive finite range and tolerances; errors name the field.
    pub fn validate(&self) -> Result<()> {
        let check = |name, value: f64, ok: bool, rule| {
            if ok && value.is_finite() {
                Ok(())
            } else {
                Err(Error::InvalidParameter { name, value, rule })
            }
        };
        check(
            "lambda_lo",
            self.lambda_lo,
            self.lambda_lo > 0.0,
            "must be finite and > 0",
        )?;
        check(
            "lambda_hi",
            self.lambda_hi,
            self.lambda_hi > self.lambda_lo,
            "must be finite and > lambda_lo",
        )?;
        check(
            "gamma_tolerance",
            self.gamma_tolerance,
            self.gamma_tolerance > 0.0,
            "must be finite and > 0",
        )?;
        check(
            "stress_tolerance",
            self.stress_tolerance,
            self.stress_tolerance > 0.0,
            "must be finite and > 0",
        )?;
        check(
            "relative_stress_tolerance",
            self.relative_stress_tolerance,
            self.relative_stress_tolerance >= 0.0,
            "must be finite and >= 0",
        )
    }
}

/// How a scene or a study represents an activation law.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum LawRepresentation {
    /// Solve the law's equation at every evaluation.
    #[default]
    Exact,
    /// Tabulate it once per damage (implicit and energy laws; the others are closed forms and
    /// stay as they are).
    Tabulated(TableSpec),
}

/// The laws that solve an equation for γ, which a table can replace.
#[derive(Debug, Clone)]
pub enum SolvedLaw<E> {
    /// [`ImplicitLaw`].
    Implicit(ImplicitLaw<E>),
    /// [`EnergyLaw`].
    Energy(EnergyLaw<E>),
}

impl<E: StrainEnergy> SolvedLaw<E> {
    fn energy(&self) -> &E {
        match self {
            SolvedLaw::Implicit(l) => l.energy(),
            SolvedLaw::Energy(l) => l.energy(),
        }
    }

    /// The activation map the exact law is solved with.
    pub fn map(&self) -> ActivationMap {
        match self {
            SolvedLaw::Implicit(l) => l.map(),
            SolvedLaw::Energy(l) => l.map(),
        }
    }

    fn lambda_min(&self) -> f64 {
        match self {
            SolvedLaw::Implicit(l) => l.curve().lambda_min(),
            SolvedLaw::Energy(l) => l.curve().lambda_min(),
        }
    }

    /// Whether γ = 0 for λ ≤ λ_min (then no table is needed there).
    fn zero_below_minimum(&self) -> bool {
        match self {
            SolvedLaw::Implicit(_) => true,
            SolvedLaw::Energy(l) => l.below_minimum_choice() == BelowMinimum::Inactive,
        }
    }

    /// The law whose root branch the table follows: the law itself, or for the energy law
    /// that jumps at λ_min its continuous variant (the same root above λ_min, and at λ_min the
    /// limit from above).
    fn continuous_branch(&self) -> Self
    where
        E: Clone,
    {
        match self {
            SolvedLaw::Energy(l) => {
                SolvedLaw::Energy(l.clone().below_minimum(BelowMinimum::ZeroWork))
            }
            other => other.clone(),
        }
    }

    /// Name of the exact law: implicit or energy.
    pub fn name(&self) -> &'static str {
        match self {
            SolvedLaw::Implicit(_) => "implicit",
            SolvedLaw::Energy(_) => "energy",
        }
    }
}

impl<E: StrainEnergy> ActivationLaw for SolvedLaw<E> {
    fn evaluate(&self, lambda: f64, drive: impl Into<Drive>) -> Result<LawValue> {
        match self {
            SolvedLaw::Implicit(l) => l.evaluate(lambda, drive),
            SolvedLaw::Energy(l) => l.evaluate(lambda, drive),
        }
    }

    fn activation(&self, lambda: f64, drive: impl Into<Drive>) -> Result<f64> {
        match self {
            SolvedLaw::Implicit(l) => l.activation(lambda, drive),
            SolvedLaw::Energy(l) => l.activation(lambda, drive),
        }
    }
}

/// One piece: γ on [lo, lo + h] as the quintic Hermite interpolant of the module docs.
#[derive(Debug, Clone, Copy)]
struct Piece {
    lo: f64,
    /// 1/h.
    inv_width: f64,
    /// c₀ … c₅.
    c: [f64; 6],
}

impl Piece {
    /// The quintic through the exact data `a` at `lo` and `b` at `hi`.
    fn hermite(lo: f64, hi: f64, a: &LawValue, b: &LawValue) -> Self {
        let h = hi - lo;
        let (d0, d1) = (h * a.slope, h * b.slope);
        let (s0, s1) = (h * h * a.curvature, h * h * b.curvature);
        let big_a = b.gamma - a.gamma - d0 - 0.5 * s0;
        let big_b = d1 - d0 - s0;
        let big_c = s1 - s0;
        Self {
            lo,
            inv_width: 1.0 / h,
            c: [
                a.gamma,
                d0,
                0.5 * s0,
                10.0 * big_a - 4.0 * big_b + 0.5 * big_c,
                -15.0 * big_a + 7.0 * big_b - big_c,
                6.0 * big_a - 3.0 * big_b + 0.5 * big_c,
            ],
        }
    }

    /// γ, γ′ and γ″ of the piece at `lambda` (Horner); a negative γ is returned as 0.
    #[inline]
    fn evaluate(&self, lambda: f64) -> LawValue {
        let t = (lambda - self.lo) * self.inv_width;
        let c = &self.c;
        let p = ((((c[5] * t + c[4]) * t + c[3]) * t + c[2]) * t + c[1]) * t + c[0];
        let dp = (((5.0 * c[5] * t + 4.0 * c[4]) * t + 3.0 * c[3]) * t + 2.0 * c[2]) * t + c[1];
        let ddp = ((20.0 * c[5] * t + 12.0 * c[4]) * t + 6.0 * c[3]) * t + 2.0 * c[2];
        LawValue {
            gamma: p.max(0.0),
            slope: dp * self.inv_width,
            curvature: ddp * self.inv_width * self.inv_width,
        }
    }
}

/// What a table's build measured: its size, its cost and its errors against the exact law at
/// the check points (points not used to build it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TableReport {
    /// Damage d the table holds.
    pub damage: f64,
    /// Polynomial pieces.
    pub pieces: usize,
    /// Memory of the table's pieces and breakpoints \[bytes\].
    pub bytes: usize,
    /// Wall time of the build, checks included \[s\].
    pub build_seconds: f64,
    /// Exact solves (with derivatives) at piece ends.
    pub solves: usize,
    /// Points at which the kept pieces were checked against the exact law.
    pub checked_points: usize,
    /// Largest |γ_table − γ_exact| at the check points.
    pub gamma_error: f64,
    /// Largest error of the frozen model's fibre stress ∂Ŵ/∂λ \[kPa\].
    pub frozen_stress_error: f64,
    /// Largest error of the consistent model's fibre stress ∂Ŵ/∂λ + ∂Ŵ/∂γ γ′ \[kPa\].
    pub consistent_stress_error: f64,
    /// Largest |γ′_table − γ′_exact| (reported, not a build criterion).
    pub slope_error: f64,
    /// Largest |γ″_table − γ″_exact| (reported, not a build criterion).
    pub curvature_error: f64,
    /// Stretch intervals left to the exact solve inside the table's range: pieces whose error
    /// did not fall below the tolerances by bisection (the exact law's own rounding is larger
    /// there), see [`TabulatedLaw::new`].
    pub exact_intervals: usize,
    /// Their total width [-].
    pub exact_width: f64,
}

/// Errors at one check point, against the exact law.
#[derive(Debug, Clone, Copy, Default)]
struct PointErrors {
    /// Largest stress error over its tolerance at the point (≤ 1 passes).
    stress_ratio: f64,
    gamma: f64,
    frozen: f64,
    consistent: f64,
    slope: f64,
    curvature: f64,
}

impl PointErrors {
    fn max(self, o: Self) -> Self {
        Self {
            stress_ratio: self.stress_ratio.max(o.stress_ratio),
            gamma: self.gamma.max(o.gamma),
            frozen: self.frozen.max(o.frozen),
            consistent: self.consistent.max(o.consistent),
            slope: self.slope.max(o.slope),
            curvature: self.curvature.max(o.curvature),
        }
    }
}

/// The table of one damage: pieces sorted by λ, their upper ends in `breaks`.
#[derive(Debug, Clone)]
struct Table {
    damage: f64,
    lo: f64,
    hi: f64,
    /// γ = 0 at and below this stretch without a table (−∞ if the law has no such rule).
    zero_up_to: f64,
    breaks: Vec<f64>,
    pieces: Vec<Piece>,
    report: TableReport,
}

impl Table {
    /// The tabulated value, or `None` outside the table (then the exact law answers).
    #[inline]
    fn evaluate(&self, lambda: f64) -> Option<LawValue> {
        if !(lambda >= self.lo && lambda <= self.hi) {
            return None;
        }
        if lambda <= self.zero_up_to {
            return Some(LawValue::default());
        }
        let i = self.breaks.partition_point(|&b| b < lambda);
        // Between two pieces (an interval left to the exact solve): None.
        self.pieces
            .get(i)
            .filter(|p| lambda >= p.lo)
            .map(|p| p.evaluate(lambda))
    }
}

/// An implicit or energy law tabulated for some damages (see the module docs).
#[derive(Clone)]
pub struct TabulatedLaw<E> {
    pub(super) exact: SolvedLaw<E>,
    spec: TableSpec,
    tables: Arc<[Table]>,
}

impl<E> fmt::Debug for TabulatedLaw<E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("TabulatedLaw")
            .field("spec", &self.spec)
            .field(
                "tables",
                &self.tables.iter().map(|t| t.report).collect::<Vec<_>>(),
            )
            .finish_non_exhaustive()
    }
}

impl<E: StrainEnergy> TabulatedLaw<E> {
    /// Tabulates `exact` for each damage in `damages` over the spec's range, checking every
    /// piece against the exact law (module docs); where no piece meets the tolerances the
    /// exact law answers ([`TableReport::exact_intervals`]). Errors if the spec is invalid, a
    /// damage lies outside [0, 1], or the exact law fails inside the range.
    pub fn new(exact: SolvedLaw<E>, damages: &[f64], spec: TableSpec) -> Result<Self> {
        spec.validate()?;
        let mut tables: Vec<Table> = Vec::with_capacity(damages.len());
        for &d in damages {
            crate::active::drive::check_damage(d)?;
            if !tables.iter().any(|t| t.damage == d) {
                tables.push(build(&exact, d, &spec)?);
            }
        }
        Ok(Self {
            exact,
            spec,
            tables: tables.into(),
        })
    }

    /// The exact law the table replaces.
    pub fn exact(&self) -> &SolvedLaw<E> {
        &self.exact
    }

    /// The range and tolerances.
    pub fn spec(&self) -> &TableSpec {
        &self.spec
    }

    /// What each table's build measured, in the order of the damages given.
    pub fn reports(&self) -> Vec<TableReport> {
        self.tables.iter().map(|t| t.report).collect()
    }

    fn table(&self, damage: f64) -> Option<&Table> {
        self.tables.iter().find(|t| t.damage == damage)
    }

    /// The table of a quasi-static drive's effective damage, if there is one.
    fn table_of(&self, drive: &Drive) -> Option<&Table> {
        drive.table_damage().and_then(|d| self.table(d))
    }

    /// The 0D measurement of the table of `damage` against the exact law at `stretches`: the
    /// largest errors (γ, frozen and consistent fibre stress) and the time per evaluation of
    /// each (γ, γ′, γ″; the smallest of `repeats` passes over all stretches), with the build's
    /// report. Errors if `damage` has no table, or if the exact law fails at a stretch.
    pub fn compare(
        &self,
        damage: f64,
        stretches: &[f64],
        repeats: usize,
    ) -> Result<TableComparison> {
        let table = self.table(damage).ok_or(Error::InvalidParameter {
            name: "damage",
            value: damage,
            rule: "must be one of the damages the law was tabulated for",
        })?;
        let mut worst = PointErrors::default();
        for &l in stretches {
            worst = worst.max(errors_at(
                &self.exact,
                damage,
                l,
                self.evaluate(l, damage)?,
                &self.spec,
            )?);
        }
        let time = |law: &dyn Fn(f64) -> Result<LawValue>| -> Result<f64> {
            let mut best = f64::INFINITY;
            for _ in 0..repeats.max(1) {
                let start = Instant::now();
                for &l in stretches {
                    std::hint::black_box(law(std::hint::black_box(l))?);
                }
                best = best.min(start.elapsed().as_secs_f64());
            }
            Ok(best / stretches.len().max(1) as f64)
        };
        Ok(TableComparison {
            report: table.report,
            gamma_error: worst.gamma,
            frozen_stress_error: worst.frozen,
            consistent_stress_error: worst.consistent,
            exact_seconds: time(&|l| self.exact.evaluate(l, damage))?,
            table_seconds: time(&|l| self.evaluate(l, damage))?,
        })
    }
}

/// A tabulated law against its exact law in 0D ([`TabulatedLaw::compare`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TableComparison {
    /// The build's report (pieces, memory, build time, errors at the check points).
    pub report: TableReport,
    /// Largest |γ_table − γ_exact| at the stretches compared.
    pub gamma_error: f64,
    /// Largest error of the frozen model's fibre stress \[kPa\].
    pub frozen_stress_error: f64,
    /// Largest error of the consistent model's fibre stress \[kPa\].
    pub consistent_stress_error: f64,
    /// Time per evaluation (γ, γ′, γ″) of the exact law \[s\].
    pub exact_seconds: f64,
    /// Time per evaluation of the table \[s\].
    pub table_seconds: f64,
}

impl<E: StrainEnergy> ActivationLaw for TabulatedLaw<E> {
    #[inline]
    fn evaluate(&self, lambda: f64, drive: impl Into<Drive>) -> Result<LawValue> {
        let drive = drive.into();
        match self.table_of(&drive).and_then(|t| t.evaluate(lambda)) {
            Some(v) => Ok(v),
            None => self.exact.evaluate(lambda, drive),
        }
    }

    #[inline]
    fn activation(&self, lambda: f64, drive: impl Into<Drive>) -> Result<f64> {
        let drive = drive.into();
        match self.table_of(&drive).and_then(|t| t.evaluate(lambda)) {
            Some(v) => Ok(v.gamma),
            None => self.exact.activation(lambda, drive),
        }
    }
}

/// The errors of `table` against `exact` at `lambda`.
fn errors_at<E: StrainEnergy>(
    exact: &SolvedLaw<E>,
    damage: f64,
    lambda: f64,
    table: LawValue,
    spec: &TableSpec,
) -> Result<PointErrors> {
    let reference = exact.evaluate(lambda, damage)?;
    let energy = exact.energy();
    let [p_t, w_g_t, _] = super::fibre_path_derivatives(energy, exact.map(), lambda, table.gamma);
    let [p_e, w_g_e, _] =
        super::fibre_path_derivatives(energy, exact.map(), lambda, reference.gamma);
    let (consistent_t, consistent_e) = (p_t + w_g_t * table.slope, p_e + w_g_e * reference.slope);
    let (frozen, consistent) = ((p_t - p_e).abs(), (consistent_t - consistent_e).abs());
    let allowed = |p: f64| spec.stress_tolerance + spec.relative_stress_tolerance * p.abs();
    let e = PointErrors {
        stress_ratio: (frozen / allowed(p_e)).max(consistent / allowed(consistent_e)),
        gamma: (table.gamma - reference.gamma).abs(),
        frozen,
        consistent,
        slope: (table.slope - reference.slope).abs(),
        curvature: (table.curvature - reference.curvature).abs(),
    };
    if [e.gamma, e.frozen, e.consistent]
        .iter()
        .all(|x| x.is_finite())
    {
        Ok(e)
    } else {
        Err(Error::NonFinite {
            quantity: "tabulated law error",
            value: e.frozen + e.consistent + e.gamma,
            context: format!(
                "at lambda = {}, d = {} (exp overflow in the range?)",
                crate::text::shortest(lambda),
                crate::text::shortest(damage)
            ),
        })
    }
}

/// 5-point Gauss–Legendre nodes (on [−1, 1]) and weights.
const GAUSS_5: [(f64, f64); 5] = [
    (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
    (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.0, 0.568_888_888_888_888_9),
    (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.906_179_845_938_664, 0.236_926_885_056_189_1),
];

/// A piece the partition kept: its ends, the solved data there and ∫γ′ over it.
#[derive(Debug, Clone, Copy)]
struct Kept {
    lo: f64,
    hi: f64,
    at_lo: LawValue,
    at_hi: LawValue,
    rise: f64,
}

/// Builds and checks the table of one damage (module docs): partition, node values, final check.
fn build<E: StrainEnergy>(exact: &SolvedLaw<E>, damage: f64, spec: &TableSpec) -> Result<Table> {
    let start = Instant::now();
    let lmin = exact.lambda_min();
    let zero_below = exact.zero_below_minimum();
    let zero_up_to = if zero_below { lmin } else { f64::NEG_INFINITY };
    let mut builder = Builder {
        exact,
        branch: exact.continuous_branch(),
        damage,
        spec,
        zero_up_to,
        solves: 0,
    };
    // Intervals left to the exact solve.
    let mut exact_left: Vec<(f64, f64)> = Vec::new();
    // The smooth segments: λ_min is always an end.
    let mut segments = Vec::new();
    if spec.lambda_lo < lmin && !zero_below {
        segments.push((spec.lambda_lo, spec.lambda_hi.min(lmin)));
    }
    if spec.lambda_hi > lmin {
        segments.push((spec.lambda_lo.max(lmin), spec.lambda_hi));
    }
    let mut kept: Vec<Kept> = Vec::new();
    for (a, b) in segments {
        builder.partition(a, b, &mut kept, &mut exact_left)?;
    }
    let values = node_values(&kept);
    let (worst, breaks, pieces) = builder.final_pieces(&kept, &values, &mut exact_left)?;
    let report = TableReport {
        damage,
        pieces: pieces.len(),
        bytes: pieces.len() * std::mem::size_of::<Piece>()
            + breaks.len() * std::mem::size_of::<f64>(),
        build_seconds: start.elapsed().as_secs_f64(),
        solves: builder.solves,
        checked_points: 3 * pieces.len(),
        gamma_error: worst.gamma,
        frozen_stress_error: worst.frozen,
        consistent_stress_error: worst.consistent,
        slope_error: worst.slope,
        curvature_error: worst.curvature,
        exact_intervals: merged(&mut exact_left).len(),
        exact_width: exact_left.iter().fold(0.0, |w, (lo, hi)| w + (hi - lo)),
    };
    Ok(Table {
        damage,
        lo: spec.lambda_lo,
        hi: spec.lambda_hi,
        zero_up_to,
        breaks,
        pieces,
        report,
    })
}

/// The build of one damage's table: the exact law, the range and tolerances, and the exact
/// solves spent so far.
struct Builder<'a, E> {
    exact: &'a SolvedLaw<E>,
    /// The data: the root branch the pieces follow (for the energy law that jumps, its
    /// continuous variant, whose value at λ_min is the limit from above).
    branch: SolvedLaw<E>,
    damage: f64,
    spec: &'a TableSpec,
    /// γ = 0 at and below this stretch without a table (−∞ if the law has no such rule).
    zero_up_to: f64,
    /// Exact solves at piece ends and quadrature nodes.
    solves: usize,
}

impl<E: StrainEnergy> Builder<'_, E> {
    /// The solved value at `l`, counted.
    fn node(&mut self, l: f64) -> Result<LawValue> {
        self.solves += 1;
        self.branch.evaluate(l, self.damage)
    }

    /// ∫γ′ over [lo, hi] by 5-point Gauss–Legendre.
    fn rise(&mut self, lo: f64, hi: f64) -> Result<f64> {
        let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        GAUSS_5.iter().try_fold(0.0, |sum, &(x, w)| {
            Ok::<_, Error>(sum + w * half * self.node(mid + half * x)?.slope)
        })
    }

    /// The worst errors of `piece` at ¼, ½ and ¾ of [lo, hi].
    fn check(&self, piece: &Piece, lo: f64, hi: f64) -> Result<PointErrors> {
        [0.25, 0.5, 0.75]
            .iter()
            .try_fold(PointErrors::default(), |worst, t| {
                let l = lo + t * (hi - lo);
                // The table's own rule decides at and below λ_min.
                let value = if l <= self.zero_up_to {
                    LawValue::default()
                } else {
                    piece.evaluate(l)
                };
                Ok(worst.max(errors_at(self.exact, self.damage, l, value, self.spec)?))
            })
    }

    /// Whether `e` meets the tolerances times `margin` (the partition keeps a margin for the
    /// node values' final adjustment, step 2).
    fn fits(&self, e: &PointErrors, margin: f64) -> bool {
        e.gamma <= margin * self.spec.gamma_tolerance && e.stress_ratio <= margin
    }

    /// How far a piece misses the tolerances (≤ 1 meets them).
    fn badness(&self, e: &PointErrors) -> f64 {
        (e.gamma / self.spec.gamma_tolerance).max(e.stress_ratio)
    }

    /// 1. Partition of the smooth segment [a, b]: bisect until each piece, with its right value
    ///    γ(lo) + ∫γ′, meets the tolerances at its check points. Pieces kept are appended to
    ///    `kept` in order of λ; those bisection cannot bring under the tolerances, to
    ///    `exact_left`.
    fn partition(
        &mut self,
        a: f64,
        b: f64,
        kept: &mut Vec<Kept>,
        exact_left: &mut Vec<(f64, f64)>,
    ) -> Result<()> {
        let n = ((b - a) / INITIAL_WIDTH).ceil().max(1.0) as usize;
        let ends: Vec<f64> = (0..=n)
            .map(|i| {
                if i == n {
                    b
                } else {
                    a + (b - a) * i as f64 / n as f64
                }
            })
            .collect();
        let values = ends
            .iter()
            .map(|&l| self.node(l))
            .collect::<Result<Vec<_>>>()?;
        // Pieces still to check, the leftmost on top (so that kept pieces come out sorted).
        let mut todo: Vec<_> = (0..n)
            .rev()
            .map(|i| {
                (
                    ends[i],
                    ends[i + 1],
                    values[i],
                    values[i + 1],
                    f64::INFINITY,
                )
            })
            .collect();
        while let Some((lo, hi, at_lo, at_hi, parent)) = todo.pop() {
            let r = self.rise(lo, hi)?;
            let right = LawValue {
                gamma: at_lo.gamma + r,
                ..at_hi
            };
            let errors = self.check(&Piece::hermite(lo, hi, &at_lo, &right), lo, hi)?;
            if self.fits(&errors, PARTITION_MARGIN) {
                kept.push(Kept {
                    lo,
                    hi,
                    at_lo,
                    at_hi,
                    rise: r,
                });
            } else {
                let miss = self.badness(&errors);
                let stalled = hi - lo < STALL_WIDTH && miss * STALL_FACTOR > parent;
                if stalled || hi - lo <= 2.0 * MIN_WIDTH {
                    exact_left.push((lo, hi));
                } else {
                    let mid = 0.5 * (lo + hi);
                    let at_mid = self.node(mid)?;
                    todo.push((mid, hi, at_mid, at_hi, miss));
                    todo.push((lo, mid, at_lo, at_mid, miss));
                }
            }
        }
        Ok(())
    }

    /// 3. The final pieces, checked again with their final node values: the worst errors of
    ///    those kept, their upper ends and the pieces. One that fails goes to `exact_left`.
    fn final_pieces(
        &self,
        kept: &[Kept],
        values: &[(LawValue, LawValue)],
        exact_left: &mut Vec<(f64, f64)>,
    ) -> Result<(PointErrors, Vec<f64>, Vec<Piece>)> {
        let mut worst = PointErrors::default();
        let (mut breaks, mut pieces) = (Vec::new(), Vec::new());
        for (k, (left, right)) in kept.iter().zip(values) {
            let piece = Piece::hermite(k.lo, k.hi, left, right);
            let errors = self.check(&piece, k.lo, k.hi)?;
            if !self.fits(&errors, FINAL_MARGIN) {
                exact_left.push((k.lo, k.hi));
                continue;
            }
            worst = worst.max(errors);
            breaks.push(k.hi);
            pieces.push(piece);
        }
        Ok((worst, breaks, pieces))
    }
}

/// 2. Node values (left, right) of each kept piece, along each chain of adjacent pieces.
fn node_values(kept: &[Kept]) -> Vec<(LawValue, LawValue)> {
    let mut values = Vec::with_capacity(kept.len() + 1);
    let mut first = 0;
    while first < kept.len() {
        let mut last = first;
        while last + 1 < kept.len() && kept[last + 1].lo == kept[last].hi {
            last += 1;
        }
        chain_values(&kept[first..=last], &mut values);
        first = last + 1;
    }
    values
}

/// The node values of one chain of adjacent pieces, appended to `values`: the running sum S of
/// the rises, plus the straight line c₀ + c₁ (λ − λ₀) that fits the solved values best (least
/// squares).
fn chain_values(chain: &[Kept], values: &mut Vec<(LawValue, LawValue)>) {
    let lambdas: Vec<f64> = std::iter::once(chain[0].lo)
        .chain(chain.iter().map(|k| k.hi))
        .collect();
    let solved: Vec<f64> = std::iter::once(chain[0].at_lo.gamma)
        .chain(chain.iter().map(|k| k.at_hi.gamma))
        .collect();
    let sums: Vec<f64> = std::iter::once(0.0)
        .chain(chain.iter().scan(0.0, |s, k| {
            *s += k.rise;
            Some(*s)
        }))
        .collect();
    let (c0, c1) = straight_line(&lambdas, &solved, &sums);
    for (k, piece) in chain.iter().enumerate() {
        let at = |i: usize, v: &LawValue| LawValue {
            gamma: sums[i] + c0 + c1 * (lambdas[i] - lambdas[0]),
            ..*v
        };
        values.push((at(k, &piece.at_lo), at(k + 1, &piece.at_hi)));
    }
}

/// `intervals` sorted, and those that touch joined.
fn merged(intervals: &mut [(f64, f64)]) -> Vec<(f64, f64)> {
    intervals.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<(f64, f64)> = Vec::new();
    for &(lo, hi) in intervals.iter() {
        match out.last_mut() {
            Some(last) if lo <= last.1 => last.1 = last.1.max(hi),
            _ => out.push((lo, hi)),
        }
    }
    out
}

/// (c₀, c₁) minimising ∫ (y − s − c₀ − c₁ (x − x₀))² dx over the chain, the integral by the
/// trapezoidal rule on its nodes x: each node weighs half its two pieces' widths, so that the
/// nodes crowded where the law is steep (and its solved values least accurate) do not dominate.
/// The differences y − s are taken relative to the first one before they are averaged: they
/// differ by ≈ 1e-15, and averaging them whole (≈ 0.2) would cost more than that in rounding.
fn straight_line(x: &[f64], y: &[f64], s: &[f64]) -> (f64, f64) {
    let n = x.len();
    let weight = |i: usize| 0.5 * (x[(i + 1).min(n - 1)] - x[i.saturating_sub(1)]);
    let total: f64 = (0..n).map(weight).sum();
    let u = |i: usize| x[i] - x[0];
    let r = |i: usize| (y[i] - s[i]) - (y[0] - s[0]);
    let mean = |f: &dyn Fn(usize) -> f64| (0..n).map(|i| weight(i) * f(i)).sum::<f64>() / total;
    let (mu, mr) = (mean(&u), mean(&r));
    let suu = mean(&|i| (u(i) - mu) * (u(i) - mu));
    let sur = mean(&|i| (u(i) - mu) * (r(i) - mr));
    let c1 = if suu > 0.0 { sur / suu } else { 0.0 };
    (y[0] - s[0] + (mr - c1 * mu), c1)
}
