//! The measuring machinery: wall time, curve errors, speed-up, error ratio and the Pareto front.
//!
//! Nothing here knows what is being measured; [`super::groups`] feeds it.

use crate::text::{cell, ratio};
use std::time::Instant;

/// Every variant runs at least this many times.
pub const MIN_RUNS: usize = 3;
/// Runs continue until at least this much time has been spent \[s\] (and ≥ [`MIN_RUNS`] runs):
/// cheap variants are repeated more, expensive ones [`MIN_RUNS`] times.
pub const REPEAT_BUDGET: f64 = 0.3;
/// At most this many runs of a cheap variant.
pub const MAX_REPEATS: usize = 10_000;
/// The smallest ratio of two median times reported as a difference (see
/// [`Timing::speedup_over`]).
pub const MEASURABLE: f64 = 1.1;

/// The wall times of repeated runs of the same work \[s\]: their median and their spread, the
/// 10th to 90th percentile (nearest rank: the minimum to the maximum for fewer than 10 runs), so
/// that one run slowed by the machine neither moves the median nor widens the spread of many.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Timing {
    /// Median \[s\].
    pub median: f64,
    /// Lower end of the spread \[s\].
    pub low: f64,
    /// Upper end of the spread \[s\].
    pub high: f64,
    /// Number of runs.
    pub runs: usize,
}

impl Timing {
    /// One run of `t` seconds (no spread).
    pub fn once(t: f64) -> Self {
        Self {
            median: t,
            low: t,
            high: t,
            runs: 1,
        }
    }

    /// Of the times of `runs` (sorted in place); NaN entries for none.
    pub fn of(runs: &mut [f64]) -> Self {
        if runs.is_empty() {
            return Self {
                runs: 0,
                ..Self::once(f64::NAN)
            };
        }
        let median = median(runs);
        let rank = |q: f64| runs[((runs.len() - 1) as f64 * q).round() as usize];
        Self {
            median,
            low: rank(0.1),
            high: rank(0.9),
            runs: runs.len(),
        }
    }

    /// This time divided by `per`: the time of one of `per` equal pieces of the work.
    pub fn per(self, per: usize) -> Self {
        let n = per as f64;
        Self {
            median: self.median / n,
            low: self.low / n,
            high: self.high / n,
            ..self
        }
    }

    /// How many times faster this is than `other` (> 1 faster, < 1 slower), measured: only if
    /// both ran more than once, their spreads do not overlap and their medians differ by at
    /// least [`MEASURABLE`]; `None`: no measurable difference.
    ///
    /// Both conditions matter. Three runs each of the same work have disjoint min–max ranges
    /// with probability 2 · 3! 3! / 6! = 10 %, and the variants run one after the other, so a
    /// machine whose load drifts between them shifts one whole spread.
    pub fn speedup_over(&self, other: &Timing) -> Option<f64> {
        let separate = self.high < other.low || other.high < self.low;
        let ratio = other.median / self.median;
        let large = ratio >= MEASURABLE || ratio <= 1.0 / MEASURABLE;
        (self.runs > 1 && other.runs > 1 && separate && large).then_some(ratio)
    }

    /// `1.49e-1 s (1.45e-1–1.55e-1, 3 runs)`.
    pub fn text(&self) -> String {
        if self.runs == 1 {
            format!("{} s (1 run)", cell(Some(self.median), 2))
        } else {
            format!(
                "{} s ({}–{}, {} runs)",
                cell(Some(self.median), 2),
                cell(Some(self.low), 2),
                cell(Some(self.high), 2),
                self.runs
            )
        }
    }

    /// `3.9× faster than the implicit law (…; …)`, `1.3× slower than …`, or `no measurable
    /// difference in time from …`, with both timings.
    pub fn against(&self, other: &Timing, other_name: &str) -> String {
        let verdict = match self.speedup_over(other) {
            Some(x) if x >= 1.0 => format!("{}× faster than {other_name}", ratio(x)),
            Some(x) => format!("{}× slower than {other_name}", ratio(1.0 / x)),
            // Why not, so that two medians far apart are not read as equal.
            None if self.runs <= 1 || other.runs <= 1 => {
                format!("not timed against {other_name} (one of them ran once)")
            }
            None if self.high >= other.low && other.high >= self.low => format!(
                "no measurable difference in time from {other_name} (the runs' spreads overlap)"
            ),
            None => format!(
                "no measurable difference in time from {other_name} (the medians within {}×)",
                ratio(MEASURABLE)
            ),
        };
        format!("{verdict} ({} against {})", self.text(), other.text())
    }
}

/// Wall times of `f` and its (last) value: at least [`MIN_RUNS`] runs, more for cheap work
/// (until [`REPEAT_BUDGET`] seconds in all, at most [`MAX_REPEATS`] runs). `f` must do the same
/// work on every call.
pub fn time_median<T, E>(f: impl FnMut() -> Result<T, E>) -> Result<(Timing, T), E> {
    time_runs(f, |_| true)
}

/// As [`time_median`], but a first value that `again` rejects (a failed run, whose time
/// compares with nothing) is not repeated.
pub fn time_runs<T, E>(
    mut f: impl FnMut() -> Result<T, E>,
    again: impl Fn(&T) -> bool,
) -> Result<(Timing, T), E> {
    let t0 = Instant::now();
    let mut value = f()?;
    let first = t0.elapsed().as_secs_f64();
    if !again(&value) {
        return Ok((Timing::once(first), value));
    }
    let mut times = vec![first];
    let mut total = first;
    while times.len() < MIN_RUNS || (total < REPEAT_BUDGET && times.len() < MAX_REPEATS) {
        let t = Instant::now();
        value = f()?;
        let dt = t.elapsed().as_secs_f64();
        times.push(dt);
        total += dt;
    }
    Ok((Timing::of(&mut times), value))
}

/// Median of `v` (sorted in place); NaN for an empty slice.
pub fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Error of a curve against a reference curve sampled at the same points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveError {
    /// max_i |c_i − r_i| (units of the curve, e.g. kPa).
    pub max_abs: f64,
    /// max_i |c_i − r_i| / max(|r_i|, 10⁻³ max_j |r_j|) [-] (the floor keeps a zero crossing of
    /// the reference from dividing by zero).
    pub max_rel: f64,
}

impl CurveError {
    /// No error (the reference against itself).
    pub const ZERO: Self = Self {
        max_abs: 0.0,
        max_rel: 0.0,
    };
    /// A variant that produced no usable value (failed run, length mismatch).
    pub const FAILED: Self = Self {
        max_abs: f64::INFINITY,
        max_rel: f64::INFINITY,
    };
}

/// Max abs and max rel error of `candidate` against `reference` (same points, same order).
///
/// A length mismatch or a non-finite entry in `candidate` gives [`CurveError::FAILED`].
pub fn curve_error(reference: &[f64], candidate: &[f64]) -> CurveError {
    if reference.len() != candidate.len() || reference.is_empty() {
        return CurveError::FAILED;
    }
    let scale = reference.iter().fold(0.0f64, |m, r| m.max(r.abs()));
    let floor = 1e-3 * scale;
    let mut e = CurveError::ZERO;
    for (r, c) in reference.iter().zip(candidate) {
        if !c.is_finite() || !r.is_finite() {
            return CurveError::FAILED;
        }
        let d = (c - r).abs();
        e.max_abs = e.max_abs.max(d);
        let denom = r.abs().max(floor);
        if denom > 0.0 {
            e.max_rel = e.max_rel.max(d / denom);
        } else if d > 0.0 {
            e.max_rel = f64::INFINITY;
        }
    }
    e
}

/// Which of the points (time, error) are on the Pareto front: not dominated by any other point
/// (another point with time ≤ and error ≤, one of them strictly). Non-finite points never are;
/// equal points are both on the front.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<bool> {
    let finite = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite();
    points
        .iter()
        .map(|p| {
            finite(p)
                && !points
                    .iter()
                    .any(|q| finite(q) && q.0 <= p.0 && q.1 <= p.1 && (q.0 < p.0 || q.1 < p.1))
        })
        .collect()
}

/// One variant of one option, measured.
#[derive(Debug, Clone, PartialEq)]
pub struct Measurement {
    /// The option being traded (e.g. `activation law`).
    pub option: String,
    /// This variant (e.g. `explicit (frozen)`).
    pub variant: String,
    /// Whether this is the option's reference (the accurate end).
    pub reference: bool,
    /// Wall times of the runs \[s\].
    pub time: Timing,
    /// Error against the reference (absolute in the quantity's unit, and relative).
    pub error: CurveError,
    /// What `error` measures (e.g. `P(λ) over the sweep \[kPa\]`, `∂P/∂F at a point \[kPa\]`).
    pub quantity: String,
    /// Max abs error of γ over the sweep (0D) or of the centre γ (FE) [-], when meaningful.
    pub gamma_error: Option<f64>,
    /// Newton iterations of the whole sweep (FE).
    pub iterations: Option<usize>,
    /// Time per Newton iteration (assembly + factorisation + solve) \[s\] (FE).
    pub per_iteration_s: Option<f64>,
    /// Free dofs (FE).
    pub dofs: Option<usize>,
    /// Anything else the row must say (e.g. tangent error of a derivative route).
    pub note: String,
    /// Reference time / this time, of the medians (filled by [`finalise`]).
    pub speedup: f64,
    /// Whether the time differs measurably from the reference's ([`Timing::speedup_over`];
    /// filled by [`finalise`]).
    pub measurable: bool,
    /// This relative error / the smallest positive relative error among the option's
    /// non-reference variants (filled by [`finalise`]; NaN if there is none).
    pub error_ratio: f64,
    /// On the option's Pareto front of (time, relative error) (filled by [`finalise`]).
    pub pareto: bool,
}

impl Measurement {
    /// A row with the two axes; the rest empty.
    pub fn new(
        option: &str,
        variant: &str,
        reference: bool,
        time: Timing,
        quantity: &str,
        error: CurveError,
    ) -> Self {
        Self {
            option: option.to_string(),
            variant: variant.to_string(),
            reference,
            time,
            error,
            quantity: quantity.to_string(),
            gamma_error: None,
            iterations: None,
            per_iteration_s: None,
            dofs: None,
            note: String::new(),
            speedup: f64::NAN,
            measurable: false,
            error_ratio: f64::NAN,
            pareto: false,
        }
    }
}

/// Fills speed-up, error ratio and Pareto membership, option by option (rows of one option need
/// not be contiguous). An option without a reference row gets NaN speed-ups.
pub fn finalise(rows: &mut [Measurement]) {
    let mut options: Vec<String> = Vec::new();
    for r in rows.iter() {
        if !options.contains(&r.option) {
            options.push(r.option.clone());
        }
    }
    for option in options {
        let idx: Vec<usize> = (0..rows.len())
            .filter(|&i| rows[i].option == option)
            .collect();
        let reference = idx
            .iter()
            .find(|&&i| rows[i].reference)
            .map(|&i| rows[i].time);
        let t_ref = reference.map_or(f64::NAN, |t| t.median);
        let best = idx
            .iter()
            .filter(|&&i| !rows[i].reference)
            .map(|&i| rows[i].error.max_rel)
            .filter(|e| e.is_finite() && *e > 0.0)
            .fold(f64::INFINITY, f64::min);
        let points: Vec<(f64, f64)> = idx
            .iter()
            .map(|&i| (rows[i].time.median, rows[i].error.max_rel))
            .collect();
        let front = pareto_front(&points);
        for (k, &i) in idx.iter().enumerate() {
            let r = &mut rows[i];
            // A failed variant's time is the time to its failure: no speed-up.
            r.speedup = if r.error.max_abs.is_infinite() {
                f64::NAN
            } else {
                t_ref / r.time.median
            };
            r.measurable = reference.is_some_and(|t| r.time.speedup_over(&t).is_some());
            r.error_ratio = if best.is_finite() {
                r.error.max_rel / best
            } else {
                f64::NAN
            };
            r.pareto = front[k];
        }
    }
}

impl Measurement {
    /// The row of a variant that could not be computed: infinite error (`failed` in the
    /// tables), no time, `e` in the note.
    pub fn failed(option: &str, variant: &str, quantity: &str, e: &dyn std::fmt::Display) -> Self {
        let mut m = Self::new(
            option,
            variant,
            false,
            Timing::of(&mut []),
            quantity,
            CurveError {
                max_abs: f64::INFINITY,
                max_rel: f64::INFINITY,
            },
        );
        m.note = format!("failed: {e}");
        m
    }

    /// Whether the variant was measured: it ran and has an error. A failed one (or one whose
    /// reference failed everywhere) has an infinite error, is drawn nowhere and has no speed-up.
    pub fn measured(&self) -> bool {
        self.error.max_rel.is_finite()
    }

    /// The row in words, both axes with their numbers:
    /// `activation law (FE) · explicit (frozen): 5.4e-1 s (5.3e-1–5.6e-1, 3 runs), speed-up 1.06
    /// (no measurable difference), max abs error 2.7e0, max rel error 1.4e-1`.
    pub fn line(&self) -> String {
        use std::fmt::Write;
        let mut s = format!(
            "{} · {}{}: {}, speed-up {}{}, max abs error {}, max rel error {}",
            self.option,
            self.variant,
            if self.reference { " (reference)" } else { "" },
            self.time.text(),
            ratio(self.speedup),
            if self.reference || self.measurable {
                ""
            } else {
                " (no measurable difference)"
            },
            cell(Some(self.error.max_abs), 1),
            cell(Some(self.error.max_rel), 1),
        );
        if let Some(g) = self.gamma_error {
            let _ = write!(s, ", γ error {}", cell(Some(g), 1));
        }
        if self.pareto {
            s.push_str(", Pareto");
        }
        if !self.measured() && !self.note.is_empty() {
            let _ = write!(s, "; {}", self.note);
        }
        s
    }
}
