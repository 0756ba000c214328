//! The uniaxial kind's figures: the passive curves and the transverse isotropy, constant γ, the
//! active curve, the laws' γ and stresses, the loss of activation with damage (the chapter's
//! Figs. 2–10 where they are the same), drawn for whatever energy, curve, laws and damages the
//! scene asks for.

use super::{Curve, CurveModel, CurvePoint, UniaxialResult};
use crate::active::drive::Drive;
use crate::active::{ActiveCurve, Approach};
use crate::models::{CouplingKind, LawKind, ModelChoice};
use crate::plot::{Figure, Panel, Scale, Series, Stroke};
use crate::studies::curves::{self, uniaxial_curve};
use crate::studies::outputs::{
    chapter, coupling_stroke, curve_parameters_text, derived, figure, key, law_colour, list, panel,
    sorted_unique, words, Context, KindOutput, Of, OwnTable, Used, GAMMA, STRESS,
};
use crate::uniaxial::Direction;

/// What the uniaxial figures are drawn from: the scene's material and every uniaxial study.
struct Run<'a> {
    /// The material's energy.
    material: String,
    curve: ActiveCurve,
    /// The scene's energy and active curve are the chapter's (see [`chapter`]).
    chapter_material: bool,
    uniaxial: Vec<Uniaxial<'a>>,
}

impl KindOutput for UniaxialResult {
    /// Its rows of `curves.csv`.
    fn tables(&self, study: &str) -> Vec<OwnTable> {
        vec![curves::own_table(&curves::uniaxial_rows(study, self))]
    }

    fn used(&self) -> Used {
        let mut used = Used::active(
            self.approach,
            self.curves.iter().filter_map(|c| match c.model {
                CurveModel::Active(m) => Some(m),
                _ => None,
            }),
        );
        for c in &self.curves {
            if !used.energies.contains(&c.energy) {
                used.energies.push(c.energy.clone());
            }
        }
        used.constant = self
            .curves
            .iter()
            .any(|c| matches!(c.model, CurveModel::Constant(_)));
        used
    }

    /// Per study in order: its passive curves, constant γ, the active curve (once), the laws'
    /// figures and the loss of activation; then the transverse isotropy over all of them.
    fn figures(studies: &[Of<Self>], cx: &Context) -> Vec<Figure> {
        let run = Run {
            material: cx.material.clone(),
            curve: cx.curve,
            chapter_material: cx.chapter_material,
            uniaxial: studies
                .iter()
                .map(|s| Uniaxial {
                    study: s.name,
                    direction: s.result.direction,
                    approach: s.result.approach,
                    curves: &s.result.curves,
                    chapter_material: cx.chapter_material,
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
            out.extend(without_a_law(&run, u));
            out.extend(loss_of_activation(u));
        }
        out.extend(isotropy);
        out
    }
}

/// A model's law and coupling (`None`: an approach without a law, active stress).
type Form = Option<(LawKind, CouplingKind)>;

/// The uniaxial curves of one study.
#[derive(Clone, Copy)]
struct Uniaxial<'a> {
    study: &'a str,
    direction: Direction,
    approach: Approach,
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

    /// The curve of `law`, `coupling` at damage `d` (of an approach that has a law).
    fn model(&self, law: LawKind, coupling: CouplingKind, d: f64) -> Option<&'a Curve> {
        self.of_form(Some((law, coupling)), d)
    }

    /// The curve of the model of law and coupling `form` (`None`: of an approach without a law)
    /// at damage `d`.
    fn of_form(&self, form: Form, d: f64) -> Option<&'a Curve> {
        self.active()
            .find(|(m, _)| m.activation_law() == form && m.damage == d)
            .map(|(_, c)| c)
    }

    fn damages(&self) -> Vec<f64> {
        sorted_unique(self.active().map(|(m, _)| m.damage).collect())
    }

    /// The models' laws and couplings in run order (`None`: an approach without a law).
    fn forms(&self) -> Vec<Form> {
        let mut v = Vec::new();
        for (m, _) in self.active() {
            if !v.contains(&m.activation_law()) {
                v.push(m.activation_law());
            }
        }
        v
    }

    /// (law, coupling) pairs in run order.
    fn pairs(&self) -> Vec<(LawKind, CouplingKind)> {
        self.forms().into_iter().flatten().collect()
    }

    /// `implicit law, frozen coupling`, or the approach of a model without a law
    /// (`active-stress`).
    fn form_words(&self, form: Form) -> String {
        match form {
            Some((l, c)) => words(l, c),
            None => self
                .active()
                .find(|(m, _)| m.activation_law().is_none())
                .map_or_else(String::new, |(m, _)| m.approach.name().to_string()),
        }
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
                (self.direction, self.approach),
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
            "Top: γ solving P_tot(λ, γ) = P_pas(λ) + (1 − d) P_act(λ) (the implicit law), d = {d}{}, energy {}. Bottom: the resulting total stress P_tot (frozen coupling) with its parts (1 − d) P_act and P_pas{}.",
            other_damages(u, d),
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

/// `, drawn at the study's first damage only (…)` when the study has others; else nothing.
fn other_damages(u: &Uniaxial, d: f64) -> String {
    let others: Vec<String> = u
        .damages()
        .into_iter()
        .filter(|&x| x != d)
        .map(|x| x.to_string())
        .collect();
    if others.is_empty() {
        return String::new();
    }
    format!(
        " (the study's first damage; its other damages, d = {}, are in curves.csv and in the loss-of-activation figure)",
        others.join(", ")
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

/// Every law × coupling of study `u` at its smallest damage: γ and P, with the target along
/// the fibres.
fn laws(run: &Run, u: &Uniaxial) -> Option<Figure> {
    let d = *u.damages().first()?;
    let pairs = u.pairs();
    if pairs.is_empty() {
        return None;
    }
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
        .filter_map(|&l| {
            u.active()
                .find(|(m, _)| m.activation_law().map(|x| x.0) == Some(l) && m.damage == d)
                .map(|(_, c)| (l, c))
        })
        .map(|(l, c)| {
            derived(
                format!("{} law", l.name()),
                xy(c, gamma),
                Stroke::Solid,
                law_colour(l),
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
            "Uniaxial tension {} the fibres, energy {}, d = {d}{}. {}",
            u.dir(),
            run.material,
            other_damages(u, d),
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

/// The models of study `u` whose approach has no law (active stress) at its smallest damage:
/// P, with the target along the fibres, which they meet by construction.
fn without_a_law(run: &Run, u: &Uniaxial) -> Option<Figure> {
    let d = *u.damages().first()?;
    let (m, c) = u
        .active()
        .find(|(m, _)| m.activation_law().is_none() && m.damage == d)?;
    let name = m.approach.name();
    let mut p = vec![u.series(c, name, stress, Stroke::Solid, 0)];
    if u.along() {
        p.push(derived(
            "P_pas + (1 − d) P_act (target)",
            xy(c, target),
            Stroke::Dotted,
            3,
        ));
    }
    figure(
        &format!("fig_{}", crate::studies::slug(name)),
        format!(
            "The {name} approach {} the fibres at d = {d} (study \"{}\")",
            u.dir(),
            u.study
        ),
        format!(
            "Uniaxial tension {} the fibres, energy {}, d = {d}, approach {name}: {}.",
            u.dir(),
            run.material,
            m.approach.no_law()
        ),
        vec![panel(format!("Nominal stress, d = {d}"), STRESS, p)],
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
        words.push("The explicit law is the chapter's closed-form approximation of the implicit one (eq. (14)), on its domain 0.7 ≤ λ_f ≤ 1.5, d_eff ≤ 0.5 only: outside it, in_domain = false in curves.csv.".into());
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
        crate::text::significant(gap, 3),
        crate::text::significant(at, 6),
        crate::text::significant(100.0 * rel, 3)
    )
}

/// One panel per law × coupling of study `u`, a curve per damage (two or more damages).
fn loss_of_activation(u: &Uniaxial) -> Option<Figure> {
    let ds = u.damages();
    if ds.len() < 2 {
        return None;
    }
    let panels = u
        .forms()
        .into_iter()
        .map(|form| {
            let mut s = Vec::new();
            for (i, &d) in ds.iter().enumerate() {
                if let Some(curve) = u.of_form(form, d) {
                    s.push(u.series(curve, format!("d = {d}"), stress, Stroke::Solid, i));
                    s.push(derived("", xy(curve, target), Stroke::Dotted, i));
                }
            }
            if u.along() {
                s.push(key("dotted: P_pas + (1 − d) P_act", Stroke::Dotted));
            }
            panel(u.form_words(form), STRESS, s)
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
            "Nominal stress in uniaxial tension {} the fibres for each damage d, a panel per {}{}.",
            u.dir(),
            if u.forms().contains(&None) {
                "approach without a law"
            } else {
                "law and coupling"
            },
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
