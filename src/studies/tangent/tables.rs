//! The tangent kind's tables (CSV files and Python's tables, from the same columns):
//! `tangent.csv` (one row per model, state, direction and step: r₀, r₁),
//! `tangent_summary.csv` (one row per model and state: orders, the central-difference error,
//! the asymmetry, the approximate tangents' errors, ellipticity, the flag and its reason),
//! and with the FE level `tangent_fe.csv` (the assembled residual's remainders) and
//! `tangent_newton.csv` (Newton's residual per iteration with each tangent).

use super::fe::{FeConfig, FeResult};
use super::run::{ModelTests, StateTest, TangentResult};
use crate::studies::cylinder::bases_name;
use crate::studies::domain::{in_domain, IN_DOMAIN};
use crate::studies::table::{every_row, Table};

/// Names of F's entries, row by row.
const F_ENTRIES: [&str; 9] = [
    "F11", "F12", "F13", "F21", "F22", "F23", "F31", "F32", "F33",
];

/// The model columns every point table starts with.
fn model_columns(t: Table, study: &str, energy: &str, rows: &[&ModelTests]) -> Table {
    let cell = |i: usize| rows.iter().map(move |m| m.model.cells()[i].clone());
    t.text("study", "the study's name", every_row(study, rows.len()))
        .text(
            "energy",
            "the passive energy",
            every_row(energy, rows.len()),
        )
        .text("approach", "activation approach (empty: passive)", cell(0))
        .text(
            "law",
            "activation law (passive for the passive material; empty for active stress)",
            cell(1),
        )
        .text("coupling", "coupling (empty: none)", cell(2))
        .number(
            "d",
            "-",
            "damage",
            rows.iter().map(|m| m.model.model.map(|c| c.damage)),
        )
        .number(
            "stretch_rate",
            "1/s",
            "fibre stretch rate λ̇ under force–velocity (empty: quasi-static)",
            rows.iter().map(|m| m.rate),
        )
}

/// The columns every FE level table starts with: the study, the model and each row's
/// configuration.
fn fe_columns(study: &str, fe: &FeResult, rows: &[&FeConfig]) -> Table {
    let of = |f: fn(&FeConfig) -> String| rows.iter().map(move |c| Some(f(c)));
    Table::default()
        .text("study", "the study's name", every_row(study, rows.len()))
        .text(
            "model",
            "the FE level's model",
            every_row(&fe.model, rows.len()),
        )
        .text(
            "element",
            "the element",
            of(|c| c.element.name().to_string()),
        )
        .text(
            "bases",
            "clamped or sliding",
            of(|c| bases_name(c.bases).to_string()),
        )
        .text(
            "incompressibility",
            "exact or the volumetric form",
            of(|c| c.incompressibility.clone()),
        )
}

/// The summary's flag, its reason and the notes of one model at one state, over its directions.
fn flag_of(
    result: &TangentResult,
    s: &StateTest,
) -> (Option<String>, Option<String>, Option<String>) {
    let mut notes = s.report.notes.clone();
    let mut flag = None;
    for (d, name) in s.directions.iter().zip(&result.directions) {
        match d {
            Ok(r) => {
                if let (None, Some(f)) = (&flag, &r.flag) {
                    flag = Some((
                        f.kind().to_string(),
                        format!("direction {name}: {}", f.reason()),
                    ));
                }
                if let Some((h, why)) = &r.unevaluable {
                    notes.push(format!(
                        "direction {name}: not evaluable at h = {} ({why})",
                        crate::text::significant(*h, 3)
                    ));
                }
            }
            Err(e) => notes.push(format!("direction {name}: {e}")),
        }
    }
    if let Some(why) = &s.report.fd_failure {
        notes.push(format!("no central differences: {why}"));
    }
    let (kind, reason) = flag.unzip();
    (kind, reason, (!notes.is_empty()).then(|| notes.join("; ")))
}

/// The least of the values over the directions.
fn least(values: impl Iterator<Item = Option<f64>>) -> Option<f64> {
    values.flatten().reduce(f64::min)
}

impl TangentResult {
    /// `tangent.csv`: one row per model, state, direction and step.
    pub fn remainder_table(&self, study: &str) -> Table {
        let mut rows = Vec::new();
        for m in &self.models {
            for (state, s) in self.states.iter().zip(&m.states) {
                let Ok(s) = s else { continue };
                for (direction, d) in self.directions.iter().zip(&s.directions) {
                    let Ok(r) = d else { continue };
                    for k in 0..r.h.len() {
                        rows.push((
                            m,
                            state.name.as_str(),
                            direction.as_str(),
                            r.h[k],
                            r.r0[k],
                            r.r1[k],
                        ));
                    }
                }
            }
        }
        let models: Vec<&ModelTests> = rows.iter().map(|r| r.0).collect();
        model_columns(Table::default(), study, &self.energy, &models)
            .text(
                "state",
                "the state's name",
                rows.iter().map(|r| Some(r.1.to_string())),
            )
            .text(
                "direction",
                "the direction ΔF's name",
                rows.iter().map(|r| Some(r.2.to_string())),
            )
            .number(
                "h",
                "-",
                "step h (ΔF of unit Frobenius norm)",
                rows.iter().map(|r| Some(r.3)),
            )
            .number(
                "r0",
                "kPa",
                "‖P(F + hΔF) − P(F)‖ (empty: not evaluable at F + hΔF)",
                rows.iter().map(|r| r.4),
            )
            .number(
                "r1",
                "kPa",
                "‖P(F + hΔF) − P(F) − h A:ΔF‖",
                rows.iter().map(|r| r.5),
            )
    }

    /// `tangent_summary.csv`: one row per model and state.
    pub fn summary_table(&self, study: &str) -> Table {
        let rows: Vec<(&ModelTests, usize)> = self
            .models
            .iter()
            .flat_map(|m| (0..self.states.len()).map(move |i| (m, i)))
            .collect();
        let models: Vec<&ModelTests> = rows.iter().map(|r| r.0).collect();
        fn test<'a>(r: &(&'a ModelTests, usize)) -> Option<&'a StateTest> {
            r.0.states.get(r.1).and_then(|s| s.as_ref().ok())
        }
        let of = |f: fn(&StateTest) -> Option<f64>| rows.iter().map(move |r| test(r).and_then(f));
        let approximation = |names: &'static [&'static str]| {
            rows.iter().map(move |r| {
                test(r).and_then(|s| {
                    s.report
                        .approximations
                        .iter()
                        .find(|(n, _)| names.contains(&n.as_str()))
                        .map(|(_, e)| *e)
                })
            })
        };
        let flags: Vec<(Option<String>, Option<String>, Option<String>)> = rows
            .iter()
            .map(|r| match &r.0.states[r.1] {
                Ok(s) => flag_of(self, s),
                Err(e) => (Some("not-evaluable".into()), Some(e.clone()), None),
            })
            .collect();
        let mut t = model_columns(Table::default(), study, &self.energy, &models).text(
            "state",
            "the state's name",
            rows.iter().map(|r| Some(self.states[r.1].name.clone())),
        );
        for (k, name) in F_ENTRIES.iter().enumerate() {
            t = t.number(
                name,
                "-",
                "the state's F, row by row",
                rows.iter()
                    .map(move |r| Some(self.states[r.1].f[(k / 3, k % 3)])),
            );
        }
        t.number("fibre_stretch", "-", "fibre stretch λ_f = |F m|", of(|s| Some(s.fibre_stretch)))
            .number("gamma", "-", "activation γ (ω for the structural approach)", of(|s| Some(s.gamma)))
            .number("order_0", "-", "observed order of r₀ (median over the pairs of steps; the least over the directions); 1 where smooth", of(|s| least(s.directions.iter().map(|d| d.as_ref().ok().and_then(|r| r.order_0)))))
            .number("order_1", "-", "observed order of r₁ (median over the pairs of steps; the least over the directions); 2 where smooth and A exact", of(|s| least(s.directions.iter().map(|d| d.as_ref().ok().and_then(|r| r.order_1)))))
            .number("order_1_least", "-", "the least order of r₁ on any pair of steps and direction", of(|s| least(s.directions.iter().map(|d| d.as_ref().ok().and_then(|r| r.least_order_1)))))
            .number("fd_error", "-", "‖A_fd − A‖/‖A‖, A_fd by central differences of P", of(|s| s.report.fd_error))
            .number("asymmetry", "-", "‖A − Aᵀ‖/‖A‖", of(|s| Some(s.report.asymmetry)))
            .number("fd_asymmetry", "-", "‖A_fd − A_fdᵀ‖/‖A_fd‖: equal to asymmetry where P is not a gradient", of(|s| s.report.fd_asymmetry))
            .text("asymmetry_reason", "why A need not be symmetric (empty: it should be)", rows.iter().map(|r| test(r).and_then(|s| s.report.asymmetry_reason.clone())))
            .number("symmetric_frozen_error", "-", "‖A_sym − A‖/‖A‖ of the frozen model's symmetric approximation", approximation(&["symmetric frozen"]))
            .number("table_error", "-", "‖A_other − A‖/‖A‖ with the law in its other representation (tabulated for an exact law, exact for a tabulated one)", approximation(&["tabulated law", "exact law"]))
            .number("ellipticity", "-", "least a·Q(N)a/‖A‖ over the sampled normals (negative: not strongly elliptic)", of(|s| s.report.ellipticity.map(|e| e.relative)))
            .text("flag", "why an order leaves its band (empty: none)", flags.iter().map(|f| f.0.clone()))
            .text("reason", "the flag in words", flags.iter().map(|f| f.1.clone()))
            .text("note", "what else the test found", flags.iter().map(|f| f.2.clone()))
            .boolean("in_domain", IN_DOMAIN, rows.iter().map(|r| test(r).and_then(|s| in_domain(r.0.model.model.as_ref(), s.outside))))
    }

    /// `tangent_fe.csv`: the assembled residual's remainders (`None` without the FE level).
    pub fn fe_table(&self, study: &str) -> Option<Table> {
        let fe = self.fe.as_ref()?;
        let mut rows = Vec::new();
        for c in &fe.configs {
            for t in &c.taylor {
                let Ok(r) = &t.outcome else { continue };
                for (k, &h) in r.h().iter().enumerate() {
                    rows.push((c, t, h, [r.u.r0[k], r.u.r1[k], r.p.r0[k], r.p.r1[k]]));
                }
            }
        }
        let configs: Vec<&FeConfig> = rows.iter().map(|r| r.0).collect();
        Some(
            fe_columns(study, fe, &configs)
                .text(
                    "state",
                    "predictor or converged",
                    rows.iter().map(|r| Some(r.1.state.to_string())),
                )
                .text(
                    "tangent",
                    "exact, symmetric frozen or finite differences",
                    rows.iter().map(|r| Some(r.1.tangent.to_string())),
                )
                .number("h", "-", "step h along v", rows.iter().map(|r| Some(r.2)))
                .number(
                    "r0_u",
                    "-",
                    "‖R(x + hv) − R(x)‖ over the displacement rows, /(σ πR²)",
                    rows.iter().map(|r| r.3[0]),
                )
                .number(
                    "r1_u",
                    "-",
                    "‖R(x + hv) − R(x) − h K v‖ over the displacement rows, /(σ πR²)",
                    rows.iter().map(|r| r.3[1]),
                )
                .number(
                    "r0_p",
                    "-",
                    "‖R(x + hv) − R(x)‖ over the pressure rows, /(πR²L)",
                    rows.iter().map(|r| r.3[2]),
                )
                .number(
                    "r1_p",
                    "-",
                    "‖R(x + hv) − R(x) − h K v‖ over the pressure rows, /(πR²L)",
                    rows.iter().map(|r| r.3[3]),
                ),
        )
    }

    /// `tangent_newton.csv`: Newton's scaled residual per iteration with each tangent.
    pub fn newton_table(&self, study: &str) -> Option<Table> {
        let fe = self.fe.as_ref()?;
        let mut rows = Vec::new();
        for c in &fe.configs {
            for n in &c.newton {
                for (k, r) in n.residuals.iter().enumerate() {
                    rows.push((c, n, k, *r));
                }
            }
        }
        let configs: Vec<&FeConfig> = rows.iter().map(|r| r.0).collect();
        Some(
            fe_columns(study, fe, &configs)
                .text(
                    "tangent",
                    "exact, symmetric frozen or finite differences",
                    rows.iter().map(|r| Some(r.1.tangent.to_string())),
                )
                .integer(
                    "iteration",
                    "Newton iteration from the load step's predictor (0: the predictor)",
                    rows.iter().map(|r| Some(r.2 as i64)),
                )
                .number(
                    "residual",
                    "-",
                    "the solver's scaled residual",
                    rows.iter().map(|r| Some(r.3)),
                )
                .boolean(
                    "converged",
                    "whether the residual reached 1e-10 within the iterations allowed",
                    rows.iter().map(|r| Some(r.1.converged)),
                )
                .number(
                    "seconds_per_iteration",
                    "s",
                    "wall time per Newton iteration (assembly with the tangent, factorisation, solve)",
                    rows.iter().map(|r| Some(r.1.seconds_per_iteration)),
                ),
        )
    }
}
