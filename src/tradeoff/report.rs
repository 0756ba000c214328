//! Outputs of the trade-off run: `tradeoff.csv`, one log–log error-versus-time figure per option
//! (PNG + SVG, the Pareto front marked) and a self-contained `tradeoff.html`.

use super::measure::Measurement;
use super::study::TradeoffResults;
use crate::output::base64;
use crate::output::plot::register_font;
use crate::output::report::escape;
use crate::output::OutputError;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::fmt::Write;
use std::path::Path;

/// Relative errors below this (the references' zero) are drawn at this value on the log axis.
pub const ERROR_FLOOR: f64 = 1e-17;

/// Columns of `tradeoff.csv`.
pub const COLUMNS: [&str; 15] = [
    "option",
    "variant",
    "reference",
    "quantity",
    "time_s",
    "error_abs",
    "error_rel",
    "gamma_error",
    "speedup",
    "error_ratio",
    "pareto",
    "newton_iterations",
    "time_per_iteration_s",
    "dofs",
    "note",
];

/// A CSV cell: non-finite values (an error that does not exist because the variant failed, a
/// ratio without a reference) are written as empty cells, never as NaN or inf.
fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.6e}")
    } else {
        String::new()
    }
}

/// The CSV text of the measured rows (one per variant; times in s, errors in the quantity's
/// unit and relative; speed-up = reference time / time; error ratio = relative error / the
/// option's smallest positive non-reference relative error).
pub fn to_csv(rows: &[Measurement]) -> Result<Vec<u8>, OutputError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let fail = |e: csv::Error| OutputError(format!("CSV: {e}"));
    w.write_record(COLUMNS).map_err(fail)?;
    for r in rows {
        let record = [
            r.option.clone(),
            r.variant.clone(),
            r.reference.to_string(),
            r.quantity.clone(),
            num(r.time_s),
            num(r.error.max_abs),
            num(r.error.max_rel),
            r.gamma_error.map(num).unwrap_or_default(),
            num(r.speedup),
            num(r.error_ratio),
            r.pareto.to_string(),
            r.iterations.map(|n| n.to_string()).unwrap_or_default(),
            r.per_iteration_s.map(num).unwrap_or_default(),
            r.dofs.map(|n| n.to_string()).unwrap_or_default(),
            r.note.clone(),
        ];
        w.write_record(&record).map_err(fail)?;
    }
    w.into_inner()
        .map_err(|e| OutputError(format!("CSV: {}", e.error())))
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
    let mut s = String::from("tradeoff");
    let mut sep = true;
    for c in option.chars() {
        if c.is_ascii_alphanumeric() {
            if sep {
                s.push('_');
            }
            s.push(c.to_ascii_lowercase());
            sep = false;
        } else {
            sep = true;
        }
    }
    s
}

const BLUE: RGBColor = RGBColor(31, 119, 180);
const RED: RGBColor = RGBColor(214, 39, 40);
const GREY: RGBColor = RGBColor(120, 120, 120);

/// Writes the log–log error-versus-time figure of `option` (relative error on y, wall time on x;
/// filled markers: the Pareto front, joined by a dashed line; the reference in red).
pub fn figure(
    option: &str,
    rows: &[Measurement],
    png: &Path,
    svg: &Path,
) -> Result<(), OutputError> {
    register_font();
    let rows: Vec<&Measurement> = rows.iter().filter(|r| r.option == option).collect();
    let err = |what: &str, e: String| OutputError(format!("{what} {option}: {e}"));
    let size = (900, 560);
    {
        let root = BitMapBackend::new(png, size).into_drawing_area();
        draw(&root, option, &rows).map_err(|e| err("drawing PNG", e))?;
        root.present()
            .map_err(|e| err("writing PNG", e.to_string()))?;
    }
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
        draw(&root, option, &rows).map_err(|e| err("drawing SVG", e))?;
        root.present()
            .map_err(|e| err("writing SVG", e.to_string()))?;
    }
    std::fs::write(svg, text).map_err(|e| err("writing SVG", e.to_string()))
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    option: &str,
    rows: &[&Measurement],
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    root.fill(&WHITE).map_err(e)?;
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (r.time_s, r.error.max_rel.max(ERROR_FLOOR)))
        .collect();
    let finite = pts.iter().filter(|p| p.0.is_finite() && p.1.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, 0.0f64, f64::INFINITY, 0.0f64);
    for &(x, y) in finite {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if !x0.is_finite() || x0 <= 0.0 {
        (x0, x1, y0, y1) = (1e-6, 1.0, ERROR_FLOOR, 1.0);
    }
    let (mut x0, mut x1) = (x0 / 3.0, x1 * 6.0);
    // At least two decades of time, so that only decades carry labels (a narrower log axis gets
    // labels at 2e-1 … 9e-1 that run into each other).
    let widen = (100.0 / (x1 / x0)).max(1.0).sqrt();
    (x0, x1) = (x0 / widen, x1 * widen);
    let (y0, y1) = (y0 / 10.0, y1 * 10.0);
    let mut chart = ChartBuilder::on(root)
        .caption(option, ("sans-serif", 22))
        .margin(14)
        .x_label_area_size(48)
        .y_label_area_size(80)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc("wall time [s]")
        .y_desc("max relative error [-]")
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 15))
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(e)?;
    let mut front: Vec<(f64, f64)> = rows
        .iter()
        .zip(&pts)
        .filter(|(r, _)| r.pareto)
        .map(|(_, p)| *p)
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    chart
        .draw_series(DashedLineSeries::new(front, 8, 5, GREY.stroke_width(2)))
        .map_err(e)?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], GREY.stroke_width(2)));
    for (r, &(x, y)) in rows.iter().zip(&pts) {
        if !(x.is_finite() && y.is_finite()) {
            continue;
        }
        let c = if r.reference { RED } else { BLUE };
        let style = if r.pareto {
            c.filled()
        } else {
            c.stroke_width(2)
        };
        chart
            .draw_series(std::iter::once(Circle::new((x, y), 6, style)))
            .map_err(e)?;
        let label = if r.reference {
            format!("{} (reference)", r.variant)
        } else {
            r.variant.clone()
        };
        chart
            .draw_series(std::iter::once(Text::new(
                label,
                (x * 1.15, y * 1.3),
                ("sans-serif", 14),
            )))
            .map_err(e)?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(e)?;
    Ok(())
}

/// A ratio: fixed-point in [0.1, 1000), scientific outside.
fn ratio(x: f64) -> String {
    if (0.1..1000.0).contains(&x.abs()) {
        format!("{x:.2}")
    } else {
        cell(Some(x), 1)
    }
}

fn cell(x: Option<f64>, digits: usize) -> String {
    match x {
        Some(v) if v.is_finite() => format!("{v:.digits$e}"),
        Some(v) if v.is_infinite() => "failed".into(),
        _ => "–".into(),
    }
}

/// The table as Markdown (what the README and BENCHMARKS.md show).
pub fn markdown(rows: &[Measurement]) -> String {
    let mut s = String::from(
        "| option | variant | time [s] | max abs error | max rel error | γ error | speed-up | error ratio | Newton its | s/iteration | dofs | Pareto |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {}{} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.option,
            r.variant,
            if r.reference { " (ref.)" } else { "" },
            cell(Some(r.time_s), 2),
            cell(Some(r.error.max_abs), 1),
            cell(Some(r.error.max_rel), 1),
            cell(r.gamma_error, 1),
            ratio(r.speedup),
            cell(Some(r.error_ratio), 1),
            r.iterations.map_or("–".into(), |n| n.to_string()),
            cell(r.per_iteration_s, 2),
            r.dofs.map_or("–".into(), |n| n.to_string()),
            if r.pareto { "yes" } else { "" }
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
        "<p>Command: <code>{}</code> · wall time {wall_s:.1} s. Times are wall times (median of repeats \
         for runs under 1 s) on a shared machine: read the ratios. Each error is against the option's \
         reference (red row), on the quantity named; relative errors use |reference| floored at \
         10⁻³ of its largest value. Speed-up = reference time / time; error ratio = relative error / \
         the option's smallest non-reference relative error.</p>",
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
        let _ = writeln!(
            h,
            "<tr{}><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            if r.reference { " class=\"ref\"" } else { "" },
            e(&r.option),
            e(&r.variant),
            cell(Some(r.time_s), 2),
            cell(Some(r.error.max_abs), 1),
            cell(Some(r.error.max_rel), 1),
            cell(r.gamma_error, 1),
            ratio(r.speedup),
            cell(Some(r.error_ratio), 1),
            r.iterations.map_or("–".into(), |n| n.to_string()),
            cell(r.per_iteration_s, 2),
            r.dofs.map_or("–".into(), |n| n.to_string()),
            if r.pareto { "yes" } else { "" },
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

/// One row in words, both axes with their numbers (the report's study table):
/// `activation law (FE) · explicit (frozen): 5.4e-1 s, speed-up 1.06, max abs error 2.7e0, max rel error 1.4e-1`.
pub fn line(r: &Measurement) -> String {
    let mut s = format!(
        "{} · {}{}: {} s, speed-up {}, max abs error {}, max rel error {}",
        r.option,
        r.variant,
        if r.reference { " (reference)" } else { "" },
        cell(Some(r.time_s), 2),
        ratio(r.speedup),
        cell(Some(r.error.max_abs), 1),
        cell(Some(r.error.max_rel), 1),
    );
    if let Some(g) = r.gamma_error {
        let _ = write!(s, ", γ error {}", cell(Some(g), 1));
    }
    if r.pareto {
        s.push_str(", Pareto");
    }
    s
}

/// One option's figure, staged.
#[derive(Debug, Clone)]
pub struct StagedFigure {
    /// The option it shows.
    pub option: String,
    /// File stem (`tradeoff_mesh_clamped` → `.png`, `.svg`).
    pub stem: String,
    /// The PNG bytes (for embedding in a report).
    pub png: Vec<u8>,
}

/// Stages `tradeoff.csv`, `tradeoff.md` (the table), one figure per option and `tradeoff.html`
/// in `staging` (committed by the caller); returns the files staged (relative names) and the
/// figures.
pub fn stage(
    results: &TradeoffResults,
    staging: &mut crate::output::Staging,
    title: &str,
    command: &str,
    wall_s: f64,
) -> Result<(Vec<String>, Vec<StagedFigure>), OutputError> {
    let mut files = Vec::new();
    staging.write("tradeoff.csv", &to_csv(&results.rows)?)?;
    files.push("tradeoff.csv".to_string());
    staging.write("tradeoff.md", markdown(&results.rows).as_bytes())?;
    files.push("tradeoff.md".to_string());
    let mut figures = Vec::new();
    for option in options(&results.rows) {
        let s = stem(&option);
        let png = staging.path(Path::new(&format!("{s}.png")))?;
        let svg = staging.path(Path::new(&format!("{s}.svg")))?;
        figure(&option, &results.rows, &png, &svg)?;
        let bytes = std::fs::read(&png)
            .map_err(|e| OutputError(format!("cannot read back {}: {e}", png.display())))?;
        files.push(format!("{s}.png"));
        files.push(format!("{s}.svg"));
        figures.push(StagedFigure {
            option,
            stem: s,
            png: bytes,
        });
    }
    let pngs: Vec<(String, Vec<u8>)> = figures
        .iter()
        .map(|f| (f.option.clone(), f.png.clone()))
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
) -> Result<Vec<String>, OutputError> {
    let mut staging = crate::output::Staging::new(out)?;
    let (files, _) = stage(results, &mut staging, title, command, wall_s)?;
    staging.commit()?;
    Ok(files)
}

/// The caption of an option's figure in a run's report.
pub fn caption(option: &str, rows: &[Measurement]) -> String {
    format!(
        "{option}: relative error of {} against wall time, log–log; filled markers and the dashed \
         line are the Pareto front, the reference is red; zero errors (the reference) are drawn at \
         {ERROR_FLOOR:.0e}. Numbers in tradeoff.csv and tradeoff.md.",
        rows.iter()
            .find(|r| r.option == option)
            .map_or("", |r| r.quantity.as_str())
    )
}
