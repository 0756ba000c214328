//! The cylinder kind's figures and report sections: γ, λ_f and P (FE and 0D) per study; FE minus
//! 0D over every study; the table of the largest |P_FE − P_0D|; the named points; why γ at the
//! centre vanishes at some stretches.

use super::{bases_name, CylinderResult, SweepPoint};
use crate::app_error::AppError;
use crate::fem::Bases;
use crate::models::{CouplingKind, LawKind};
use crate::plot::{short, Figure, Series, Stroke, GREY};
use crate::studies::curves::{self, sweep_curve};
use crate::studies::outputs::{
    chapter, derived, figure, key, list, model_cells, model_words, panel, Context, KindOutput, Of,
    OwnTable, Used, GAMMA, STRESS,
};
use crate::studies::slug;
use crate::studies::table::{every_row, Table};
use crate::text::escape_html as escape;
use std::fmt::Write;
use std::path::{Path, PathBuf};

impl CylinderResult {
    /// The table of `points_<study>.csv`: the displacement (u_r, u_z) of each named point
    /// (reference r, z; the mesh's length unit) per sweep and stretch.
    pub fn points_table(&self, study: &str) -> Table {
        let mut rows = Vec::new();
        for sweep in &self.sweeps {
            for (p, u) in sweep.points.iter().zip(&sweep.displacements) {
                for ((name, at), u) in self.points.iter().zip(u) {
                    rows.push((sweep.model, name, *at, p.lambda, *u));
                }
            }
        }
        let cells = |m| model_cells(self.approach, Some(m));
        let cell = |i: usize| rows.iter().map(move |r| cells(r.0)[i].clone());
        let length = "the mesh's length unit";
        Table::default()
            .text("study", "the study's name", every_row(study, rows.len()))
            .text(
                "point",
                "the point's name ([study.points])",
                rows.iter().map(|r| Some(r.1.clone())),
            )
            .number(
                "r",
                length,
                "reference radial position",
                rows.iter().map(|r| Some(r.2[0])),
            )
            .number(
                "z",
                length,
                "reference axial position",
                rows.iter().map(|r| Some(r.2[1])),
            )
            .text(
                "law",
                "implicit, explicit or energy (empty: an approach without a law, active stress)",
                cell(1),
            )
            .text(
                "coupling",
                "frozen or consistent (empty: an approach without a law)",
                cell(2),
            )
            .number("d", "-", "damage d", rows.iter().map(|r| Some(r.0.damage)))
            .number(
                "lambda",
                "-",
                "imposed stretch L/L₀",
                rows.iter().map(|r| Some(r.3)),
            )
            .number(
                "u_r",
                length,
                "radial displacement",
                rows.iter().map(|r| Some(r.4[0])),
            )
            .number(
                "u_z",
                length,
                "axial displacement",
                rows.iter().map(|r| Some(r.4[1])),
            )
            .text(
                "approach",
                "activation approach, active-strain, active-stress or structural",
                cell(0),
            )
    }
}

impl KindOutput for CylinderResult {
    /// Its rows of `curves.csv` and, if it names points, `points_<study>.csv`.
    fn tables(&self, study: &str) -> Vec<OwnTable> {
        let mut tables = vec![curves::own_table(&curves::cylinder_rows(study, self))];
        if !self.points.is_empty() {
            tables.push(OwnTable {
                key: "named_points",
                file: format!("points_{}.csv", slug(study)),
                rows_are: "one row per named point, model and stretch: its displacement",
                table: self.points_table(study),
            });
        }
        tables
    }

    fn used(&self) -> Used {
        Used::active(self.approach, self.sweeps.iter().map(|s| s.model))
    }

    fn vtk_files(&self) -> Vec<&Path> {
        self.sweeps
            .iter()
            .flat_map(|s| s.vtk_files.iter().map(PathBuf::as_path))
            .collect()
    }

    /// The verification of sliding bases: the largest |P_FE − P_0D| per sweep (with regions, the
    /// distance from the uniform model's curve, said so).
    fn console(&self, _study: &str) -> Vec<String> {
        if self.bases != Bases::Sliding {
            return Vec::new();
        }
        self.sweeps
            .iter()
            .filter_map(|s| {
                s.worst_against_0d().map(|(worst, _, _)| match self.regions_in_words() {
                    None => format!(
                        "verification (sliding bases, {}): max |P_FE − P_0D| = {worst:.2e} kPa",
                        s.label
                    ),
                    Some(r) => format!(
                        "sliding bases with regions ({r}), {}: max |P_FE − P_0D| = {worst:.2e} kPa against the uniform model's 0D curve, the regions' own damage or activation (not a verification)",
                        s.label
                    ),
                })
            })
            .collect()
    }

    fn figures(studies: &[Of<Self>], cx: &Context) -> Vec<Figure> {
        let mut out: Vec<Figure> = studies.iter().filter_map(|s| cylinder(cx, s)).collect();
        out.extend(fe_vs_0d(studies));
        out
    }

    fn report(studies: &[Of<Self>], cx: &Context, h: &mut String) -> Result<(), AppError> {
        fe_table(h, studies);
        points_table(h, studies);
        centre_note(h, cx, studies);
        super::volume::volume_note(h, studies);
        Ok(())
    }
}

/// A cylinder study: γ and λ_f at the centre, and the nominal stress (FE solid, the homogeneous
/// 0D curve of the same model dashed), a curve per damage.
fn cylinder(cx: &Context, study: &Of<CylinderResult>) -> Option<Figure> {
    let (c, details) = (study.result, study.details);
    let study = study.name;
    // A study none of whose sweeps converged at a stretch has nothing to draw.
    if c.sweeps.iter().all(|s| s.points.is_empty()) {
        return None;
    }
    let by_damage = |y: fn(&SweepPoint) -> f64| -> Vec<Option<Series>> {
        c.sweeps
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let points: Vec<(f64, f64)> = s.points.iter().map(|p| (p.lambda, y(p))).collect();
                (!points.is_empty()).then(|| {
                    Series::new(format!("d = {}", s.model.damage), points, Stroke::Solid, i)
                        .drawing(sweep_curve(study, c, s))
                })
            })
            .collect()
    };
    let mut fibre = by_damage(|p| p.fibre_stretch_centre);
    fibre.push(lambda_min_line(c, cx.curve.lambda_min()));
    let mut p = by_damage(|p| p.stress);
    for (i, s) in c.sweeps.iter().enumerate() {
        p.push(derived(
            "",
            s.points
                .iter()
                .filter_map(|q| q.stress_0d.map(|z| (q.lambda, z)))
                .collect(),
            Stroke::Dashed,
            i,
        ));
    }
    p.push(key("dashed: homogeneous (0D)", Stroke::Dashed));
    let m = c.sweeps.first()?.model;
    let ds: Vec<f64> = c.sweeps.iter().map(|s| s.model.damage).collect();
    let lawful = m.activation_law().is_some();
    let like_fig_12 = c.bases == Bases::Clamped
        && m.activation_law() == Some((LawKind::Explicit, CouplingKind::Frozen));
    let geometry = details.first().map_or(String::new(), |d| format!(" ({d})"));
    figure(
        "fig_cylinder",
        format!(
            "The cylinder \"{study}\": {} bases, {}, d = {}{}",
            bases_name(c.bases),
            model_words(&m),
            list(&ds),
            if like_fig_12 {
                chapter(12, &c.energy, cx.chapter_material)
            } else {
                String::new()
            }
        ),
        caption(c, &geometry, lawful),
        vec![
            lawful
                .then(|| {
                    panel(
                        "γ at the centre of the cylinder",
                        GAMMA,
                        by_damage(|p| p.gamma_centre),
                    )
                })
                .flatten(),
            panel(
                "Fibre stretch λ_f at the centre",
                "fibre stretch λ_f [-]",
                fibre,
            ),
            panel("Nominal axial stress", STRESS, p),
        ],
    )
}

/// The dashed line at λ_f = `lmin` across the stretches of `c`.
fn lambda_min_line(c: &CylinderResult, lmin: f64) -> Option<Series> {
    let (lo, hi) = c
        .sweeps
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.lambda))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |a, l| {
            (a.0.min(l), a.1.max(l))
        });
    derived(
        format!("λ_min = {lmin}"),
        vec![(lo, lmin), (hi, lmin)],
        Stroke::Dashed,
        GREY,
    )
}

/// The caption of [`cylinder`]: what its panels show (no γ panel for a model without a law).
fn caption(c: &CylinderResult, geometry: &str, lawful: bool) -> String {
    format!(
        "Axisymmetric FE cylinder{geometry}, energy {}. {}; bottom: nominal axial stress (axial reaction / πR²), dashed: {}.",
        c.energy,
        if lawful {
            "Top: γ at the quadrature point nearest the centre of the cylinder; middle: the fibre stretch λ_f there, the argument of the law (the implicit and explicit laws give γ = 0 where λ_f ≤ λ_min)"
        } else {
            "Top: the fibre stretch λ_f at the quadrature point nearest the centre of the cylinder, the argument of the active stress (0 where λ_f ≤ λ_min): the approach has no activation variable"
        },
        match c.regions_in_words() {
            None => "the homogeneous uniaxial (0D) curve of the same model".to_string(),
            Some(regions) => format!(
                "the homogeneous uniaxial (0D) curve of the uniform model at the sweep's d, \
                 without the regions ({regions}): a reference, not the same body"
            ),
        }
    )
}

/// P_FE − P_0D of every sweep, a panel per cylinder study.
fn fe_vs_0d(studies: &[Of<CylinderResult>]) -> Option<Figure> {
    let drawn = || {
        studies
            .iter()
            .map(|s| (s.name, s.result))
            .filter(|(_, c)| c.sweeps.iter().any(|s| !s.points.is_empty()))
    };
    let regions: Vec<String> = drawn()
        .filter_map(|(study, c)| {
            c.regions_in_words().map(|r| {
                let bases = match c.bases {
                    Bases::Sliding => "its sliding bases add no end effect",
                    _ => "its clamped bases add their end effect",
                };
                format!("\"{study}\" has regions ({r}); {bases}")
            })
        })
        .collect();
    let panels = drawn()
        .map(|(study, c)| {
            let s = c
                .sweeps
                .iter()
                .enumerate()
                .map(|(i, w)| {
                    let points = w
                        .points
                        .iter()
                        .filter_map(|p| p.stress_0d.map(|z| (p.lambda, p.stress - z)))
                        .collect();
                    derived(format!("d = {}", w.model.damage), points, Stroke::Solid, i)
                })
                .collect();
            let model = c
                .sweeps
                .first()
                .map_or(String::new(), |w| format!(", {}", model_words(&w.model)));
            panel(
                format!(
                    "{study} ({} bases{model}): P_FE − P_0D",
                    bases_name(c.bases)
                ),
                "P_FE − P_0D [kPa]",
                s,
            )
        })
        .collect();
    figure(
        "fig_fe_vs_0d",
        "FE cylinder against homogeneous (0D) tension (ours)".into(),
        format!(
            "Nominal stress of the FE cylinder (axial reaction / πR²) minus the homogeneous uniaxial curve of the same model, per damage. For a uniform body, sliding bases must match the 0D curve to solver tolerance (the built-in verification); clamped bases do not, the difference is the end effect.{} The table \"FE vs homogeneous (0D) tension\" gives the largest difference where the active stress dominates.",
            if regions.is_empty() {
                String::new()
            } else {
                format!(
                    " {}: the 0D curve of a study with regions is the uniform model's at the sweep's d, so the difference is mostly the regions' own damage or activation, not a verification.",
                    regions.join("; ")
                )
            }
        ),
        panels,
    )
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
fn points_table(h: &mut String, studies: &[Of<CylinderResult>]) {
    let e = escape;
    let studies: Vec<_> = studies
        .iter()
        .map(|s| (s.name, s.result))
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
                        "<tr><td>{}</td><td>{}</td><td>({}, {})</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                        e(study),
                        e(name),
                        at[0],
                        at[1],
                        e(&sweep.label),
                        p.lambda,
                        crate::text::significant(u[0], 7),
                        crate::text::significant(u[1], 7)
                    );
                }
            }
        }
    }
    h.push_str("</table>\n");
}

/// Each FE sweep against the homogeneous (0D) curve of the same model: the largest difference
/// where the activation shows (the active range) and over every stretch.
fn fe_table(h: &mut String, studies: &[Of<CylinderResult>]) {
    let e = escape;
    let sweeps: Vec<_> = studies
        .iter()
        .map(|s| (s.name, s.result))
        .flat_map(|(study, c)| c.sweeps.iter().map(move |s| (study, c, s)))
        .collect();
    if sweeps.is_empty() {
        return;
    }
    let regions = studies
        .iter()
        .map(|s| (s.name, s.result))
        .any(|(_, c)| !c.regions.is_empty());
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
fn centre_note(h: &mut String, cx: &Context, studies: &[Of<CylinderResult>]) {
    let lmin = cx.curve.lambda_min();
    let mut rows = String::new();
    for (study, c) in studies.iter().map(|s| (s.name, s.result)) {
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
