//! The stability kind's figure (the stress along the fibres, softening and lost ellipticity
//! marked) and its report table (the intervals per model).

use super::StabilityCurve;
use crate::app_error::{finite, AppError};
use crate::plot::{Figure, Stroke};
use crate::studies::outputs::{
    coupling_stroke, derived, each_study, figure, law_colour, panel, prefixed, sorted_unique,
    Context, KindOutput, Of, STRESS,
};
use crate::text::escape_html as escape;
use std::fmt::Write;

impl KindOutput for Vec<StabilityCurve> {
    fn figures(studies: &[Of<Self>], _: &Context) -> Vec<Figure> {
        each_study(studies, |name, curves| stability_figure(name, curves))
    }

    fn report(studies: &[Of<Self>], _: &Context, h: &mut String) -> Result<(), AppError> {
        stability_table(h, studies)
    }
}

/// The figure of a stability study, a panel per damage value: the stress along the fibres of
/// each law × coupling (solid frozen, dashed consistent), with markers on the points where the
/// curve softens (dP/dλ < 0) and, in pink, where strong ellipticity is lost.
fn stability_figure(study: &str, curves: &[StabilityCurve]) -> Option<Figure> {
    let mut ds = sorted_unique(curves.iter().filter_map(StabilityCurve::damage).collect());
    if ds.is_empty() {
        ds.push(0.0);
    }
    let colour = |c: &StabilityCurve| c.model.map_or(5, |m| law_colour(m.law));
    let mut panels = Vec::new();
    for d in &ds {
        let mut s = Vec::new();
        let (mut soft_labelled, mut lost_labelled) = (false, false);
        for c in curves
            .iter()
            .filter(|c| c.damage().is_none() || c.damage() == Some(*d))
        {
            let stroke = c
                .model
                .map_or(Stroke::Dotted, |m| coupling_stroke(m.coupling));
            let all: Vec<(f64, f64)> = c.points.iter().map(|p| (p.lambda, p.stress)).collect();
            s.push(derived(c.label(), all, stroke, colour(c)));
            let soft: Vec<(f64, f64)> = c
                .points
                .iter()
                .filter(|p| p.slope < 0.0)
                .map(|p| (p.lambda, p.stress))
                .collect();
            let label = if soft.is_empty() || soft_labelled {
                String::new()
            } else {
                soft_labelled = true;
                "dP/dλ < 0 (circles in the curve's colour)".to_string()
            };
            s.push(derived(label, soft, Stroke::Markers, colour(c)));
            let lost: Vec<(f64, f64)> = c
                .points
                .iter()
                .filter(|p| !p.elliptic)
                .map(|p| (p.lambda, p.stress))
                .collect();
            let label = if lost.is_empty() || lost_labelled {
                String::new()
            } else {
                lost_labelled = true;
                "strong ellipticity lost".to_string()
            };
            s.push(derived(label, lost, Stroke::Markers, 6));
        }
        panels.push(panel(
            format!("Stability along the fibres, d = {d}"),
            STRESS,
            s,
        ));
    }
    figure(
        &prefixed("stability", study),
        format!("Material stability along the fibres (study \"{study}\")"),
        "Uniaxial tension along the fibres, nominal stress of each law × coupling (solid: frozen, dashed: consistent, dotted: passive). Circles in the curve's colour mark dP/dλ < 0 (softening: the homogeneous state is unstable under load control); pink circles mark the loss of strong ellipticity (a·Q(N)a ≤ 0 for some sampled normal N and a ⊥ F⁻ᵀN). The table above gives the intervals.".into(),
        panels,
    )
}

/// Intervals of softening and of lost strong ellipticity, per model.
fn stability_table(h: &mut String, studies: &[Of<Vec<StabilityCurve>>]) -> Result<(), AppError> {
    let studies: Vec<(&str, &[StabilityCurve])> = studies
        .iter()
        .map(|s| (s.name, s.result.as_slice()))
        .collect();
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
