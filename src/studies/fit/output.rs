//! The fit kind's figures (data, the fitted model, the model at the reference values), its
//! report table (values ± standard errors, or at a bound; correlations, RMS, weights,
//! convergence) and its own table, `fit_points.csv` ([`super::points`]).

use super::{correlations, FitCurves, FitKind, FitOutcome};
use crate::app_error::{finite, AppError};
use crate::plot::{Figure, Panel, Series, Stroke};
use crate::studies::outputs::{
    derived, each_study, figure, panel_over, prefixed, Context, KindOutput, Of, OwnTable,
};
use crate::text::escape_html as escape;
use std::fmt::Write;

impl KindOutput for Vec<FitOutcome> {
    fn own_table(&self, study: &str) -> Option<OwnTable> {
        Some(OwnTable {
            file: "fit_points.csv",
            rows_are: "one row per datum of a fit (with the fitted model there and the residual) and per point of its fitted curve",
            table: super::points::points_table(study, self),
        })
    }

    fn figures(studies: &[Of<Self>], _: &Context) -> Vec<Figure> {
        each_study(studies, |name, fits| fit_figure(name, fits))
    }

    fn report(studies: &[Of<Self>], _: &Context, h: &mut String) -> Result<(), AppError> {
        fits_table(h, studies)
    }
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
    panel_over(fit_heading(study), &c.x_label, &c.y_label, s)
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
        p
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
