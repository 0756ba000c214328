//! The measuring machinery: wall time, curve errors, speed-up, error ratio and the Pareto front.
//!
//! Nothing here knows what is being measured; [`super::groups`] feeds it.

use std::time::Instant;

/// Runs shorter than this are repeated and their median is reported \[s\].
pub const SHORT_RUN: f64 = 1.0;
/// Repeated runs continue until at least this much time has been spent \[s\] (and ≥ 3 runs).
pub const REPEAT_BUDGET: f64 = 0.3;
/// At most this many repeats of a short run.
pub const MAX_REPEATS: usize = 10_000;

/// Wall time of `f` \[s\] and its (last) value.
///
/// A first run of `f` taking ≥ [`SHORT_RUN`] is reported as it is. A shorter one is repeated
/// until at least 3 runs and [`REPEAT_BUDGET`] seconds in total (at most [`MAX_REPEATS`] runs);
/// the median of the per-run times is reported. `f` must do the same work on every call.
pub fn time_median<T, E>(mut f: impl FnMut() -> Result<T, E>) -> Result<(f64, T), E> {
    let t0 = Instant::now();
    let mut value = f()?;
    let first = t0.elapsed().as_secs_f64();
    if first >= SHORT_RUN {
        return Ok((first, value));
    }
    let mut times = vec![first];
    let mut total = first;
    while times.len() < 3 || (total < REPEAT_BUDGET && times.len() < MAX_REPEATS) {
        let t = Instant::now();
        value = f()?;
        let dt = t.elapsed().as_secs_f64();
        times.push(dt);
        total += dt;
    }
    Ok((median(&mut times), value))
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
    /// Wall time \[s\] (median of repeats for short runs).
    pub time_s: f64,
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
    /// Reference time / this time (filled by [`finalise`]).
    pub speedup: f64,
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
        time_s: f64,
        quantity: &str,
        error: CurveError,
    ) -> Self {
        Self {
            option: option.to_string(),
            variant: variant.to_string(),
            reference,
            time_s,
            error,
            quantity: quantity.to_string(),
            gamma_error: None,
            iterations: None,
            per_iteration_s: None,
            dofs: None,
            note: String::new(),
            speedup: f64::NAN,
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
        let t_ref = idx
            .iter()
            .find(|&&i| rows[i].reference)
            .map_or(f64::NAN, |&i| rows[i].time_s);
        let best = idx
            .iter()
            .filter(|&&i| !rows[i].reference)
            .map(|&i| rows[i].error.max_rel)
            .filter(|e| e.is_finite() && *e > 0.0)
            .fold(f64::INFINITY, f64::min);
        let points: Vec<(f64, f64)> = idx
            .iter()
            .map(|&i| (rows[i].time_s, rows[i].error.max_rel))
            .collect();
        let front = pareto_front(&points);
        for (k, &i) in idx.iter().enumerate() {
            let r = &mut rows[i];
            r.speedup = t_ref / r.time_s;
            r.error_ratio = if best.is_finite() {
                r.error.max_rel / best
            } else {
                f64::NAN
            };
            r.pareto = front[k];
        }
    }
}

/// A ratio: fixed-point in [0.1, 1000), scientific outside.
pub fn ratio(x: f64) -> String {
    if (0.1..1000.0).contains(&x.abs()) {
        format!("{x:.2}")
    } else {
        cell(Some(x), 1)
    }
}

/// A number in scientific notation with `digits` digits; `failed` for an infinite error, `–`
/// for none.
pub fn cell(x: Option<f64>, digits: usize) -> String {
    match x {
        Some(v) if v.is_finite() => format!("{v:.digits$e}"),
        Some(v) if v.is_infinite() => "failed".into(),
        _ => "–".into(),
    }
}

impl Measurement {
    /// The row in words, both axes with their numbers:
    /// `activation law (FE) · explicit (frozen): 5.4e-1 s, speed-up 1.06, max abs error 2.7e0, max rel error 1.4e-1`.
    pub fn line(&self) -> String {
        use std::fmt::Write;
        let mut s = format!(
            "{} · {}{}: {} s, speed-up {}, max abs error {}, max rel error {}",
            self.option,
            self.variant,
            if self.reference { " (reference)" } else { "" },
            cell(Some(self.time_s), 2),
            ratio(self.speedup),
            cell(Some(self.error.max_abs), 1),
            cell(Some(self.error.max_rel), 1),
        );
        if let Some(g) = self.gamma_error {
            let _ = write!(s, ", γ error {}", cell(Some(g), 1));
        }
        if self.pareto {
            s.push_str(", Pareto");
        }
        s
    }
}
