//! Fit 3: (a, b) of the explicit activation law (eq. (14)) against the implicit law
//! (eq. (13)) on a set of stretches λ_i, with residuals either in the activation,
//!
//! r_i = γ_expl(λ_i; a, b) − γ_impl(λ_i)  [-],
//!
//! or in the stress it produces,
//!
//! r_i = P_tot(λ_i, γ_expl(λ_i; a, b)) − [P_pas(λ_i) + (1 − d) P_act(λ_i)]  \[kPa\],
//!
//! the target being exactly the total stress the implicit law reproduces. P_tot = ∂Ŵ/∂λ along the
//! fibres is evaluated with λ as a dual number nested over the (a, b) dual.

use super::{Bounds, FitError, FitReport, FitSetup, Residuals, Selection};
use crate::active::drive::check_damage;
use crate::active::drive::Drive;
use crate::active::{fibre_path_energy, ActivationLaw, ActiveCurve, ExplicitLaw, ImplicitLaw};
use crate::energy::{positive, GiantesioMusesti};
use crate::material::Muscle;
use crate::uniaxial::along_fibres;
use crate::Scalar;
use num_dual::Dual;

/// What the explicit law is fitted to (in a scene: `residual = "stress" | "activation"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ExplicitTarget {
    /// The implicit activation γ(λ) (dimensionless residuals).
    Activation,
    /// The total stress the implicit law reproduces (residuals in kPa; the chapter's choice:
    /// "a least square optimization on the resulting P_act").
    #[default]
    Stress,
}

/// A fitted explicit law, its report and its errors on the fitting stretches.
#[derive(Debug, Clone, PartialEq)]
pub struct ExplicitFit {
    /// The law with the fitted (a, b).
    pub law: ExplicitLaw,
    /// Statistics of the fit (parameters `a`, `b`).
    pub report: FitReport,
    /// max_i |γ_expl(λ_i) − γ_impl(λ_i)| [-].
    pub max_activation_error: f64,
    /// max_i |P_tot(λ_i, γ_expl) − P_pas − (1 − d) P_act| \[kPa\].
    pub max_stress_error: f64,
}

/// P_tot(λ, γ) = ∂Ŵ/∂λ along the fibres \[kPa\] for any scalar γ.
fn total_stress<T: Scalar>(energy: &GiantesioMusesti, lambda: f64, gamma: T) -> T {
    let l = Dual::from_re(T::from(lambda)).derivative();
    fibre_path_energy(energy, l, Dual::from_re(gamma)).eps
}

struct ExplicitProblem<'a> {
    law: ExplicitLaw,
    selection: &'a Selection,
    lambda: &'a [f64],
    damage: f64,
    target: ExplicitTarget,
    energy: GiantesioMusesti,
    /// γ_impl(λ_i) or P_pas + (1 − d) P_act at λ_i.
    reference: Vec<f64>,
}

impl Residuals for ExplicitProblem<'_> {
    fn count(&self) -> usize {
        self.lambda.len()
    }

    fn residuals<T: Scalar>(&self, theta: &[T]) -> crate::Result<Vec<T>> {
        let p = self.selection.assemble(theta);
        // a = 0 or b = 0 (the bounds' ends) is not a law.
        positive("a", p[0].re())?;
        positive("b", p[1].re())?;
        self.lambda
            .iter()
            .zip(&self.reference)
            .map(|(&l, &reference)| {
                let gamma = self.law.gamma_with(p[0], p[1], T::from(l), self.damage)?;
                Ok(match self.target {
                    ExplicitTarget::Activation => gamma - reference,
                    ExplicitTarget::Stress => total_stress(&self.energy, l, gamma) - reference,
                })
            })
            .collect()
    }
}

/// Errors of an explicit law against the implicit one on the stretches `lambda`:
/// (max |Δγ|, max |ΔP| \[kPa\]).
pub fn explicit_law_errors(
    law: &ExplicitLaw,
    energy: &GiantesioMusesti,
    curve: &ActiveCurve,
    lambda: &[f64],
    damage: f64,
) -> Result<(f64, f64), FitError> {
    let implicit = ImplicitLaw::new(*energy, *curve);
    let passive = Muscle::passive(*energy);
    let (mut dg, mut dp) = (0.0f64, 0.0f64);
    for &l in lambda {
        let g = law.gamma(l, damage)?;
        dg = dg.max((g - implicit.evaluate(l, damage)?.gamma).abs());
        let target = along_fibres(&passive, l)?.stress + Drive::from(damage).target(curve, l);
        dp = dp.max((total_stress(energy, l, g) - target).abs());
    }
    Ok((dg, dp))
}

/// The default bounds of each coefficient a, b of a fit.
pub const COEFFICIENT_BOUNDS: Bounds = Bounds::new(0.0, 10.0);

/// Fits (a, b) (names `a`, `b`; starts: the chapter's 1.0133, 0.2050; bounds a ∈ (0, 10],
/// b ∈ (0, 10]) of the explicit law built on `energy` and `curve`, against the implicit law on
/// the stretches `lambda` (increasing, > λ_min) at damage `damage`.
pub fn fit_explicit_law(
    energy: &GiantesioMusesti,
    curve: &ActiveCurve,
    lambda: &[f64],
    damage: f64,
    target: ExplicitTarget,
    setup: &FitSetup,
) -> Result<ExplicitFit, FitError> {
    check_damage(damage)?;
    let paper = ExplicitLaw::paper().coefficients();
    let selection = setup.resolve(
        &["a", "b"],
        &[paper.0, paper.1],
        &[COEFFICIENT_BOUNDS, COEFFICIENT_BOUNDS],
        &["a", "b"],
    )?;
    // Validates the stretches (positive, increasing, no duplicates).
    super::Data::new(lambda.to_vec(), vec![0.0; lambda.len()])?;
    let implicit = ImplicitLaw::new(*energy, *curve);
    let passive = Muscle::passive(*energy);
    let reference = lambda
        .iter()
        .map(|&l| {
            Ok(match target {
                ExplicitTarget::Activation => implicit.evaluate(l, damage)?.gamma,
                ExplicitTarget::Stress => {
                    along_fibres(&passive, l)?.stress + Drive::from(damage).target(curve, l)
                }
            })
        })
        .collect::<crate::Result<Vec<f64>>>()?;
    let problem = ExplicitProblem {
        law: ExplicitLaw::new(paper.0, paper.1, *energy, *curve)?,
        selection: &selection,
        lambda,
        damage,
        target,
        energy: *energy,
        reference,
    };
    let report = selection.solve(&problem, setup, &problem.reference)?;
    let v = selection.assemble_values(&report.values);
    let law = ExplicitLaw::new(v[0], v[1], *energy, *curve)?;
    let (max_activation_error, max_stress_error) =
        explicit_law_errors(&law, energy, curve, lambda, damage)?;
    Ok(ExplicitFit {
        law,
        report,
        max_activation_error,
        max_stress_error,
    })
}
