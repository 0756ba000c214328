//! `fit = "passive"`: the material's passive parameters (eq. (11)) to a uniaxial curve along or
//! across the fibres.

use super::source::{case, need, one_source, sample, DataSource};
use super::{FitCase, FitKind, FitSpec, Model, Problem};
use crate::app_error::SpecError;
use crate::energy::{Energy, Parametric};
use crate::fit::{default_passive_free, fit_passive, FitError, FitReport, FitSetup};
use crate::uniaxial::Direction;
use crate::{Muscle, StrainEnergy};

/// Passive parameters of the material's energy (eq. (11)).
#[derive(Debug, Clone)]
pub(super) struct Passive {
    pub(super) energy: Energy,
    pub(super) direction: Direction,
}

impl Problem for Passive {
    fn model(&self) -> Model {
        let names = self.energy.parameter_names();
        Model {
            kind: FitKind::Passive,
            default_free: default_passive_free(&names),
            names,
            values: self.energy.parameter_values(),
            y_label: "P_pas [kPa]",
            reference_label: "scene's material",
            unit: "kPa",
        }
    }
    fn cases(
        &self,
        spec: &FitSpec,
        stretches: Option<&[f64]>,
        source: &mut DataSource,
    ) -> Result<(Vec<FitCase>, String), SpecError> {
        match (&spec.data, &spec.reference) {
            (Some(file), None) => {
                source.file(file, stretches, Some(self.energy.parameter_values()), "")
            }
            (None, Some(r)) => {
                let reference = r.build().map_err(|e| e.within("reference"))?;
                let lambdas = need(stretches, "a reference curve")?;
                let muscle = Muscle::passive(reference.clone());
                let data =
                    source.synthetic(lambdas, |l| Ok(self.direction.point(&muscle, l)?.stress))?;
                let name = reference.name();
                Ok((
                    vec![case(
                        &format!("{name} curve"),
                        data,
                        Some(self.energy.parameter_values()),
                    )],
                    format!(
                        "{name} passive curve {} the fibres{}",
                        self.direction.name(),
                        source.noise_text
                    ),
                ))
            }
            _ => Err(one_source("passive", "reference = { energy = ... }")),
        }
    }
    fn fit(&self, case: &FitCase, setup: &FitSetup) -> Result<(FitReport, Vec<String>), FitError> {
        fit_passive(&self.energy, &[(self.direction, &case.data)], setup)
            .map(|f| (f.report, vec![]))
    }
    fn curve(&self, values: &[f64], _: &FitCase, grid: &[f64]) -> Vec<(f64, f64)> {
        match self.energy.rebuilt(values) {
            Ok(e) => {
                let muscle = Muscle::passive(e);
                sample(grid, |l| Ok(self.direction.point(&muscle, l)?.stress))
            }
            Err(_) => vec![],
        }
    }
}
