//! The stability kind's figure (the stress along the fibres, softening and lost ellipticity
//! marked) and its report table (the intervals per model).

use super::StabilityCurve;
use crate::app_error::{finite, AppError};
use crate::plot::{Figure, Series, Stroke, GREY};
use crate::studies::domain::{in_domain, IN_DOMAIN};
use crate::studies::outputs::{
    coupling_stroke, derived, each_study, figure, hidden_curves, law_colour, model_cells, panel,
    prefixed, sorted_unique, Context, KindOutput, Of, OwnTable, Used, STRESS,
};
use crate::studies::table::{every_row, Table};
use crate::text::escape_html as escape;
use std::fmt::Write;

impl KindOutput for Vec<StabilityCurve> {
    /// Its rows of `stability.csv`.
    fn tables(&self, study: &str) -> Vec<OwnTable> {
        vec![OwnTable::rows(
            FILE,
            "one row per model and stretch",
            stability_table_of(study, self),
        )]
    }

    fn used(&self) -> Used {
        let mut used = Used::default();
        for c in self.iter().filter(|c| c.model.is_some()) {
            used.merge(Used::active(c.approach, c.model));
        }
        used
    }

    fn figures(studies: &[Of<Self>], _: &Context) -> Vec<Figure> {
        each_study(studies, |name, curves| stability_figure(name, curves))
    }

    fn report(studies: &[Of<Self>], _: &Context, h: &mut String) -> Result<(), AppError> {
        stability_table(h, studies)
    }
}

/// The file.
pub const FILE: &str = "stability.csv";

/// The table of `stability.csv` for the curves of `study`: one row per model and stretch.
pub fn stability_table_of(study: &str, curves: &[StabilityCurve]) -> Table {
    let rows: Vec<(&StabilityCurve, &super::StabilityPoint)> = curves
        .iter()
        .flat_map(|c| c.points.iter().map(move |p| (c, p)))
        .collect();
    let cell = |i: usize| {
        rows.iter()
            .map(move |(c, _)| model_cells(c.approach, c.model)[i].clone())
    };
    let at = |f: fn(&super::StabilityPoint) -> f64| rows.iter().map(move |(_, p)| Some(f(p)));
    Table::default()
        .text("study", "the study's name", every_row(study, rows.len()))
        .text("law", "passive, implicit, explicit or energy (empty: an approach without a law, active stress)", cell(1))
        .text("coupling", "frozen or consistent (active rows; empty: passive, or an approach without a law)", cell(2))
        .number("d", "-", "damage d (active rows)", rows.iter().map(|(c, _)| c.damage()))
        .number("lambda", "-", "stretch λ of homogeneous uniaxial tension along the fibres", at(|p| p.lambda))
        .number("P", "kPa", "nominal stress", at(|p| p.stress))
        .number("dP_dlambda", "kPa", "slope of the nominal stress, dP/dλ", at(|p| p.slope))
        .number("ellipticity_min", "kPa", "min a·Q(N)a of the acoustic tensor over the sampled normals (strong ellipticity: > 0)", at(|p| p.least))
        .number("ellipticity_relative", "-", "ellipticity_min relative to the tangent's norm", at(|p| p.relative))
        .boolean("strongly_elliptic", "whether ellipticity_relative > −1e-12", rows.iter().map(|(_, p)| Some(p.elliptic)))
        .boolean("softening", "whether dP/dλ < 0", rows.iter().map(|(_, p)| Some(p.slope < 0.0)))
        .number("cauchy", "kPa", "Cauchy stress along the stretch", at(|p| p.cauchy))
        .text("approach", "activation approach, active-strain, active-stress or structural (empty: the passive material)", cell(0))
        .boolean("in_domain", IN_DOMAIN, rows.iter().map(|(c, p)| in_domain(c.model.as_ref(), p.outside)))
}

/// The palette's pink: the points where strong ellipticity is lost.
const LOST: usize = 6;

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
        // The markers' legend entries come last, once, after the curves': the legend reads
        // model by model, then what the circles mean.
        let (mut softening, mut lost_somewhere) = (false, false);
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
            softening |= !soft.is_empty();
            s.push(derived("", soft, Stroke::Markers, colour(c)));
            let lost: Vec<(f64, f64)> = c
                .points
                .iter()
                .filter(|p| !p.elliptic)
                .map(|p| (p.lambda, p.stress))
                .collect();
            lost_somewhere |= !lost.is_empty();
            s.push(derived("", lost, Stroke::Markers, LOST));
        }
        if softening {
            s.push(Some(Series::new(
                "dP/dλ < 0 (circles in the curve's colour)",
                Vec::new(),
                Stroke::Markers,
                GREY,
            )));
        }
        if lost_somewhere {
            s.push(Some(Series::new(
                "strong ellipticity lost (pink circles)",
                Vec::new(),
                Stroke::Markers,
                LOST,
            )));
        }
        panels.extend(panel(
            format!("Stability along the fibres, d = {d}"),
            STRESS,
            s,
        ));
    }
    let hidden = hidden_curves(&mut panels);
    figure(
        &prefixed("stability", study),
        format!("Material stability along the fibres (study \"{study}\")"),
        format!("Uniaxial tension along the fibres, nominal stress of each law × coupling (solid: frozen, dashed: consistent, dotted: passive). Circles in the curve's colour mark dP/dλ < 0 (softening: the homogeneous state is unstable under load control); pink circles mark the loss of strong ellipticity (a·Q(N)a ≤ 0 for some sampled normal N and a ⊥ F⁻ᵀN).{hidden} The table above gives the intervals."),
        panels.into_iter().map(Some).collect(),
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
