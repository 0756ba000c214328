//! Fit 4: the damage d that best explains a weakened total curve (the chapter's loss of
//! activation read backwards). With the implicit activation law the total stress along the fibres
//! is exactly (eq. (13))
//!
//! P(λ; d) = P_pas(λ) + (1 − d) P_act(λ),
//!
//! so r_i = P_pas(λ_i) + (1 − d) P_act(λ_i) − P_i \[kPa\], linear in d (Gauss–Newton converges in
//! one step). d ∈ [0, 1]; a best d outside it (a muscle stronger than the reference) is held at
//! the bound and reported so ([`super::AtBound`]).

use super::{Bounds, Data, FitError, FitReport, FitSetup, Residuals};
use crate::active::ActiveCurve;
use crate::material::Muscle;
use crate::uniaxial::along_fibres;
use crate::{Scalar, StrainEnergy};

/// A fitted damage and its report.
#[derive(Debug, Clone, PartialEq)]
pub struct DamageFit {
    /// d ∈ [0, 1].
    pub damage: f64,
    /// Statistics of the fit (one parameter, `d`).
    pub report: FitReport,
}

struct DamageProblem<'a> {
    passive: Vec<f64>,
    active: Vec<f64>,
    data: &'a Data,
}

impl Residuals for DamageProblem<'_> {
    fn count(&self) -> usize {
        self.data.len()
    }

    fn residuals<T: Scalar>(&self, theta: &[T]) -> crate::Result<Vec<T>> {
        let d = theta[0];
        Ok((0..self.data.len())
            .map(|i| (-d + 1.0) * self.active[i] + self.passive[i] - self.data.stress()[i])
            .collect())
    }
}

/// Fits d (parameter name `d`, start 0, bounds [0, 1]) to total-stress data along the fibres of a
/// muscle with passive `energy` and active curve `curve`.
pub fn fit_damage<E: StrainEnergy>(
    energy: &E,
    curve: &ActiveCurve,
    data: &Data,
    setup: &FitSetup,
) -> Result<DamageFit, FitError> {
    let selection = setup.resolve(&["d"], &[0.0], &[Bounds::UNIT], &["d"])?;
    let muscle = Muscle::passive(energy.clone());
    let passive = data
        .lambda()
        .iter()
        .map(|&l| Ok(along_fibres(&muscle, l)?.stress))
        .collect::<crate::Result<Vec<f64>>>()?;
    let active = data.lambda().iter().map(|&l| curve.value(l)).collect();
    let problem = DamageProblem {
        passive,
        active,
        data,
    };
    let report = selection.solve(&problem, setup, data.stress())?;
    Ok(DamageFit {
        damage: report.values[0],
        report,
    })
}
