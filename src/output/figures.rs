//! The chapter's figures (and two of ours) from the typed results of a run. A figure whose data
//! the scene did not compute is skipped.

use super::plot::{Figure, Panel, Scale, Series, Stroke};
use crate::active::ActiveCurve;
use crate::fem::Bases;
use crate::models::{CouplingKind, LawKind, ModelChoice};
use crate::scene::{Results, Scene};
use crate::studies::cylinder::{bases_name, Sweep, SweepPoint};
use crate::studies::fit::{FitKind, FitOutcome};
use crate::studies::slug;
use crate::studies::stability::StabilityCurve;
use crate::studies::uniaxial::{Curve, CurveModel, CurvePoint};
use crate::uniaxial::Direction;
use crate::StrainEnergy;

const LAMBDA: &str = "stretch λ [-]";
const STRESS: &str = "nominal stress P [kPa]";
const GAMMA: &str = "activation γ [-]";

/// (λ, y) of every point of `curves` where `y` has a value, sorted by λ (stably: curves in run
/// order).
fn xy<'a>(
    curves: impl Iterator<Item = &'a Curve>,
    y: impl Fn(&CurvePoint) -> Option<f64>,
) -> Vec<(f64, f64)> {
    let mut v: Vec<(f64, f64)> = curves
        .flat_map(|c| c.points.iter())
        .filter_map(|p| y(p).map(|y| (p.lambda, y)))
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
        Some(Series::new(label, points, stroke, colour))
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
            x_range: None,
            y_range,
            scale: Scale::Linear,
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

fn sorted_unique(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    v.dedup();
    v
}

/// The uniaxial curves of a run, by direction.
struct Uniaxial<'a> {
    curves: Vec<(Direction, &'a Curve)>,
}

impl<'a> Uniaxial<'a> {
    fn new(results: &'a Results) -> Self {
        Self {
            curves: results
                .uniaxial()
                .flat_map(|(_, u)| u.curves.iter().map(move |c| (u.direction, c)))
                .collect(),
        }
    }

    /// The curves in direction `d` that `keep` accepts.
    fn curves<'b>(
        &'b self,
        d: Direction,
        keep: impl Fn(&Curve) -> bool + 'b,
    ) -> impl Iterator<Item = &'a Curve> + 'b {
        self.curves
            .iter()
            .filter(move |(dir, c)| *dir == d && keep(c))
            .map(|(_, c)| *c)
    }

    /// (λ, y) of the curves along the fibres that `keep` accepts.
    fn along(
        &self,
        keep: impl Fn(&Curve) -> bool,
        y: impl Fn(&CurvePoint) -> Option<f64>,
    ) -> Vec<(f64, f64)> {
        xy(self.curves(Direction::Along, keep), y)
    }
}

fn passive(c: &Curve) -> bool {
    c.model == CurveModel::Passive
}

fn active_model(c: &Curve) -> Option<ModelChoice> {
    match c.model {
        CurveModel::Active(m) => Some(m),
        _ => None,
    }
}

/// The curve of `law`, `coupling` at damage `d`.
fn active(law: LawKind, coupling: CouplingKind, d: f64) -> impl Fn(&Curve) -> bool {
    move |c| {
        active_model(c).is_some_and(|m| m.law == law && m.coupling == coupling && m.damage == d)
    }
}

/// What the figures are drawn from.
struct Run<'a> {
    u: Uniaxial<'a>,
    results: &'a Results,
    material: String,
    curve: ActiveCurve,
}

/// Stress range in which the active model's features are visible (the passive exponential
/// reaches hundreds of kPa at λ = 1.6).
const ACTIVE_RANGE: Option<(f64, f64)> = Some((-5.0, 160.0));

fn stress(p: &CurvePoint) -> Option<f64> {
    Some(p.stress)
}

fn gamma(p: &CurvePoint) -> Option<f64> {
    Some(p.gamma)
}

/// P_pas + (1 − d) P_act, the target of an active curve along the fibres.
fn target(p: &CurvePoint) -> Option<f64> {
    Some(p.passive? + p.active_target?)
}

/// Every figure the results support, in the chapter's order, then ours.
pub fn figures(scene: &Scene, results: &Results) -> Vec<Figure> {
    let run = Run {
        u: Uniaxial::new(results),
        results,
        material: scene.models.energy.name().to_string(),
        curve: scene.models.curve,
    };
    let pact = run.active_curve();
    let mut out: Vec<Figure> = [
        passive_energies(&run),
        transverse_isotropy(&run),
        constant_gamma(&run),
        active_curve(&pact),
        gamma_and_stresses(&run),
        damage_active(&run, &pact),
        explicit_vs_implicit_gamma(&run),
        explicit_ptot(&run),
        cylinder(&run),
        frozen_vs_consistent(&run),
        fe_vs_0d(results),
    ]
    .into_iter()
    .flatten()
    .collect();
    for (name, fits) in results.fits() {
        out.extend(fit_figure(name, fits));
    }
    for (name, curves) in results.stability() {
        out.extend(stability_figure(name, curves));
    }
    out
}

impl Run<'_> {
    /// P_act at every stretch of the curves along the fibres.
    fn active_curve(&self) -> Vec<(f64, f64)> {
        let lambdas = sorted_unique(
            self.u
                .curves(Direction::Along, |_| true)
                .flat_map(|c| c.points.iter().map(|p| p.lambda))
                .collect(),
        );
        lambdas.iter().map(|&l| (l, self.curve.value(l))).collect()
    }
}

/// The chapter's Fig. 3: passive energies along the fibres.
fn passive_energies(run: &Run) -> Option<Figure> {
    let mut energies: Vec<&str> = run
        .u
        .curves(Direction::Along, passive)
        .map(|c| c.energy.as_str())
        .collect();
    energies.sort();
    energies.dedup();
    if energies.len() < 2 {
        return None;
    }
    let s = energies
        .iter()
        .enumerate()
        .map(|(i, e)| {
            let stroke = if i == 0 {
                Stroke::Solid
            } else {
                Stroke::Dashed
            };
            series(
                *e,
                run.u.along(|c| passive(c) && c.energy == *e, stress),
                stroke,
                i,
            )
        })
        .collect();
    figure(
        "fig_passive_vs_ebi",
        "The chapter's Fig. 3 — passive energies in uniaxial tension along the fibres",
        "Nominal stress of the chapter's passive energy (eq. (1)) and of the Ehret–Böl–Itskov energy (eq. (4)) it simplifies, uniaxial tension along the fibres.",
        vec![panel("Passive stress along the fibres", STRESS, s, Some((-5.0, 160.0)))],
    )
}

/// The chapter's Fig. 2: transverse isotropy.
fn transverse_isotropy(run: &Run) -> Option<Figure> {
    let passive_dir = |d: Direction| {
        xy(
            run.u.curves(d, |c| passive(c) && c.energy == run.material),
            stress,
        )
    };
    figure(
        "fig_transverse_isotropy",
        "The chapter's Fig. 2 — transversely isotropic behaviour",
        "Passive nominal stress of the chapter's energy in uniaxial tension along and across the fibres (both lateral faces traction free).",
        vec![panel(
            "Passive stress along and across the fibres",
            STRESS,
            vec![
                series("along the fibres", passive_dir(Direction::Along), Stroke::Solid, 0),
                series("across the fibres", passive_dir(Direction::Across), Stroke::Dashed, 1),
            ],
            Some((-5.0, 160.0)),
        )],
    )
}

/// The chapter's Fig. 5: constant γ.
fn constant_gamma(run: &Run) -> Option<Figure> {
    let gammas = sorted_unique(
        run.u
            .curves(Direction::Along, |_| true)
            .filter_map(|c| match c.model {
                CurveModel::Constant(g) => Some(g),
                _ => None,
            })
            .collect(),
    );
    let constant = |g: f64| move |c: &Curve| c.model == CurveModel::Constant(g);
    figure(
        "fig_constant_gamma",
        "The chapter's Fig. 5 — stress–stretch curves for constant γ",
        "Uniaxial tension along the fibres with γ held constant: the stress grows with γ and its zero moves below λ = 1 (to about 1 − γ). The y range is narrow (μ = 0.16 kPa) so that the zero crossings show.",
        vec![panel(
            "Constant activation γ",
            STRESS,
            gammas
                .iter()
                .enumerate()
                .map(|(i, g)| series(format!("γ = {g}"), run.u.along(constant(*g), stress), Stroke::Solid, i))
                .collect(),
            Some((-0.5, 3.0)),
        )],
    )
}

/// The chapter's Fig. 7: the active curve.
fn active_curve(pact: &[(f64, f64)]) -> Option<Figure> {
    figure(
        "fig_active_curve",
        "The chapter's Fig. 7 — the active curve",
        "P_act(λ) of eq. (8) with the parameters of Table 2 (the chapter also shows the experimental data of the rat tibialis anterior, which are not part of this program).",
        vec![panel("Active curve P_act (eq. (8))", STRESS, vec![series("P_act", pact.to_vec(), Stroke::Solid, 1)], None)],
    )
}

/// The chapter's Fig. 8: γ(λ) of the implicit law; P_tot, P_act, P_pas.
fn gamma_and_stresses(run: &Run) -> Option<Figure> {
    let implicit = active(LawKind::Implicit, CouplingKind::Frozen, 0.0);
    figure(
        "fig_gamma_and_stresses",
        "The chapter's Fig. 8 — γ(λ) and the stresses P_tot, P_act, P_pas",
        "Top: γ solving eq. (13) (implicit law, d = 0). Bottom: the resulting total stress P_tot with P_act and P_pas (frozen model).",
        vec![
            panel("Activation γ (implicit law, d = 0)", GAMMA, vec![series("γ implicit", run.u.along(&implicit, gamma), Stroke::Solid, 0)], None),
            panel(
                "Total, active and passive stress",
                STRESS,
                vec![
                    series("P_tot", run.u.along(&implicit, stress), Stroke::Solid, 0),
                    series("P_act", run.u.along(&implicit, |p| p.active_target), Stroke::Dashed, 1),
                    series("P_pas", run.u.along(&implicit, |p| p.passive), Stroke::Dotted, 2),
                ],
                ACTIVE_RANGE,
            ),
        ],
    )
}

/// The chapter's Fig. 9: (1 − d) P_act for the damages of the implicit law.
fn damage_active(run: &Run, pact: &[(f64, f64)]) -> Option<Figure> {
    let ds = sorted_unique(
        run.u
            .curves(Direction::Along, |_| true)
            .filter_map(active_model)
            .filter(|m| m.law == LawKind::Implicit)
            .map(|m| m.damage)
            .collect(),
    );
    figure(
        "fig_damage_active",
        "The chapter's Fig. 9 — (1 − d) P_act for d = 0 … 0.5",
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
    )
}

/// The chapter's Fig. 10: explicit (solid) vs implicit (dotted) γ.
fn explicit_vs_implicit_gamma(run: &Run) -> Option<Figure> {
    let implicit = active(LawKind::Implicit, CouplingKind::Frozen, 0.0);
    let explicit = active(LawKind::Explicit, CouplingKind::Frozen, 0.0);
    figure(
        "fig_explicit_vs_implicit_gamma",
        "The chapter's Fig. 10 — explicit γ (eq. (14)) vs the implicit solution",
        "γ from the closed form eq. (14) (solid) and from solving eq. (13) (dotted), d = 0.",
        vec![panel(
            "Explicit and implicit γ",
            GAMMA,
            vec![
                series(
                    "explicit, eq. (14)",
                    run.u.along(&explicit, gamma),
                    Stroke::Solid,
                    0,
                ),
                series(
                    "implicit, eq. (13)",
                    run.u.along(&implicit, gamma),
                    Stroke::Dotted,
                    1,
                ),
            ],
            None,
        )],
    )
}

/// The chapter's Fig. 11: P_tot with the explicit γ.
fn explicit_ptot(run: &Run) -> Option<Figure> {
    let explicit = active(LawKind::Explicit, CouplingKind::Frozen, 0.0);
    figure(
        "fig_explicit_ptot",
        "The chapter's Fig. 11 — P_tot with the explicit γ",
        "Total stress of the frozen model with γ from eq. (14), against the target P_pas + P_act it approximates (the chapter compares with the experimental data instead).",
        vec![panel(
            "P_tot with explicit γ",
            STRESS,
            vec![
                series("P_tot, explicit γ", run.u.along(&explicit, stress), Stroke::Solid, 0),
                series("P_pas + P_act (target)", run.u.along(&explicit, target), Stroke::Dashed, 1),
            ],
            ACTIVE_RANGE,
        )],
    )
}

/// The chapter's Fig. 12: the clamped cylinder, explicit law, frozen, d = 0 … 0.5.
fn cylinder(run: &Run) -> Option<Figure> {
    let sweeps: Vec<&Sweep> = run
        .results
        .cylinders()
        .filter(|(_, c)| c.bases == Bases::Clamped)
        .flat_map(|(_, c)| c.sweeps.iter())
        .filter(|s| s.model.law == LawKind::Explicit && s.model.coupling == CouplingKind::Frozen)
        .collect();
    let points = |d: f64, y: fn(&SweepPoint) -> f64| {
        let mut v: Vec<(f64, f64)> = sweeps
            .iter()
            .filter(|s| s.model.damage == d)
            .flat_map(|s| s.points.iter().map(|p| (p.lambda, y(p))))
            .collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        v
    };
    let ds = sorted_unique(sweeps.iter().map(|s| s.model.damage).collect());
    let by_damage = |y: fn(&SweepPoint) -> f64| -> Vec<Option<Series>> {
        ds.iter()
            .enumerate()
            .map(|(i, d)| series(format!("d = {d}"), points(*d, y), Stroke::Solid, i))
            .collect()
    };
    figure(
        "fig_cylinder",
        "The chapter's Fig. 12 — the cylinder: γ and P_tot for d = 0 … 0.5",
        "Axisymmetric FE cylinder (R = 1, L = 4 unless the scene says otherwise), clamped bases, explicit law, frozen coupling. Top: γ at the centre of the cylinder; bottom: nominal axial stress (reaction / πR²).",
        vec![
            panel("γ at the centre of the cylinder", GAMMA, by_damage(|p| p.gamma_centre), None),
            panel("Nominal axial stress", STRESS, by_damage(|p| p.stress), ACTIVE_RANGE),
        ],
    )
}

/// Ours: frozen against consistent coupling of each law, d = 0.
fn frozen_vs_consistent(run: &Run) -> Option<Figure> {
    use CouplingKind::{Consistent, Frozen};
    let mut s = Vec::new();
    for (i, law) in [LawKind::Implicit, LawKind::Explicit, LawKind::Energy]
        .into_iter()
        .enumerate()
    {
        s.push(series(
            format!("{}, frozen", law.name()),
            run.u.along(active(law, Frozen, 0.0), stress),
            Stroke::Solid,
            i,
        ));
        s.push(series(
            format!("{}, consistent", law.name()),
            run.u.along(active(law, Consistent, 0.0), stress),
            Stroke::Dashed,
            i,
        ));
    }
    s.push(series(
        "P_pas + P_act (target)",
        run.u.along(active(LawKind::Implicit, Frozen, 0.0), target),
        Stroke::Dotted,
        3,
    ));
    if s.iter().filter(|x| x.is_some()).count() < 3 {
        return None;
    }
    figure(
        "fig_frozen_vs_consistent",
        "Frozen vs consistent coupling (ours)",
        "Uniaxial tension along the fibres, d = 0. Frozen: P = ∂Ŵ/∂F at γ = g(λ) held (the chapter's model). Consistent: the hyperelastic Ψ(F) = Ŵ(F, g(λ_f(F))). The energy law is built so that its consistent model reproduces P_pas + P_act; the implicit law so that its frozen model does.",
        vec![panel("Frozen vs consistent coupling, d = 0", STRESS, s, ACTIVE_RANGE)],
    )
}

/// Ours: FE against 0D, at the smallest and the largest damage of each cylinder study.
fn fe_vs_0d(results: &Results) -> Option<Figure> {
    let mut s = Vec::new();
    let mut colour = 0;
    for (_, c) in results.cylinders() {
        let dmax = c.sweeps.iter().map(|w| w.model.damage).fold(0.0, f64::max);
        for w in &c.sweeps {
            if !(w.model.damage == 0.0 || w.model.damage == dmax) {
                continue;
            }
            let short = w.label.split(", ").skip(1).collect::<Vec<_>>().join(", ");
            let compared: Vec<(f64, f64, f64)> = w
                .points
                .iter()
                .filter_map(|p| p.stress_0d.map(|z| (p.lambda, p.stress, z)))
                .collect();
            s.push(series(
                format!("FE {} bases: {short}", bases_name(c.bases)),
                compared.iter().map(|p| (p.0, p.1)).collect(),
                Stroke::Markers,
                colour,
            ));
            s.push(series(
                format!("0D: {short}"),
                compared.iter().map(|p| (p.0, p.2)).collect(),
                Stroke::Solid,
                colour,
            ));
            colour += 1;
        }
    }
    if s.is_empty() {
        return None;
    }
    figure(
        "fig_fe_vs_0d",
        "FE cylinder vs homogeneous (0D) tension (ours)",
        "Markers: FE nominal stress (axial reaction / πR²); lines: the homogeneous uniaxial curve of the same model. Sliding bases must match the 0D curve to solver tolerance (the built-in verification); clamped bases do not, the difference is the end effect.",
        vec![panel("FE vs 0D", STRESS, s, ACTIVE_RANGE)],
    )
}

/// The figure of a fit study: data (markers), the fit (solid) and the model at the reference or
/// starting values (dashed). Damage fits share one panel; other fits get a panel per data set.
fn fit_figure(study: &str, fits: &[FitOutcome]) -> Option<Figure> {
    let first = fits.first()?;
    let mut panels = Vec::new();
    let status = |f: &FitOutcome| {
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
    if first.kind == FitKind::Damage {
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
        panels.push(panel(study, &first.plot.y_label, s, None));
    } else {
        for f in fits {
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
                &format!("{study}: {}", f.case),
                &f.plot.y_label,
                s,
                None,
            ));
        }
    }
    figure(
        &prefixed("fit", study),
        &format!("Fit: {study}"),
        &format!(
            "Least-squares fit ({}) to {}. Markers: data; solid: the fitted model; dashed: the model at the reference values.",
            first.kind.name(),
            first.source
        ),
        panels.into_iter().flatten().map(Some).collect(),
    )
}

/// The figure of a stability study, a panel per damage value: the stress along the fibres of
/// each law × coupling (solid frozen, dashed consistent), with markers on the points where the
/// curve softens (dP/dλ < 0) and, in pink, where strong ellipticity is lost.
fn stability_figure(study: &str, curves: &[StabilityCurve]) -> Option<Figure> {
    let mut ds = sorted_unique(curves.iter().filter_map(StabilityCurve::damage).collect());
    if ds.is_empty() {
        ds.push(0.0);
    }
    let colour = |c: &StabilityCurve| match c.model.map(|m| m.law) {
        Some(LawKind::Implicit) => 0,
        Some(LawKind::Explicit) => 1,
        Some(LawKind::Energy) => 2,
        None => 5,
    };
    let mut panels = Vec::new();
    for d in &ds {
        let mut s = Vec::new();
        let (mut soft_labelled, mut lost_labelled) = (false, false);
        for c in curves
            .iter()
            .filter(|c| c.damage().is_none() || c.damage() == Some(*d))
        {
            let stroke = match c.model {
                Some(m) if m.coupling == CouplingKind::Consistent => Stroke::Dashed,
                None => Stroke::Dotted,
                Some(_) => Stroke::Solid,
            };
            let all: Vec<(f64, f64)> = c.points.iter().map(|p| (p.lambda, p.stress)).collect();
            s.push(series(c.label(), all, stroke, colour(c)));
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
            s.push(series(label, soft, Stroke::Markers, colour(c)));
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
    figure(
        &prefixed("stability", study),
        &format!("Material stability along the fibres: {study}"),
        "Uniaxial tension along the fibres, nominal stress of each law × coupling (solid: frozen, dashed: consistent, dotted: passive). Circles in the curve's colour mark dP/dλ < 0 (softening: the homogeneous state is unstable under load control); pink circles mark the loss of strong ellipticity (a·Q(N)a ≤ 0 for some sampled normal N and a ⊥ F⁻ᵀN). The table above gives the intervals.",
        panels.into_iter().flatten().map(Some).collect(),
    )
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
