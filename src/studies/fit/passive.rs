//! `fit = "passive"`: the material's passive parameters (eq. (11)) to a uniaxial curve along or
//! across the fibres, or to planar biaxial rows (λ₁, λ₂, P₁₁, P₂₂) ([`crate::fit::biaxial`]:
//! λ₁ along the fibres, λ₂ across, λ₃ = 1/(λ₁λ₂), the e₃ faces traction free, residuals
//! P₁₁ − P₁₁ᵢ and P₂₂ − P₂₂ᵢ).

use super::source::{case, need, one_source, sample, DataSource};
use super::{CaseData, FitCase, FitKind, FitSpec, Model, Problem, Shown};
use crate::app_error::SpecError;
use crate::energy::{Energy, Parametric};
use crate::fit::{
    biaxial_stress_with, default_passive_free, fit_passive, fit_passive_biaxial, FitError,
    FitReport, FitSetup,
};
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
            default_free: default_passive_free(&names)
                .iter()
                .map(|n| n.to_string())
                .collect(),
            names: names.iter().map(|n| n.to_string()).collect(),
            values: self.energy.parameter_values(),
            bounds: crate::fit::parameter_bounds(&self.energy),
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
                let values = Some(self.energy.parameter_values());
                let (cases, words) = source.file(FitKind::Passive, file, stretches, values, "")?;
                let biaxial = cases.iter().any(|c| matches!(c.data, CaseData::Biaxial(_)));
                if biaxial && spec.direction.is_some() {
                    return Err(SpecError::new(
                        "direction",
                        "(given)",
                        "biaxial data load along and across the fibres at once: remove direction",
                    ));
                }
                Ok((cases, words))
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
                        CaseData::Uniaxial(data),
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
        let fit = match &case.data {
            CaseData::Uniaxial(data) => fit_passive(&self.energy, &[(self.direction, data)], setup),
            CaseData::Biaxial(rows) => fit_passive_biaxial(&self.energy, rows, setup),
        };
        fit.map(|f| (f.report, vec![]))
    }
    fn curves(&self, values: &[f64], case: &FitCase, grid: &[f64]) -> Vec<Vec<(f64, f64)>> {
        let Ok(energy) = self.energy.rebuilt(values) else {
            return vec![];
        };
        match &case.data {
            CaseData::Uniaxial(_) => {
                let muscle = Muscle::passive(energy);
                vec![sample(grid, |l| {
                    Ok(self.direction.point(&muscle, l)?.stress)
                })]
            }
            CaseData::Biaxial(rows) => (0..2)
                .map(|k| {
                    rows.stretches()
                        .iter()
                        .map(|&row| (row[0], biaxial_stress_with(&energy, values, row)[k]))
                        .filter(|(_, p)| p.is_finite())
                        .collect()
                })
                .collect(),
        }
    }
    fn shown(&self, case: &FitCase) -> Vec<Shown> {
        let CaseData::Biaxial(rows) = &case.data else {
            return Shown::uniaxial(&self.model(), case);
        };
        [
            ("P₁₁, along the fibres", "P₁₁ [kPa]"),
            ("P₂₂, across the fibres", "P₂₂ [kPa]"),
        ]
        .into_iter()
        .enumerate()
        .map(|(k, (what, y_label))| Shown {
            what: what.to_string(),
            x_label: "λ₁ [-]",
            y_label: y_label.to_string(),
            label: case.label.clone(),
            data: rows
                .stretches()
                .iter()
                .zip(rows.stresses())
                .map(|(l, p)| (l[0], p[k]))
                .collect(),
        })
        .collect()
    }
}
