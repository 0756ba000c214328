//! `fit = "damage"`: the damage d of a weakened total curve.

use super::source::{need, one_source, sample, DataSource};
use super::{CaseData, FitCase, FitKind, FitSpec, Model, Problem};
use crate::active::drive::Drive;
use crate::active::ActiveCurve;
use crate::app_error::SpecError;
use crate::energy::Energy;
use crate::fit::{fit_damage, FitError, FitReport, FitSetup};
use crate::studies::spec::damages;
use crate::uniaxial::along_fibres;
use crate::Muscle;

/// The damage d of a weakened total curve, P_pas + (1 − d) P_act.
#[derive(Debug, Clone)]
pub(super) struct DamageFit {
    pub(super) energy: Energy,
    pub(super) curve: ActiveCurve,
}

impl Problem for DamageFit {
    fn model(&self) -> Model {
        Model {
            kind: FitKind::Damage,
            names: vec!["d".into()],
            values: vec![0.0],
            bounds: vec![crate::fit::Bounds::UNIT],
            default_free: vec!["d".into()],
            y_label: "P_total [kPa]",
            reference_label: "healthy muscle (d = 0)",
            unit: "kPa",
        }
    }
    fn cases(
        &self,
        spec: &FitSpec,
        stretches: Option<&[f64]>,
        source: &mut DataSource,
    ) -> Result<(Vec<FitCase>, String), SpecError> {
        match (&spec.data, &spec.true_damage) {
            (Some(file), None) => source.file(
                FitKind::Damage,
                file,
                stretches,
                None,
                " (total stress along the fibres)",
            ),
            (None, Some(ds)) => {
                let ds = damages("true_damage", ds)?;
                let lambdas = need(stretches, "a synthetic weakened curve")?;
                let passive = Muscle::passive(self.energy.clone());
                let mut cases = Vec::with_capacity(ds.len());
                for d in ds {
                    let data = source.synthetic(lambdas, |l| {
                        Ok(along_fibres(&passive, l)?.stress
                            + Drive::from(d).target(&self.curve, l))
                    })?;
                    cases.push(FitCase {
                        label: format!("true d = {d}"),
                        data: CaseData::Uniaxial(data),
                        damage: Some(d),
                        reference: Some(vec![d]),
                    });
                }
                Ok((
                    cases,
                    format!(
                        "synthetic weakened total curves P_pas + (1 − d) P_act{}",
                        source.noise_text
                    ),
                ))
            }
            _ => Err(one_source("damage", "true_damage = [...]")),
        }
    }
    fn fit(&self, case: &FitCase, setup: &FitSetup) -> Result<(FitReport, Vec<String>), FitError> {
        let data = case.data.uniaxial(FitKind::Damage)?;
        fit_damage(&self.energy, &self.curve, data, setup).map(|f| (f.report, vec![]))
    }
    fn curves(&self, v: &[f64], _: &FitCase, grid: &[f64]) -> Vec<Vec<(f64, f64)>> {
        let passive = Muscle::passive(self.energy.clone());
        let d = v[0];
        vec![sample(grid, |l| {
            Ok(along_fibres(&passive, l)?.stress + Drive::from(d).target(&self.curve, l))
        })]
    }
}
