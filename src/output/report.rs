//! `report.html`: one self-contained page (figures embedded as base64 PNG) with the run's
//! summary, the notes of studies that stopped, the figures, the scene and the versions.

use super::base64;
use super::csv::COLUMNS;
use super::plot::Rendered;
use crate::app_error::{finite, AppError};
use crate::scene::{Results, Scene};
use crate::studies::cylinder::bases_name;
use std::fmt::Write;
use std::time::Duration;

/// Facts about the run shown in the report.
#[derive(Debug, Clone)]
pub struct RunInfo {
    /// Command line.
    pub command: String,
    /// Wall time of the computation and the outputs.
    pub wall: Duration,
    /// Crate version.
    pub version: String,
    /// `rustc --version` on this machine, if available.
    pub rustc: Option<String>,
    /// Other files written (relative names).
    pub files: Vec<String>,
    /// Rows of `curves.csv`.
    pub rows: usize,
}

/// Escapes text for HTML.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The report page. `pngs` holds the PNG bytes of each figure, in the same order. A non-finite
/// number in a table is an error naming it, never written.
pub fn html(
    scene: &Scene,
    results: &Results,
    figures: &[Rendered],
    info: &RunInfo,
) -> Result<String, AppError> {
    let mut h = String::new();
    let e = escape;
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{}</title>\n<style>\
         body{{font-family:sans-serif;max-width:1000px;margin:2em auto;padding:0 1em;color:#222}}\
         table{{border-collapse:collapse;margin:1em 0}}td,th{{border:1px solid #ccc;padding:3px 8px;text-align:left;vertical-align:top}}\
         th{{background:#f2f2f2}}pre{{background:#f7f7f7;padding:1em;overflow-x:auto;font-size:85%}}\
         figure{{margin:2em 0}}img{{max-width:100%;border:1px solid #eee}}figcaption{{color:#444}}\
         .note{{background:#fff6e0;border-left:4px solid #e0a000;padding:.5em 1em;margin:.5em 0}}</style></head><body>\n",
        e(&scene.title)
    );
    let _ = writeln!(h, "<h1>{}</h1>", e(&scene.title));
    let _ = writeln!(
        h,
        "<p>activemuscle {} · {} · scene <code>{}</code> · wall time {:.1} s · <code>{}</code></p>",
        e(&info.version),
        e(info.rustc.as_deref().unwrap_or("rustc: unknown")),
        e(&scene.file),
        info.wall.as_secs_f64(),
        e(&info.command)
    );

    studies_table(&mut h, results);
    failures(&mut h, results);
    fe_table(&mut h, results)?;
    fits_table(&mut h, results)?;
    stability_table(&mut h, results)?;

    figures_and_data(&mut h, figures, info);
    h.push_str("<h2>Scene as resolved (every default written out)</h2>\n<pre>");
    h.push_str(&e(&scene
        .resolved_toml()
        .unwrap_or_else(|err| format!("(cannot print: {err})"))));
    h.push_str("</pre>\n<h2>Scene as given</h2>\n<pre>");
    h.push_str(&e(&scene.source));
    h.push_str("</pre>\n</body></html>\n");
    Ok(h)
}

/// The studies with their summaries.
fn studies_table(h: &mut String, results: &Results) {
    let e = escape;
    h.push_str("<h2>Studies</h2>\n<table><tr><th>study</th><th>kind</th><th>models</th><th>points</th><th>time [s]</th><th>details</th></tr>\n");
    for s in &results.studies {
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}/{}</td><td>{:.2}</td><td>{}</td></tr>",
            e(&s.name),
            s.kind.name(),
            s.models,
            s.points,
            s.requested,
            s.elapsed.as_secs_f64(),
            s.details
                .iter()
                .map(|d| e(d))
                .collect::<Vec<_>>()
                .join("<br>")
        );
    }
    h.push_str("</table>\n");
}

/// What could not be computed, and why.
fn failures(h: &mut String, results: &Results) {
    let e = escape;
    h.push_str("<h2>Where a model stopped</h2>\n");
    if results.failures().next().is_none() {
        h.push_str("<p>Every requested point was computed.</p>\n");
    }
    for (study, n) in results.failures() {
        let _ = writeln!(
            h,
            "<div class=\"note\"><b>{}</b> — {}:<br>{}</div>",
            e(study),
            e(&n.model),
            e(&n.message)
        );
    }
}

/// Each FE sweep against the homogeneous (0D) curve of the same model.
fn fe_table(h: &mut String, results: &Results) -> Result<(), AppError> {
    let e = escape;
    let sweeps: Vec<_> = results
        .cylinders()
        .flat_map(|(_, c)| c.sweeps.iter().map(move |s| (c.bases, s)))
        .collect();
    if !sweeps.is_empty() {
        h.push_str("<h2>FE vs homogeneous (0D) tension</h2>\n<table><tr><th>bases</th><th>model</th><th>stretches</th><th>max |P_FE − P_0D| [kPa]</th><th>at λ</th></tr>\n");
        for (bases, s) in sweeps {
            // A sweep that reached no stretch is in the notes, not in this table.
            let Some(worst) = s.worst_against_0d() else {
                continue;
            };
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{:.3e}</td><td>{}</td></tr>",
                bases_name(bases),
                e(&s.label),
                s.points.iter().filter(|p| p.stress_0d.is_some()).count(),
                finite(worst.0, "max |P_FE − P_0D|", || format!(
                    "report: {}",
                    s.label
                ))?,
                finite(
                    worst.1,
                    "lambda of the largest FE − 0D difference",
                    || format!("report: {}", s.label)
                )?
            );
        }
        h.push_str("</table>\n");
    }
    Ok(())
}

/// The figures (embedded) and the list of data files.
fn figures_and_data(h: &mut String, figures: &[Rendered], info: &RunInfo) {
    let e = escape;
    h.push_str("<h2>Figures</h2>\n");
    for (f, png) in figures {
        let _ = writeln!(
            h,
            "<figure><h3>{}</h3><img alt=\"{}\" src=\"data:image/png;base64,{}\"><figcaption>{} <small>(<code>{}.png</code>, <code>{}.svg</code>)</small></figcaption></figure>",
            e(&f.heading),
            e(&f.stem),
            base64::encode(png),
            e(&f.caption),
            e(&f.stem),
            e(&f.stem)
        );
    }

    h.push_str("<h2>Data</h2>\n<p><code>curves.csv</code>: one row per point, columns ");
    h.push_str(
        &COLUMNS
            .iter()
            .map(|c| format!("<code>{c}</code>"))
            .collect::<Vec<_>>()
            .join(", "),
    );
    let _ = writeln!(
        h,
        ". Stresses in kPa (nominal, along the stretch); an empty cell does not apply. {} rows.</p>",
        info.rows
    );
    h.push_str("<p>Other files: ");
    h.push_str(
        &info
            .files
            .iter()
            .map(|f| format!("<code>{}</code>", e(f)))
            .collect::<Vec<_>>()
            .join(", "),
    );
    h.push_str("</p>\n");
}

/// Parameters ± standard errors, reference values, correlation, RMS, iterations, convergence.
fn fits_table(h: &mut String, results: &Results) -> Result<(), AppError> {
    let studies = results.fits();
    if studies.iter().all(|(_, f)| f.is_empty()) {
        return Ok(());
    }
    let e = escape;
    h.push_str("<h2>Fits</h2>\n<p>Least squares with dual-number Jacobians (<code>fits.csv</code> has the same numbers). Standard errors σ = √(s²(JᵀJ)⁻¹); a fit marked <b>NOT converged</b> shows the best point found, which is not a solution.</p>\n<table><tr><th>study</th><th>data</th><th>parameter</th><th>value ± std. error</th><th>reference</th><th>correlation</th><th>RMS</th><th>iterations</th><th>status</th></tr>\n");
    for (study, f) in studies
        .iter()
        .flat_map(|&(s, fits)| fits.iter().map(move |f| (s, f)))
    {
        let origin = || format!("report: fit {study:?}, {}", f.case);
        let n = f.names.len();
        for j in 0..n {
            let value = finite(f.values[j], "fitted value", origin)?;
            let se = match f.standard_errors.get(j).copied().flatten() {
                Some(s) => format!(" ± {:.3e}", finite(s, "standard error", origin)?),
                None => " ± (n/a)".into(),
            };
            let reference = match f.reference.get(j).copied().flatten() {
                Some(r) => finite(r, "reference value", origin)?.to_string(),
                None => String::new(),
            };
            let corr = f
                .correlation
                .get(j)
                .map(|row| {
                    row.iter()
                        .map(|c| c.map_or("n/a".to_string(), |c| format!("{c:.4}")))
                        .collect::<Vec<_>>()
                        .join(", ")
                })
                .unwrap_or_default();
            if j == 0 {
                let mut status = if f.converged {
                    "converged".to_string()
                } else {
                    format!("<b>NOT converged</b> ({})", e(&f.termination))
                };
                for x in &f.extra {
                    status.push_str(&format!("<br>{}", e(x)));
                }
                let _ = write!(
                    h,
                    "<tr><td rowspan=\"{n}\">{}</td><td rowspan=\"{n}\">{} ({} points)</td>",
                    e(study),
                    e(&f.case),
                    f.points
                );
                let _ = writeln!(
                    h,
                    "<td>{}</td><td>{value:.6}{se}</td><td>{reference}</td><td>[{corr}]</td><td rowspan=\"{n}\">{:.3e} {}</td><td rowspan=\"{n}\">{}</td><td rowspan=\"{n}\">{status}</td></tr>",
                    e(&f.names[j]),
                    finite(f.rms, "RMS error", origin)?,
                    f.unit,
                    f.iterations,
                );
            } else {
                let _ = writeln!(
                    h,
                    "<tr><td>{}</td><td>{value:.6}{se}</td><td>{reference}</td><td>[{corr}]</td></tr>",
                    e(&f.names[j]),
                );
            }
        }
    }
    h.push_str("</table>\n");
    Ok(())
}

/// Intervals of softening and of lost strong ellipticity, per model.
fn stability_table(h: &mut String, results: &Results) -> Result<(), AppError> {
    let studies = results.stability();
    if studies.iter().all(|(_, c)| c.is_empty()) {
        return Ok(());
    }
    let e = escape;
    let fmt = |v: Vec<(f64, f64)>| {
        if v.is_empty() {
            "none".to_string()
        } else {
            v.iter()
                .map(|(a, b)| format!("{a:.3}–{b:.3}"))
                .collect::<Vec<_>>()
                .join(", ")
        }
    };
    h.push_str("<h2>Material stability along the fibres</h2>\n<p>Uniaxial path along the fibres: intervals of the stretch grid where dP/dλ &lt; 0 and where strong ellipticity (incompressible, a ⊥ F⁻ᵀN) is lost; per-point values in <code>stability.csv</code>.</p>\n<table><tr><th>study</th><th>model</th><th>d</th><th>stretches</th><th>dP/dλ &lt; 0 on</th><th>not strongly elliptic on</th><th>least relative a·Q(N)a</th></tr>\n");
    for (name, c) in studies
        .iter()
        .flat_map(|&(s, cs)| cs.iter().map(move |c| (s, c)))
    {
        let least = c
            .points
            .iter()
            .map(|p| p.relative)
            .fold(f64::INFINITY, f64::min);
        let least = if c.points.is_empty() {
            "n/a".to_string()
        } else {
            let least = finite(least, "relative ellipticity", || {
                format!("report: {name}, {}, d = {:?}", c.label(), c.damage())
            })?;
            format!("{least:.3e}")
        };
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{least}</td></tr>",
            e(name),
            e(&c.label()),
            c.damage().map_or(String::new(), |d| d.to_string()),
            c.points.len(),
            fmt(c.intervals(|p| p.slope < 0.0)),
            fmt(c.intervals(|p| !p.elliptic)),
        );
    }
    h.push_str("</table>\n");
    Ok(())
}
