//! The activation-in-time kind's figure: a(t) with its schedule, the stress or stretch history
//! and γ(t) per damage (and J(t) for a nearly incompressible block).

use super::{HistoryPoint, HistoryResult};
use crate::models::ModelChoice;
use crate::plot::{Figure, Panel, Series, Stroke, GREY};
use crate::studies::outputs::{
    derived, each_study, figure, model_words, prefixed, Context, KindOutput, Of, GAMMA, LAMBDA,
    STRESS,
};

impl KindOutput for HistoryResult {
    fn figures(studies: &[Of<Self>], _: &Context) -> Vec<Figure> {
        each_study(studies, history_figure)
    }
}

/// The stretch axis of a free contraction from its deepest shortening up to rest (λ = 1
/// wherever a = 0).
fn down_to_rest(p: &mut Panel) {
    let low = p
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|q| q.1))
        .fold(1.0, f64::min);
    let pad = 0.05 * (1.0 - low).max(1e-3);
    p.y_range = Some((low - pad, 1.0 + pad));
}

/// The caption of [`history_figure`]: the block, its model, its loading.
fn caption(r: &HistoryResult, m: &ModelChoice, free: bool) -> String {
    let block = match &r.volumetric {
        None => "A homogeneous incompressible block".to_string(),
        Some(v) => format!(
            "A homogeneous nearly incompressible block (Ŵ + U(J), U = {}; lateral stretches from zero lateral traction at each step)",
            v.formula()
        ),
    };
    format!(
        "{block} along the fibres, quasi-static in time: {}, {} the active stress scaled by (1 − d)·a(t). {} Values per step in history.csv.",
        model_words(m),
        if m.activation_law().is_some() {
            "the laws evaluated at each step with"
        } else {
            "no law:"
        },
        if free {
            "Zero axial load: the stretch solves P(λ) = 0 at each step."
        } else {
            "Prescribed stretch λ(t): the stress history."
        }
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
        down_to_rest(p);
    }
    let m = first.model;
    let mut panels = vec![
        over("Activation level".into(), "activation level a [-]", level),
        response,
        // An approach without a law has no γ (≡ 0) to draw.
        m.activation_law()
            .and_then(|_| over("Activation γ".into(), GAMMA, per_damage(|p| p.gamma))),
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
        caption(r, &m, free),
        panels,
    )
}
