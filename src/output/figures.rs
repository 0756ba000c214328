//! The figures of a run, built from what each study computed: every curve of `curves.csv` is
//! drawn in some figure with a legend entry (the series carry its
//! [`CurveId`](crate::plot::CurveId)), headings and captions name the scene's energy, laws,
//! couplings and damages, axes follow the data (clipped where a curve blows up, and the caption
//! says so: [`Panel::frame`]). Where a figure shows what one of the chapter's figures shows, its
//! heading says which.
//!
//! | figure | drawn when | shows |
//! |---|---|---|
//! | `fig_passive_<direction>` | a uniaxial study has passive curves (not only the material's, already in `fig_transverse_isotropy`) | each passive energy |
//! | `fig_transverse_isotropy` | the material's passive curve is computed along and across the fibres | both |
//! | `fig_constant_gamma` | constant γ | each γ; a zoom on the zero crossings |
//! | `fig_active_curve`, `fig_damage_active` | active models along the fibres (two damages or more for the second) | P_act, (1 − d) P_act |
//! | `fig_gamma_and_stresses` | the implicit law, frozen, along the fibres | γ; P_tot, P_pas, (1 − d) P_act at the smallest damage |
//! | `fig_explicit_vs_implicit_gamma`, `fig_explicit_ptot` | the explicit (and implicit) law, frozen, along the fibres | γ of both; P_tot against its target |
//! | `fig_laws` | active models | γ and P of every law × coupling at the smallest damage, with the target |
//! | `fig_loss_of_activation` | two damages or more | P per law × coupling, a curve per damage |
//! | `fig_cylinder` | a cylinder study | γ and λ_f at the centre, P (FE and 0D) per damage |
//! | `fig_fe_vs_0d` | cylinder studies | P_FE − P_0D per damage, a panel per study |
//! | `fig_fit_*`, `fig_stability_*` | fit and stability studies | data and fits; stability along the fibres |
//! | `fig_history_*` | activation-in-time studies | a(t); P(t) or λ(t) and γ(t) per damage |
//!
//! A stem that two studies would share gets the study's name appended.

use crate::studies::curves::{sweep_curve, uniaxial_curve};
use crate::active::drive::Drive;
use crate::active::ActiveCurve;
use crate::fem::Bases;
use crate::models::{CouplingKind, LawKind, ModelChoice};
use crate::plot::{Figure, Panel, Scale, Series, Stroke, GREY};
use crate::scene::{Results, Scene};
use crate::studies::cylinder::{bases_name, CylinderResult, SweepPoint};
use crate::studies::fit::{FitKind, FitOutcome};
use crate::studies::history::{HistoryPoint, HistoryResult};
use crate::studies::slug;
use crate::studies::stability::StabilityCurve;
use crate::studies::uniaxial::{Curve, CurveModel, CurvePoint};
use crate::studies::StudyResult;
use crate::text;
use crate::uniaxial::Direction;
use crate::StrainEnergy;

const LAMBDA: &str = "stretch λ [-]";
const STRESS: &str = "nominal stress P [kPa]";
const GAMMA: &str = "activation γ [-]";

/// `0, 0.1, 0.5`.
fn list(values: &[f64]) -> String {
    values
        .iter()
        .map(f64::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

fn sorted_unique(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    v.dedup();
    v
}

/// ` — the chapter's Fig. n` for a figure of the chapter's energy and parameters
/// (`chapter_material`: the scene's energy and active curve are the chapter's); with other
/// parameters or another energy, ` — as the chapter's Fig. n` and what differs.
fn chapter(n: u32, energy: &str, chapter_material: bool) -> String {
    if energy != "giantesio-musesti" {
        format!(" — as the chapter's Fig. {n}, with the {energy} energy")
    } else if chapter_material {
        format!(" — the chapter's Fig. {n}")
    } else {
        format!(" — as the chapter's Fig. {n}, with this scene's parameters")
    }
}

/// `implicit law, frozen coupling`.
fn words(law: LawKind, coupling: CouplingKind) -> String {
    format!("{} law, {} coupling", law.name(), coupling.name())
}

/// The uniaxial curves of one study.
#[derive(Clone, Copy)]
struct Uniaxial<'a> {
    study: &'a str,
    direction: Direction,
    curves: &'a [Curve],
    /// The scene's energy and active curve are the chapter's (see [`chapter`]).
    chapter_material: bool,
}

impl<'a> Uniaxial<'a> {
    fn along(&self) -> bool {
        self.direction == Direction::Along
    }

    fn dir(&self) -> &'static str {
        match self.direction {
            Direction::Along => "along",
            Direction::Across => "across",
        }
    }

    fn passive(&self) -> impl Iterator<Item = &'a Curve> {
        self.curves
            .iter()
            .filter(|c| c.model == CurveModel::Passive)
    }

    fn active(&self) -> impl Iterator<Item = (ModelChoice, &'a Curve)> {
        self.curves.iter().filter_map(|c| match c.model {
            CurveModel::Active(m) => Some((m, c)),
            _ => None,
        })
    }

    /// The curve of `law`, `coupling` at damage `d`.
    fn model(&self, law: LawKind, coupling: CouplingKind, d: f64) -> Option<&'a Curve> {
        self.active()
            .find(|(m, _)| m.law == law && m.coupling == coupling && m.damage == d)
            .map(|(_, c)| c)
    }

    fn damages(&self) -> Vec<f64> {
        sorted_unique(self.active().map(|(m, _)| m.damage).collect())
    }

    /// (law, coupling) pairs in run order.
    fn pairs(&self) -> Vec<(LawKind, CouplingKind)> {
        let mut v = Vec::new();
        for (m, _) in self.active() {
            if !v.contains(&(m.law, m.coupling)) {
                v.push((m.law, m.coupling));
            }
        }
        v
    }

    /// A series of `y` along curve `c`, marked as drawing it; `None` without points.
    fn series(
        &self,
        c: &Curve,
        label: impl Into<String>,
        y: impl Fn(&CurvePoint) -> Option<f64>,
        stroke: Stroke,
        colour: usize,
    ) -> Option<Series> {
        let points: Vec<(f64, f64)> = c
            .points
            .iter()
            .filter_map(|p| y(p).map(|v| (p.lambda, v)))
            .collect();
        (!points.is_empty()).then(|| {
            Series::new(label, points, stroke, colour).drawing(uniaxial_curve(
                self.study,
                self.direction,
                c,
            ))
        })
    }
}

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

/// A series that draws no curve of `curves.csv` (a derived quantity); `None` without points.
fn derived(
    label: impl Into<String>,
    points: Vec<(f64, f64)>,
    stroke: Stroke,
    colour: usize,
) -> Option<Series> {
    (!points.is_empty()).then(|| Series::new(label, points, stroke, colour))
}

/// A legend entry without points, in grey: what a stroke means.
fn key(label: &str, stroke: Stroke) -> Option<Series> {
    Some(Series::new(label, Vec::new(), stroke, GREY))
}

/// A panel over λ, or `None` if none of its series has points.
fn panel(title: impl Into<String>, y_label: &str, series: Vec<Option<Series>>) -> Option<Panel> {
    let series: Vec<Series> = series.into_iter().flatten().collect();
    series
        .iter()
        .any(|s| !s.points.is_empty())
        .then(|| Panel::new(title, LAMBDA, y_label, series))
}

/// A figure of the panels that have data, or `None` if none has.
fn figure(
    stem: &str,
    heading: String,
    caption: String,
    panels: Vec<Option<Panel>>,
) -> Option<Figure> {
    let panels: Vec<Panel> = panels.into_iter().flatten().collect();
    (!panels.is_empty()).then(|| Figure::new(stem, heading, caption, panels))
}

/// What the figures are drawn from.
struct Run<'a> {
    results: &'a Results,
    /// The material's energy.
    material: String,
    curve: ActiveCurve,
    /// The scene's energy and active curve are the chapter's (see [`chapter`]).
    chapter_material: bool,
    uniaxial: Vec<Uniaxial<'a>>,
}

/// Every figure the results support: the uniaxial studies' (in study order), the transverse
/// isotropy, the cylinders', the FE-vs-0D differences, the fits' and the stability studies'.
pub fn figures(scene: &Scene, results: &Results) -> Vec<Figure> {
    let paper = crate::models::Models::paper();
    let chapter_material = scene.models.energy == paper.energy && scene.models.curve == paper.curve;
    let run = Run {
        results,
        material: scene.models.energy.name().to_string(),
        curve: scene.models.curve,
        chapter_material,
        uniaxial: results
            .uniaxial()
            .map(|(study, u)| Uniaxial {
                study,
                direction: u.direction,
                curves: &u.curves,
                chapter_material,
            })
            .collect(),
    };
    let isotropy = transverse_isotropy(&run);
    let mut out: Vec<Figure> = Vec::new();
    let mut active_curve_drawn = false;
    for u in &run.uniaxial {
        out.extend(passive(&run, u, isotropy.is_some()));
        out.extend(constant_gamma(u));
        if u.along() && u.active().next().is_some() && !active_curve_drawn {
            active_curve_drawn = true;
            out.extend(active_curve(&run, u));
        }
        out.extend(gamma_and_stresses(&run, u));
        out.extend(damage_active(&run, u));
        out.extend(explicit_vs_implicit_gamma(u));
        out.extend(explicit_ptot(u));
        out.extend(laws(&run, u));
        out.extend(loss_of_activation(u));
    }
    out.extend(isotropy);
    for (study, c) in results.cylinders() {
        out.extend(cylinder(&run, study, c));
    }
    out.extend(fe_vs_0d(results));
    for (name, fits) in results.fits() {
        out.extend(fit_figure(name, fits));
    }
    for (name, curves) in results.stability() {
        out.extend(stability_figure(name, curves));
    }
    for (name, h) in results.histories() {
        out.extend(history_figure(name, h));
    }
    for s in &results.studies {
        out.extend(match &s.result {
            StudyResult::Shear(r) => super::planar_figures::shear_figure(&s.name, r),
            StudyResult::Biaxial(r) => super::planar_figures::biaxial_figure(&s.name, r),
            _ => None,
        });
    }
    unique_stems(&mut out, &run);
    // The figures are written with the active-strain γ; the structural approach's variable is ω.
    if let Ok(map) = scene.models.activation_map() {
        if map.variable() != "γ" {
            for f in &mut out {
                f.rename_symbol("γ", map.variable());
            }
        }
    }
    out
}

/// Appends the study's name to a stem that another figure already has (and a number if that
/// is taken too).
fn unique_stems(figures: &mut [Figure], run: &Run) {
    let studies: Vec<&str> = run
        .results
        .studies
        .iter()
        .map(|s| s.name.as_str())
        .collect();
    for i in 1..figures.len() {
        if figures[..i].iter().any(|f| f.stem == figures[i].stem) {
            let own = studies
                .iter()
                .find(|s| figures[i].heading.contains(&format!("\"{s}\"")))
                .map_or(i.to_string(), |s| slug(s));
            let kind = figures[i].stem.trim_start_matches("fig_").to_string();
            let stem = if own.starts_with(&kind) {
                format!("fig_{own}")
            } else {
                format!("fig_{kind}_{own}")
            };
            // Two study names may give one slug ("cyl A", "cyl-a"): then a number as well.
            let taken = |t: &str| figures[..i].iter().any(|f| f.stem == t);
            figures[i].stem = (1..)
                .map(|n| {
                    if n == 1 {
                        stem.clone()
                    } else {
                        format!("{stem}_{n}")
                    }
                })
                .find(|t| !taken(t))
                .unwrap_or(stem);
        }
    }
}

/// Passive stress of each passive energy of study `u`; left out when its only curve is the
/// material's and the transverse-isotropy figure draws it.
fn passive(run: &Run, u: &Uniaxial, in_isotropy: bool) -> Option<Figure> {
    let curves: Vec<&Curve> = u.passive().collect();
    if curves.is_empty() || (in_isotropy && curves.len() == 1 && curves[0].energy == run.material) {
        return None;
    }
    let energies: Vec<&str> = curves.iter().map(|c| c.energy.as_str()).collect();
    let like_fig_3 = u.along()
        && energies.contains(&"giantesio-musesti")
        && energies.contains(&"ehret-bol-itskov");
    let series = curves
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let stroke = if i == 0 {
                Stroke::Solid
            } else {
                Stroke::Dashed
            };
            u.series(c, c.energy.clone(), stress, stroke, i)
        })
        .collect();
    figure(
        &format!("fig_passive_{}", u.dir()),
        format!(
            "Passive stress {} the fibres: {}{} (study \"{}\")",
            u.dir(),
            energies.join(", "),
            if like_fig_3 && u.chapter_material {
                " — the chapter's Fig. 3"
            } else {
                ""
            },
            u.study
        ),
        format!(
            "Nominal stress of the passive energ{} {} in uniaxial tension {} the fibres (lateral faces traction free).",
            if energies.len() == 1 { "y" } else { "ies" },
            energies.join(" and "),
            u.dir()
        ),
        vec![panel(
            format!("Passive stress {} the fibres", u.dir()),
            STRESS,
            series,
        )],
    )
}

/// The chapter's Fig. 2: the material's passive stress along and across the fibres.
fn transverse_isotropy(run: &Run) -> Option<Figure> {
    let find = |d: Direction| {
        run.uniaxial
            .iter()
            .filter(|u| u.direction == d)
            .find_map(|u| {
                u.passive()
                    .find(|c| c.energy == run.material)
                    .map(|c| (*u, c))
            })
    };
    let ((ua, along), (ux, across)) = (find(Direction::Along)?, find(Direction::Across)?);
    // An isotropic energy gives the same curve both ways (where both were computed).
    let isotropic = along
        .points
        .iter()
        .filter_map(|a| {
            let x = across.points.iter().find(|x| x.lambda == a.lambda)?;
            Some((a.stress - x.stress).abs() <= 1e-9 * (1.0 + a.stress.abs()))
        })
        .fold(None, |all, same| Some(all.unwrap_or(true) && same))
        .unwrap_or(false);
    let (title, shape) = if isotropic {
        (
            format!(
                "Passive stress along and across the fibres: {} is isotropic",
                run.material
            ),
            "The two curves coincide: the energy does not see the fibre direction.",
        )
    } else {
        (
            format!(
                "Transversely isotropic behaviour of {}{}",
                run.material,
                chapter(2, &run.material, run.chapter_material)
            ),
            "On the scale of the softer curve across the fibres.",
        )
    };
    figure(
        "fig_transverse_isotropy",
        title,
        format!(
            "Passive nominal stress of {} in uniaxial tension along and across the fibres (lateral faces traction free). {shape}",
            run.material
        ),
        vec![panel(
            "Passive stress along and across the fibres",
            STRESS,
            vec![ua.series(along, "along the fibres", stress, Stroke::Solid, 0), ux.series(across, "across the fibres", stress, Stroke::Dashed, 1)],
        )],
    )
}

/// The chapter's Fig. 5 (along the fibres): constant γ; a second panel zooms on P = 0 when a
/// curve crosses it, to show the zero crossings move below λ = 1.
fn constant_gamma(u: &Uniaxial) -> Option<Figure> {
    let curves: Vec<(f64, &Curve)> = u
        .curves
        .iter()
        .filter_map(|c| match c.model {
            CurveModel::Constant(g) => Some((g, c)),
            _ => None,
        })
        .collect();
    let gammas: Vec<f64> = curves.iter().map(|c| c.0).collect();
    let all = || -> Vec<Option<Series>> {
        curves
            .iter()
            .enumerate()
            .map(|(i, (g, c))| u.series(c, format!("γ = {g}"), stress, Stroke::Solid, i))
            .collect()
    };
    let stresses = || {
        curves
            .iter()
            .flat_map(|(_, c)| c.points.iter().map(|p| p.stress))
    };
    let lowest = stresses().fold(f64::INFINITY, f64::min);
    let positive = stresses().filter(|&p| p > 0.0);
    let (small, large) = positive.fold((f64::INFINITY, 0.0f64), |(a, b), p| (a.min(p), b.max(p)));
    // Over three decades or more (γ shifts the exponential stiffening): a log axis, and a
    // linear one near P = 0 for the zero crossings.
    let log = large > 1e3 * small;
    let top = if log {
        panel(
            format!("Constant activation, {} the fibres (log axis)", u.dir()),
            STRESS,
            all(),
        )
        .map(|p| Panel {
            scale: Scale::LogY,
            ..p
        })
    } else {
        panel(
            format!("Constant activation, {} the fibres", u.dir()),
            STRESS,
            all(),
        )
    };
    let zoom = (log && lowest < 0.0).then(|| {
        let mut p = panel("Near P = 0: the zero crossings", STRESS, all())?;
        p.y_range = Some((1.2 * lowest, -6.0 * lowest));
        Some(p)
    });
    figure(
        "fig_constant_gamma",
        format!(
            "Stress–stretch curves for constant γ = {}{} (study \"{}\")",
            list(&gammas),
            match curves.first() {
                Some((_, c)) if u.along() => chapter(5, &c.energy, u.chapter_material),
                _ => String::new(),
            },
            u.study
        ),
        format!(
            "Uniaxial tension {} the fibres with γ held constant: the stress grows with γ{}.{}",
            u.dir(),
            if u.along() {
                " and its zero moves below λ = 1 (to about 1 − γ)"
            } else {
                ""
            },
            if log {
                " Top: P > 0 on a log axis (γ shifts the exponential stiffening to smaller λ); bottom: a linear axis near P = 0."
            } else {
                ""
            }
        ),
        vec![top, zoom.flatten()],
    )
}

/// The chapter's Fig. 7: P_act at the stretches of study `u`.
fn active_curve(run: &Run, u: &Uniaxial) -> Option<Figure> {
    let lambdas = sorted_unique(
        u.curves
            .iter()
            .flat_map(|c| c.points.iter().map(|p| p.lambda))
            .collect(),
    );
    let points = lambdas.iter().map(|&l| (l, run.curve.value(l))).collect();
    figure(
        "fig_active_curve",
        format!(
            "The active curve P_act{}",
            chapter(7, "giantesio-musesti", run.curve == ActiveCurve::paper())
        ),
        format!(
            "P_act(λ) of the scene's active curve, {} ({}: {}, for λ > λ_min, 0 below), with {}; the chapter's values of its own curve are in its Table 2. The chapter also shows the experimental data of the rat tibialis anterior, which are not part of this program.",
            run.curve.name(),
            run.curve.source(),
            run.curve.formula(),
            curve_parameters_text(&run.curve)
        ),
        vec![panel("Active curve P_act", STRESS, vec![derived("P_act", points, Stroke::Solid, 1)])],
    )
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

/// The chapter's Fig. 8: γ of the implicit law (frozen) and its stresses, at the smallest damage.
fn gamma_and_stresses(run: &Run, u: &Uniaxial) -> Option<Figure> {
    let d = *u.damages().first()?;
    let c = u
        .model(LawKind::Implicit, CouplingKind::Frozen, d)
        .filter(|_| u.along())?;
    let act = |p: &CurvePoint| p.active_target;
    figure(
        "fig_gamma_and_stresses",
        format!(
            "γ(λ) of the implicit law and the stresses P_tot, P_act, P_pas at d = {d}{}",
            if d == 0.0 { chapter(8, &c.energy, u.chapter_material) } else { String::new() }
        ),
        format!(
            "Top: γ solving P_tot(λ, γ) = P_pas(λ) + (1 − d) P_act(λ) (the implicit law), d = {d}, energy {}. Bottom: the resulting total stress P_tot (frozen coupling) with its parts (1 − d) P_act and P_pas{}.",
            run.material,
            match target_gap(c) {
                Some(g) if g.2 > 1e-8 => format!(
                    ". The law solves that equation under exact incompressibility; in this scene P_tot is not their sum: it misses it by up to {}",
                    distance(g)
                ),
                _ => String::new(),
            }
        ),
        vec![
            panel(format!("Activation γ, implicit law, d = {d}"), GAMMA, vec![u.series(c, "γ, implicit law", gamma, Stroke::Solid, 0)]),
            panel(
                "Total, active and passive stress",
                STRESS,
                vec![
                    u.series(c, "P_tot", stress, Stroke::Solid, 0),
                    derived("(1 − d) P_act", xy(c, act), Stroke::Dashed, 1),
                    derived("P_pas", xy(c, |p| p.passive), Stroke::Dotted, 2),
                ],
            ),
        ],
    )
}

/// (λ, y) of the points of `c` where `y` has a value.
fn xy(c: &Curve, y: impl Fn(&CurvePoint) -> Option<f64>) -> Vec<(f64, f64)> {
    c.points
        .iter()
        .filter_map(|p| y(p).map(|v| (p.lambda, v)))
        .collect()
}

/// The chapter's Fig. 9: (1 − d) P_act for the damages of study `u` (two or more).
fn damage_active(run: &Run, u: &Uniaxial) -> Option<Figure> {
    let ds = u.damages();
    if ds.len() < 2 || !u.along() {
        return None;
    }
    let lambdas = sorted_unique(
        u.active()
            .flat_map(|(_, c)| c.points.iter().map(|p| p.lambda))
            .collect(),
    );
    let series = ds
        .iter()
        .enumerate()
        .map(|(i, d)| {
            let points = lambdas
                .iter()
                .map(|&l| (l, Drive::from(*d).target(&run.curve, l)))
                .collect();
            derived(format!("d = {d}"), points, Stroke::Solid, i)
        })
        .collect();
    figure(
        "fig_damage_active",
        format!(
            "(1 − d) P_act for d = {}{}",
            list(&ds),
            chapter(9, "giantesio-musesti", run.curve == ActiveCurve::paper())
        ),
        "The active curve scaled by the loss of activation 1 − d.".into(),
        vec![panel("(1 − d) P_act", STRESS, series)],
    )
}

/// The damage of the chapter's figures: 0 if computed, else the smallest, for `laws` frozen.
fn common_damage(u: &Uniaxial, laws: &[LawKind]) -> Option<f64> {
    u.damages().into_iter().find(|&d| {
        laws.iter()
            .all(|&l| u.model(l, CouplingKind::Frozen, d).is_some())
    })
}

/// The chapter's Fig. 10: explicit against implicit γ (frozen, along the fibres).
fn explicit_vs_implicit_gamma(u: &Uniaxial) -> Option<Figure> {
    let d = common_damage(u, &[LawKind::Explicit, LawKind::Implicit]).filter(|_| u.along())?;
    let of = |l| u.model(l, CouplingKind::Frozen, d);
    let energy = &of(LawKind::Explicit)?.energy;
    figure(
        "fig_explicit_vs_implicit_gamma",
        format!(
            "Explicit against implicit γ at d = {d}{}",
            if d == 0.0 { chapter(10, energy, u.chapter_material) } else { String::new() }
        ),
        format!("γ from the explicit law's closed form (solid) and from solving the implicit law (dotted), d = {d}."),
        vec![panel(
            "Explicit and implicit γ",
            GAMMA,
            vec![
                u.series(of(LawKind::Explicit)?, "explicit law", gamma, Stroke::Solid, 0),
                u.series(of(LawKind::Implicit)?, "implicit law", gamma, Stroke::Dotted, 1),
            ],
        )],
    )
}

/// The chapter's Fig. 11: P_tot with the explicit γ against its target.
fn explicit_ptot(u: &Uniaxial) -> Option<Figure> {
    let d = common_damage(u, &[LawKind::Explicit]).filter(|_| u.along())?;
    let c = u.model(LawKind::Explicit, CouplingKind::Frozen, d)?;
    figure(
        "fig_explicit_ptot",
        format!(
            "P_tot with the explicit γ at d = {d}{}",
            if d == 0.0 { chapter(11, &c.energy, u.chapter_material) } else { String::new() }
        ),
        format!("Total stress of the frozen model with γ from the explicit law, d = {d}, against the target P_pas + (1 − d) P_act it approximates (the chapter compares with the experimental data instead)."),
        vec![panel(
            "P_tot with the explicit γ",
            STRESS,
            vec![
                u.series(c, "P_tot, explicit law", stress, Stroke::Solid, 0),
                derived("P_pas + (1 − d) P_act (target)", xy(c, target), Stroke::Dashed, 1),
            ],
        )],
    )
}

/// Colour of a law.
fn law_colour(law: LawKind) -> usize {
    match law {
        LawKind::Implicit => 0,
        LawKind::Explicit => 1,
        LawKind::Energy => 2,
    }
}

/// Solid for frozen, dashed for consistent.
fn coupling_stroke(c: CouplingKind) -> Stroke {
    match c {
        CouplingKind::Frozen => Stroke::Solid,
        CouplingKind::Consistent => Stroke::Dashed,
    }
}

/// Every law × coupling of study `u` at its smallest damage: γ and P, with the target along
/// the fibres.
fn laws(run: &Run, u: &Uniaxial) -> Option<Figure> {
    let d = *u.damages().first()?;
    let pairs = u.pairs();
    let of = |y: fn(&CurvePoint) -> Option<f64>| -> Vec<Option<Series>> {
        pairs
            .iter()
            .filter_map(|&(l, c)| u.model(l, c, d).map(|curve| (l, c, curve)))
            .map(|(l, c, curve)| u.series(curve, words(l, c), y, coupling_stroke(c), law_colour(l)))
            .collect()
    };
    // γ = g(λ_f) does not depend on the coupling: one curve per law.
    let mut laws: Vec<LawKind> = pairs.iter().map(|p| p.0).collect();
    laws.dedup();
    let gammas = laws
        .iter()
        .filter_map(|&l| u.active().find(|(m, _)| m.law == l && m.damage == d))
        .map(|(m, c)| {
            derived(
                format!("{} law", m.law.name()),
                xy(c, gamma),
                Stroke::Solid,
                law_colour(m.law),
            )
        })
        .collect();
    let mut p = of(stress);
    if u.along() {
        let c = u.active().find(|(m, _)| m.damage == d).map(|(_, c)| c)?;
        p.push(derived(
            "P_pas + (1 − d) P_act (target)",
            xy(c, target),
            Stroke::Dotted,
            3,
        ));
    }
    let names: Vec<String> = pairs.iter().map(|&(l, c)| words(l, c)).collect();
    figure(
        "fig_laws",
        format!(
            "Activation laws and couplings {} the fibres at d = {d}: {} (study \"{}\")",
            u.dir(),
            names.join("; "),
            u.study
        ),
        format!(
            "Uniaxial tension {} the fibres, energy {}, d = {d}. {}",
            u.dir(),
            run.material,
            laws_caption(u, &pairs, d)
        ),
        vec![
            panel(
                format!("Activation γ, d = {d} (either coupling)"),
                GAMMA,
                gammas,
            ),
            panel(format!("Nominal stress, d = {d}"), STRESS, p),
        ],
    )
}

/// What the strokes and the laws of [`laws`] mean, for the pairs drawn only.
fn laws_caption(u: &Uniaxial, pairs: &[(LawKind, CouplingKind)], d: f64) -> String {
    let has_law = |l: LawKind| pairs.iter().any(|p| p.0 == l);
    let has_coupling = |c: CouplingKind| pairs.iter().any(|p| p.1 == c);
    const FROZEN: &str = "frozen coupling, P = ∂Ŵ/∂F at γ = g(λ_f) held (the chapter's model)";
    const CONSISTENT: &str = "consistent coupling, the hyperelastic Ψ(F) = Ŵ(F, g(λ_f(F)))";
    let mut words = match (
        has_coupling(CouplingKind::Frozen),
        has_coupling(CouplingKind::Consistent),
    ) {
        (true, true) => vec![format!("Solid: {FROZEN}; dashed: {CONSISTENT}.")],
        (true, false) => vec![format!("Solid: {FROZEN}.")],
        (false, true) => vec![format!("Dashed: {CONSISTENT}.")],
        (false, false) => Vec::new(),
    };
    if has_law(LawKind::Implicit) {
        words.push(format!(
            "The implicit law is built so that its frozen model reproduces the target P_pas + (1 − d) P_act along the fibres{}.",
            gap_words(u.model(LawKind::Implicit, CouplingKind::Frozen, d))
        ));
    }
    if has_law(LawKind::Explicit) {
        words.push("The explicit law is the chapter's closed-form approximation of the implicit one (eq. (14)).".into());
    }
    if has_law(LawKind::Energy) {
        words.push(format!(
            "The energy law is built so that its consistent model reproduces the target along the fibres{}.",
            gap_words(u.model(LawKind::Energy, CouplingKind::Consistent, d))
        ));
    }
    words.join(" ")
}

/// The largest |P − (P_pas + (1 − d) P_act)| of `curve` \[kPa\], where, and relative to the
/// target there.
fn target_gap(curve: &Curve) -> Option<(f64, f64, f64)> {
    curve
        .points
        .iter()
        .filter_map(|p| target(p).map(|t| ((p.stress - t).abs(), p.lambda, t.abs())))
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(gap, at, t)| (gap, at, if t > 0.0 { gap / t } else { f64::INFINITY }))
}

/// How far `curve` (a law in the coupling it is built for) is from its target, in words for a
/// caption: nothing if it is on it to 1e-8 relative, or not along the fibres. The laws are built
/// for exact incompressibility; with a volumetric energy the curve leaves the target.
fn gap_words(curve: Option<&Curve>) -> String {
    match curve.and_then(target_gap) {
        Some(g) if g.2 > 1e-8 => format!(
            " under exact incompressibility; in this scene it misses it by up to {}",
            distance(g)
        ),
        _ => String::new(),
    }
}

/// `X kPa at λ = Y (Z % of the target there)` of a [`target_gap`].
fn distance((gap, at, rel): (f64, f64, f64)) -> String {
    format!(
        "{} kPa at λ = {} ({} % of the target there)",
        text::significant(gap, 3),
        text::significant(at, 6),
        text::significant(100.0 * rel, 3)
    )
}

/// One panel per law × coupling of study `u`, a curve per damage (two or more damages).
fn loss_of_activation(u: &Uniaxial) -> Option<Figure> {
    let ds = u.damages();
    if ds.len() < 2 {
        return None;
    }
    let panels = u
        .pairs()
        .into_iter()
        .map(|(l, c)| {
            let mut s = Vec::new();
            for (i, &d) in ds.iter().enumerate() {
                if let Some(curve) = u.model(l, c, d) {
                    s.push(u.series(curve, format!("d = {d}"), stress, Stroke::Solid, i));
                    s.push(derived("", xy(curve, target), Stroke::Dotted, i));
                }
            }
            if u.along() {
                s.push(key("dotted: P_pas + (1 − d) P_act", Stroke::Dotted));
            }
            panel(words(l, c), STRESS, s)
        })
        .collect();
    figure(
        "fig_loss_of_activation",
        format!(
            "Loss of activation {} the fibres, d = {} (study \"{}\")",
            u.dir(),
            list(&ds),
            u.study
        ),
        format!(
            "Nominal stress in uniaxial tension {} the fibres for each damage d, a panel per law and coupling{}.",
            u.dir(),
            if u.along() {
                let worst = u
                    .active()
                    .filter_map(|(_, c)| target_gap(c))
                    .max_by(|a, b| a.2.total_cmp(&b.2));
                match worst {
                    Some(g) if g.2 > 1e-8 => format!(
                        "; dotted in the same colour: the target P_pas + (1 − d) P_act, which the laws are built to reproduce under exact incompressibility (the explicit law approximately); the largest distance from it here is {}",
                        distance(g)
                    ),
                    _ => "; dotted in the same colour: the target P_pas + (1 − d) P_act".into(),
                }
            } else {
                String::new()
            }
        ),
        panels,
    )
}

/// A cylinder study: γ and λ_f at the centre, and the nominal stress (FE solid, the homogeneous
/// 0D curve of the same model dashed), a curve per damage.
fn cylinder(run: &Run, study: &str, c: &CylinderResult) -> Option<Figure> {
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
    let lambdas: Vec<f64> = c
        .sweeps
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.lambda))
        .collect();
    let (lo, hi) = lambdas
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |a, &l| {
            (a.0.min(l), a.1.max(l))
        });
    let lmin = run.curve.lambda_min();
    fibre.push(derived(
        format!("λ_min = {lmin}"),
        vec![(lo, lmin), (hi, lmin)],
        Stroke::Dashed,
        GREY,
    ));
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
    let like_fig_12 = c.bases == Bases::Clamped
        && m.law == LawKind::Explicit
        && m.coupling == CouplingKind::Frozen;
    let geometry = run
        .results
        .studies
        .iter()
        .find(|s| s.name == study && matches!(s.result, StudyResult::Cylinder(_)))
        .and_then(|s| s.details.first())
        .map_or(String::new(), |d| format!(" ({d})"));
    figure(
        "fig_cylinder",
        format!(
            "The cylinder \"{study}\": {} bases, {}, d = {}{}",
            bases_name(c.bases),
            words(m.law, m.coupling),
            list(&ds),
            if like_fig_12 { chapter(12, &c.energy, run.chapter_material) } else { String::new() }
        ),
        format!(
            "Axisymmetric FE cylinder{geometry}, energy {}. Top: γ at the quadrature point nearest the centre of the cylinder; middle: the fibre stretch λ_f there, the argument of the law (the implicit and explicit laws give γ = 0 where λ_f ≤ λ_min); bottom: nominal axial stress (axial reaction / πR²), dashed: {}.",
            c.energy,
            match c.regions_in_words() {
                None => "the homogeneous uniaxial (0D) curve of the same model".to_string(),
                Some(regions) => format!(
                    "the homogeneous uniaxial (0D) curve of the uniform model at the sweep's d, \
                     without the regions ({regions}): a reference, not the same body"
                ),
            }
        ),
        vec![
            panel("γ at the centre of the cylinder", GAMMA, by_damage(|p| p.gamma_centre)),
            panel("Fibre stretch λ_f at the centre", "fibre stretch λ_f [-]", fibre),
            panel("Nominal axial stress", STRESS, p),
        ],
    )
}

/// P_FE − P_0D of every sweep, a panel per cylinder study.
fn fe_vs_0d(results: &Results) -> Option<Figure> {
    let drawn = || {
        results
            .cylinders()
            .filter(|(_, c)| c.sweeps.iter().any(|s| !s.points.is_empty()))
    };
    let regions: Vec<String> = drawn()
        .filter_map(|(study, c)| {
            c.regions_in_words()
                .map(|r| format!("\"{study}\" has regions ({r})"))
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
            panel(
                format!("{study} ({} bases): P_FE − P_0D", bases_name(c.bases)),
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
                    " {}: its 0D curve is the uniform model's at the sweep's d, so the difference is mostly the regions' own damage or activation, with the end effect of clamped bases on top.",
                    regions.join("; ")
                )
            }
        ),
        panels,
    )
}

/// `Fit: chapter's energy …` for a study called `fit: chapter's energy …` or `chapter's energy …`.
fn fit_heading(study: &str) -> String {
    let rest = study
        .strip_prefix("fit:")
        .or_else(|| study.strip_prefix("Fit:"))
        .unwrap_or(study)
        .trim();
    format!("Fit: {rest}")
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
    let start = |f: &FitOutcome, colour| {
        f.plot.start.as_ref().and_then(|(label, points)| {
            derived(label.clone(), points.clone(), Stroke::Dashed, colour)
        })
    };
    if first.kind == FitKind::Damage {
        let mut s = Vec::new();
        for (i, f) in fits.iter().enumerate() {
            s.push(derived(
                f.case.clone(),
                f.plot.data.clone(),
                Stroke::Markers,
                i,
            ));
            s.push(derived(status(f), f.plot.fitted.clone(), Stroke::Solid, i));
        }
        s.push(start(first, 7));
        panels.push(panel(fit_heading(study), &first.plot.y_label, s));
    } else {
        for f in fits {
            let s = vec![
                derived(
                    f.plot.data_label.clone(),
                    f.plot.data.clone(),
                    Stroke::Markers,
                    1,
                ),
                derived(status(f), f.plot.fitted.clone(), Stroke::Solid, 0),
                start(f, 2),
            ];
            panels.push(panel(
                format!("{}: {}", fit_heading(study), f.case),
                &f.plot.y_label,
                s,
            ));
        }
    }
    figure(
        &prefixed("fit", study),
        fit_heading(study),
        format!(
            "Least-squares fit ({}) to {}. Markers: data; solid: the fitted model; dashed: the model at the reference values.",
            first.kind.name(),
            first.source
        ),
        panels,
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

/// The figure of an activation-in-time study: a(t) with its schedule, then per damage value the
/// stress history (prescribed stretch) or the stretch history (free contraction), and γ(t).
fn history_figure(study: &str, r: &HistoryResult) -> Option<Figure> {
    const TIME: &str = "time t [s]";
    let over = |title: String, y: &str, series: Vec<Option<Series>>| -> Option<Panel> {
        let series: Vec<Series> = series.into_iter().flatten().collect();
        series
            .iter()
            .any(|s| !s.points.is_empty())
            .then(|| Panel::new(title, TIME, y, series))
    };
    let first = r.histories.first()?;
    let level = vec![
        derived(
            "activation level a(t)",
            first.points.iter().map(|p| (p.t, p.level)).collect(),
            Stroke::Solid,
            0,
        ),
        derived(
            "schedule a_s(t)",
            first.points.iter().map(|p| (p.t, p.schedule)).collect(),
            Stroke::Dashed,
            GREY,
        ),
    ];
    let free = r.loading == "free";
    let per_damage = |y: fn(&HistoryPoint) -> f64| -> Vec<Option<Series>> {
        r.histories
            .iter()
            .enumerate()
            .map(|(i, h)| {
                derived(
                    format!("d = {}", h.model.damage),
                    h.points.iter().map(|p| (p.t, y(p))).collect(),
                    Stroke::Solid,
                    i % 6,
                )
            })
            .collect()
    };
    let (title, y_label, response): (&str, &str, Vec<Option<Series>>) = if free {
        (
            "Free contraction: stretch along the fibres",
            LAMBDA,
            per_damage(|p| p.lambda),
        )
    } else {
        (
            "Prescribed stretch: nominal stress along the fibres",
            STRESS,
            per_damage(|p| p.stress),
        )
    };
    let mut response = over(title.into(), y_label, response);
    if let (true, Some(p)) = (free, response.as_mut()) {
        // λ = 1 wherever a = 0: the whole range, from the deepest shortening to rest.
        let low = p
            .series
            .iter()
            .flat_map(|s| s.points.iter().map(|q| q.1))
            .fold(1.0, f64::min);
        let pad = 0.05 * (1.0 - low).max(1e-3);
        p.y_range = Some((low - pad, 1.0 + pad));
    }
    let m = first.model;
    let block = match &r.volumetric {
        None => "A homogeneous incompressible block".to_string(),
        Some(v) => format!(
            "A homogeneous nearly incompressible block (Ŵ + U(J), U = {}; lateral stretches from zero lateral traction at each step)",
            v.formula()
        ),
    };
    let mut panels = vec![
        over("Activation level".into(), "activation level a [-]", level),
        response,
        over("Activation γ".into(), GAMMA, per_damage(|p| p.gamma)),
    ];
    if r.volumetric.is_some() {
        panels.push(over(
            "Volume ratio".into(),
            "volume ratio J = λ λ₂ λ₃ [-]",
            per_damage(|p| p.volume),
        ));
    }
    figure(
        &prefixed("history", study),
        format!("Activation in time (study \"{study}\")"),
        format!(
            "{block} along the fibres, quasi-static in time: {} law, {} coupling, the laws evaluated at each step with the active stress scaled by (1 − d)·a(t). {} Values per step in history.csv.",
            m.law.name(),
            m.coupling.name(),
            if free {
                "Zero axial load: the stretch solves P(λ) = 0 at each step."
            } else {
                "Prescribed stretch λ(t): the stress history."
            }
        ),
        panels,
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_headings_say_fit_once() {
        assert_eq!(
            fit_heading("fit: damage of weakened muscles"),
            "Fit: damage of weakened muscles"
        );
        assert_eq!(fit_heading("my damage"), "Fit: my damage");
    }
}
