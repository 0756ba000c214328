//! The trade-off kind's table, `tradeoff.csv`: one row per measured variant (its page and
//! figures are `output/tradeoff.rs`'s).

use super::{Measurement, TradeoffResults};
use crate::studies::outputs::{KindOutput, OwnTable};
use crate::studies::table::Table;

impl KindOutput for TradeoffResults {
    fn tables(&self, _study: &str) -> Vec<OwnTable> {
        vec![OwnTable::rows(
            "tradeoff.csv",
            "one row per measured variant of an option",
            table(&self.rows),
        )]
    }

    fn findings(&self) -> Vec<String> {
        self.findings.clone()
    }
}

/// `x` to seven significant digits, the precision a timing or an error ratio is measured to;
/// `None` if not finite (an error that does not exist because the variant failed, a ratio
/// without a reference).
fn seven(x: f64) -> Option<f64> {
    x.is_finite()
        .then(|| format!("{x:.6e}").parse().ok())
        .flatten()
}

/// The table of `tradeoff.csv`: times in s (the median of the runs and their spread, 10th to
/// 90th percentile; `time_differs`: measurably different from the reference's,
/// [`super::Timing::speedup_over`]); errors in the quantity's unit and relative; speed-up =
/// reference time / time, of the medians; error ratio = relative error / the option's smallest
/// positive non-reference relative error. Numbers to seven significant digits.
pub fn table(rows: &[Measurement]) -> Table {
    let words = |f: fn(&Measurement) -> &str| rows.iter().map(move |r| Some(f(r).to_string()));
    let flag = |f: fn(&Measurement) -> bool| rows.iter().map(move |r| Some(f(r)));
    let number =
        |f: fn(&Measurement) -> Option<f64>| rows.iter().map(move |r| f(r).and_then(seven));
    let count =
        |f: fn(&Measurement) -> Option<usize>| rows.iter().map(move |r| f(r).map(|n| n as i64));
    Table::default()
        .text("option", "the option traded (activation law, element, mesh, …)", words(|r| &r.option))
        .text("variant", "the option's variant", words(|r| &r.variant))
        .boolean("reference", "whether this variant is the option's reference", flag(|r| r.reference))
        .text("quantity", "what is compared with the reference, with its unit", words(|r| &r.quantity))
        .number("time_s", "s", "median time of the runs", number(|r| Some(r.time.median)))
        .number("time_low_s", "s", "10th percentile of the runs' times", number(|r| Some(r.time.low)))
        .number("time_high_s", "s", "90th percentile of the runs' times", number(|r| Some(r.time.high)))
        .integer("runs", "timed runs", count(|r| Some(r.time.runs)))
        .boolean("time_differs", "whether the time differs measurably from the reference's (spreads do not overlap)", flag(|r| r.measurable))
        .number("error_abs", "see quantity", "largest absolute difference from the reference, in the quantity's unit (empty: the variant failed)", number(|r| Some(r.error.max_abs)))
        .number("error_rel", "-", "largest relative difference from the reference (empty: the variant failed)", number(|r| Some(r.error.max_rel)))
        .number("gamma_error", "-", "largest |γ − γ_reference|", number(|r| r.gamma_error))
        .number("speedup", "-", "reference time / time (medians)", number(|r| Some(r.speedup)))
        .number("error_ratio", "-", "relative error / the option's smallest positive non-reference relative error (empty: none)", number(|r| Some(r.error_ratio)))
        .boolean("pareto", "whether on the option's Pareto front of (time, relative error)", flag(|r| r.pareto))
        .integer("newton_iterations", "Newton iterations of the FE sweep", count(|r| r.iterations))
        .number("time_per_iteration_s", "s", "time per Newton iteration", number(|r| r.per_iteration_s))
        .integer("dofs", "free degrees of freedom of the FE solve", count(|r| r.dofs))
        .text("note", "what else the measurement says (where the error is largest, why a variant did not converge)", words(|r| &r.note))
}
