//! Fit 2: the active curve (eq. (8)) to active-stress data,
//!
//! r_i = P_act(λ_i; λ_min, λ_opt, k, P_opt) − P_i \[kPa\],
//!
//! with P_opt fixed by default (the chapter's practice: Table 2). Data of the total stress
//! of a tetanised muscle become active data by subtracting the model's passive stress
//! ([`active_from_total`]): P_act,i = P_i − P_pas(λ_i).

use super::{Bounds, Data, FitError, FitReport, FitSetup, Residuals, Selection};
use crate::active::ActiveCurve;
use crate::material::Muscle;
use crate::uniaxial::along_fibres;
use crate::{Scalar, StrainEnergy};

/// Names of the active-curve parameters, in order.
pub const CURVE_PARAMETERS: [&str; 4] = ["lambda_min", "lambda_opt", "k", "p_opt"];

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
        ActiveCurve::new(p[0].re(), p[1].re(), p[2].re(), p[3].re())?;
        Ok(self
            .data
            .lambda()
            .iter()
            .zip(self.data.stress())
            .map(|(&l, &s)| ActiveCurve::value_with(p[0], p[1], p[2], p[3], T::from(l)) - s)
            .collect())
    }
}

/// Fits the parameters of `curve` chosen in `setup` (default λ_min, λ_opt, k; starts: the
/// curve's values; bounds: λ_min ∈ [0, 1], λ_opt ∈ [0.5, 2], k, P_opt > 0) to active data.
pub fn fit_active_curve(
    curve: &ActiveCurve,
    data: &Data,
    setup: &FitSetup,
) -> Result<ActiveFit, FitError> {
    let values = [
        curve.lambda_min(),
        curve.lambda_opt(),
        curve.k(),
        curve.p_opt(),
    ];
    let bounds = [
        Bounds::new(0.0, 1.0),
        Bounds::new(0.5, 2.0),
        Bounds::POSITIVE,
        Bounds::POSITIVE,
    ];
    let selection = setup.resolve(&CURVE_PARAMETERS, &values, &bounds, &CURVE_PARAMETERS[..3])?;
    let problem = CurveProblem {
        selection: &selection,
        data,
    };
    let report = selection.solve(&problem, &setup.options)?;
    let v = selection.assemble_values(&report.values);
    let curve = ActiveCurve::new(v[0], v[1], v[2], v[3])?;
    Ok(ActiveFit { curve, report })
}
