//! The chapter's figures (and two of ours) built from the rows of a run. A figure whose data the
//! scene did not compute is skipped.

use super::plot::{Figure, Panel, Series, Stroke};
use crate::energy::StrainEnergy;
use crate::scene::run::{Results, Row};
use crate::scene::Scene;

const LAMBDA: &str = "stretch λ [-]";
const STRESS: &str = "nominal stress P [kPa]";
const GAMMA: &str = "activation γ [-]";

fn curve(
    rows: &[Row],
    keep: impl Fn(&Row) -> bool,
    y: impl Fn(&Row) -> Option<f64>,
) -> Vec<(f64, f64)> {
    let mut v: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| keep(r))
        .filter_map(|r| y(r).map(|y| (r.lambda, y)))
        .collect();
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    v
}

fn series(
    label: impl Into<String>,
    points: Vec<(f64, f64)>,
    stroke: Stroke,
    colour: usize,
) -> Option<Series> {
    if points.is_empty() {
        None
    } else {
        Some(Series {
            label: label.into(),
            points,
            stroke,
            colour,
        })
    }
}

fn panel(
    title: &str,
    y_label: &str,
    series: Vec<Option<Series>>,
    y_range: Option<(f64, f64)>,
) -> Option<Panel> {
    let series: Vec<Series> = series.into_iter().flatten().collect();
    if series.is_empty() {
        None
    } else {
        Some(Panel {
            title: title.into(),
            x_label: LAMBDA.into(),
            y_label: y_label.into(),
            series,
            y_range,
        })
    }
}

fn figure(stem: &str, heading: &str, caption: &str, panels: Vec<Option<Panel>>) -> Option<Figure> {
    if panels.is_empty() || panels.iter().any(Option::is_none) {
        return None;
    }
    Some(Figure {
        stem: stem.into(),
        heading: heading.into(),
        caption: caption.into(),
        panels: panels.into_iter().flatten().collect(),
    })
}

fn along(r: &Row) -> bool {
    r.model == "uniaxial" && r.direction == Some("along")
}

fn active(r: &Row, law: &str, coupling: &str, d: f64) -> bool {
    along(r) && r.law == law && r.coupling == Some(coupling) && r.d == Some(d)
}

fn damages(rows: &[Row], keep: impl Fn(&Row) -> bool) -> Vec<f64> {
    let mut d: Vec<f64> = rows
        .iter()
        .filter(|r| keep(r))
        .filter_map(|r| r.d)
        .collect();
    d.sort_by(f64::total_cmp);
    d.dedup();
    d
}

/// Every figure the results support, in the chapter's order, then ours.
pub fn figures(scene: &Scene, results: &Results) -> Vec<Figure> {
    let rows = &results.rows;
    let material = scene.material.name().to_string();
    let mut out = Vec::new();
    // Stress range in which the active model's features are visible (the passive exponential
    // reaches hundreds of kPa at λ = 1.6).
    let active_range = Some((-5.0, 160.0));

    // D:paragoneebi — passive energies along the fibres.
    let mut energies: Vec<String> = rows
        .iter()
        .filter(|r| along(r) && r.law == "passive")
        .map(|r| r.energy.clone())
        .collect();
    energies.dedup();
    energies.sort();
    energies.dedup();
    if energies.len() >= 2 {
        let s = energies
            .iter()
            .enumerate()
            .map(|(i, e)| {
                series(
                    e.clone(),
                    curve(
                        rows,
                        |r| along(r) && r.law == "passive" && &r.energy == e,
                        |r| Some(r.p),
                    ),
                    if i == 0 {
                        Stroke::Solid
                    } else {
                        Stroke::Dashed
                    },
                    i,
                )
            })
            .collect();
        out.extend(figure(
            "fig_passive_vs_ebi",
            "Fig. D:paragoneebi — passive energies in uniaxial tension along the fibres",
            "Nominal stress of the chapter's passive energy (eq. D:Wpassiva) and of the Ehret–Böl–Itskov energy (eq. D:Webi) it simplifies, uniaxial tension along the fibres.",
            vec![panel("Passive stress along the fibres", STRESS, s, Some((-5.0, 160.0)))],
        ));
    }

    // D:biaxial — transverse isotropy.
    let material = &material;
    let passive_dir = |dir: &'static str| {
        curve(
            rows,
            move |r| {
                r.model == "uniaxial"
                    && r.direction == Some(dir)
                    && r.law == "passive"
                    && &r.energy == material
            },
            |r| Some(r.p),
        )
    };
    out.extend(figure(
        "fig_transverse_isotropy",
        "Fig. D:biaxial — transversely isotropic behaviour",
        "Passive nominal stress of the chapter's energy in uniaxial tension along and across the fibres (both lateral faces traction free).",
        vec![panel(
            "Passive stress along and across the fibres",
            STRESS,
            vec![
                series("along the fibres", passive_dir("along"), Stroke::Solid, 0),
                series("across the fibres", passive_dir("across"), Stroke::Dashed, 1),
            ],
            Some((-5.0, 160.0)),
        )],
    ));

    // D:gamma-s-s — constant γ.
    let mut gammas: Vec<f64> = rows
        .iter()
        .filter(|r| along(r) && r.law == "constant")
        .filter_map(|r| r.gamma)
        .collect();
    gammas.sort_by(f64::total_cmp);
    gammas.dedup();
    out.extend(figure(
        "fig_constant_gamma",
        "Fig. D:gamma-s-s — stress–stretch curves for constant γ",
        "Uniaxial tension along the fibres with γ held constant: the stress grows with γ and its zero moves below λ = 1 (to about 1 − γ). The y range is narrow (μ = 0.16 kPa) so that the zero crossings show.",
        vec![panel(
            "Constant activation γ",
            STRESS,
            gammas
                .iter()
                .enumerate()
                .map(|(i, g)| series(format!("γ = {g}"), curve(rows, |r| along(r) && r.law == "constant" && r.gamma == Some(*g), |r| Some(r.p)), Stroke::Solid, i))
                .collect(),
            Some((-0.5, 3.0)),
        )],
    ));

    // D:fattiva — the active curve.
    let lambdas: Vec<f64> = {
        let mut l: Vec<f64> = rows.iter().filter(|r| along(r)).map(|r| r.lambda).collect();
        l.sort_by(f64::total_cmp);
        l.dedup();
        l
    };
    let pact: Vec<(f64, f64)> = lambdas.iter().map(|&l| (l, scene.curve.value(l))).collect();
    out.extend(figure(
        "fig_active_curve",
        "Fig. D:fattiva — the active curve",
        "P_act(λ) of eq. D:pact with the parameters of Table D:paratt (the chapter also shows the experimental data of the rat tibialis anterior, which are not part of this program).",
        vec![panel("Active curve P_act (eq. D:pact)", STRESS, vec![series("P_act", pact.clone(), Stroke::Solid, 1)], None)],
    ));

    // D:pactgamma — γ(λ) of the implicit law; P_tot, P_act, P_pas.
    let implicit = |r: &Row| active(r, "implicit", "frozen", 0.0);
    out.extend(figure(
        "fig_gamma_and_stresses",
        "Fig. D:pactgamma — γ(λ) and the stresses P_tot, P_act, P_pas",
        "Top: γ solving eq. D:eqgammaesplicita (implicit law, d = 0). Bottom: the resulting total stress P_tot with P_act and P_pas (frozen model).",
        vec![
            panel("Activation γ (implicit law, d = 0)", GAMMA, vec![series("γ implicit", curve(rows, implicit, |r| r.gamma), Stroke::Solid, 0)], None),
            panel(
                "Total, active and passive stress",
                STRESS,
                vec![
                    series("P_tot", curve(rows, implicit, |r| Some(r.p)), Stroke::Solid, 0),
                    series("P_act", curve(rows, implicit, |r| r.p_act), Stroke::Dashed, 1),
                    series("P_pas", curve(rows, implicit, |r| r.p_pas), Stroke::Dotted, 2),
                ],
                active_range,
            ),
        ],
    ));

    // D:figdpact — (1 − d) P_act.
    let ds = damages(rows, |r| along(r) && r.law == "implicit");
    out.extend(figure(
        "fig_damage_active",
        "Fig. D:figdpact — (1 − d) P_act for d = 0 … 0.5",
        "The active curve scaled by the loss of activation 1 − d.",
        vec![panel(
            "(1 − d) P_act",
            STRESS,
            ds.iter()
                .enumerate()
                .map(|(i, d)| {
                    series(
                        format!("d = {d}"),
                        pact.iter().map(|&(l, p)| (l, (1.0 - d) * p)).collect(),
                        Stroke::Solid,
                        i,
                    )
                })
                .collect(),
            None,
        )],
    ));

    // D:figapprgamma — explicit (solid) vs implicit (dotted) γ.
    out.extend(figure(
        "fig_explicit_vs_implicit_gamma",
        "Fig. D:figapprgamma — explicit γ (eq. D:gamma) vs the implicit solution",
        "γ from the closed form eq. D:gamma (solid) and from solving eq. D:eqgammaesplicita (dotted), d = 0.",
        vec![panel(
            "Explicit and implicit γ",
            GAMMA,
            vec![
                series("explicit, eq. D:gamma", curve(rows, |r| active(r, "explicit", "frozen", 0.0), |r| r.gamma), Stroke::Solid, 0),
                series("implicit, eq. D:eqgammaesplicita", curve(rows, implicit, |r| r.gamma), Stroke::Dotted, 1),
            ],
            None,
        )],
    ));

    // D:figapprgammaptot — P_tot with explicit γ.
    let explicit = |r: &Row| active(r, "explicit", "frozen", 0.0);
    out.extend(figure(
        "fig_explicit_ptot",
        "Fig. D:figapprgammaptot — P_tot with the explicit γ",
        "Total stress of the frozen model with γ from eq. D:gamma, against the target P_pas + P_act it approximates (the chapter compares with the experimental data instead).",
        vec![panel(
            "P_tot with explicit γ",
            STRESS,
            vec![
                series("P_tot, explicit γ", curve(rows, explicit, |r| Some(r.p)), Stroke::Solid, 0),
                series("P_pas + P_act (target)", curve(rows, explicit, |r| Some(r.p_pas? + r.p_act?)), Stroke::Dashed, 1),
            ],
            active_range,
        )],
    ));

    // D:figfenics — the clamped cylinder, explicit law, frozen, d = 0 … 0.5.
    let cyl = |r: &Row| {
        r.model == "cylinder"
            && r.bases == Some("clamped")
            && r.law == "explicit"
            && r.coupling == Some("frozen")
    };
    let cds = damages(rows, cyl);
    out.extend(figure(
        "fig_cylinder",
        "Fig. D:figfenics — the cylinder: γ and P_tot for d = 0 … 0.5",
        "Axisymmetric FE cylinder (R = 1, L = 4 unless the scene says otherwise), clamped bases, explicit law, frozen coupling. Top: γ at the centre of the cylinder; bottom: nominal axial stress (reaction / πR²).",
        vec![
            panel("γ at the centre of the cylinder", GAMMA, cds.iter().enumerate().map(|(i, d)| series(format!("d = {d}"), curve(rows, |r| cyl(r) && r.d == Some(*d), |r| r.gamma), Stroke::Solid, i)).collect(), None),
            panel("Nominal axial stress", STRESS, cds.iter().enumerate().map(|(i, d)| series(format!("d = {d}"), curve(rows, |r| cyl(r) && r.d == Some(*d), |r| Some(r.p)), Stroke::Solid, i)).collect(), active_range),
        ],
    ));

    // Ours: frozen vs consistent.
    let mut s = Vec::new();
    for (i, law) in ["implicit", "explicit", "energy"].iter().enumerate() {
        s.push(series(
            format!("{law}, frozen"),
            curve(rows, |r| active(r, law, "frozen", 0.0), |r| Some(r.p)),
            Stroke::Solid,
            i,
        ));
        s.push(series(
            format!("{law}, consistent"),
            curve(rows, |r| active(r, law, "consistent", 0.0), |r| Some(r.p)),
            Stroke::Dashed,
            i,
        ));
    }
    s.push(series(
        "P_pas + P_act (target)",
        curve(rows, implicit, |r| Some(r.p_pas? + r.p_act?)),
        Stroke::Dotted,
        3,
    ));
    if s.iter().filter(|x| x.is_some()).count() >= 3 {
        out.extend(figure(
            "fig_frozen_vs_consistent",
            "Frozen vs consistent coupling (ours)",
            "Uniaxial tension along the fibres, d = 0. Frozen: P = ∂Ŵ/∂F at γ = g(λ) held (the chapter's model). Consistent: the hyperelastic Ψ(F) = Ŵ(F, g(λ_f(F))). The energy law is built so that its consistent model reproduces P_pas + P_act; the implicit law so that its frozen model does.",
            vec![panel("Frozen vs consistent coupling, d = 0", STRESS, s, active_range)],
        ));
    }

    // Ours: FE vs 0D.
    let mut s = Vec::new();
    let mut colour = 0;
    for c in &results.fe_vs_0d {
        let dmax = results
            .fe_vs_0d
            .iter()
            .filter(|o| o.study == c.study)
            .map(|o| o.d)
            .fold(0.0, f64::max);
        if !(c.d == 0.0 || c.d == dmax) {
            continue;
        }
        let short = c.label.split(", ").skip(1).collect::<Vec<_>>().join(", ");
        s.push(series(
            format!("FE {} bases: {short}", c.bases),
            c.points.iter().map(|p| (p.0, p.1)).collect(),
            Stroke::Markers,
            colour,
        ));
        s.push(series(
            format!("0D: {short}"),
            c.points.iter().map(|p| (p.0, p.2)).collect(),
            Stroke::Solid,
            colour,
        ));
        colour += 1;
    }
    if !s.is_empty() {
        out.extend(figure(
            "fig_fe_vs_0d",
            "FE cylinder vs homogeneous (0D) tension (ours)",
            "Markers: FE nominal stress (axial reaction / πR²); lines: the homogeneous uniaxial curve of the same model. Sliding bases must match the 0D curve to solver tolerance (the built-in verification); clamped bases do not, the difference is the end effect.",
            vec![panel("FE vs 0D", STRESS, s, active_range)],
        ));
    }
    out.extend(fit_figures(results));
    out.extend(stability_figures(results));
    out
}

/// One figure per fit study: data (markers), the fit (solid) and the model at the reference or
/// starting values (dashed). Damage fits share one panel; other fits get a panel per data set.
fn fit_figures(results: &Results) -> Vec<Figure> {
    let mut studies: Vec<usize> = results.fits.iter().map(|f| f.study).collect();
    studies.dedup();
    let mut out = Vec::new();
    for study in studies {
        let fits: Vec<_> = results.fits.iter().filter(|f| f.study == study).collect();
        let Some(first) = fits.first() else { continue };
        let mut panels = Vec::new();
        let status = |f: &crate::scene::FitOutcome| {
            let values: Vec<String> = f
                .names
                .iter()
                .zip(&f.values)
                .map(|(n, v)| format!("{n} = {v:.4}"))
                .collect();
            format!(
                "fit: {}{}",
                values.join(", "),
                if f.converged { "" } else { " (NOT converged)" }
            )
        };
        if first.fit == "damage" {
            let mut s = Vec::new();
            for (i, f) in fits.iter().enumerate() {
                s.push(series(
                    f.case.clone(),
                    f.plot.data.clone(),
                    Stroke::Markers,
                    i,
                ));
                s.push(series(status(f), f.plot.fitted.clone(), Stroke::Solid, i));
            }
            if let Some((label, points)) = &first.plot.start {
                s.push(series(label.clone(), points.clone(), Stroke::Dashed, 7));
            }
            panels.push(panel(&first.study_name, &first.plot.y_label, s, None));
        } else {
            for f in &fits {
                let mut s = vec![
                    series(
                        f.plot.data_label.clone(),
                        f.plot.data.clone(),
                        Stroke::Markers,
                        1,
                    ),
                    series(status(f), f.plot.fitted.clone(), Stroke::Solid, 0),
                ];
                if let Some((label, points)) = &f.plot.start {
                    s.push(series(label.clone(), points.clone(), Stroke::Dashed, 2));
                }
                panels.push(panel(
                    &format!("{}: {}", f.study_name, f.case),
                    &f.plot.y_label,
                    s,
                    None,
                ));
            }
        }
        let stem = prefixed("fit", &first.study_name);
        out.extend(figure(
            &stem,
            &format!("Fit: {}", first.study_name),
            &format!(
                "Least-squares fit ({}) to {}. Markers: data; solid: the fitted model; dashed: the model at the reference values.",
                first.fit, first.source
            ),
            panels.into_iter().flatten().map(Some).collect(),
        ));
    }
    out
}

/// One figure per stability study, a panel per damage value: the stress along the fibres of each
/// law × coupling (solid frozen, dashed consistent), with markers on the points where the curve
/// softens (dP/dλ < 0) and, in black-ish, where strong ellipticity is lost.
fn stability_figures(results: &Results) -> Vec<Figure> {
    let mut studies: Vec<usize> = results.stability.iter().map(|c| c.study).collect();
    studies.dedup();
    let mut out = Vec::new();
    for study in studies {
        let curves: Vec<_> = results
            .stability
            .iter()
            .filter(|c| c.study == study)
            .collect();
        let name = results
            .studies
            .get(study)
            .map_or("stability".to_string(), |s| s.name.clone());
        let mut ds: Vec<f64> = curves.iter().filter_map(|c| c.d).collect();
        ds.sort_by(f64::total_cmp);
        ds.dedup();
        if ds.is_empty() {
            ds.push(0.0);
        }
        let colour = |law: &str| match law {
            "implicit" => 0,
            "explicit" => 1,
            "energy" => 2,
            _ => 5,
        };
        let mut panels = Vec::new();
        for d in &ds {
            let mut s = Vec::new();
            let (mut soft_labelled, mut lost_labelled) = (false, false);
            for c in curves.iter().filter(|c| c.d.is_none() || c.d == Some(*d)) {
                let stroke = if c.coupling == Some("consistent") {
                    Stroke::Dashed
                } else if c.law == "passive" {
                    Stroke::Dotted
                } else {
                    Stroke::Solid
                };
                let all: Vec<(f64, f64)> = c.points.iter().map(|p| (p.lambda, p.stress)).collect();
                s.push(series(c.label(), all, stroke, colour(c.law)));
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
                s.push(series(label, soft, Stroke::Markers, colour(c.law)));
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
                s.push(series(label, lost, Stroke::Markers, 6));
            }
            panels.push(panel(
                &format!("Stability along the fibres, d = {d}"),
                STRESS,
                s,
                Some((-5.0, 160.0)),
            ));
        }
        out.extend(figure(
            &prefixed("stability", &name),
            &format!("Material stability along the fibres: {name}"),
            "Uniaxial tension along the fibres, nominal stress of each law × coupling (solid: frozen, dashed: consistent, dotted: passive). Circles in the curve's colour mark dP/dλ < 0 (softening: the homogeneous state is unstable under load control); pink circles mark the loss of strong ellipticity (a·Q(N)a ≤ 0 for some sampled normal N and a ⊥ F⁻ᵀN). The table above gives the intervals.",
            panels.into_iter().flatten().map(Some).collect(),
        ));
    }
    out
}

/// `fig_<kind>_<name>`, without repeating the kind when the name starts with it.
fn prefixed(kind: &str, name: &str) -> String {
    let s = slug(name);
    if s.starts_with(kind) {
        format!("fig_{s}")
    } else {
        format!("fig_{kind}_{s}")
    }
}

/// A file-name-safe lower-case form of `text` (runs of other characters become one `_`).
pub fn slug(text: &str) -> String {
    let mut s: String = text
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect();
    while s.contains("__") {
        s = s.replace("__", "_");
    }
    s.trim_matches('_').to_string()
}
