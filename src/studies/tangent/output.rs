//! The tangent kind's outputs: its four tables, its figures (the remainders on log–log axes with
//! slope-1 and slope-2 guides; with the FE level, Newton's residual per iteration with each
//! tangent and the assembled residual's remainders) and its report section (per model: orders,
//! central-difference error, asymmetry, approximate tangents, ellipticity, flagged states).

use super::fe::{FeResult, TangentCost};
use super::run::{ModelTests, StateTest, TangentResult};
use crate::app_error::{finite, AppError};
use crate::plot::{Figure, Panel, Scale, Series, Stroke, GREY};
use crate::studies::cylinder::bases_name;
use crate::studies::outputs::{
    each_study, prefixed, strokes, Context, KindOutput, Of, OwnTable, Used,
};
use crate::tangent_check::Remainders;
use crate::text::{escape_html as escape, significant};
use std::fmt::Write;

/// The most unflagged remainder curves drawn (evenly chosen; every one is in tangent.csv).
const MAX_SMOOTH_CURVES: usize = 300;
/// The most flagged remainder curves drawn.
const MAX_FLAGGED_CURVES: usize = 200;
/// The most flagged states listed in the report (every one is in tangent_summary.csv).
const MAX_LISTED: usize = 30;

impl KindOutput for TangentResult {
    /// The summary is the study's `table`; the remainders, the FE level's remainders and its
    /// Newton histories are `remainders`, `fe_remainders` and `newton` in Python.
    fn tables(&self, study: &str) -> Vec<OwnTable> {
        let table = |key, file: &str, rows_are, table| OwnTable {
            key,
            file: file.to_string(),
            rows_are,
            table,
        };
        let mut out = vec![
            table(
                "table",
                super::run::SUMMARY_FILE,
                "one row per tangent study, model and state",
                self.summary_table(study),
            ),
            table(
                "remainders",
                "tangent.csv",
                "one row per tangent study, model, state, direction and step h",
                self.remainder_table(study),
            ),
        ];
        if let Some(t) = self.fe_table(study) {
            out.push(table(
                "fe_remainders",
                "tangent_fe.csv",
                "one row per FE configuration, state, tangent and step h",
                t,
            ));
        }
        if let Some(t) = self.newton_table(study) {
            out.push(table(
                "newton",
                "tangent_newton.csv",
                "one row per FE configuration, tangent and Newton iteration",
                t,
            ));
        }
        out
    }

    fn used(&self) -> Used {
        Used {
            models: self.models.iter().map(|m| m.model.clone()).collect(),
            ..Used::default()
        }
    }

    /// Per model: its least order of r₁ and its flagged states; with the FE level, what each
    /// tangent cost Newton.
    fn console(&self, study: &str) -> Vec<String> {
        let fe = self.fe.iter().flat_map(|fe| {
            cost_words(fe)
                .into_iter()
                .map(move |w| format!("{study}: FE level, Newton from the predictor with the {w}"))
        });
        self.models
            .iter()
            .map(|m| {
                let least = over_states(m, true, |s| least_over(s, |r| r.order_1));
                let rate = m.rate.map_or(String::new(), |r| format!(", λ̇ = {r} 1/s"));
                format!(
                    "{study}: {}{rate}: order of r1 ≥ {}; {} of {} states flagged",
                    m.label,
                    least.map_or("–".into(), |o| significant(o, 3)),
                    flagged(m),
                    m.states.len()
                )
            })
            .chain(fe)
            .collect()
    }

    /// How many model–state pairs were flagged, by kind.
    fn findings(&self) -> Vec<String> {
        let mut kinds: Vec<(String, usize)> = Vec::new();
        for m in &self.models {
            for s in &m.states {
                let kind = match s {
                    Err(_) => Some("not-evaluable".to_string()),
                    Ok(s) => s
                        .directions
                        .iter()
                        .flatten()
                        .find_map(|d| d.flag.as_ref().map(|f| f.kind().to_string())),
                };
                if let Some(kind) = kind {
                    match kinds.iter_mut().find(|(k, _)| *k == kind) {
                        Some((_, n)) => *n += 1,
                        None => kinds.push((kind, 1)),
                    }
                }
            }
        }
        let pairs = self.models.len() * self.states.len();
        let flagged: usize = kinds.iter().map(|(_, n)| n).sum();
        let by: Vec<String> = kinds.iter().map(|(k, n)| format!("{n} {k}")).collect();
        vec![format!(
            "{flagged} of {pairs} model–state pairs flagged{}",
            if by.is_empty() {
                String::new()
            } else {
                format!(" ({})", by.join(", "))
            }
        )]
    }

    fn figures(studies: &[Of<Self>], _: &Context) -> Vec<Figure> {
        let mut out = each_study(studies, remainder_figure);
        out.extend(each_study(studies, fe_figure));
        out
    }

    fn report(studies: &[Of<Self>], _: &Context, h: &mut String) -> Result<(), AppError> {
        for s in studies {
            section(h, s.name, s.result)?;
        }
        Ok(())
    }
}

/// The least of a remainder statistic over a state's directions.
fn least_over(s: &StateTest, f: fn(&Remainders) -> Option<f64>) -> Option<f64> {
    s.directions.iter().flatten().filter_map(f).reduce(f64::min)
}

/// The states of `m` flagged along some direction, or not evaluable.
fn flagged(m: &ModelTests) -> usize {
    m.states
        .iter()
        .filter(|s| {
            s.as_ref().map_or(true, |s| {
                s.directions.iter().flatten().any(|d| d.flag.is_some())
            })
        })
        .count()
}

/// `(h, r(h)/r(hₙ))` of the remainders above `floor`, hₙ the smallest such step: every curve
/// ends at 1 where it is asymptotic, and a kink or jump that the larger steps reach shows as
/// a departure above its slope.
fn normalised(h: &[f64], r: &[Option<f64>], floor: f64) -> Vec<(f64, f64)> {
    let valid: Vec<(f64, f64)> = h
        .iter()
        .zip(r)
        .filter_map(|(h, r)| r.filter(|r| *r > floor).map(|r| (*h, r)))
        .collect();
    let Some(&(_, last)) = valid.last() else {
        return Vec::new();
    };
    valid.iter().map(|(h, r)| (*h, r / last)).collect()
}

/// The slope-1 and slope-2 guides through (hₙ, 1) over `h`, hₙ the smallest step.
fn guides(h: &[f64]) -> Vec<Series> {
    let (Some(&h0), Some(&hn)) = (h.first(), h.last()) else {
        return Vec::new();
    };
    [(2.0, Stroke::Dashed), (1.0, Stroke::Dotted)]
        .into_iter()
        .map(|(p, stroke)| {
            Series::new(
                format!("slope {p}"),
                vec![(hn, 1.0), (h0, (h0 / hn).powf(p))],
                stroke,
                GREY,
            )
        })
        .collect()
}

/// The curves of one remainder (0 or 1): unflagged ones in grey, flagged ones coloured by the
/// kind of their flag, each kind labelled once.
fn remainder_series(r: &TangentResult, which: u8) -> (Vec<Series>, usize, usize) {
    let (mut smooth, mut flagged) = (Vec::new(), Vec::new());
    let mut kinds: Vec<&'static str> = Vec::new();
    for m in &r.models {
        for s in m.states.iter().flatten() {
            for d in s.directions.iter().flatten() {
                let values = if which == 0 { &d.r0 } else { &d.r1 };
                let points = normalised(&d.h, values, d.floor);
                match &d.flag {
                    None => smooth.push(points),
                    Some(f) => {
                        let kind = f.kind();
                        if !kinds.contains(&kind) {
                            kinds.push(kind);
                        }
                        flagged.push((kind, points));
                    }
                }
            }
        }
    }
    let (n_smooth, n_flagged) = (smooth.len(), flagged.len());
    let stride = n_smooth.div_ceil(MAX_SMOOTH_CURVES).max(1);
    let mut out: Vec<Series> = smooth
        .into_iter()
        .step_by(stride)
        .enumerate()
        .map(|(i, p)| {
            let label = if i == 0 {
                format!("no flag ({n_smooth} tests)")
            } else {
                String::new()
            };
            Series::new(label, p, Stroke::Solid, 0)
        })
        .collect();
    let mut labelled: Vec<&str> = Vec::new();
    for (kind, p) in flagged.into_iter().take(MAX_FLAGGED_CURVES) {
        // Colour 0 is the tests without a flag.
        let colour = 1 + kinds.iter().position(|k| *k == kind).unwrap_or(0);
        let count = kinds_count(r, kind);
        let label = if labelled.contains(&kind) {
            String::new()
        } else {
            format!("flag {kind} ({count} tests)")
        };
        labelled.push(kind);
        out.push(Series::new(label, p, Stroke::Solid, colour));
    }
    out.extend(guides(&r.h));
    (out, n_smooth, n_flagged)
}

/// The tests flagged with `kind`.
fn kinds_count(r: &TangentResult, kind: &str) -> usize {
    r.models
        .iter()
        .flat_map(|m| m.states.iter().flatten())
        .flat_map(|s| s.directions.iter().flatten())
        .filter(|d| d.flag.as_ref().is_some_and(|f| f.kind() == kind))
        .count()
}

/// A log–log panel.
/// A log–log panel over the steps: its x range the steps' own, widened by a factor 1.5 (the
/// default range is padded linearly, which a log axis over decades cannot take).
fn log_log(title: &str, x: &str, y: &str, series: Vec<Series>) -> Panel {
    let steps = series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
    let (lo, hi) = steps.fold((f64::INFINITY, 0.0f64), |(l, h), x| (l.min(x), h.max(x)));
    let mut p = Panel::new(title, x, y, series);
    p.scale = Scale::LogLog;
    if lo > 0.0 && hi > lo {
        p.x_range = Some((lo / 1.5, hi * 1.5));
    }
    p
}

/// The remainders of every model, state and direction, normalised by their value at the
/// largest step, with the guides.
pub fn remainder_figure(study: &str, r: &TangentResult) -> Option<Figure> {
    let (one, n_smooth, n_flagged) = remainder_series(r, 1);
    let (zero, _, _) = remainder_series(r, 0);
    if n_smooth + n_flagged == 0 {
        return None;
    }
    let panels = vec![
        log_log(
            "r₁(h) = ‖P(F + hΔF) − P(F) − h A:ΔF‖ over its value at the smallest step",
            "step h [-]",
            "r₁(h)/r₁(hₙ) [-]",
            one,
        ),
        log_log(
            "r₀(h) = ‖P(F + hΔF) − P(F)‖, over its value at the smallest step",
            "step h [-]",
            "r₀(h)/r₀(hₙ) [-]",
            zero,
        ),
    ];
    Some(Figure::new(
        prefixed("tangent", study),
        format!("Taylor remainders of every model (study \"{study}\")"),
        format!(
            "The Taylor test of the {} energy's models at {} states along {} directions: where a model is smooth and its tangent A the derivative of its stress P, r₁ falls as h² (the dashed guide) and r₀ as h (the dotted one). Each curve is divided by its value at its smallest step above the rounding floor (points below the floor are not drawn), so that it ends at 1 where it is asymptotic: a kink or a jump of P that only the larger steps reach lifts the curve off its slope there. Blue: no flag ({n_smooth} tests{}); in other colours: the {n_flagged} tests where an order left its band (1 for r₀, 2 for r₁), by cause (tangent_summary.csv says why, state by state). Values in tangent.csv.",
            r.energy,
            r.states.len(),
            r.directions.len(),
            if n_smooth > MAX_SMOOTH_CURVES { format!(", {MAX_SMOOTH_CURVES} of them drawn") } else { String::new() },
        ),
        panels,
    ))
}

/// The drawing order of a tangent: the exact one last, on top of central differences that
/// agree with it.
fn tangent_order(name: &str) -> usize {
    match name {
        "exact" => 2,
        "symmetric frozen" => 1,
        _ => 0,
    }
}

/// The colour of a tangent.
fn tangent_colour(name: &str) -> usize {
    match name {
        "exact" => 0,
        "symmetric frozen" => 1,
        _ => 2,
    }
}

/// What each tangent cost Newton, in words: the iterations and the time to the tolerance
/// (least–largest over the configurations that reached it), the median time per iteration, and
/// how many configurations did not reach it, with the residual they left.
pub fn cost_words(fe: &FeResult) -> Vec<String> {
    let ms = |s: f64| significant(s * 1e3, 2);
    let span = |lo: String, hi: String| if lo == hi { lo } else { format!("{lo}–{hi}") };
    fe.costs()
        .iter()
        .map(|c: &TangentCost| {
            let mut w = format!("{}: ", c.tangent);
            if let (Some((k0, k1)), Some((t0, t1))) = (c.iterations, c.seconds_to_converge) {
                let _ = write!(
                    w,
                    "{} iterations, {} ms to 1e-10",
                    span(k0.to_string(), k1.to_string()),
                    span(ms(t0), ms(t1))
                );
                if c.converged < c.runs {
                    let _ = write!(w, " in {} of {} configurations", c.converged, c.runs);
                }
                w.push_str(", ");
            }
            if let Some(t) = c.seconds_per_iteration {
                let _ = write!(w, "{} ms per iteration", ms(t));
            }
            let missed = c.runs - c.converged - c.failed;
            if let (true, Some((k, r))) = (missed > 0, c.left) {
                let _ = write!(w, "; {missed} of {} configurations not at 1e-10 after {k} iterations (residual up to {r:.1e})", c.runs);
            }
            if c.failed > 0 {
                let _ = write!(w, "; {} of {} failed", c.failed, c.runs);
            }
            w
        })
        .collect()
}

/// Newton's residual per iteration with each tangent (one line per configuration, the legend
/// once per tangent with its median time per iteration).
fn newton_series(fe: &FeResult) -> Vec<Series> {
    let costs = fe.costs();
    let mut out = Vec::new();
    let mut labelled: Vec<&str> = Vec::new();
    for (i, c) in fe.configs.iter().enumerate() {
        for n in &c.newton {
            let points = n
                .residuals
                .iter()
                .enumerate()
                .map(|(k, v)| (k as f64, *v))
                .collect();
            let time = costs
                .iter()
                .find(|c| c.tangent == n.tangent)
                .and_then(|c| c.seconds_per_iteration);
            let label = match (labelled.contains(&n.tangent), time) {
                (false, Some(t)) => {
                    labelled.push(n.tangent);
                    format!(
                        "{} ({} ms per iteration)",
                        n.tangent,
                        significant(t * 1e3, 2)
                    )
                }
                _ => String::new(),
            };
            out.push((
                n.tangent,
                Series::new(label, points, strokes(i), tangent_colour(n.tangent)),
            ));
        }
    }
    out.sort_by_key(|(t, _)| tangent_order(t));
    out.into_iter().map(|(_, s)| s).collect()
}

/// Newton's residual per iteration and the assembled residual's r₁ with each tangent.
pub fn fe_figure(study: &str, r: &TangentResult) -> Option<Figure> {
    let fe = r.fe.as_ref()?;
    let newton = newton_series(fe);
    let mut taylor: Vec<(&str, Series)> = Vec::new();
    for (i, c) in fe.configs.iter().enumerate() {
        for t in &c.taylor {
            let Ok(a) = &t.outcome else { continue };
            let stroke = if t.state == "converged" {
                Stroke::Solid
            } else {
                Stroke::Dashed
            };
            let label = if i == 0 {
                format!("{}, {}", t.tangent, t.state)
            } else {
                String::new()
            };
            let points = normalised(a.h(), &a.u.r1, a.floor());
            let series = Series::new(label, points, stroke, tangent_colour(t.tangent));
            taylor.push((t.tangent, series));
        }
    }
    taylor.sort_by_key(|(t, _)| tangent_order(t));
    let mut taylor: Vec<Series> = taylor.into_iter().map(|(_, s)| s).collect();
    taylor.extend(guides(&r.h));
    let mut iterations = Panel::new(
        "Newton from the predictor of the load step λ₀ → λ₁: the solver's scaled residual per iteration",
        "Newton iteration (0: the predictor) [-]",
        "scaled residual [-]",
        newton,
    );
    iterations.scale = Scale::CountedLogY;
    let panels = vec![
        iterations,
        log_log(
            "Assembled residual, displacement rows: r₁(h) = ‖R(x + hv) − R(x) − h K v‖ over r₁(hₙ)",
            "step h [-]",
            "r₁(h)/r₁(hₙ) [-]",
            taylor,
        ),
    ];
    Some(Figure::new(
        prefixed("tangent_fe", study),
        format!("What a tangent costs the Newton solver (study \"{study}\")"),
        format!(
            "The cylinder of the FE level ({} × {} cells), model {}, load step λ = {} → {}: Newton's residual with each tangent the solver can use (exact: quadratic; the frozen model's symmetric approximation: linear; central differences of the stress at every quadrature point: quadratic to their accuracy, drawn under the exact tangent's lines where they coincide, at the cost per iteration in the legend), one line per element, bases and incompressibility ({} of them; strokes cycle through solid, dashed, dotted), the time per iteration the median over them (each one's in tangent_newton.csv). Below, the Taylor test of the assembled residual's displacement rows with each tangent at the converged state (solid) and at the step's predictor (dashed): slope 2 (dashed guide) for an exact tangent, slope 1 (dotted guide) for an approximate one. Values in tangent_newton.csv and tangent_fe.csv.",
            fe.cells.0, fe.cells.1, fe.model, significant(fe.stretches.0, 6), significant(fe.stretches.1, 6), fe.configs.len()
        ),
        panels,
    ))
}

/// `x` with 3 significant digits (below 1e-3 in scientific notation), or `–` for none; a
/// non-finite value is an error naming it.
fn cell(x: Option<f64>, what: &str, study: &str) -> Result<String, AppError> {
    match x {
        None => Ok("–".into()),
        Some(v) => {
            let v = finite(v, what, || format!("tangent study \"{study}\""))?;
            Ok(if v != 0.0 && v.abs() < 1e-3 {
                format!("{v:.2e}")
            } else {
                significant(v, 3)
            })
        }
    }
}

/// The largest (or with `least`, the least) of a model's values over its states.
fn over_states(m: &ModelTests, least: bool, f: impl Fn(&StateTest) -> Option<f64>) -> Option<f64> {
    let values = m.states.iter().flatten().filter_map(f);
    if least {
        values.reduce(f64::min)
    } else {
        values.reduce(f64::max)
    }
}

/// One row of the per-model table.
fn model_row(h: &mut String, m: &ModelTests, study: &str) -> Result<(), AppError> {
    let directions = least_over;
    let approximation = |names: &'static [&'static str]| {
        over_states(m, false, |s| {
            s.report
                .approximations
                .iter()
                .find(|(n, _)| names.contains(&n.as_str()))
                .map(|(_, e)| *e)
        })
    };
    let flagged = flagged(m);
    let rate = m.rate.map_or(String::new(), |r| format!(", λ̇ = {r} 1/s"));
    let _ = writeln!(
        h,
        "<tr><td>{}{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{} of {}</td></tr>",
        escape(&m.label),
        escape(&rate),
        cell(over_states(m, true, |s| directions(s, |r| r.order_0)), "order_0", study)?,
        cell(over_states(m, true, |s| directions(s, |r| r.order_1)), "order_1", study)?,
        cell(over_states(m, true, |s| directions(s, |r| r.least_order_1)), "order_1_least", study)?,
        cell(over_states(m, false, |s| s.report.fd_error), "fd_error", study)?,
        cell(over_states(m, false, |s| Some(s.report.asymmetry)), "asymmetry", study)?,
        cell(approximation(&["symmetric frozen"]), "symmetric_frozen_error", study)?,
        cell(approximation(&["tabulated law", "exact law"]), "table_error", study)?,
        cell(over_states(m, true, |s| s.report.ellipticity.map(|e| e.relative)), "ellipticity", study)?,
        flagged,
        m.states.len()
    );
    Ok(())
}

/// The flagged states, up to [`MAX_LISTED`].
fn flagged_list(h: &mut String, r: &TangentResult) {
    let mut rows = Vec::new();
    for m in &r.models {
        for (state, s) in r.states.iter().zip(&m.states) {
            let why = match s {
                Err(e) => Some(format!("not evaluable: {e}")),
                Ok(s) => s
                    .directions
                    .iter()
                    .zip(&r.directions)
                    .find_map(|(d, name)| {
                        d.as_ref()
                            .ok()?
                            .flag
                            .as_ref()
                            .map(|f| format!("direction {name}: {}", f.reason()))
                    }),
            };
            if let Some(why) = why {
                rows.push((m.label.as_str(), state.name.as_str(), why));
            }
        }
    }
    if rows.is_empty() {
        h.push_str("<p>Every order lies in its band at every model, state and direction.</p>\n");
        return;
    }
    let _ = writeln!(h, "<p>Where an order left its band ({} model–state pairs{}):</p>\n<table><tr><th>model</th><th>state</th><th>why</th></tr>", rows.len(), if rows.len() > MAX_LISTED { format!("; the first {MAX_LISTED}, every one in tangent_summary.csv") } else { String::new() });
    for (model, state, why) in rows.iter().take(MAX_LISTED) {
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td></tr>",
            escape(model),
            escape(state),
            escape(why)
        );
    }
    h.push_str("</table>\n");
}

/// The FE level's tables: the assembled residual's orders and Newton with each tangent.
fn fe_section(h: &mut String, fe: &FeResult, study: &str) -> Result<(), AppError> {
    let _ = writeln!(h, "<h3>The finite-element level</h3>\n<p>{} × {} cells, model {}, the load step λ = {} → {}. Taylor test of the assembled residual (order of r₁, median over the steps, the least of the displacement and the pressure rows; 2 for an exact tangent) at the step's predictor and at the converged state, and Newton from the predictor with each tangent the solver can use (full steps, the same LU; iterations to a scaled residual of 1e-10).</p>\n<table><tr><th>element, bases, incompressibility</th><th>dofs</th><th>tangent</th><th>order r₁ at the predictor</th><th>order r₁ converged</th><th>Newton iterations</th><th>ms per iteration</th><th>ms to 1e-10</th></tr>", fe.cells.0, fe.cells.1, escape(&fe.model), significant(fe.stretches.0, 6), significant(fe.stretches.1, 6));
    for c in &fe.configs {
        for n in &c.newton {
            let order = |state: &str| {
                c.taylor
                    .iter()
                    .find(|t| t.state == state && t.tangent == n.tangent)
                    .and_then(|t| t.outcome.as_ref().ok())
                    .and_then(|a| a.order_1)
            };
            let iterations = match (n.converged, &n.failure) {
                (true, _) => format!("{}", n.residuals.len().saturating_sub(1)),
                (false, None) => format!(
                    "not converged in {}: residual {}",
                    n.residuals.len().saturating_sub(1),
                    n.residuals
                        .last()
                        .map_or("–".into(), |r| format!("{r:.2e}"))
                ),
                (false, Some(e)) => format!("failed: {e}"),
            };
            let _ = writeln!(
                h,
                "<tr><td>{}, {}, {}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                c.element,
                bases_name(c.bases),
                escape(&c.incompressibility),
                c.dofs,
                n.tangent,
                cell(order("predictor"), "FE order", study)?,
                cell(order("converged"), "FE order", study)?,
                escape(&iterations),
                cell(Some(n.seconds_per_iteration * 1e3), "seconds per iteration", study)?,
                cell(n.seconds_to_converge().map(|s| s * 1e3), "seconds to converge", study)?
            );
        }
    }
    h.push_str(
        "</table>\n<p>What each tangent cost (least–largest over the configurations, the time per iteration their median):</p>\n<ul>\n",
    );
    for w in cost_words(fe) {
        let _ = writeln!(h, "<li>{}</li>", escape(&w));
    }
    h.push_str("</ul>\n");
    Ok(())
}

/// The report section of one tangent study.
fn section(h: &mut String, study: &str, r: &TangentResult) -> Result<(), AppError> {
    let pressure = match &r.volumetric {
        None => {
            "exactly incompressible, with the pressure held fixed: its term −p F⁻ᵀ is the solver's"
                .to_string()
        }
        Some(v) => format!("nearly incompressible, with U(J) = {}", escape(v)),
    };
    let frozen = match r.frozen_tangent {
        crate::active::FrozenTangent::Exact => "exact",
        crate::active::FrozenTangent::Symmetric => "symmetric",
    };
    let _ = writeln!(
        h,
        "<h2>Tangent check (study \"{}\")</h2>\n<p>The Taylor test of every model of the {} energy ({pressure}) at {} states along {} directions (unit Frobenius norm), steps h = {} … {}: r₀(h) = ‖P(F + hΔF) − P(F)‖ falls as h and r₁(h) = ‖P(F + hΔF) − P(F) − h A:ΔF‖ as h² where the model is smooth and its tangent A the derivative of its stress. Frozen models are tested with their exact tangent; the scene's solver uses the {frozen} one, and the symmetric approximation's distance from the exact tangent is in the table. Orders are medians over the pairs of steps above the rounding floor (the least over states and directions here); fd_error is ‖A_fd − A‖/‖A‖ with A_fd by central differences (≈ 1e-10 when A is right); asymmetry ‖A − Aᵀ‖/‖A‖ is not zero for the frozen coupling's exact tangent (its stress is not a gradient); ellipticity is the least a·Q(N)a/‖A‖ (negative: not strongly elliptic). Everything per state is in tangent_summary.csv, every remainder in tangent.csv.</p>\n<table><tr><th>model</th><th>order r₀</th><th>order r₁</th><th>least pair order r₁</th><th>largest fd_error</th><th>largest asymmetry</th><th>symmetric frozen error</th><th>table error</th><th>least ellipticity</th><th>flagged states</th></tr>",
        escape(study),
        escape(&r.energy),
        r.states.len(),
        r.directions.len(),
        significant(r.h.first().copied().unwrap_or(0.0), 3),
        significant(r.h.last().copied().unwrap_or(0.0), 3)
    );
    for m in &r.models {
        model_row(h, m, study)?;
    }
    h.push_str("</table>\n");
    flagged_list(h, r);
    if let Some(fe) = &r.fe {
        fe_section(h, fe, study)?;
    }
    Ok(())
}
