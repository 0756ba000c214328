//! Safeguarded scalar root finding.

/// Iterations [`newton_bisection`] takes at most (bisection alone shrinks any bracket of f64
/// numbers to one ulp in fewer).
pub const MAX_ITERATIONS: usize = 200;

/// Root of `f` in [lo, hi] with f(lo) < 0 < f(hi), by Newton steps that fall back to bisection
/// whenever a step leaves the bracket or the derivative is unusable (rtsafe). `f` returns the
/// value and the derivative; a non-finite value shrinks the bracket from above. Converges when
/// the bracket or the step is below `xtol`; after [`MAX_ITERATIONS`] returns why it failed, with
/// the bracket and the last iterate.
pub fn newton_bisection(
    f: impl Fn(f64) -> (f64, f64),
    mut lo: f64,
    mut hi: f64,
    xtol: f64,
) -> Result<f64, String> {
    let mut x = 0.5 * (lo + hi);
    let mut fx = f64::NAN;
    for _ in 0..MAX_ITERATIONS {
        let dfx;
        (fx, dfx) = f(x);
        if fx == 0.0 {
            return Ok(x);
        }
        if !fx.is_finite() || fx > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        let newton = x - fx / dfx;
        let next = if fx.is_finite() && dfx.is_finite() && dfx != 0.0 && newton > lo && newton < hi
        {
            newton
        } else {
            0.5 * (lo + hi)
        };
        let converged = (next - x).abs() <= xtol || hi - lo <= xtol;
        x = next;
        if converged {
            return Ok(x);
        }
    }
    Err(format!(
        "no convergence in {MAX_ITERATIONS} iterations (bracket [{lo}, {hi}], next x = {x}, last residual {fx}, tolerance {xtol})"
    ))
}
