//! The fit kind's figures (data, the fitted model, the model at the reference values), its
//! report table (values ± standard errors, or at a bound; correlations, RMS, weights,
//! convergence) and its own table, `fit_points.csv` ([`super::points`]).

use super::{correlations, FitCurves, FitKind, FitOutcome};
use crate::app_error::{finite, AppError};
use crate::plot::{Figure, Panel, Series, Stroke};
use crate::studies::outputs::{
    derived, each_study, figure, panel_over, prefixed, Context, KindOutput, Of, OwnTable,
};
use crate::studies::table::{every_row, Table};
use crate::text::escape_html as escape;
use std::fmt::Write;

impl KindOutput for Vec<FitOutcome> {
    /// Its rows of `fits.csv`, and of `fit_points.csv` (each datum with the fitted model and
    /// the residual, then the fitted curve).
    fn tables(&self, study: &str) -> Vec<OwnTable> {
        vec![
            OwnTable::rows(
                "fits.csv",
                "one row per fitted parameter",
                fits_table_of(study, self),
            ),
            OwnTable {
                key: "fit_points",
                file: "fit_points.csv".into(),
                rows_are: "one row per datum of a fit (with the fitted model there and the residual) and per point of its fitted curve",
                table: super::points::points_table(study, self),
            },
        ]
    }

    /// Each fitted value with its standard error (or its bound).
    fn console(&self, study: &str) -> Vec<String> {
        self.iter()
            .map(|f| format!("{study} — {}", f.summary()))
            .collect()
    }

    fn figures(studies: &[Of<Self>], _: &Context) -> Vec<Figure> {
        each_study(studies, |name, fits| fit_figure(name, fits))
    }

    fn report(studies: &[Of<Self>], _: &Context, h: &mut String) -> Result<(), AppError> {
        fits_table(h, studies)
    }
}

/// The approach whose model a fit of `kind` fits: the explicit law (eq. (14)) is active strain's;
/// the other fits are to the uniaxial target, which every approach reproduces.
fn approach(kind: FitKind) -> Option<String> {
    (kind == FitKind::ExplicitLaw).then(|| crate::active::Approach::ActiveStrain.name().into())
}

/// The table of `fits.csv` for the fits of `study`: one row per fitted parameter, its
/// correlations with the others in one readable cell (`w0: 0.99988`).
pub fn fits_table_of(study: &str, fits: &[FitOutcome]) -> Table {
    let rows: Vec<(&FitOutcome, usize)> = fits
        .iter()
        .flat_map(|f| (0..f.names.len()).map(move |j| (f, j)))
        .collect();
    let of = |f: fn(&FitOutcome, usize) -> Option<f64>| rows.iter().map(move |&(r, j)| f(r, j));
    let words = |f: fn(&FitOutcome, usize) -> String| rows.iter().map(move |&(r, j)| Some(f(r, j)));
    let unit = "the parameter's unit";
    Table::default()
        .text("study", "the study's name", every_row(study, rows.len()))
        .text("fit", "what was fitted (the fit kind)", words(|f, _| f.kind.name().into()))
        .text("case", "the data set or case fitted", words(|f, _| f.case.clone()))
        .text("parameter", "the fitted parameter's name", words(|f, j| f.names[j].clone()))
        .number("value", unit, "fitted value, in the parameter's own unit (kPa for moduli and stresses, - for exponents and fractions)", of(|f, j| Some(f.values[j])))
        .number("standard_error", unit, "standard error of the value from the Jacobian at the optimum (empty: not estimable)", of(|f, j| f.standard_errors.get(j).copied().flatten()))
        .number("reference", unit, "the chapter's (or the scene's) value for comparison (empty: none)", of(|f, j| f.reference.get(j).copied().flatten()))
        .text("correlation", "correlations with the other parameters, 'name: value; …' (n/a: not estimable)", words(correlation_cell))
        .boolean("converged", "whether the least-squares solver met its tolerance", rows.iter().map(|(f, _)| Some(f.converged)))
        .number("rms", "see rms_unit", "root-mean-square residual of the fit", of(|f, _| Some(f.rms)))
        .text("rms_unit", "the unit of rms (kPa for stresses)", words(|f, _| f.unit.into()))
        .number("residual_norm", "see rms_unit", "Euclidean norm of the residual vector", of(|f, _| Some(f.residual_norm)))
        .integer("iterations", "iterations of the least-squares solver", rows.iter().map(|(f, _)| Some(f.iterations as i64)))
        .integer("points", "data points fitted", rows.iter().map(|(f, _)| Some(f.points as i64)))
        .text("termination", "why the least-squares solver stopped", words(|f, _| f.termination.clone()))
        .text(
            "approach",
            "the activation approach whose law is fitted: active-strain for the explicit law (eq. (14)); empty: the fit does not depend on the approach (passive parameters, the active curve and the damage are fitted to the uniaxial target P_pas + (1 − d) P_act along the fibres, which every approach reproduces)",
            rows.iter().map(|(f, _)| approach(f.kind)),
        )
        .number("at_bound", unit, "the bound the parameter is held at, the least-squares minimum lying beyond it (empty: estimated inside its bounds)", of(|f, j| f.at_bound.get(j).copied().flatten().map(|b| b.bound)))
        .text("weights", "how the residuals were weighted: equal, relative (to the datum) or sigma (each datum's standard deviation)", words(|f, _| f.weights.name().into()))
}

/// The correlations of parameter `j` of `f` with the others, five decimals (`n/a` where not
/// estimable or not finite).
fn correlation_cell(f: &FitOutcome, j: usize) -> String {
    let number = |c: f64| {
        Ok(if c.is_finite() {
            format!("{c:.5}")
        } else {
            "n/a".into()
        })
    };
    f.correlation
        .get(j)
        .map(|row| correlations(row, &f.names, j, number).unwrap_or_default())
        .unwrap_or_default()
}

/// `Fit: chapter's energy …` for a study called `fit: chapter's energy …` or `chapter's energy …`.
fn fit_heading(study: &str) -> String {
    let rest = study
        .strip_prefix("fit:")
        .or_else(|| study.strip_prefix("Fit:"))
        .unwrap_or(study)
        .trim();
    format!("Fit: {rest}")
}

/// The figure of a fit study: data (markers), the fit (solid) and the model at the reference or
/// starting values (dashed). Damage fits share one panel; other fits get a panel per data set
/// and stress.
fn fit_figure(study: &str, fits: &[FitOutcome]) -> Option<Figure> {
    let first = fits.first()?;
    let panels = if first.kind == FitKind::Damage {
        vec![damage_panel(study, fits)]
    } else {
        fits.iter()
            .flat_map(|f| f.plot.iter().map(move |c| case_panel(study, f, c)))
            .collect()
    };
    let drawn = if fits.iter().flat_map(|f| &f.plot).any(|c| c.at_rows) {
        "Open markers: data; filled: the fitted model at each row of the data (λ₁ on the x axis, so rows of several load paths share it)."
    } else {
        "Markers: data; solid: the fitted model; dashed: the model at the reference values."
    };
    figure(
        &prefixed("fit", study),
        fit_heading(study),
        format!(
            "Least-squares fit ({}) to {}. {drawn}",
            first.kind.name(),
            first.source
        ),
        panels,
    )
}

/// The legend entry of a fit: `fit: d = 0.3012` (and NOT converged).
fn fit_status(f: &FitOutcome) -> String {
    let values: Vec<String> = f
        .names
        .iter()
        .zip(&f.values)
        .enumerate()
        .map(|(j, (n, v))| match f.at_bound.get(j).copied().flatten() {
            Some(b) => format!("{n} = {v:.4} (at its bound {})", b.bound),
            None => format!("{n} = {v:.4}"),
        })
        .collect();
    format!(
        "fit: {}{}",
        values.join(", "),
        if f.converged { "" } else { " (NOT converged)" }
    )
}

/// The model at the reference values of a case, if it has them.
fn reference_series(c: &FitCurves, stroke: Stroke, colour: usize) -> Option<Series> {
    c.start
        .as_ref()
        .and_then(|(label, points)| derived(label.clone(), points.clone(), stroke, colour))
}

/// Every damage fit in one panel, a colour per data set, with the healthy muscle dashed.
fn damage_panel(study: &str, fits: &[FitOutcome]) -> Option<Panel> {
    let mut s = Vec::new();
    for (i, (f, c)) in fits
        .iter()
        .filter_map(|f| Some((f, f.plot.first()?)))
        .enumerate()
    {
        s.push(derived(f.case.clone(), c.data.clone(), Stroke::Markers, i));
        s.push(derived(fit_status(f), c.fitted.clone(), Stroke::Solid, i));
    }
    let c = fits.first()?.plot.first()?;
    s.push(reference_series(c, Stroke::Dashed, 7));
    let data = fits.iter().filter_map(|f| f.plot.first());
    let data: Vec<f64> = data.flat_map(|c| c.data.iter().map(|q| q.1)).collect();
    panel_over(fit_heading(study), &c.x_label, &c.y_label, s).map(|p| with_data(p, &data))
}

/// `p` with its y axis widened, where it would cut them, to every `data` value: a fit's data
/// are what it is judged on (a passive fit's largest stresses are its most informative ones),
/// and only the model's curves may leave the frame.
fn with_data(mut p: Panel, data: &[f64]) -> Panel {
    let (y0, y1) = p.frame().y;
    let outside = data.iter().any(|v| v.is_finite() && (*v < y0 || *v > y1));
    if outside {
        p.y_range = whole_range(data.iter().copied().chain([y0, y1]));
    }
    p
}

/// The panel of one stress of one data set.
fn case_panel(study: &str, f: &FitOutcome, c: &FitCurves) -> Option<Panel> {
    // The model at the rows of a biaxial path, which may turn back: points, no line.
    let (fitted, reference) = if c.at_rows {
        (Stroke::Filled, Stroke::Dotted)
    } else {
        (Stroke::Solid, Stroke::Dashed)
    };
    let s = vec![
        derived(c.data_label.clone(), c.data.clone(), Stroke::Markers, 1),
        derived(fit_status(f), c.fitted.clone(), fitted, 0),
        reference_series(c, reference, 2).filter(|_| !c.at_rows),
    ];
    let what = if c.what.is_empty() {
        String::new()
    } else {
        format!(" — {}", c.what)
    };
    let panel = panel_over(
        format!("{}: {}{what}", fit_heading(study), f.case),
        &c.x_label,
        &c.y_label,
        s,
    );
    // Measured rows do not blow up: the axis shows them all, uncut.
    panel.map(|mut p| {
        if c.at_rows {
            p.y_range = whole_range(c.data.iter().chain(&c.fitted).map(|q| q.1));
        }
        let data: Vec<f64> = c.data.iter().map(|q| q.1).collect();
        with_data(p, &data)
    })
}

/// The range of `y` padded by 5 % each way (`None` if no value is finite or all are equal).
fn whole_range(y: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = y
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    let pad = 0.05 * (hi - lo);
    (hi > lo).then_some((lo - pad, hi + pad))
}

/// ` ± 1.2e-3`, ` at its bound 0 (the minimum lies beyond, at -0.03)` or ` ± (n/a)`: what the
/// report says of the estimate of parameter `j` of `f`.
fn error_cell(f: &FitOutcome, j: usize, origin: &dyn Fn() -> String) -> Result<String, AppError> {
    let held = f.at_bound.get(j).copied().flatten();
    Ok(match (held, f.standard_errors.get(j).copied().flatten()) {
        (Some(b), _) => format!(
            " <b>at its bound</b> {} (the minimum lies beyond, at {})",
            crate::text::shortest(b.bound),
            crate::text::significant(b.beyond, 6)
        ),
        (None, Some(s)) => format!(" ± {:.3e}", finite(s, "standard error", origin)?),
        (None, None) => " ± (n/a)".into(),
    })
}

/// Converged or not (and why), the weights, the fit's further facts.
fn status_cell(f: &FitOutcome) -> String {
    let e = escape;
    let mut status = if f.converged {
        "converged".to_string()
    } else {
        format!("<b>NOT converged</b> ({})", e(&f.termination))
    };
    if f.weights != super::WeightsKind::Equal {
        status.push_str(&format!("<br>residuals weighted: {}", f.weights.name()));
    }
    for x in &f.extra {
        status.push_str(&format!("<br>{}", e(x)));
    }
    status
}

/// Parameters ± standard errors, reference values, correlation, RMS, iterations, convergence.
fn fits_table(h: &mut String, studies: &[Of<Vec<FitOutcome>>]) -> Result<(), AppError> {
    let studies: Vec<(&str, &[FitOutcome])> = studies
        .iter()
        .map(|s| (s.name, s.result.as_slice()))
        .collect();
    if studies.iter().all(|(_, f)| f.is_empty()) {
        return Ok(());
    }
    let e = escape;
    h.push_str("<h2>Fits</h2>\n<p>Least squares with dual-number Jacobians (<code>fits.csv</code> has the same numbers). Standard errors σ = √(s²(JᵀJ)⁻¹), of the weighted residuals where the fit weights them; a parameter <b>at its bound</b> is held there, the minimum lying beyond it (it has no standard error, the others are fitted with it held); a fit marked <b>NOT converged</b> shows the best point found, which is not a solution. Each datum with the fitted model and the residual, and the fitted curve, are in <code>fit_points.csv</code>.</p>\n<table><tr><th>study</th><th>data</th><th>parameter</th><th>value ± std. error</th><th>reference</th><th>correlation with the others</th><th>RMS</th><th>iterations</th><th>status</th></tr>\n");
    for (study, f) in studies
        .iter()
        .flat_map(|&(s, fits)| fits.iter().map(move |f| (s, f)))
    {
        let origin = || format!("report: fit {study:?}, {}", f.case);
        let n = f.names.len();
        for j in 0..n {
            let value = finite(f.values[j], "fitted value", origin)?;
            let se = error_cell(f, j, &origin)?;
            let reference = match f.reference.get(j).copied().flatten() {
                Some(r) => finite(r, "reference value", origin)?.to_string(),
                None => String::new(),
            };
            let corr = match f.correlation.get(j) {
                Some(row) => correlations(row, &f.names, j, |c| {
                    finite(c, "correlation", origin).map(|c| format!("{c:.4}"))
                })?,
                None => String::new(),
            };
            if j == 0 {
                let status = status_cell(f);
                // Biaxial rows give two stresses each.
                let points = if f.plot.iter().any(|c| c.at_rows) {
                    "rows of (P₁₁, P₂₂)"
                } else {
                    "points"
                };
                let _ = write!(
                    h,
                    "<tr><td rowspan=\"{n}\">{}</td><td rowspan=\"{n}\">{} ({} {points})</td>",
                    e(study),
                    e(&f.case),
                    f.points
                );
                let _ = writeln!(
                    h,
                    "<td>{}</td><td>{value:.6}{se}</td><td>{reference}</td><td>{}</td><td rowspan=\"{n}\">{:.3e} {}</td><td rowspan=\"{n}\">{}</td><td rowspan=\"{n}\">{status}</td></tr>",
                    e(&f.names[j]),
                    e(&corr),
                    finite(f.rms, "RMS error", origin)?,
                    f.unit,
                    f.iterations,
                );
            } else {
                let _ = writeln!(
                    h,
                    "<tr><td>{}</td><td>{value:.6}{se}</td><td>{reference}</td><td>{}</td></tr>",
                    e(&f.names[j]),
                    e(&corr),
                );
            }
        }
    }
    h.push_str("</table>\n");
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_headings_say_fit_once() {
        assert_eq!(
            fit_heading("fit: damage of weakened muscles"),
            "Fit: damage of weakened muscles"
        );
        assert_eq!(fit_heading("my damage"), "Fit: my damage");
    }
}
