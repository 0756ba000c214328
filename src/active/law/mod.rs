//! Activation laws γ = g(λ_f, d): the activation as a function of the fibre stretch λ_f and the
//! damage d. Every law returns exact first and second derivatives in λ_f, which the consistent
//! coupling and the frozen model's exact tangent need.
//!
//! | law | definition | cost per evaluation |
//! |---|---|---|
//! | [`ConstantLaw`] | γ fixed | nothing |
//! | [`ImplicitLaw`] | P_tot(λ, γ) = P_pas(λ) + (1 − d) P_act(λ) (eq. D:eqgammaesplicita) | a bracketed Newton solve |
//! | [`ExplicitLaw`] | the chapter's closed form (eq. D:gamma), an approximation on its [`Domain`] 0.7 ≤ λ_f ≤ 1.5, d_eff ≤ 0.5 only | a formula |
//! | [`EnergyLaw`] | Ŵ(λ, γ) = W_pas(λ) + (1 − d) ∫ P_act (truly hyperelastic fit) | a quadrature and a bracketed Newton solve |
//! | [`TabulatedLaw`] | the implicit or energy law as a checked piecewise Chebyshev table per damage | a table lookup |
//!
//! [`Law::represented`] turns a law into its tabulated (or back into its exact) representation.

mod constant;
mod domain;
mod energy_fit;
mod explicit;
mod implicit;
mod tabulated;

pub use constant::ConstantLaw;
pub use domain::{Domain, OutsideDomain};
pub use energy_fit::{BelowMinimum, EnergyLaw};
pub use explicit::ExplicitLaw;
pub use implicit::ImplicitLaw;
pub use tabulated::{
    LawRepresentation, SolvedLaw, TableComparison, TableReport, TableSpec, TabulatedLaw, MIN_WIDTH,
};

use crate::active::drive::Drive;
use crate::active::map::ActivationMap;
use crate::energy::StrainEnergy;
use crate::roots::newton_bisection;
use crate::{Error, Result, Scalar};
use num_dual::{HyperDual64, HyperHyperDual64};

/// γ and its derivatives with respect to the fibre stretch at one point.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LawValue {
    /// γ [-].
    pub gamma: f64,
    /// dγ/dλ_f.
    pub slope: f64,
    /// d²γ/dλ_f².
    pub curvature: f64,
}

/// A map from fibre stretch (and what drives the activation) to activation.
///
/// The drive is a [`Drive`]: damage d, activation level a and, in a time study with
/// force–velocity, the stretch-rate state; a plain `f64` is a damage d ∈ [0, 1] at a = 1,
/// quasi-static. Every law reproduces the drive's target (1 − d)·a·f_v·P_act ([`Drive::target`]),
/// and gives γ = 0 wherever that target is 0.
pub trait ActivationLaw {
    /// γ, dγ/dλ and d²γ/dλ² at fibre stretch `lambda` [-] under `drive`.
    fn evaluate(&self, lambda: f64, drive: impl Into<Drive>) -> Result<LawValue>;

    /// γ alone, without its derivatives (cheaper for the laws that solve for γ).
    fn activation(&self, lambda: f64, drive: impl Into<Drive>) -> Result<f64> {
        Ok(self.evaluate(lambda, drive)?.gamma)
    }

    /// γ and dγ/dλ, without d²γ/dλ²: what the frozen model's exact tangent and the consistent
    /// stress need (a law written once on dual numbers then carries first-order duals only).
    fn gamma_and_slope(&self, lambda: f64, drive: impl Into<Drive>) -> Result<(f64, f64)> {
        let v = self.evaluate(lambda, drive)?;
        Ok((v.gamma, v.slope))
    }

    /// γ on a generic scalar: the second-order Taylor expansion of [`evaluate`](Self::evaluate)
    /// about the real part, which carries exact first and second derivatives through any dual
    /// number of order ≤ 2.
    fn gamma<T: Scalar>(&self, lambda: T, drive: impl Into<Drive>) -> Result<T> {
        Ok(self.evaluate(lambda.re(), drive)?.lift(lambda))
    }

    /// Where γ at `lambda` under `drive` is outside the domain the law holds on, if it is
    /// ([`Domain`]): `None` for the laws that solve their equation (they hold wherever they
    /// have a root) and wherever a law gives γ = 0 exactly (no activation).
    fn outside(&self, _lambda: f64, _drive: impl Into<Drive>) -> Option<OutsideDomain> {
        None
    }
}

impl LawValue {
    /// γ(λ) on a generic scalar from the value and derivatives at λ's real part:
    /// γ + γ′ h + ½ γ″ h² with h = λ − re λ (exact to second order).
    pub fn lift<T: Scalar>(&self, lambda: T) -> T {
        let h = lambda - lambda.re();
        h * h * (0.5 * self.curvature) + h * self.slope + self.gamma
    }
}

/// An activation law by name (`law = "implicit"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum LawKind {
    /// The chapter's exact fit, eq. (13) solved numerically ([`ImplicitLaw`]).
    #[default]
    Implicit,
    /// The chapter's closed form, eq. (14) ([`ExplicitLaw`]).
    Explicit,
    /// The energy-consistent fit ([`EnergyLaw`]).
    Energy,
}

impl LawKind {
    /// Every law, in the order of the enum.
    pub const ALL: [LawKind; 3] = [LawKind::Implicit, LawKind::Explicit, LawKind::Energy];

    /// The domain the law holds on, if it has one ([`Domain`]): the explicit law's
    /// ([`ExplicitLaw::DOMAIN`]); the others solve their equation and hold wherever it has a root.
    pub fn domain(self) -> Option<Domain> {
        match self {
            LawKind::Explicit => Some(ExplicitLaw::DOMAIN),
            LawKind::Implicit | LawKind::Energy => None,
        }
    }

    /// Whether the law solves an equation of Ŵ for γ (implicit, energy): those a table can
    /// represent ([`TabulatedLaw`]).
    pub fn solves(self) -> bool {
        matches!(self, LawKind::Implicit | LawKind::Energy)
    }

    /// Name in scene files and outputs.
    pub fn name(self) -> &'static str {
        match self {
            LawKind::Implicit => "implicit",
            LawKind::Explicit => "explicit",
            LawKind::Energy => "energy",
        }
    }
}

/// Any of the shipped laws, chosen at run time.
#[derive(Debug, Clone)]
pub enum Law<E> {
    /// No activation: γ ≡ 0, the passive material.
    Passive,
    /// γ fixed.
    Constant(ConstantLaw),
    /// The chapter's exact fit (eq. D:eqgammaesplicita).
    Implicit(ImplicitLaw<E>),
    /// The chapter's closed-form approximation (eq. D:gamma).
    Explicit(ExplicitLaw),
    /// The energy-consistent (truly hyperelastic) fit.
    Energy(EnergyLaw<E>),
    /// The implicit or the energy law, tabulated (see [`TabulatedLaw`]).
    Tabulated(TabulatedLaw<E>),
}

impl<E> Law<E> {
    /// The fibre stretch at which γ(λ) is discontinuous, if any: the energy law jumps at λ_min
    /// from 0 to the root of Ŵ(λ_min, γ) = W_pas(λ_min) (see [`EnergyLaw`]).
    pub fn jump(&self) -> Option<f64> {
        match self {
            Law::Energy(l)
            | Law::Tabulated(TabulatedLaw {
                exact: SolvedLaw::Energy(l),
                ..
            }) if l.below_minimum_choice() == BelowMinimum::Inactive => {
                Some(l.curve().lambda_min())
            }
            _ => None,
        }
    }

    /// Name used in logs and output files: passive, constant, implicit, explicit, energy,
    /// implicit-tabulated, energy-tabulated.
    pub fn name(&self) -> &'static str {
        match self {
            Law::Passive => "passive",
            Law::Constant(_) => "constant",
            Law::Implicit(_) => "implicit",
            Law::Explicit(_) => "explicit",
            Law::Energy(_) => "energy",
            Law::Tabulated(l) => match &l.exact {
                SolvedLaw::Implicit(_) => "implicit-tabulated",
                SolvedLaw::Energy(_) => "energy-tabulated",
            },
        }
    }
}

impl<E: StrainEnergy> Law<E> {
    /// The activation map the law is solved with (the implicit and energy laws, tabulated or
    /// not); `None` for the laws that do not solve an equation of Ŵ.
    pub fn map(&self) -> Option<ActivationMap> {
        match self {
            Law::Implicit(l) => Some(l.map()),
            Law::Energy(l) => Some(l.map()),
            Law::Tabulated(l) => Some(l.exact.map()),
            _ => None,
        }
    }

    /// The same law in the representation asked for: [`LawRepresentation::Tabulated`] builds a
    /// table per damage in `damages` for the implicit and the energy law (an already tabulated
    /// law is rebuilt from its exact law); [`LawRepresentation::Exact`] returns a tabulated
    /// law's exact law. The closed-form laws (passive, constant, explicit) are returned as
    /// they are in both representations. Errors as [`TabulatedLaw::new`].
    pub fn represented(self, representation: LawRepresentation, damages: &[f64]) -> Result<Self> {
        let exact = match self {
            Law::Implicit(l) => SolvedLaw::Implicit(l),
            Law::Energy(l) => SolvedLaw::Energy(l),
            Law::Tabulated(l) => l.exact,
            closed_form => return Ok(closed_form),
        };
        Ok(match representation {
            LawRepresentation::Exact => match exact {
                SolvedLaw::Implicit(l) => Law::Implicit(l),
                SolvedLaw::Energy(l) => Law::Energy(l),
            },
            LawRepresentation::Tabulated(spec) => {
                Law::Tabulated(TabulatedLaw::new(exact, damages, spec)?)
            }
        })
    }
}

impl<E: StrainEnergy> ActivationLaw for Law<E> {
    fn evaluate(&self, lambda: f64, drive: impl Into<Drive>) -> Result<LawValue> {
        let drive = drive.into();
        match self {
            Law::Passive => Ok(LawValue::default()),
            Law::Constant(l) => l.evaluate(lambda, drive),
            Law::Implicit(l) => l.evaluate(lambda, drive),
            Law::Explicit(l) => l.evaluate(lambda, drive),
            Law::Energy(l) => l.evaluate(lambda, drive),
            Law::Tabulated(l) => l.evaluate(lambda, drive),
        }
    }

    fn activation(&self, lambda: f64, drive: impl Into<Drive>) -> Result<f64> {
        let drive = drive.into();
        match self {
            Law::Passive => Ok(0.0),
            Law::Constant(l) => l.activation(lambda, drive),
            Law::Implicit(l) => l.activation(lambda, drive),
            Law::Explicit(l) => l.activation(lambda, drive),
            Law::Energy(l) => l.activation(lambda, drive),
            Law::Tabulated(l) => l.activation(lambda, drive),
        }
    }

    fn gamma_and_slope(&self, lambda: f64, drive: impl Into<Drive>) -> Result<(f64, f64)> {
        let drive = drive.into();
        match self {
            Law::Passive => Ok((0.0, 0.0)),
            Law::Constant(l) => l.gamma_and_slope(lambda, drive),
            Law::Implicit(l) => l.gamma_and_slope(lambda, drive),
            Law::Explicit(l) => l.gamma_and_slope(lambda, drive),
            Law::Energy(l) => l.gamma_and_slope(lambda, drive),
            Law::Tabulated(l) => l.gamma_and_slope(lambda, drive),
        }
    }

    fn gamma<T: Scalar>(&self, lambda: T, drive: impl Into<Drive>) -> Result<T> {
        let drive = drive.into();
        match self {
            Law::Explicit(l) => l.gamma(lambda, drive),
            _ => Ok(self.evaluate(lambda.re(), drive)?.lift(lambda)),
        }
    }

    fn outside(&self, lambda: f64, drive: impl Into<Drive>) -> Option<OutsideDomain> {
        match self {
            Law::Explicit(l) => l.outside(lambda, drive),
            _ => None,
        }
    }
}

/// Partial derivatives of Ŵ(λ, γ) along the uniaxial fibre path up to third order
/// (subscripts: l = λ, g = γ).
#[derive(Debug, Clone, Copy)]
pub(crate) struct PathPartials {
    pub w: f64,
    pub w_l: f64,
    pub w_ll: f64,
    pub w_lll: f64,
    pub w_g: f64,
    pub w_lg: f64,
    pub w_llg: f64,
    pub w_gg: f64,
    pub w_lgg: f64,
}

impl PathPartials {
    /// Three hyper-hyper-dual evaluations of Ŵ(λ, γ) with the active-strain map `map`.
    pub fn at<E: StrainEnergy>(
        energy: &E,
        map: ActivationMap,
        lambda: f64,
        gamma: f64,
    ) -> Result<Self> {
        let hhd = HyperHyperDual64::from_re;
        let fibre_path_energy = |e: &E, l, g| map.fibre_path_energy(e, l, g);
        let l3 = hhd(lambda).derivative1().derivative2().derivative3();
        let a = fibre_path_energy(energy, l3, hhd(gamma));
        let b = fibre_path_energy(
            energy,
            hhd(lambda).derivative1().derivative2(),
            hhd(gamma).derivative3(),
        );
        let c = fibre_path_energy(
            energy,
            hhd(lambda).derivative1(),
            hhd(gamma).derivative2().derivative3(),
        );
        let p = Self {
            w: a.re,
            w_l: a.eps1,
            w_ll: a.eps1eps2,
            w_lll: a.eps1eps2eps3,
            w_g: b.eps3,
            w_lg: b.eps1eps3,
            w_llg: b.eps1eps2eps3,
            w_gg: c.eps2eps3,
            w_lgg: c.eps1eps2eps3,
        };
        let all = [
            p.w, p.w_l, p.w_ll, p.w_lll, p.w_g, p.w_lg, p.w_llg, p.w_gg, p.w_lgg,
        ];
        if all.iter().all(|x| x.is_finite()) {
            Ok(p)
        } else {
            Err(Error::NonFinite {
                quantity: "derivatives of the fibre-path energy",
                value: all
                    .iter()
                    .copied()
                    .find(|x| !x.is_finite())
                    .unwrap_or(f64::NAN),
                context: format!(
                    "at lambda = {}, gamma = {} (exp overflow?)",
                    crate::text::significant(lambda, 6),
                    crate::text::significant(gamma, 6)
                ),
            })
        }
    }
}

/// ∂Ŵ/∂λ = P_tot(λ, γ) (eq. D:Ptotcalcolato), ∂Ŵ/∂γ and ∂P_tot/∂γ along the fibre path, by one
/// hyper-dual.
pub(crate) fn fibre_path_derivatives<E: StrainEnergy>(
    energy: &E,
    map: ActivationMap,
    lambda: f64,
    gamma: f64,
) -> [f64; 3] {
    let w = map.fibre_path_energy(
        energy,
        HyperDual64::from_re(lambda).derivative1(),
        HyperDual64::from_re(gamma).derivative2(),
    );
    [w.eps1, w.eps2, w.eps1eps2]
}

/// ∂P_tot/∂λ = ∂²Ŵ/∂λ² along the fibre path at (λ, γ), by one hyper-dual. Errors if it is not
/// finite (exp overflow).
pub(crate) fn fibre_stiffness<E: StrainEnergy>(
    energy: &E,
    map: ActivationMap,
    lambda: f64,
    gamma: f64,
) -> Result<f64> {
    let l = HyperDual64::from_re(lambda).derivative1().derivative2();
    let w_ll = map
        .fibre_path_energy(energy, l, HyperDual64::from_re(gamma))
        .eps1eps2;
    if w_ll.is_finite() {
        Ok(w_ll)
    } else {
        Err(Error::NonFinite {
            quantity: "fibre stiffness dP_tot/dlambda",
            value: w_ll,
            context: format!(
                "at lambda = {}, gamma = {} (exp overflow?)",
                crate::text::significant(lambda, 6),
                crate::text::significant(gamma, 6)
            ),
        })
    }
}

/// P_tot(λ, γ) = ∂Ŵ/∂λ and ∂P_tot/∂γ along the fibre path ([`fibre_path_derivatives`]).
pub(crate) fn fibre_stress_and_slope<E: StrainEnergy>(
    energy: &E,
    map: ActivationMap,
    lambda: f64,
    gamma: f64,
) -> (f64, f64) {
    let [p, _, slope] = fibre_path_derivatives(energy, map, lambda, gamma);
    (p, slope)
}

/// The smallest root γ ∈ (0, `upper`) of `residual` with residual(0) < 0, found by stepping up
/// in steps of 0.05 until the sign changes (a non-finite value — exp overflow — counts as "past
/// the root" and halves the step; at most 400 evaluations, ≈ 100 when the overflow is monotone;
/// above 1, for the structural map's unbounded ω, the step doubles each time), then safeguarded
/// Newton to 1e-15 in γ.
pub(crate) fn first_activation_root(
    upper: f64,
    equation: impl Fn() -> String,
    residual: impl Fn(f64) -> (f64, f64),
) -> Result<f64> {
    let (mut lo, mut hi) = (0.0, f64::NAN);
    let mut step = 0.05;
    let mut evaluations = 0;
    while step > 1e-12 && evaluations < 400 {
        let trial = lo + step;
        if trial >= upper {
            step *= 0.5;
            continue;
        }
        let (f, _) = residual(trial);
        evaluations += 1;
        if !f.is_finite() {
            step *= 0.5;
        } else if f > 0.0 {
            hi = trial;
            break;
        } else {
            lo = trial;
            if lo >= 1.0 {
                step *= 2.0;
            }
        }
    }
    if hi.is_nan() {
        return Err(Error::NoSolution {
            equation: equation(),
            reason: format!("no sign change of the residual for the activation in [0, {lo}] before exp overflow or the end of its range ({evaluations} evaluations, last step {step:e})"),
        });
    }
    newton_bisection(&residual, lo, hi, 1e-15).map_err(|reason| Error::NoSolution {
        equation: equation(),
        reason,
    })
}

/// Derivatives of the root γ(λ) of F(λ, γ) = 0 by the implicit-function theorem:
/// g′ = −F_λ/F_γ, g″ = −(F_λλ + 2 F_λγ g′ + F_γγ g′²)/F_γ.
pub(crate) fn implicit_derivatives(
    gamma: f64,
    f_l: f64,
    f_g: f64,
    f_ll: f64,
    f_lg: f64,
    f_gg: f64,
) -> LawValue {
    let slope = -f_l / f_g;
    let curvature = -(f_ll + 2.0 * f_lg * slope + f_gg * slope * slope) / f_g;
    LawValue {
        gamma,
        slope,
        curvature,
    }
}
