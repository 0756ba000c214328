//! `fit = "active-curve"`: the active curve's parameters (eq. (8)) to active or total stresses.

use super::source::{case, need, sample, DataSource};
use super::{CaseData, FitCase, FitKind, FitSpec, Model, Problem, Shown, StressKind};
use crate::active::ActiveCurve;
use crate::app_error::SpecError;
use crate::energy::Energy;
use crate::fit::{active_from_total, fit_active_curve, Data, FitError, FitReport, FitSetup};
use crate::uniaxial::along_fibres;
use crate::Muscle;

/// The active curve (eq. (8)).
#[derive(Debug, Clone)]
pub(super) struct ActiveCurveFit {
    pub(super) energy: Energy,
    pub(super) curve: ActiveCurve,
    pub(super) stress: StressKind,
}

impl ActiveCurveFit {
    /// The active stresses of a case: as given, or total minus the model's passive stress.
    fn active(&self, case: &FitCase) -> Result<Data, FitError> {
        let data = case.data.uniaxial(FitKind::ActiveCurve)?;
        match self.stress {
            StressKind::Active => Ok(data.clone()),
            StressKind::Total => active_from_total(&self.energy, data),
        }
    }
}

impl Problem for ActiveCurveFit {
    fn model(&self) -> Model {
        let c = &self.curve;
        Model {
            kind: FitKind::ActiveCurve,
            names: c.parameters().iter().map(|p| p.name.to_string()).collect(),
            values: c.parameter_values(),
            bounds: c
                .parameters()
                .iter()
                .map(|p| crate::fit::Bounds::new(p.range.0, p.range.1))
                .collect(),
            default_free: c
                .parameters()
                .iter()
                .map(|p| p.name.to_string())
                .filter(|n| n != "p_opt")
                .collect(),
            y_label: "P_act [kPa]",
            reference_label: "scene's active curve",
            unit: "kPa",
        }
    }
    fn cases(
        &self,
        spec: &FitSpec,
        stretches: Option<&[f64]>,
        source: &mut DataSource,
    ) -> Result<(Vec<FitCase>, String), SpecError> {
        if let Some(file) = &spec.data {
            let what = match self.stress {
                StressKind::Active => " (active stress)",
                StressKind::Total => " (total stress)",
            };
            return source.file(FitKind::ActiveCurve, file, stretches, None, what);
        }
        let lambdas = need(stretches, "a synthetic active curve")?;
        let passive = Muscle::passive(self.energy.clone());
        let data = source.synthetic(lambdas, |l| {
            let p = self.curve.value(l);
            Ok(match self.stress {
                StressKind::Active => p,
                StressKind::Total => p + along_fibres(&passive, l)?.stress,
            })
        })?;
        Ok((
            vec![case(
                "synthetic active curve",
                CaseData::Uniaxial(data),
                Some(self.model().values),
            )],
            format!(
                "the scene's active curve ([activation]){}",
                source.noise_text
            ),
        ))
    }
    fn fit(&self, case: &FitCase, setup: &FitSetup) -> Result<(FitReport, Vec<String>), FitError> {
        self.active(case)
            .and_then(|d| fit_active_curve(&self.curve, &d, setup).map(|f| (f.report, vec![])))
    }
    fn curves(&self, v: &[f64], _: &FitCase, grid: &[f64]) -> Vec<Vec<(f64, f64)>> {
        match self.curve.rebuilt(v) {
            Ok(c) => vec![sample(grid, |l| Ok(c.value(l)))],
            Err(_) => vec![],
        }
    }
    fn shown(&self, case: &FitCase) -> Vec<Shown> {
        Shown::curve(
            &self.model(),
            match self.stress {
                StressKind::Active => case.label.clone(),
                StressKind::Total => format!("{} − P_pas", case.label),
            },
            self.active(case).map(|d| d.points()).unwrap_or_default(),
        )
    }
}
