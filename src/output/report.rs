//! `report.html`: one self-contained page (figures embedded as base64 PNG) with the run's
//! summary, the notes of studies that stopped, the figures, the scene and the versions.

use super::base64;
use super::csv::CsvFile;
use crate::app_error::AppError;
use crate::energy::{Parametric, ShippedEnergy};
use crate::models::{CouplingKind, LawKind, ModelChoice};
use crate::plot::Rendered;
use crate::scene::{Results, Scene};
use crate::studies::outputs::Used;
use crate::studies::StudyResult;
use crate::text::escape_html as escape;
use crate::StrainEnergy;
use std::fmt::Write;
use std::time::Duration;

/// Facts about the run shown in the report. `RunInfo::default()`: nothing known (empty command
/// and version, zero wall time, no files), e.g. for a report built by a test.
#[derive(Debug, Clone, Default)]
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
    /// The CSV files written.
    pub tables: Vec<DataFile>,
}

/// A CSV file of the run as the report lists it.
#[derive(Debug, Clone, Default)]
pub struct DataFile {
    /// The file name.
    pub file: String,
    /// What one row is.
    pub rows_are: String,
    /// Number of rows.
    pub rows: usize,
    /// The columns' names.
    pub columns: Vec<String>,
}

impl DataFile {
    /// What the report says of `f`.
    pub fn of(f: &CsvFile) -> Self {
        DataFile {
            file: f.file.clone(),
            rows_are: f.rows_are.to_string(),
            rows: f.rows(),
            columns: f.columns().iter().map(|c| c.to_string()).collect(),
        }
    }
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
    left_domain(&mut h, results);
    models_table(&mut h, scene, results);
    StudyResult::report(&results.studies, &super::figures::context(scene), &mut h)?;

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
    h.push_str("<h2>Studies</h2>\n<table>");
    if results.ran_together() {
        h.push_str("<caption>The studies ran at the same time on the machine's cores, so their wall times overlap: each includes the time it shared the cores with the others.</caption>");
    }
    h.push_str("\n<tr><th>study</th><th>kind</th><th>models</th><th>points</th><th>wall time [s]</th><th>details</th></tr>\n");
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

/// The models computed outside the domain their law holds on (none: no section).
fn left_domain(h: &mut String, results: &Results) {
    let e = escape;
    let notes: Vec<_> = results
        .studies
        .iter()
        .flat_map(|s| s.left_domain.iter().map(move |l| (&s.name, l)))
        .collect();
    if notes.is_empty() {
        return;
    }
    h.push_str("<h2>Where a law left its domain</h2>\n<p>Computed and written all the same, each row flagged <code>in_domain = false</code> in its table (see <code>docs/explicit_law.md</code>).</p>\n");
    for (study, l) in notes {
        let _ = writeln!(
            h,
            "<div class=\"note\"><b>{}</b> — {}:<br>{}</div>",
            e(study),
            e(&l.model),
            e(&l.message)
        );
    }
}

/// What a run used: the energies (the material's first), the (approach, model) pairs of every
/// study, whether a constant activation ([`crate::studies::outputs::KindOutput::used`]).
fn used(scene: &Scene, results: &Results) -> Used {
    let mut used = Used {
        energies: vec![scene.models.energy.name().to_string()],
        ..Used::default()
    };
    for s in &results.studies {
        used.merge(s.result.used());
    }
    used
}

/// The models the run used, in the words of the figures and `curves.csv`, with their equations
/// and where the chapter has them.
fn models_table(h: &mut String, scene: &Scene, results: &Results) {
    let used = used(scene, results);
    let mut rows = energy_rows(scene, &used.energies);
    rows.extend(model_rows(scene, &used));
    if let Some(v) = &scene.models.volumetric {
        rows.push((
            format!("incompressibility: {}", v.form().name()),
            format!(
                "nearly incompressible: Ŵ + U(J), U = {}{}, bulk modulus U″(1) = {} kPa; uniaxial, cylinder and activation-in-time studies (fit and stability: exact)",
                v.formula(),
                if v.shift() == 0.0 {
                    ""
                } else {
                    " (the linear term makes the reference stress free)"
                },
                v.bulk_modulus()
            ),
            "not in the chapter (eq. (2) is exact: det C = 1)".to_string(),
        ));
    }
    h.push_str("<h2>Models and the chapter's equations</h2>\n<p>The names the figures and the CSV files use, what each is, and where the chapter has it (equation, table and figure numbers of the arXiv preprint, see <code>docs/equations.md</code>).</p>\n<table><tr><th>name</th><th>what it is</th><th>chapter</th></tr>\n");
    for (name, what, chapter) in rows {
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td></tr>",
            escape(&name),
            escape(&what),
            escape(&chapter)
        );
    }
    h.push_str("</table>\n");
}

/// A row of the models table: (name, what it is, where the chapter has it).
type ModelRow = (String, String, String);

/// A row per energy; the material's with its parameter values.
fn energy_rows(scene: &Scene, energies: &[String]) -> Vec<ModelRow> {
    let m = &scene.models;
    let mut rows = Vec::new();
    for name in energies {
        let (what, chapter) = ShippedEnergy::find(name)
            .map_or(("a user-defined energy", "not in the chapter"), |e| {
                (e.formula, e.chapter)
            });
        let mut what = what.to_string();
        if let (true, crate::energy::Energy::Formula(f)) = (*name == m.energy.name(), &m.energy) {
            let written = crate::models::FormulaSpec::parameters_text(f);
            rows.push((
                format!("{name} (energy)"),
                format!(
                    "the material: an energy written as a formula in the scene, W = {} [kPa]; with {written}",
                    f.formula_line()
                ),
                "not in the chapter".into(),
            ));
            continue;
        }
        if *name == m.energy.name() {
            let values: Vec<String> = m
                .energy
                .parameters()
                .iter()
                .zip(m.energy.parameter_values())
                .map(|(p, v)| format!("{} = {v}", p.symbol))
                .collect();
            what.push_str(&format!("; the material, with {}", values.join(", ")));
        }
        rows.push((format!("{name} (energy)"), what, chapter.into()));
    }
    rows
}

/// The rows of the activation, the active curve, damage, laws and couplings the run used.
fn model_rows(scene: &Scene, used: &Used) -> Vec<ModelRow> {
    let m = &scene.models;
    let constant = used.constant;
    // Every activation model (of any approach; active stress has no law).
    let chosen: Vec<ModelChoice> = used.models.iter().filter_map(|a| a.model).collect();
    // The scene's approach first, then the others its studies used, each as the registry
    // describes it.
    let mut approaches = Vec::new();
    if constant || !chosen.is_empty() {
        approaches.push(scene.defaults.approach);
    }
    for a in chosen.iter().map(|c| c.approach) {
        if !approaches.contains(&a) {
            approaches.push(a);
        }
    }
    let mut rows: Vec<ModelRow> = Vec::new();
    if !approaches.is_empty() {
        rows.push((
            "λ_f, fibre stretch".into(),
            "λ_f = √(C:M), the argument of the activation laws and of the active curve".into(),
            "–".into(),
        ));
        rows.push((
            "P_tot, P_pas".into(),
            "nominal stress in uniaxial tension along the fibres, P_tot(λ, γ) = ∂Ŵ/∂λ; P_pas(λ) = P_tot(λ, 0)".into(),
            "eqs. (10), (11)".into(),
        ));
    }
    if !chosen.is_empty() {
        rows.extend(curve_rows(m));
    }
    rows.extend(law_rows(m, &chosen, constant));
    // The rows are written with the active-strain γ; the scene's approach may name its
    // variable otherwise (the structural ω).
    if let Some(v) = scene.defaults.approach.variable().filter(|v| *v != "γ") {
        for row in &mut rows {
            row.1 = row.1.replace('γ', v);
        }
    }
    let mut all: Vec<ModelRow> = approaches.iter().map(|a| approach_row(*a, m)).collect();
    all.extend(rows);
    all
}

/// The rows of the active curve, the damage and the force–velocity factor.
fn curve_rows(m: &crate::models::Models) -> Vec<ModelRow> {
    let c = &m.curve;
    let chapter = matches!(c, crate::active::ActiveCurve::Chapter(_));
    let mut rows = vec![
        (
            format!("P_act, active curve ({})", c.name()),
            format!(
                "P_act(λ) = {} for λ > λ_min, else 0 ({}); here {}",
                c.formula(),
                c.source(),
                crate::studies::outputs::curve_parameters_text(c)
            ),
            if chapter {
                "eq. (8); parameters Table 2".into()
            } else {
                "not in the chapter".into()
            },
        ),
        (
            "d, damage".into(),
            "loss of activation: the active stress becomes (1 − d) P_act".into(),
            "the chapter's loss of activation (Fig. 9)".into(),
        ),
    ];
    if m.force_velocity.is_some() {
        rows.push((
            "f_v, force–velocity".into(),
            "Böl & Reese (2008): the target becomes (1 − d)·a·f_v(λ̇)·P_act in activation-in-time studies, λ̇ by backward Euler over the time step (0 at the first step); quasi-static studies have λ̇ = 0, f_v = 1".into(),
            "not in the chapter".into(),
        ));
    }
    rows
}

/// The rows of the constant γ, the laws and the couplings the `chosen` models (of approaches
/// that have a law) used.
fn law_rows(m: &crate::models::Models, chosen: &[ModelChoice], constant: bool) -> Vec<ModelRow> {
    let laws: Vec<(LawKind, CouplingKind)> = chosen
        .iter()
        .filter_map(ModelChoice::activation_law)
        .collect();
    let used = |law: LawKind| laws.iter().any(|x| x.0 == law);
    let mut rows: Vec<ModelRow> = Vec::new();
    if constant {
        rows.push(("constant γ".into(), "γ held fixed".into(), "Fig. 5".into()));
    }
    if used(LawKind::Implicit) {
        rows.push((
            "implicit law".into(),
            "γ(λ) solves P_tot(λ, γ) = P_pas(λ) + (1 − d) P_act(λ) (γ = 0 for λ ≤ λ_min)".into(),
            "eqs. (12)–(13)".into(),
        ));
    }
    if used(LawKind::Explicit) {
        rows.push((
            "explicit law".into(),
            format!(
                "the closed-form approximation of the implicit law, γ(λ; a, b) with a = {}, b = {} (γ = 0 for λ ≤ λ_min), on its domain 0.7 ≤ λ_f ≤ 1.5, d_eff = d + (1 − d)(1 − a) ≤ 0.5 only (docs/explicit_law.md)",
                m.explicit.0, m.explicit.1
            ),
            "eq. (14)".into(),
        ));
    }
    if used(LawKind::Energy) {
        rows.push((
            "energy law".into(),
            "γ(λ) solves Ŵ(λ, γ) = W_pas(λ) + (1 − d) ∫_{λ_min}^{λ} P_act: its consistent model reproduces P_pas + (1 − d) P_act".into(),
            "not in the chapter (Giantesio & Musesti 2017, strain-dependent internal parameters)".into(),
        ));
    }
    if laws.iter().any(|x| x.1 == CouplingKind::Frozen) {
        rows.push((
            "frozen coupling".into(),
            "P = ∂Ŵ/∂F − p F⁻ᵀ at γ = g(λ_f) held: the chapter's model (not a gradient)".into(),
            "eq. (7)".into(),
        ));
    }
    if laws.iter().any(|x| x.1 == CouplingKind::Consistent) {
        rows.push((
            "consistent coupling".into(),
            "the hyperelastic Ψ(F) = Ŵ(F, g(λ_f(F))), differentiated through the law".into(),
            "not in the chapter".into(),
        ));
    }
    rows
}

/// The row of an activation approach, with the scene's map, as the registry describes it.
fn approach_row(approach: crate::active::Approach, m: &crate::models::Models) -> ModelRow {
    let [name, what, chapter] = approach.row(m.map);
    (name.into(), what.into(), chapter.into())
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

    h.push_str("<h2>Data</h2>\n<p>One CSV file per table; every column's type, unit and meaning in <code>datapackage.json</code>. An empty cell does not apply to its row.</p>\n<table><tr><th>file</th><th>rows</th><th>one row per</th><th>columns</th></tr>\n");
    for t in &info.tables {
        let _ = writeln!(
            h,
            "<tr><td><code>{}</code></td><td>{}</td><td>{}</td><td>{}</td></tr>",
            e(&t.file),
            t.rows,
            e(t.rows_are.trim_start_matches("one row per ")),
            code_list(t.columns.iter().map(String::as_str))
        );
    }
    h.push_str("</table>\n");
    h.push_str("<p>Other files: ");
    h.push_str(&code_list(info.files.iter().map(String::as_str)));
    h.push_str("</p>\n");
}

/// `items` as `<code>` elements (escaped), separated by commas.
fn code_list<'a>(items: impl IntoIterator<Item = &'a str>) -> String {
    items
        .into_iter()
        .map(|c| format!("<code>{}</code>", escape(c)))
        .collect::<Vec<_>>()
        .join(", ")
}
