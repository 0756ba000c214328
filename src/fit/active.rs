//! Fit 2: an active curve ([`crate::active::curve`]: the chapter's eq. (8) or any shipped one) to
//! active-stress data,
//!
//! r_i = P_act(λ_i; θ) − P_i \[kPa\],
//!
//! over the curve's own parameters θ (by name), with P_opt fixed by default (the chapter's
//! practice: Table 2). Data of the total stress of a tetanised muscle become active data by
//! subtracting the model's passive stress ([`active_from_total`]): P_act,i = P_i − P_pas(λ_i).

use super::{Bounds, Data, FitError, FitReport, FitSetup, Residuals, Selection};
use crate::active::ActiveCurve;
use crate::material::Muscle;
use crate::uniaxial::along_fibres;
use crate::{Scalar, StrainEnergy};

/// A fitted active curve and its report.
#[derive(Debug, Clone, PartialEq)]
pub struct ActiveFit {
    /// The curve with the fitted parameters.
    pub curve: ActiveCurve,
    /// Statistics of the fit.
    pub report: FitReport,
}

/// Active data P_i − P_pas(λ_i) from total-stress data along the fibres, with P_pas of the
/// passive `energy` (eq. (11)).
pub fn active_from_total<E: StrainEnergy>(energy: &E, total: &Data) -> Result<Data, FitError> {
    let muscle = Muscle::passive(energy.clone());
    let stress = total
        .lambda()
        .iter()
        .zip(total.stress())
        .map(|(&l, &p)| Ok(p - along_fibres(&muscle, l)?.stress))
        .collect::<crate::Result<Vec<f64>>>()?;
    total.with_stress(stress)
}

struct CurveProblem<'a> {
    curve: &'a ActiveCurve,
    selection: &'a Selection,
    data: &'a Data,
}

impl Residuals for CurveProblem<'_> {
    fn count(&self) -> usize {
        self.data.len()
    }

    fn residuals<T: Scalar>(&self, theta: &[T]) -> crate::Result<Vec<T>> {
        let p = self.selection.assemble(theta);
        // Parameters the curve's constructor refuses (λ_opt ≤ λ_min, k = 0) are outside the model.
        let values: Vec<f64> = p.iter().map(|x| x.re()).collect();
        self.curve.rebuilt(&values)?;
        Ok(self
            .data
            .lambda()
            .iter()
            .zip(self.data.stress())
            .map(|(&l, &s)| self.curve.value_with(&p, T::from(l)) - s)
            .collect())
    }
}

/// Fits the parameters of `curve` chosen in `setup` (default: all but P_opt; starts: the curve's
/// values; bounds: the ranges of its parameter table, e.g. λ_min ∈ [0, 1], λ_opt ∈ [0.5, 2],
/// k, P_opt > 0) to active data.
pub fn fit_active_curve(
    curve: &ActiveCurve,
    data: &Data,
    setup: &FitSetup,
) -> Result<ActiveFit, FitError> {
    let parameters = curve.parameters();
    let names: Vec<&str> = parameters.iter().map(|p| p.name.as_ref()).collect();
    let values = curve.parameter_values();
    let bounds: Vec<Bounds> = parameters
        .iter()
        .map(|p| Bounds::new(p.bounds.0, p.bounds.1))
        .collect();
    let default_free: Vec<&str> = names.iter().copied().filter(|n| *n != "p_opt").collect();
    let selection = setup.resolve(&names, &values, &bounds, &default_free)?;
    let problem = CurveProblem {
        curve,
        selection: &selection,
        data,
    };
    let report = selection.solve(&problem, setup, data.stress())?;
    let v = selection.assemble_values(&report.values);
    let curve = curve.rebuilt(&v)?;
    Ok(ActiveFit { curve, report })
}
