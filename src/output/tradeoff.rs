//! Outputs of the trade-off run: `tradeoff.csv`, one log–log error-versus-time figure per option
//! (PNG + SVG, the Pareto front marked) and a self-contained `tradeoff.html`.

use super::base64;
use super::{Staging, Writer};
use crate::app_error::AppError;
use crate::plot::{render_bytes, Figure, Panel, Rendered, Scale, Series, Stroke, GREY};
use crate::studies::slug;
use crate::studies::tradeoff::{Measurement, TradeoffResults};
use crate::text::{cell, escape_html as escape, ratio};
use std::fmt::Write;
use std::path::Path;

/// The CSV text of `tradeoff.csv`, the trade-off kind's table
/// ([`crate::studies::tradeoff::output::table`]).
pub fn to_csv(rows: &[Measurement]) -> Result<Vec<u8>, AppError> {
    super::csv::table_csv(
        "tradeoff.csv",
        &[&crate::studies::tradeoff::output::table(rows)],
    )
}

/// Options in the order they were run.
pub fn options(rows: &[Measurement]) -> Vec<String> {
    let mut v: Vec<String> = Vec::new();
    for r in rows {
        if !v.contains(&r.option) {
            v.push(r.option.clone());
        }
    }
    v
}

/// File stem of an option's figure: `tradeoff_` + the option name in lower-case ASCII words.
pub fn stem(option: &str) -> String {
    format!("tradeoff_{}", slug(option))
}

/// The (time, error) ranges of the figure of `rows`: the times of the drawn rows (a failed
/// row, whose error is infinite, is not drawn and does not stretch the axis), widened to at
/// least two decades; the positive errors, a decade beyond each end.
fn ranges(rows: &[&Measurement]) -> ((f64, f64), (f64, f64)) {
    let positive = |e: f64| e.is_finite() && e > 0.0;
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, 0.0f64, f64::INFINITY, 0.0f64);
    for r in rows {
        if r.measured() && r.time.median.is_finite() && r.time.median > 0.0 {
            x0 = x0.min(r.time.low);
            x1 = x1.max(r.time.high);
        }
        if positive(r.error.max_rel) {
            y0 = y0.min(r.error.max_rel);
            y1 = y1.max(r.error.max_rel);
        }
    }
    if !(x0.is_finite() && x0 > 0.0) {
        (x0, x1) = (1e-6, 1.0);
    }
    if !y0.is_finite() {
        (y0, y1) = (1e-16, 1.0);
    }
    let (y0, y1) = (y0 / 10.0, y1 * 10.0);
    let (mut x0, mut x1) = (x0 / 3.0, x1 * 6.0);
    // At least two decades of time, so that only decades carry labels (a narrower log axis gets
    // labels at 2e-1 … 9e-1 that run into each other).
    let widen = (100.0 / (x1 / x0)).max(1.0).sqrt();
    (x0, x1) = (x0 / widen, x1 * widen);
    ((x0, x1), (y0, y1))
}

/// The log–log error-versus-time figure of `option` (relative error on y, the median wall time
/// on x with the spread of the runs as a horizontal bar; filled markers: the Pareto front, joined
/// by a dashed line; the reference in red). A zero error (the reference's own) has no place on a
/// log axis: it is drawn on the lower edge of the frame, a decade below the smallest error, and
/// labelled `error 0`.
pub fn figure(option: &str, all: &[Measurement]) -> Figure {
    let rows: Vec<&Measurement> = all.iter().filter(|r| r.option == option).collect();
    let positive = |e: f64| e.is_finite() && e > 0.0;
    let ((x0, x1), (y0, y1)) = ranges(&rows);
    // Where each row is drawn: a zero error on the lower edge; a failed row nowhere.
    let at = |r: &Measurement| -> Option<(f64, f64)> {
        let e = r.error.max_rel;
        let y = if e == 0.0 { y0 } else { e };
        (positive(y) && r.time.median.is_finite()).then_some((r.time.median, y))
    };
    let mut front: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.pareto)
        .filter_map(|r| at(r))
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut series = vec![
        Series::new("Pareto front", front, Stroke::Dashed, GREY),
        Series::new("spread of the runs' times", Vec::new(), Stroke::Solid, GREY),
    ];
    // Variants drawn on (nearly) the same spot share one label: (spot, series, text).
    let mut labelled: Vec<((f64, f64), usize, String)> = Vec::new();
    for r in &rows {
        let Some(p) = at(r) else { continue };
        let colour = usize::from(r.reference);
        if r.time.runs > 1 {
            series.push(Series::new(
                "",
                vec![(r.time.low, p.1), (r.time.high, p.1)],
                Stroke::Solid,
                colour,
            ));
        }
        let stroke = if r.pareto {
            Stroke::Filled
        } else {
            Stroke::Markers
        };
        series.push(Series::new("", vec![p], stroke, colour));
        let mut text = r.variant.clone();
        if r.reference {
            text.push_str(" (reference)");
        }
        if r.error.max_rel == 0.0 {
            text.push_str(": error 0");
        }
        let near = |q: (f64, f64)| (q.0 / p.0).ln().abs() < 0.1 && (q.1 / p.1).ln().abs() < 0.1;
        match labelled.iter_mut().find(|(q, _, _)| near(*q)) {
            Some((_, _, t)) => *t = format!("{t}, {text}"),
            None => labelled.push((p, series.len() - 1, text)),
        }
    }
    for (_, i, text) in labelled {
        series[i].annotation = Some(text);
    }
    Figure::new(
        stem(option),
        format!("Speed versus accuracy: {option}"),
        caption(option, all),
        vec![Panel {
            x_range: Some((x0, x1)),
            y_range: Some((y0, y1)),
            scale: Scale::LogLog,
            ..Panel::new(option, "wall time [s]", "max relative error [-]", series)
        }],
    )
}

/// `1.4e-1–1.6e-1 (3)`, or `– (1)` for one run.
fn spread(r: &Measurement) -> String {
    if r.time.runs > 1 {
        format!(
            "{}–{} ({})",
            cell(Some(r.time.low), 1),
            cell(Some(r.time.high), 1),
            r.time.runs
        )
    } else {
        format!("– ({})", r.time.runs)
    }
}

/// The number cells of a row (time, spread, errors, speed-up, error ratio, Newton iterations,
/// time per iteration, dofs) and its Pareto mark, as the Markdown and HTML tables show them.
fn cells(r: &Measurement) -> Vec<String> {
    vec![
        cell(Some(r.time.median), 2),
        spread(r),
        cell(Some(r.error.max_abs), 1),
        cell(Some(r.error.max_rel), 1),
        cell(r.gamma_error, 1),
        if r.reference || r.measurable {
            ratio(r.speedup)
        } else {
            format!("≈ {}", ratio(r.speedup))
        },
        cell(Some(r.error_ratio), 1),
        r.iterations.map_or("–".into(), |n| n.to_string()),
        cell(r.per_iteration_s, 2),
        r.dofs.map_or("–".into(), |n| n.to_string()),
        if r.pareto { "yes" } else { "" }.to_string(),
    ]
}

/// The table as Markdown (what the README and BENCHMARKS.md show).
pub fn markdown(rows: &[Measurement]) -> String {
    let mut s = String::from(
        "| option | variant | time [s] | spread [s] (runs) | max abs error | max rel error | γ error | speed-up | error ratio | Newton its | s/iteration | dofs | Pareto |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {}{} | {} |",
            r.option,
            r.variant,
            if r.reference { " (ref.)" } else { "" },
            cells(r).join(" | ")
        );
    }
    s
}

/// The self-contained page: findings, the table, one embedded figure per option.
/// `figures` holds (option, PNG bytes).
pub fn html(
    title: &str,
    command: &str,
    wall_s: f64,
    results: &TradeoffResults,
    figures: &[(String, Vec<u8>)],
) -> String {
    let e = escape;
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>Speed versus accuracy: {}</title>\n<style>\
         body{{font-family:sans-serif;max-width:1200px;margin:2em auto;padding:0 1em;color:#222}}\
         table{{border-collapse:collapse;margin:1em 0;font-size:90%}}td,th{{border:1px solid #ccc;padding:3px 6px;text-align:right;vertical-align:top}}\
         td:nth-child(-n+2),td:last-child{{text-align:left}}th{{background:#f2f2f2}}tr.ref{{background:#fff0f0}}\
         img{{max-width:100%;border:1px solid #eee}}</style></head><body>\n",
        e(title)
    );
    let _ = writeln!(h, "<h1>Speed versus accuracy</h1>\n<p>{}</p>", e(title));
    let _ = writeln!(
        h,
        "<p>Command: <code>{}</code> · wall time {wall_s:.1} s. Times are wall times: the median of at \
         least three runs (more for cheap variants; a failed variant runs once) and their spread, the \
         10th to 90th percentile (the minimum to the maximum for fewer than ten runs). A speed-up \
         marked ≈ is no measurable difference from the reference: the spreads overlap, or the \
         medians differ by less than 10 % (load drifts between variants run one after the other). Each error is \
         against the option's reference (red row), on the quantity named; relative errors use \
         |reference| floored at 10⁻³ of its largest value. Speed-up = reference time / time (medians); \
         error ratio = relative error / the option's smallest non-reference relative error.</p>",
        e(command)
    );
    let _ = writeln!(h, "<h2>Findings</h2><ul>");
    for f in &results.findings {
        let _ = writeln!(h, "<li>{}</li>", e(f));
    }
    let _ = writeln!(h, "</ul><h2>Table</h2><table><tr>");
    for c in [
        "option",
        "variant",
        "time [s]",
        "spread [s] (runs)",
        "abs error",
        "rel error",
        "γ error",
        "speed-up",
        "error ratio",
        "Newton its",
        "s/iteration",
        "dofs",
        "Pareto",
        "note",
    ] {
        let _ = write!(h, "<th>{c}</th>");
    }
    let _ = writeln!(h, "</tr>");
    for r in &results.rows {
        let numbers: String = cells(r).iter().map(|c| format!("<td>{c}</td>")).collect();
        let _ = writeln!(
            h,
            "<tr{}><td>{}</td><td>{}</td>{numbers}<td>{}</td></tr>",
            if r.reference { " class=\"ref\"" } else { "" },
            e(&r.option),
            e(&r.variant),
            e(&format!("{} {}", r.quantity, r.note)),
        );
    }
    let _ = writeln!(h, "</table><h2>Error versus time</h2>");
    for (option, png) in figures {
        let _ = writeln!(
            h,
            "<figure><img alt=\"{}\" src=\"data:image/png;base64,{}\"><figcaption>{}</figcaption></figure>",
            e(option),
            base64::encode(png),
            e(&caption(option, &results.rows))
        );
    }
    h.push_str("</body></html>\n");
    h
}

/// Stages `tradeoff.csv`, `tradeoff.md` (the table), one figure per option and `tradeoff.html`
/// in `staging` (committed by the caller), as the `tradeoff` command writes them; returns the
/// files staged (relative names) and the figures with their PNG bytes.
pub fn stage(
    results: &TradeoffResults,
    staging: &mut Staging,
    title: &str,
    command: &str,
    wall_s: f64,
) -> Result<(Vec<String>, Vec<Rendered>), AppError> {
    staging.write("tradeoff.csv", &to_csv(&results.rows)?)?;
    let (mut files, figures) = stage_pages(results, staging, title, command, wall_s)?;
    files.insert(0, "tradeoff.csv".to_string());
    Ok((files, figures))
}

/// Stages `tradeoff.md` (the table), one figure per option and `tradeoff.html` in `staging`
/// (a run writes `tradeoff.csv` with its other tables); returns the files staged (relative
/// names) and the figures with their PNG bytes (for embedding in a report).
pub fn stage_pages(
    results: &TradeoffResults,
    staging: &mut Staging,
    title: &str,
    command: &str,
    wall_s: f64,
) -> Result<(Vec<String>, Vec<Rendered>), AppError> {
    let mut files = Vec::new();
    staging.write("tradeoff.md", markdown(&results.rows).as_bytes())?;
    files.push("tradeoff.md".to_string());
    let mut figures = Vec::new();
    for option in options(&results.rows) {
        // No variant measured (every one failed, or the reference did): no empty frame.
        if !results
            .rows
            .iter()
            .any(|r| r.option == option && r.measured())
        {
            continue;
        }
        let f = figure(&option, &results.rows);
        let (png, svg) = render_bytes(&f)?;
        staging.write(&format!("{}.png", f.stem), &png)?;
        staging.write(&format!("{}.svg", f.stem), svg.as_bytes())?;
        files.push(format!("{}.png", f.stem));
        files.push(format!("{}.svg", f.stem));
        figures.push((f, png));
    }
    let pngs: Vec<(String, Vec<u8>)> = figures
        .iter()
        .map(|(f, png)| (f.panels[0].title.clone(), png.clone()))
        .collect();
    staging.write(
        "tradeoff.html",
        html(title, command, wall_s, results, &pngs).as_bytes(),
    )?;
    files.push("tradeoff.html".to_string());
    Ok((files, figures))
}

/// Writes `tradeoff.csv`, `tradeoff.md` (the table), the figures and `tradeoff.html` into
/// `out` atomically; returns the files written (relative names).
pub fn write_all(
    results: &TradeoffResults,
    out: &Path,
    title: &str,
    command: &str,
    wall_s: f64,
) -> Result<Vec<String>, AppError> {
    let mut staging = Staging::new(out, Writer::Tradeoff)?;
    let (files, _) = stage(results, &mut staging, title, command, wall_s)?;
    staging.commit()?;
    Ok(files)
}

/// The caption of an option's figure.
pub fn caption(option: &str, rows: &[Measurement]) -> String {
    let mine = || rows.iter().filter(|r| r.option == option);
    let failed: Vec<&str> = mine()
        .filter(|r| !r.measured())
        .map(|r| r.variant.as_str())
        .collect();
    format!(
        "{option}: relative error [-] of {} against wall time, log–log: the median of the runs, the \
         bar their spread (10th to 90th percentile); filled markers and the dashed line are the \
         Pareto front, the reference is red. An error of 0 (the reference's own) is drawn on the \
         lower edge of the frame and labelled so.{} Numbers in tradeoff.csv and tradeoff.md.",
        // The quantity without its unit: the error is relative.
        mine().next().map_or("", |r| r
            .quantity
            .rsplit_once(" [")
            .map_or(r.quantity.as_str(), |(q, _)| q)),
        if failed.is_empty() {
            String::new()
        } else {
            format!(" Not drawn (failed): {}.", failed.join(", "))
        }
    )
}
