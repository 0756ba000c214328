//! What a study kind gives a run's outputs: its figures and its report section ([`KindOutput`]),
//! drawn from every study of the kind at once, so that a figure may compare them (FE against 0D
//! over every cylinder study). The drivers in `output/` iterate over the kinds through the
//! dispatch that `study_kinds!` generates ([`super::StudyResult::figures`],
//! [`super::StudyResult::report`]); a kind's own figures and section live in its module. The
//! helpers below are the vocabulary the kinds' figures share (axis labels, the chapter's figure
//! numbers, colours per law and strokes per coupling).

use crate::active::{ActiveCurve, Approach};
use crate::app_error::AppError;
use crate::models::{CouplingKind, LawKind, ModelChoice};
use crate::plot::{Figure, Panel, Series, Stroke, GREY};
use crate::studies::spec::ApproachModel;
use crate::studies::table::Table;
use crate::studies::{slug, Outcome, StudyResult};
use std::path::Path;

/// One study of a kind, as the outputs see it.
#[derive(Debug, Clone, Copy)]
pub struct Of<'a, R> {
    /// The study's name.
    pub name: &'a str,
    /// Its summary lines ([`super::Outcome::details`]: mesh, dofs, verification).
    pub details: &'a [String],
    /// What it computed.
    pub result: &'a R,
}

/// What the kinds' figures and sections take from the scene.
#[derive(Debug, Clone)]
pub struct Context {
    /// The material's energy (its name).
    pub material: String,
    /// The active curve.
    pub curve: ActiveCurve,
    /// The scene's energy and active curve are the chapter's (see [`chapter`]).
    pub chapter_material: bool,
}

/// A kind's part of a run's outputs. Both hooks get every study of the kind, in scene order (at
/// least one); the defaults draw and write nothing.
pub trait KindOutput: Sized {
    /// The kind's figures.
    fn figures(_studies: &[Of<Self>], _cx: &Context) -> Vec<Figure> {
        Vec::new()
    }

    /// The kind's section of the report (HTML appended to `h`). A non-finite number is an error
    /// naming it, never written.
    fn report(_studies: &[Of<Self>], _cx: &Context, _h: &mut String) -> Result<(), AppError> {
        Ok(())
    }

    /// The tables of one study of the kind ([`OwnTable`]): each written to its CSV file (the
    /// tables of every study that writes to one file appended, their columns the same),
    /// described in `datapackage.json`, and returned by Python, all from the same columns. A
    /// new kind declares its columns here, with [`Table`]'s builders.
    fn tables(&self, _study: &str) -> Vec<OwnTable> {
        Vec::new()
    }

    /// The energies, approaches and models the result computed, whose equations the report's
    /// table of models lists.
    fn used(&self) -> Used {
        Used::default()
    }

    /// The VTK files the study wrote, relative to the run's VTK directory.
    fn vtk_files(&self) -> Vec<&Path> {
        Vec::new()
    }

    /// Lines the command line prints after the table of studies (a verification, the fitted
    /// values), each a fact about the study `study`.
    fn console(&self, _study: &str) -> Vec<String> {
        Vec::new()
    }

    /// What the study found, in sentences (Python's `findings`).
    fn findings(&self) -> Vec<String> {
        Vec::new()
    }
}

/// What a study computed with, for the report's table of models.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Used {
    /// Passive energies other than the material's (compared curves), by name.
    pub energies: Vec<String>,
    /// The (approach, model) pairs; `model: None` is the passive material.
    pub models: Vec<ApproachModel>,
    /// Whether a curve has a constant activation.
    pub constant: bool,
}

impl Used {
    /// `self` with `other`'s energies (each once), models and constant activation added.
    pub fn merge(&mut self, other: Used) {
        for e in other.energies {
            if !self.energies.contains(&e) {
                self.energies.push(e);
            }
        }
        self.models.extend(other.models);
        self.constant |= other.constant;
    }

    /// The active models of `approach` computed with `models` (law × coupling × damage each).
    pub fn active(approach: Approach, models: impl IntoIterator<Item = ModelChoice>) -> Self {
        Used {
            models: models
                .into_iter()
                .map(|m| ApproachModel {
                    approach,
                    model: Some(m),
                })
                .collect(),
            ..Used::default()
        }
    }
}

/// A kind's result as the registry files it in a [`StudyResult`] (`study_kinds!` implements it).
pub trait OfResult: Sized {
    /// The result if `result` is of this kind.
    fn of(result: &StudyResult) -> Option<&Self>;
}

/// The studies of `outcomes` whose result is of kind `R`, in scene order.
fn studies<R: OfResult>(outcomes: &[Outcome]) -> Vec<Of<'_, R>> {
    outcomes
        .iter()
        .filter_map(|o| {
            R::of(&o.result).map(|result| Of {
                name: &o.name,
                details: &o.details,
                result,
            })
        })
        .collect()
}

/// The figures of kind `R` ([`KindOutput::figures`]), if `outcomes` hold any study of it.
pub fn figures_of<R: OfResult + KindOutput>(outcomes: &[Outcome], cx: &Context) -> Vec<Figure> {
    let of = studies::<R>(outcomes);
    if of.is_empty() {
        return Vec::new();
    }
    R::figures(&of, cx)
}

/// The report section of kind `R` ([`KindOutput::report`]), if `outcomes` hold any study of it.
pub fn report_of<R: OfResult + KindOutput>(
    outcomes: &[Outcome],
    cx: &Context,
    h: &mut String,
) -> Result<(), AppError> {
    let of = studies::<R>(outcomes);
    if of.is_empty() {
        return Ok(());
    }
    R::report(&of, cx, h)
}

/// One figure per study, by `figure` (the studies it draws nothing for left out).
pub fn each_study<R>(
    studies: &[Of<R>],
    figure: impl Fn(&str, &R) -> Option<Figure>,
) -> Vec<Figure> {
    studies
        .iter()
        .filter_map(|s| figure(s.name, s.result))
        .collect()
}

/// A table of one study: its columns, the CSV file it is written to and its key in Python.
#[derive(Debug, Clone, PartialEq)]
pub struct OwnTable {
    /// The table's key in Python's study (`table`: the study's rows; `named_points`: a
    /// cylinder's named points).
    pub key: &'static str,
    /// The CSV file (`curves.csv`, `points_<study>.csv`); the tables of several studies (of
    /// one kind or more) may share one.
    pub file: String,
    /// What one row is, for `datapackage.json`.
    pub rows_are: &'static str,
    /// The columns.
    pub table: Table,
}

impl OwnTable {
    /// The study's own rows (Python's `table`), written to `file`.
    pub fn rows(file: &str, rows_are: &'static str, table: Table) -> Self {
        OwnTable {
            key: "table",
            file: file.to_string(),
            rows_are,
            table,
        }
    }
}

/// The (approach, law, coupling) cells of a row: the approach of an activation model, its law
/// and coupling where the approach has them ([`ApproachModel::cells`]: active stress has
/// neither); `passive` as the law of the passive material, without approach.
pub fn model_cells(approach: Approach, model: Option<ModelChoice>) -> [Option<String>; 3] {
    ApproachModel { approach, model }.cells()
}

/// x label of a curve over the stretch.
pub const LAMBDA: &str = "stretch λ [-]";
/// y label of a nominal stress.
pub const STRESS: &str = "nominal stress P [kPa]";
/// y label of the activation.
pub const GAMMA: &str = "activation γ [-]";

/// `0, 0.1, 0.5`.
pub fn list(values: &[f64]) -> String {
    values
        .iter()
        .map(f64::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// `v` sorted, each value once.
pub fn sorted_unique(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    v.dedup();
    v
}

/// ` — the chapter's Fig. n` for a figure of the chapter's energy and parameters
/// (`chapter_material`: the scene's energy and active curve are the chapter's); with other
/// parameters or another energy, ` — as the chapter's Fig. n` and what differs.
pub fn chapter(n: u32, energy: &str, chapter_material: bool) -> String {
    if energy != "giantesio-musesti" {
        format!(" — as the chapter's Fig. {n}, with the {energy} energy")
    } else if chapter_material {
        format!(" — the chapter's Fig. {n}")
    } else {
        format!(" — as the chapter's Fig. {n}, with this scene's parameters")
    }
}

/// `implicit law, frozen coupling`.
pub fn words(law: LawKind, coupling: CouplingKind) -> String {
    format!("{} law, {} coupling", law.name(), coupling.name())
}

/// The law and coupling of `m` in [`words`], or its approach if it has no law (`active-stress`).
pub fn model_words(m: &ModelChoice) -> String {
    m.activation_law()
        .map_or_else(|| m.approach.name().to_string(), |(l, c)| words(l, c))
}

/// A series that draws no curve of `curves.csv` (a derived quantity); `None` without points.
pub fn derived(
    label: impl Into<String>,
    points: Vec<(f64, f64)>,
    stroke: Stroke,
    colour: usize,
) -> Option<Series> {
    (!points.is_empty()).then(|| Series::new(label, points, stroke, colour))
}

/// A legend entry without points, in grey: what a stroke means.
pub fn key(label: &str, stroke: Stroke) -> Option<Series> {
    Some(Series::new(label, Vec::new(), stroke, GREY))
}

/// A panel over λ, or `None` if none of its series has points.
pub fn panel(
    title: impl Into<String>,
    y_label: &str,
    series: Vec<Option<Series>>,
) -> Option<Panel> {
    panel_over(title, LAMBDA, y_label, series)
}

/// A panel over `x_label`, or `None` if none of its series has points.
pub fn panel_over(
    title: impl Into<String>,
    x_label: &str,
    y_label: &str,
    series: Vec<Option<Series>>,
) -> Option<Panel> {
    let series: Vec<Series> = series.into_iter().flatten().collect();
    series
        .iter()
        .any(|s| !s.points.is_empty())
        .then(|| Panel::new(title, x_label, y_label, series))
}

/// A figure of the panels that have data, or `None` if none has.
pub fn figure(
    stem: &str,
    heading: String,
    caption: String,
    panels: Vec<Option<Panel>>,
) -> Option<Figure> {
    let panels: Vec<Panel> = panels.into_iter().flatten().collect();
    (!panels.is_empty()).then(|| Figure::new(stem, heading, caption, panels))
}

/// `fig_<kind>_<name>`, without repeating the kind when the name starts with it.
pub fn prefixed(kind: &str, name: &str) -> String {
    let s = slug(name);
    if s.starts_with(kind) {
        format!("fig_{s}")
    } else {
        format!("fig_{kind}_{s}")
    }
}

/// The colour of a law, the same in every figure.
pub fn law_colour(law: LawKind) -> usize {
    match law {
        LawKind::Implicit => 0,
        LawKind::Explicit => 1,
        LawKind::Energy => 2,
    }
}

/// The stroke of a coupling: solid frozen, dashed consistent.
pub fn coupling_stroke(c: CouplingKind) -> Stroke {
    match c {
        CouplingKind::Frozen => Stroke::Solid,
        CouplingKind::Consistent => Stroke::Dashed,
    }
}

/// `λ_min = 0.6243, λ_opt = 1.1704, k = 0.4342, P_opt = 73.52 kPa`: a curve's parameters as the
/// figures and the report print them.
pub fn curve_parameters_text(curve: &ActiveCurve) -> String {
    let v: Vec<String> = curve
        .parameters()
        .iter()
        .zip(curve.parameter_values())
        .map(|(p, v)| {
            let unit = if p.unit == "-" {
                String::new()
            } else {
                format!(" {}", p.unit)
            };
            format!("{} = {v}{unit}", p.symbol)
        })
        .collect();
    v.join(", ")
}

/// A panel of the series that have points over `x_label`, or `None` if none has.
pub fn panel_of(title: &str, x_label: &str, y_label: &str, series: Vec<Series>) -> Option<Panel> {
    let series: Vec<Series> = series
        .into_iter()
        .filter(|s| !s.points.is_empty())
        .collect();
    (!series.is_empty()).then(|| Panel::new(title, x_label, y_label, series))
}

/// Solid, dashed, dotted, in turn.
pub fn strokes(i: usize) -> Stroke {
    [Stroke::Solid, Stroke::Dashed, Stroke::Dotted][i % 3]
}

/// How close two curves of a panel must be for the panel not to tell them apart: the largest
/// |Δy| within this fraction of the larger |y| of the two, at the same x values.
pub const INDISTINCT: f64 = 0.005;

/// The curves each of `panels` cannot tell apart ([`Panel::coinciding`] within [`INDISTINCT`],
/// as active stress's P₂₂ is the passive one's), among the curves with a legend entry: each
/// hidden curve named under the last curve drawn over it, in a grey legend entry on the panel, and in the caption's sentences
/// (returned, each starting with a space; empty where no curve hides another).
pub fn hidden_curves(panels: &mut [Panel]) -> String {
    let mut words = String::new();
    for p in panels {
        // Only the curves the legend names (markers and guides without a label are not).
        let named = |k: usize| !p.series[k].label.is_empty();
        let pairs: Vec<(usize, usize, f64)> = p
            .coinciding(INDISTINCT)
            .into_iter()
            .filter(|&(i, j, _)| named(i) && named(j))
            .collect();
        let mut groups: Vec<(usize, Vec<usize>, f64)> = Vec::new();
        for &(i, _, _) in &pairs {
            let Some(&(_, top, _)) = pairs.iter().filter(|q| q.0 == i).max_by_key(|q| q.1) else {
                continue;
            };
            let d = pairs
                .iter()
                .filter(|q| q.1 == top)
                .fold(0.0, |m, q| q.2.max(m));
            match groups.iter_mut().find(|g| g.0 == top) {
                Some(g) if !g.1.contains(&i) => g.1.push(i),
                Some(_) => {}
                None => groups.push((top, vec![i], d)),
            }
        }
        let unit = crate::plot::axis_unit(&p.y_label);
        for (top, hidden, d) in groups {
            let label = |k: usize| p.series[k].label.clone();
            let under: Vec<String> = hidden.into_iter().map(label).collect();
            let over = label(top);
            words.push_str(&format!(
                " In \"{}\", {} under \"{over}\" (largest difference {}{unit}).",
                p.title,
                match under.len() {
                    1 => format!("\"{}\" lies", under[0]),
                    _ => format!("\"{}\" lie", under.join("\", \"")),
                },
                crate::plot::short(d)
            ));
            p.series.push(Series::new(
                format!("({}: under {over})", under.join("; ")),
                Vec::new(),
                Stroke::Solid,
                GREY,
            ));
        }
    }
    words
}

#[cfg(test)]
mod tests {
    use super::{hidden_curves, INDISTINCT};
    use crate::plot::{Panel, Series, Stroke, GREY};

    fn line(label: &str, ys: &[f64]) -> Series {
        let points = ys.iter().enumerate().map(|(i, &y)| (i as f64, y)).collect();
        Series::new(label, points, Stroke::Solid, 0)
    }

    fn panel(title: &str, series: Vec<Series>) -> Panel {
        Panel::new(title, "x [-]", "σ [kPa]", series)
    }

    /// A curve is said to lie under another exactly when the two coincide within the plotting
    /// tolerance (|Δy| ≤ INDISTINCT × the larger |y|, same x), in every panel, by the same rule.
    #[test]
    fn a_hidden_curve_is_named_in_every_panel_exactly_when_it_coincides_with_a_later_one() {
        let base = [1.0, 2.0, 4.0, 8.0];
        let within: Vec<f64> = base.iter().map(|y| y * (1.0 + 0.9 * INDISTINCT)).collect();
        let beyond: Vec<f64> = base.iter().map(|y| y * (1.0 + 1.1 * INDISTINCT)).collect();
        let mut panels = vec![
            panel(
                "same",
                vec![line("a", &base), line("b", &base), line("c", &[0.0; 4])],
            ),
            panel("within", vec![line("a", &base), line("b", &within)]),
            panel("beyond", vec![line("a", &base), line("b", &beyond)]),
            panel("unnamed", vec![line("", &base), line("", &base)]),
        ];
        let words = hidden_curves(&mut panels);
        let keys = |p: &Panel| -> Vec<String> {
            p.series
                .iter()
                .filter(|s| s.colour == GREY && s.points.is_empty())
                .map(|s| s.label.clone())
                .collect()
        };
        assert_eq!(keys(&panels[0]), ["(a: under b)"]);
        assert_eq!(keys(&panels[1]), ["(a: under b)"]);
        assert!(keys(&panels[2]).is_empty());
        assert!(keys(&panels[3]).is_empty());
        assert!(words.contains("In \"same\", \"a\" lies under \"b\" (largest difference 0 kPa)."));
        assert!(words.contains("In \"within\", \"a\" lies under \"b\""));
        assert!(!words.contains("beyond"), "{words}");
    }
}
