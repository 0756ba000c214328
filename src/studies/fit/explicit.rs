//! `fit = "explicit-law"`: the explicit law's (a, b) (eq. (14)) against the implicit law (eq. (13)).

use super::source::{need, sample, DataSource};
use super::{CaseData, FitCase, FitKind, FitSpec, Model, Problem, Shown};
use crate::active::{ActivationLaw, ActiveCurve, ExplicitLaw, ImplicitLaw};
use crate::app_error::SpecError;
use crate::energy::GiantesioMusesti;
use crate::fit::{
    explicit_law_errors, fit_explicit_law, Data, ExplicitTarget, FitError, FitReport, FitSetup,
};
use crate::studies::spec::{damages, fmt_list};

/// (a, b) of the explicit law (eq. (14)) against the implicit law (eq. (13)).
#[derive(Debug, Clone)]
pub(super) struct ExplicitLawFit {
    pub(super) energy: GiantesioMusesti,
    pub(super) curve: ActiveCurve,
    pub(super) residual: ExplicitTarget,
}

impl Problem for ExplicitLawFit {
    fn model(&self) -> Model {
        let (a, b) = ExplicitLaw::paper().coefficients();
        Model {
            kind: FitKind::ExplicitLaw,
            names: vec!["a".into(), "b".into()],
            values: vec![a, b],
            bounds: vec![crate::fit::COEFFICIENT_BOUNDS; 2],
            default_free: vec!["a".into(), "b".into()],
            y_label: "activation γ [-]",
            reference_label: "chapter's (a, b)",
            unit: match self.residual {
                ExplicitTarget::Stress => "kPa",
                ExplicitTarget::Activation => "-",
            },
        }
    }
    fn cases(
        &self,
        spec: &FitSpec,
        stretches: Option<&[f64]>,
        _: &mut DataSource,
    ) -> Result<(Vec<FitCase>, String), SpecError> {
        let lambdas = need(stretches, "an explicit-law fit")?;
        let lambda_min = self.curve.lambda_min();
        if let Some(bad) = lambdas.iter().find(|&&l| l <= lambda_min) {
            return Err(SpecError::new(
                "stretch",
                bad,
                format!("the implicit law is defined above lambda_min = {lambda_min}"),
            ));
        }
        let ds = damages("damage", spec.damage.as_deref().unwrap_or(&[0.0]))?;
        if ds.iter().any(|&d| d >= 1.0) {
            return Err(SpecError::new(
                "damage",
                fmt_list(&ds),
                "at d = 1 there is no activation to fit: each d must be < 1",
            ));
        }
        let mut cases = Vec::with_capacity(ds.len());
        for d in ds {
            cases.push(FitCase {
                label: format!("d = {d}"),
                data: CaseData::Uniaxial(
                    Data::new(lambdas.to_vec(), vec![0.0; lambdas.len()])
                        .map_err(|e| SpecError::new("stretch", "", e.to_string()))?,
                ),
                damage: Some(d),
                reference: Some(self.model().values),
            });
        }
        let residual = match self.residual {
            ExplicitTarget::Stress => "the total stress [kPa]",
            ExplicitTarget::Activation => "γ [-]",
        };
        Ok((
            cases,
            format!("the implicit law (eq. (13)), residual in {residual}"),
        ))
    }
    fn fit(&self, case: &FitCase, setup: &FitSetup) -> Result<(FitReport, Vec<String>), FitError> {
        let (gm, curve) = (&self.energy, &self.curve);
        let d = case.damage.unwrap_or(0.0);
        let lambdas = case.data.uniaxial(FitKind::ExplicitLaw)?.lambda();
        fit_explicit_law(gm, curve, lambdas, d, self.residual, setup).map(|f| {
            let mut extra = vec![format!(
                "fitted (a, b): max |Δγ| = {:.3e}, max |ΔP| = {:.4} kPa",
                f.max_activation_error, f.max_stress_error
            )];
            let (a, b) = ExplicitLaw::paper().coefficients();
            if let Ok(law) = ExplicitLaw::new(a, b, *gm, *curve) {
                if let Ok((dg, dp)) = explicit_law_errors(&law, gm, curve, lambdas, d) {
                    extra.push(format!(
                        "chapter's (a, b) = ({a:.4}, {b:.4}): max |Δγ| = {dg:.3e}, max |ΔP| = {dp:.4} kPa"
                    ));
                }
            }
            (f.report, extra)
        })
    }
    fn curves(&self, v: &[f64], case: &FitCase, grid: &[f64]) -> Vec<Vec<(f64, f64)>> {
        let d = case.damage.unwrap_or(0.0);
        match ExplicitLaw::new(v[0], v[1], self.energy, self.curve) {
            Ok(law) => vec![sample(grid, |l| law.gamma(l, d))],
            Err(_) => vec![],
        }
    }
    fn shown(&self, case: &FitCase) -> Vec<Shown> {
        let implicit = ImplicitLaw::new(self.energy, self.curve);
        let d = case.damage.unwrap_or(0.0);
        let lambdas = case.data.uniaxial(FitKind::ExplicitLaw).map(Data::lambda);
        Shown::curve(
            &self.model(),
            "implicit γ (eq. (13))".into(),
            sample(lambdas.unwrap_or_default(), |l| {
                Ok(implicit.evaluate(l, d)?.gamma)
            }),
        )
    }
}
