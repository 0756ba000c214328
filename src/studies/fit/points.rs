//! The fit kind's own table, `fit_points.csv` (and Python's): per fit, each datum with the fitted
//! model there, the residual and the scale it was divided by, then the fitted curve. What a reader
//! needs to judge a fit beside `fits.csv`'s numbers: where the residuals are, whether they are
//! noise or a shape the model misses.

use super::{CaseData, FitCase, FitKind, FitOutcome};
use crate::studies::table::Table;

/// One row: which fit, which stress, a datum or a point of the curve.
struct Row<'a> {
    fit: &'a FitOutcome,
    stress: String,
    kind: &'static str,
    lambda: f64,
    datum: Option<f64>,
    model: Option<f64>,
    residual: Option<f64>,
    sigma: Option<f64>,
}

/// The rows of one fit: data rows (residual i of stress k of the plot: i for one stress, 2i + k
/// for the two of biaxial rows), then the fitted curve of each stress.
fn rows(f: &FitOutcome) -> Vec<Row<'_>> {
    let stride = f.plot.len().max(1);
    // The explicit-law fit's stress residuals are not in the unit of its plotted γ.
    let comparable = f.kind != FitKind::ExplicitLaw || f.unit == "-";
    let mut out = Vec::new();
    for (k, c) in f.plot.iter().enumerate() {
        let stress = if c.what.is_empty() {
            c.y_label.clone()
        } else {
            c.what.clone()
        };
        if c.data.len() * stride == f.residuals.len() {
            for (i, &(lambda, datum)) in c.data.iter().enumerate() {
                let r = f.residuals[i * stride + k];
                out.push(Row {
                    fit: f,
                    stress: stress.clone(),
                    kind: "data",
                    lambda,
                    datum: comparable.then_some(datum),
                    model: comparable.then_some(datum + r),
                    residual: Some(r),
                    sigma: f.sigma.as_ref().map(|s| s[i * stride + k]),
                });
            }
        }
        for &(lambda, model) in &c.fitted {
            out.push(Row {
                fit: f,
                stress: stress.clone(),
                kind: "curve",
                lambda,
                datum: None,
                model: Some(model),
                residual: None,
                sigma: None,
            });
        }
    }
    out
}

/// The rows [`points_table`] writes for `cases` (what a scene's size estimate counts): each
/// datum of each stress, and the fitted curve of each (201 stretches of a uniaxial case, the
/// rows of a biaxial one, whose two stresses each have a datum and a model per row).
pub fn rows_of(cases: &[FitCase]) -> usize {
    cases
        .iter()
        .map(|c| match &c.data {
            CaseData::Uniaxial(d) => d.len() + c.data.grid().len(),
            CaseData::Biaxial(b) => 4 * b.len(),
        })
        .sum()
}

/// The table of a fit study's outcomes.
pub fn points_table(study: &str, fits: &[FitOutcome]) -> Table {
    let rows: Vec<Row> = fits.iter().flat_map(rows).collect();
    let text = |f: &dyn Fn(&Row) -> String| rows.iter().map(|r| Some(f(r))).collect::<Vec<_>>();
    let number = |f: &dyn Fn(&Row) -> Option<f64>| rows.iter().map(f).collect::<Vec<_>>();
    Table::default()
        .text("study", "the study's name", text(&|_| study.to_string()))
        .text(
            "fit",
            "what was fitted (the fit kind)",
            text(&|r| r.fit.kind.name().into()),
        )
        .text(
            "case",
            "the data set or case fitted",
            text(&|r| r.fit.case.clone()),
        )
        .text(
            "stress",
            "which stress of the data (and its unit)",
            text(&|r| r.stress.clone()),
        )
        .text(
            "row",
            "data: a datum with the model there; curve: a point of the fitted curve",
            text(&|r| r.kind.into()),
        )
        .number(
            "lambda",
            "-",
            "stretch λ (biaxial rows: λ₁, along the fibres)",
            number(&|r| Some(r.lambda)),
        )
        .number(
            "data",
            "see unit",
            "the datum (data rows)",
            number(&|r| r.datum),
        )
        .number(
            "model",
            "see unit",
            "the fitted model at λ",
            number(&|r| r.model),
        )
        .number(
            "residual",
            "see unit",
            "model − datum (data rows)",
            number(&|r| r.residual),
        )
        .number(
            "sigma",
            "see unit",
            "the scale the residual was divided by in the fit (weighted fits)",
            number(&|r| r.sigma),
        )
        .text(
            "unit",
            "the unit of data, model, residual and sigma (kPa for stresses, - for γ)",
            text(&|r| r.fit.unit.into()),
        )
        .text(
            "weights",
            "how the residuals were weighted: equal, relative or sigma",
            text(&|r| r.fit.weights.name().into()),
        )
}
