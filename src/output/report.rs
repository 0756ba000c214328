//! `report.html`: one self-contained page (figures embedded as base64 PNG) with the run's
//! summary, the notes of studies that stopped, the figures, the scene and the versions.

use super::base64;
use super::csv::{correlations, COLUMNS, HISTORY_COLUMNS};
use crate::app_error::{finite, AppError};
use crate::energy::Parametric;
use crate::models::{CouplingKind, LawKind, ModelChoice};
use crate::plot::{short, Rendered};
use crate::scene::{Results, Scene};
use crate::studies::cylinder::{bases_name, SweepPoint};
use crate::studies::uniaxial::CurveModel;
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
    /// Rows of `curves.csv`.
    pub rows: usize,
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
    models_table(&mut h, scene, results);
    fe_table(&mut h, results);
    points_table(&mut h, results);
    centre_note(&mut h, scene, results);
    fits_table(&mut h, results)?;
    stability_table(&mut h, results)?;
    shear_section(&mut h, results);
    biaxial_section(&mut h, results);

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

/// What the chapter calls the shipped energies: (name, what, where in the chapter).
const ENERGIES: &[(&str, &str, &str)] = &[
    (
        "giantesio-musesti",
        "the chapter's passive energy, W = μ/4 {[e^{α(I_p−1)} − 1]/α + K_p − 1}, I_p = (w0/3) tr C + (1−w0) C:M, K_p = (w0/3) tr C⁻¹ + (1−w0) C⁻¹:M",
        "eq. (1); parameters Table 1",
    ),
    (
        "ehret-bol-itskov",
        "the Ehret–Böl–Itskov energy: the K_p − 1 term becomes [e^{β(K_p−1)} − 1]/β",
        "eq. (4)",
    ),
    ("neo-hookean", "neo-Hookean reference, W = μ/2 (tr C − 3)", "not in the chapter"),
];

/// What a run used: the energies (the material's first), the active models, whether constant γ.
struct Used {
    energies: Vec<String>,
    chosen: Vec<ModelChoice>,
    constant: bool,
}

/// What `results` used (the scene gives the material).
fn used(scene: &Scene, results: &Results) -> Used {
    let m = &scene.models;
    let mut energies = vec![m.energy.name().to_string()];
    let mut chosen: Vec<ModelChoice> = Vec::new();
    let mut constant = false;
    for (_, u) in results.uniaxial() {
        for c in &u.curves {
            if !energies.contains(&c.energy) {
                energies.push(c.energy.clone());
            }
            match c.model {
                CurveModel::Active(x) => chosen.push(x),
                CurveModel::Constant(_) => constant = true,
                CurveModel::Passive => {}
            }
        }
    }
    for (_, c) in results.cylinders() {
        chosen.extend(c.sweeps.iter().map(|s| s.model));
    }
    for (_, curves) in results.stability() {
        chosen.extend(curves.iter().filter_map(|c| c.model));
    }
    for (_, r) in results.histories() {
        chosen.extend(r.histories.iter().map(|h| h.model));
    }
    for s in &results.studies {
        let models: Vec<&crate::studies::spec::ApproachModel> = match &s.result {
            StudyResult::Shear(r) => r.curves.iter().map(|c| &c.model).collect(),
            StudyResult::Biaxial(r) => r.curves.iter().map(|c| &c.model).collect(),
            _ => continue,
        };
        chosen.extend(
            models
                .iter()
                .filter(|a| a.approach.has_law())
                .filter_map(|a| a.model),
        );
    }
    Used {
        energies,
        chosen,
        constant,
    }
}

/// The models the run used, in the words of the figures and `curves.csv`, with their equations
/// and where the chapter has them.
fn models_table(h: &mut String, scene: &Scene, results: &Results) {
    let used = used(scene, results);
    let mut rows = energy_rows(scene, &used.energies);
    rows.extend(model_rows(scene, &used));
    // The approaches of shear and biaxial studies other than the scene's.
    let mut approaches: Vec<crate::active::Approach> = vec![scene.models.approach];
    for s in &results.studies {
        let models: Vec<&crate::studies::spec::ApproachModel> = match &s.result {
            StudyResult::Shear(r) => r.curves.iter().map(|c| &c.model).collect(),
            StudyResult::Biaxial(r) => r.curves.iter().map(|c| &c.model).collect(),
            _ => continue,
        };
        for m in models.iter().filter(|m| m.model.is_some()) {
            if !approaches.contains(&m.approach) {
                approaches.push(m.approach);
                rows.push(approach_row(&crate::models::Models {
                    approach: m.approach,
                    ..scene.models.clone()
                }));
            }
        }
    }
    if let Some(v) = &scene.models.volumetric {
        let form = v.form().formula();
        rows.push((
            format!("incompressibility: {}", v.form().name()),
            format!(
                "nearly incompressible: Ŵ + U(J), U = {form}{}, bulk modulus U″(1) = {} kPa; uniaxial, cylinder and activation-in-time studies (fit and stability: exact)",
                match v.shift() {
                    0.0 => String::new(),
                    c if c > 0.0 => format!(" + {c} kPa (J − 1) (stress-free reference)"),
                    c => format!(" − {} kPa (J − 1) (stress-free reference)", -c),
                },
                v.bulk_modulus()
            ),
            "not in the chapter (eq. (2) is exact: det C = 1)".to_string(),
        ));
    }
    h.push_str("<h2>Models and the chapter's equations</h2>\n<p>The names the figures, the tables and <code>curves.csv</code> use, what each is, and where the chapter has it (equation, table and figure numbers of the arXiv preprint, see <code>docs/equations.md</code>).</p>\n<table><tr><th>name</th><th>what it is</th><th>chapter</th></tr>\n");
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
        let (what, chapter) = ENERGIES
            .iter()
            .find(|(n, _, _)| n == name)
            .map_or(("a shipped energy", "not in the chapter"), |(_, w, c)| {
                (*w, *c)
            });
        let mut what = what.to_string();
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
    let (chosen, constant) = (&used.chosen, used.constant);
    let mut rows: Vec<ModelRow> = Vec::new();
    let active = !chosen.is_empty() || constant;
    if active {
        rows.push(approach_row(m));
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
        let c = &m.curve;
        let chapter = matches!(c, crate::active::ActiveCurve::Chapter(_));
        rows.push((
            format!("P_act, active curve ({})", c.name()),
            format!(
                "P_act(λ) = {} for λ > λ_min, else 0 ({}); here {}",
                c.formula(),
                c.source(),
                crate::output::figures::curve_parameters_text(c)
            ),
            if chapter {
                "eq. (8); parameters Table 2".into()
            } else {
                "not in the chapter".into()
            },
        ));
        rows.push((
            "d, damage".into(),
            "loss of activation: the active stress becomes (1 − d) P_act".into(),
            "the chapter's loss of activation (Fig. 9)".into(),
        ));
        if m.force_velocity.is_some() {
            rows.push((
                "f_v, force–velocity".into(),
                "Böl & Reese (2008): the target becomes (1 − d)·a·f_v(λ̇)·P_act in activation-in-time studies, λ̇ by backward Euler over the time step (0 at the first step); quasi-static studies have λ̇ = 0, f_v = 1".into(),
                "not in the chapter".into(),
            ));
        }
    }
    if !m.approach.has_law() {
        return rows;
    }
    let used = |law: LawKind| chosen.iter().any(|x| x.law == law);
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
                "the closed-form approximation of the implicit law, γ(λ; a, b) with a = {}, b = {} (γ = 0 for λ ≤ λ_min)",
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
    if chosen.iter().any(|x| x.coupling == CouplingKind::Frozen) {
        rows.push((
            "frozen coupling".into(),
            "P = ∂Ŵ/∂F − p F⁻ᵀ at γ = g(λ_f) held: the chapter's model (not a gradient)".into(),
            "eq. (7)".into(),
        ));
    }
    if chosen
        .iter()
        .any(|x| x.coupling == CouplingKind::Consistent)
    {
        rows.push((
            "consistent coupling".into(),
            "the hyperelastic Ψ(F) = Ŵ(F, g(λ_f(F))), differentiated through the law".into(),
            "not in the chapter".into(),
        ));
    }
    // The rows are written with the active-strain γ; the structural approach's variable is ω.
    if let Ok(map) = m.activation_map() {
        for row in rows.iter_mut().skip(1) {
            row.1 = row.1.replace('γ', map.variable());
        }
    }
    rows
}

/// The row of the scene's activation approach and map.
fn approach_row(m: &crate::models::Models) -> ModelRow {
    use crate::active::{ActiveStrainMap, Approach};
    match (m.approach, m.map) {
        (Approach::ActiveStress, _) => (
            "active stress".into(),
            "Ψ = W_pas(C) + (1 − d) ∫_{λ_min}^{λ_f} P_act, P = ∂W_pas/∂F + (1 − d) P_act(λ_f) F M/λ_f (FEBio, Blemker): no activation variable, no law; hyperelastic".into(),
            "not in the chapter".into(),
        ),
        (Approach::Structural, _) => (
            "ω, activation".into(),
            "activation in the structural tensor (Ehret, Böl & Itskov 2011; 4C's MAT_Muscle_Weickenmeier): W with I = C:(L + ωM), L = (w0/3) I + (1 − w0) M, ω = g(λ_f)".into(),
            "not in the chapter".into(),
        ),
        (Approach::ActiveStrain, ActiveStrainMap::VolumePreserving) => (
            "γ, activation".into(),
            "active strain F = F_e F_a with the volume-preserving F_a = (1 − γ) m⊗m + (1 − γ)^(−½)(I − m⊗m) (Weickenmeier et al. 2014; 4C's MAT_Muscle_Giantesio), Ŵ(F, γ) = W(C_e)".into(),
            "eqs. (5)–(6) with another F_a".into(),
        ),
        (Approach::ActiveStrain, ActiveStrainMap::Chapter) => (
            "γ, activation".into(),
            "active strain F = F_e F_a, F_a = I − γ m⊗m, Ŵ(F, γ) = (1 − γ) W(C_e)".into(),
            "eqs. (5)–(6)".into(),
        ),
    }
}

/// The largest |P_FE − P_0D| over the points `keep` accepts, as (difference, λ, P_0D).
fn largest(points: &[SweepPoint], keep: impl Fn(&SweepPoint) -> bool) -> Option<(f64, f64, f64)> {
    points
        .iter()
        .filter(|p| keep(p))
        .filter_map(|p| p.stress_0d.map(|z| ((p.stress - z).abs(), p.lambda, z)))
        .filter(|d| d.0.is_finite())
        .max_by(|a, b| a.0.total_cmp(&b.0))
}

/// Where the activation shows: the target active stress exceeds the passive one,
/// (1 − d) P_act(λ) > max(P_pas(λ), 0).
fn active(p: &SweepPoint) -> bool {
    p.passive_0d.is_some_and(|pas| p.active_0d > pas.max(0.0))
}

/// `2.95 kPa at λ = 1.3 (3.6 % of P_0D)`.
fn difference(d: Option<(f64, f64, f64)>) -> String {
    d.map_or("–".into(), |(d, l, z)| {
        format!(
            "{} kPa at λ = {l} ({} % of P_0D)",
            short(d),
            short(100.0 * d / z.abs().max(1e-300))
        )
    })
}

/// The displacements of the named boundary points of each cylinder study (`[study.points]`),
/// one row per point, model and stretch (also in `points_<study>.csv`).
fn points_table(h: &mut String, results: &Results) {
    let e = escape;
    let studies: Vec<_> = results
        .cylinders()
        .filter(|(_, c)| !c.points.is_empty())
        .collect();
    if studies.is_empty() {
        return;
    }
    h.push_str("<h2>Named points</h2>\n<p>Nodal displacements of the boundary points named in the scene (reference coordinates r, z; lengths in the mesh's unit), per model and stretch (<code>points_&lt;study&gt;.csv</code>).</p>\n<table><tr><th>study</th><th>point</th><th>(r, z)</th><th>model</th><th>λ</th><th>u_r</th><th>u_z</th></tr>\n");
    for (study, c) in studies {
        for sweep in &c.sweeps {
            for (p, u) in sweep.points.iter().zip(&sweep.displacements) {
                for ((name, at), u) in c.points.iter().zip(u) {
                    let _ = writeln!(
                        h,
                        "<tr><td>{}</td><td>{}</td><td>({}, {})</td><td>{}</td><td>{}</td><td>{:.6e}</td><td>{:.6e}</td></tr>",
                        e(study),
                        e(name),
                        at[0],
                        at[1],
                        e(&sweep.label),
                        p.lambda,
                        u[0],
                        u[1]
                    );
                }
            }
        }
    }
    h.push_str("</table>\n");
}

/// Each FE sweep against the homogeneous (0D) curve of the same model: the largest difference
/// where the activation shows (the active range) and over every stretch.
fn fe_table(h: &mut String, results: &Results) {
    let e = escape;
    let sweeps: Vec<_> = results
        .cylinders()
        .flat_map(|(study, c)| c.sweeps.iter().map(move |s| (study, c, s)))
        .collect();
    if sweeps.is_empty() {
        return;
    }
    let regions = results.cylinders().any(|(_, c)| !c.regions.is_empty());
    h.push_str("<h2>FE vs homogeneous (0D) tension</h2>\n<p>P_FE: the nominal axial stress of the FE cylinder (axial reaction / πR²); P_0D: homogeneous uniaxial tension of the same model. The <i>active range</i> is where the target active stress exceeds the passive one, (1 − d) P_act(λ) &gt; max(P_pas(λ), 0): there the activation shows. Beyond it the passive stress dominates, and with it the end effect of clamped bases. The last column is the number the studies table gives per sweep.");
    if regions {
        h.push_str(" A study with regions (their own damage or activation, listed under the model) is compared with the uniform model at the sweep's d: there the difference is mostly the regions', not the end effect.");
    }
    h.push_str("</p>\n<table><tr><th>study</th><th>bases</th><th>free dofs</th><th>model</th><th>stretches</th><th>active range</th><th>max |P_FE − P_0D| in the active range</th><th>max |P_FE − P_0D| over all stretches</th></tr>\n");
    for (study, c, s) in sweeps {
        let bases = c.bases;
        let model = match c.regions_in_words() {
            None => e(&s.label),
            Some(r) => format!("{}<br><small>regions: {}</small>", e(&s.label), e(&r)),
        };
        let range: Vec<f64> = s
            .points
            .iter()
            .filter(|p| active(p))
            .map(|p| p.lambda)
            .collect();
        let range = match (range.first(), range.last()) {
            (Some(a), Some(b)) => format!("λ = {a} … {b} ({} stretches)", range.len()),
            _ => "none".into(),
        };
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{range}</td><td>{}</td><td>{}</td></tr>",
            e(study),
            bases_name(bases),
            s.dofs,
            model,
            s.points.iter().filter(|p| p.stress_0d.is_some()).count(),
            difference(largest(&s.points, active)),
            difference(largest(&s.points, |_| true)),
        );
    }
    h.push_str("</table>\n");
}

/// Why γ at the centre of a cylinder is 0 at some stretches: the fibre stretch there is at or
/// below λ_min (the laws' γ = 0 region), shown with the numbers of every such stretch.
fn centre_note(h: &mut String, scene: &Scene, results: &Results) {
    let lmin = scene.models.curve.lambda_min();
    let mut rows = String::new();
    for (study, c) in results.cylinders() {
        for s in &c.sweeps {
            let below: Vec<&SweepPoint> = s
                .points
                .iter()
                .filter(|p| p.fibre_stretch_centre <= lmin)
                .collect();
            if below.is_empty() {
                continue;
            }
            let _ = writeln!(
                rows,
                "<tr><td>{}</td><td>{}</td><td>{}</td></tr>",
                escape(study),
                escape(&s.label),
                below
                    .iter()
                    .map(|p| format!(
                        "λ = {}: λ_f = {}, γ = {}",
                        p.lambda,
                        short(p.fibre_stretch_centre),
                        short(p.gamma_centre)
                    ))
                    .collect::<Vec<_>>()
                    .join("<br>")
            );
        }
    }
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(
        h,
        "<h2>γ at the centre of the cylinder</h2>\n<p>At these applied stretches the fibre stretch λ_f at the centre of the cylinder is at or below λ_min = {lmin}, where the active curve vanishes (P_act = 0 for λ ≤ λ_min, eq. (8)): the implicit and explicit laws give γ = 0 there, for every d. In compression a cylinder with clamped bases cannot widen at its ends, so the ends shorten less and the middle more than the applied stretch; with sliding bases the deformation is homogeneous and λ_f = λ. The energy law continued below λ_min on its zero-work branch (<code>below_minimum = \"zero-work\"</code>) keeps γ &gt; 0 there. The middle panel of each cylinder figure shows λ_f at the centre against λ_min.</p>\n<table><tr><th>study</th><th>model</th><th>stretches with λ_f ≤ λ_min at the centre</th></tr>\n{rows}</table>"
    );
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
    h.push_str(&code_list(COLUMNS));
    let _ = writeln!(
        h,
        ". Stresses in kPa (nominal, along the stretch; <code>cauchy</code> the Cauchy stress); \
         <code>P_act</code> is the active stress with its damage, (1 − d) P_act(λ); \
         <code>gamma</code> is γ at the point for uniaxial rows and γ at the centre of the \
         cylinder for cylinder rows; an empty cell does not apply. {}</p>",
        if info.rows == 0 {
            "No rows: this scene has no uniaxial or cylinder study.".to_string()
        } else {
            format!("{} rows.", info.rows)
        }
    );
    if info.files.iter().any(|f| f == "history.csv") {
        h.push_str("<p><code>history.csv</code>: one row per activation-in-time model and time step, columns ");
        h.push_str(&code_list(HISTORY_COLUMNS));
        h.push_str(". t in s; a_schedule (the schedule), a (the activation level used), λ, γ and the volume ratio J dimensionless; P (nominal), cauchy (σ₁₁ = P λ / J), P_pas and P_act (the target (1 − d) a P_act(λ)) in kPa.</p>\n");
    }
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

/// Parameters ± standard errors, reference values, correlation, RMS, iterations, convergence.
fn fits_table(h: &mut String, results: &Results) -> Result<(), AppError> {
    let studies = results.fits();
    if studies.iter().all(|(_, f)| f.is_empty()) {
        return Ok(());
    }
    let e = escape;
    h.push_str("<h2>Fits</h2>\n<p>Least squares with dual-number Jacobians (<code>fits.csv</code> has the same numbers). Standard errors σ = √(s²(JᵀJ)⁻¹); a fit marked <b>NOT converged</b> shows the best point found, which is not a solution.</p>\n<table><tr><th>study</th><th>data</th><th>parameter</th><th>value ± std. error</th><th>reference</th><th>correlation with the others</th><th>RMS</th><th>iterations</th><th>status</th></tr>\n");
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
            let corr = match f.correlation.get(j) {
                Some(row) => correlations(row, &f.names, j, |c| {
                    finite(c, "correlation", origin).map(|c| format!("{c:.4}"))
                })?,
                None => String::new(),
            };
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

/// What differs in simple shear and why: σ₁₂ at the largest amount of shear per model and fibre
/// angle, with the boundary conditions.
fn shear_section(h: &mut String, results: &Results) {
    for s in &results.studies {
        let StudyResult::Shear(r) = &s.result else {
            continue;
        };
        let _ = writeln!(
            h,
            "<h2>Simple shear (study \"{}\")</h2>\n<p>F = I + k e₁⊗e₂, incompressible; the faces normal to e₃ are traction free (σ₃₃ = 0 fixes the pressure), the others carry what the homogeneous state needs. The fibre lies in the shear plane at θ to e₁. Every approach is calibrated to the same uniaxial target along the fibres, so uniaxial tests cannot tell them apart; in shear they differ. With the fibre along the shear direction (θ = 0) the fibre stretch stays 1: active stress adds only a tension (1 − d) P_act(1) along e₁ (σ₁₁), while active strain (and the structural activation) stiffen or soften the shear response itself (Giantesio, Musesti &amp; Riccobelli 2019).</p>\n<table><tr><th>model</th><th>θ</th><th>k</th><th>σ₁₂ [kPa]</th><th>σ₁₁ [kPa]</th><th>σ₂₂ [kPa]</th></tr>",
            escape(&s.name)
        );
        for c in &r.curves {
            let Some(p) = c.points.last() else { continue };
            let words = c.model.words();
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td>{}°</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                escape(&words),
                c.angle,
                p.k,
                crate::text::significant(p.sigma[0], 6),
                crate::text::significant(p.sigma[1], 6),
                crate::text::significant(p.sigma[2], 6)
            );
        }
        h.push_str("</table>\n");
    }
}

/// Planar biaxial stretch: the boundary conditions, and both stresses at the last state of the
/// path per model.
fn biaxial_section(h: &mut String, results: &Results) {
    for s in &results.studies {
        let StudyResult::Biaxial(r) = &s.result else {
            continue;
        };
        let _ = writeln!(
            h,
            "<h2>Planar biaxial stretch (study \"{}\", {} path)</h2>\n<p>F = diag(λ₁, λ₂, λ₃), λ₁ along the fibres and λ₂ across; the faces normal to e₃ are traction free, so λ₃ = 1/(λ₁λ₂) (incompressible) or solves P₃₃ = 0 with the volumetric energy. An isotropic material has P₁₁ = P₂₂ on the equibiaxial path; the fibres, and an activation along them, break that symmetry. Active stress adds (1 − d) P_act(λ₁) to P₁₁ alone; active strain changes the stiffness across the fibres too.</p>\n<table><tr><th>model</th><th>λ₁</th><th>λ₂</th><th>λ₃</th><th>P₁₁ [kPa]</th><th>P₂₂ [kPa]</th><th>σ₁₁ [kPa]</th><th>σ₂₂ [kPa]</th></tr>",
            escape(&s.name),
            r.path
        );
        let number = |x: f64| crate::text::significant(x, 6);
        for c in &r.curves {
            let Some(p) = c.points.last() else { continue };
            let [l1, l2, l3] = p.stretches;
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                escape(&c.model.words()),
                number(l1),
                number(l2),
                number(l3),
                number(p.nominal[0]),
                number(p.nominal[1]),
                number(p.cauchy[0]),
                number(p.cauchy[1])
            );
        }
        h.push_str("</table>\n");
    }
}
