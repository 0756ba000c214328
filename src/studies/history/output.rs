//! The activation-in-time kind's figure: a(t) with its schedule, the stress or stretch history
//! and γ(t) per damage (and J(t) for a nearly incompressible block).

use super::{HistoryPoint, HistoryResult};
use crate::models::ModelChoice;
use crate::plot::{Figure, Panel, Series, Stroke, GREY};
use crate::studies::domain::{in_domain, IN_DOMAIN};
use crate::studies::outputs::{
    derived, each_study, figure, model_cells, model_words, prefixed, Context, KindOutput, Of,
    OwnTable, Used, GAMMA, LAMBDA, STRESS,
};
use crate::studies::table::{every_row, Table};

/// The file.
pub const FILE: &str = "history.csv";

impl KindOutput for HistoryResult {
    /// Its rows of `history.csv`.
    fn tables(&self, study: &str) -> Vec<OwnTable> {
        vec![OwnTable::rows(
            FILE,
            "one row per activation-in-time model and time step",
            self.table(study),
        )]
    }

    fn used(&self) -> Used {
        Used::active(self.approach, self.histories.iter().map(|h| h.model))
    }

    fn figures(studies: &[Of<Self>], _: &Context) -> Vec<Figure> {
        each_study(studies, history_figure)
    }
}

impl HistoryResult {
    /// The table of `history.csv` for study `study`: t \[s\], the schedule a_s and the activation
    /// level a [-], λ, γ [-], P, the Cauchy stress σ₁₁, the volume ratio J [-], P_pas and the
    /// target (1 − d)·a·f_v·P_act(λ) \[kPa\], λ̇ [1/s] and f_v [-] (with force–velocity), and
    /// whether the law holds there, per model and time step.
    pub fn table(&self, study: &str) -> Table {
        let rows: Vec<(&super::History, &HistoryPoint)> = self
            .histories
            .iter()
            .flat_map(|h| h.points.iter().map(move |p| (h, p)))
            .collect();
        let cell = |i: usize| {
            rows.iter()
                .map(move |(h, _)| model_cells(self.approach, Some(h.model))[i].clone())
        };
        let at = |f: fn(&HistoryPoint) -> f64| rows.iter().map(move |(_, p)| Some(f(p)));
        Table::default()
            .text("study", "the study's name", every_row(study, rows.len()))
            .text("loading", "prescribed (the stretch as scheduled) or free (no load)", every_row(self.loading, rows.len()))
            .text("energy", "the strain energy's name", every_row(&self.energy, rows.len()))
            .text("law", "implicit, explicit or energy (empty: an approach without a law, active stress)", cell(1))
            .text("coupling", "frozen or consistent (empty: an approach without a law)", cell(2))
            .number("d", "-", "damage d", rows.iter().map(|(h, _)| Some(h.model.damage)))
            .number("t", "s", "time", at(|p| p.t))
            .number("a_schedule", "-", "the activation schedule at t", at(|p| p.schedule))
            .number("a", "-", "the activation level used at t", at(|p| p.level))
            .number("lambda", "-", "stretch λ", at(|p| p.lambda))
            .number("gamma", "-", "γ (ω for the structural approach, 0 for active stress)", at(|p| p.gamma))
            .number("P", "kPa", "nominal stress along the stretch", at(|p| p.stress))
            .number("cauchy", "kPa", "Cauchy stress σ₁₁ = P λ / J", at(|p| p.cauchy))
            .number("J", "-", "volume ratio", at(|p| p.volume))
            .number("P_pas", "kPa", "passive stress at λ", at(|p| p.passive))
            .number("P_act", "kPa", "target active stress (1 − d)·a·f_v·P_act(λ), f_v the force–velocity factor at the step's stretch rate (1 without [activation.force_velocity])", at(|p| p.active_target))
            .text("approach", "activation approach, active-strain, active-stress or structural", cell(0))
            .number("lambda_rate", "1/s", "fibre stretch rate λ̇ = (λ − λ_prev)/Δt of the step, backward Euler, 0 at the first step (empty without [activation.force_velocity])", rows.iter().map(|(_, p)| p.rate))
            .number("f_v", "-", "force–velocity factor f_v(λ̇) of the step (empty without [activation.force_velocity]: f_v = 1)", rows.iter().map(|(_, p)| p.velocity_factor))
            .boolean("in_domain", IN_DOMAIN, rows.iter().map(|(h, p)| in_domain(Some(&h.model), p.outside)))
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
    // With force–velocity every point has its factor (`HistoryPoint::velocity_factor`).
    let velocity = r
        .histories
        .iter()
        .flat_map(|h| &h.points)
        .any(|p| p.velocity_factor.is_some());
    format!(
        "{block} along the fibres, quasi-static in time: {}, {} the active stress scaled by {}. {} Values per step in history.csv.",
        model_words(m),
        if m.activation_law().is_some() {
            "the laws evaluated at each step with"
        } else {
            "no law:"
        },
        if velocity {
            "(1 − d)·a(t)·f_v(λ̇), f_v the force–velocity factor at the step's fibre stretch rate λ̇ (backward Euler, 0 at the first step; columns lambda_rate and f_v)"
        } else {
            "(1 − d)·a(t)"
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
