//! `report.html`: one self-contained page (figures embedded as base64 PNG) with the run's
//! summary, the notes of studies that stopped, the figures, the scene and the versions.

use super::base64;
use super::csv::COLUMNS;
use super::plot::Figure;
use crate::scene::run::Results;
use crate::scene::Scene;
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
}

/// Escapes text for HTML.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The report page. `pngs` holds the PNG bytes of each figure, in the same order.
pub fn html(
    scene: &Scene,
    results: &Results,
    figures: &[(Figure, Vec<u8>)],
    info: &RunInfo,
) -> String {
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

    h.push_str("<h2>Studies</h2>\n<table><tr><th>study</th><th>kind</th><th>models</th><th>points</th><th>time [s]</th><th>details</th></tr>\n");
    for s in &results.studies {
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}/{}</td><td>{:.2}</td><td>{}</td></tr>",
            e(&s.name),
            s.kind,
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

    h.push_str("<h2>Where a model stopped</h2>\n");
    if results.notes.is_empty() {
        h.push_str("<p>Every requested point was computed.</p>\n");
    }
    for n in &results.notes {
        let _ = writeln!(
            h,
            "<div class=\"note\"><b>{}</b> — {}:<br>{}</div>",
            e(&n.study),
            e(&n.model),
            e(&n.message)
        );
    }

    if !results.fe_vs_0d.is_empty() {
        h.push_str("<h2>FE vs homogeneous (0D) tension</h2>\n<table><tr><th>bases</th><th>model</th><th>stretches</th><th>max |P_FE − P_0D| [kPa]</th><th>at λ</th></tr>\n");
        for c in &results.fe_vs_0d {
            let worst = c
                .points
                .iter()
                .map(|p| ((p.1 - p.2).abs(), p.0))
                .fold((0.0f64, f64::NAN), |a, b| if b.0 > a.0 { b } else { a });
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{:.3e}</td><td>{}</td></tr>",
                c.bases,
                e(&c.label),
                c.points.len(),
                worst.0,
                worst.1
            );
        }
        h.push_str("</table>\n");
    }

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
        results.rows.len()
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

    h.push_str("<h2>Scene as resolved (every default written out)</h2>\n<pre>");
    h.push_str(&e(&toml::to_string_pretty(&scene.resolved)
        .unwrap_or_else(|err| format!("(cannot print: {err})"))));
    h.push_str("</pre>\n<h2>Scene as given</h2>\n<pre>");
    h.push_str(&e(&scene.source));
    h.push_str("</pre>\n</body></html>\n");
    h
}
