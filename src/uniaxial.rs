//! Homogeneous (0D) tests of an incompressible muscle: uniaxial tension along and across the fibres
//! with traction-free lateral faces. Fibres along e₁.
//!
//! - Along: F = diag(λ, λ^-½, λ^-½); the pressure follows from P₂₂ = 0, p = F₂₂ ∂Ψ/∂F₂₂, and the
//!   nominal stress is P₁₁ = ∂Ψ/∂F₁₁ − p/λ. With γ = g(λ) this is P_tot(λ, g(λ)) (frozen) or
//!   dΨ/dλ (consistent).
//! - Across (stretch along e₂): F = diag(a, λ, 1/(aλ)) with the fibre stretch a unknown; both
//!   lateral faces traction free: a ∂Ψ/∂F₁₁ = F₃₃ ∂Ψ/∂F₃₃ (= p), solved for a by safeguarded Newton
//!   with the exact tangent. Nominal stress P₂₂ = ∂Ψ/∂F₂₂ − p/λ.
//! - Cauchy stress along the stretch from the full tensor, σ = J⁻¹ P Fᵀ with
//!   P = ∂Ψ/∂F − p F⁻ᵀ ([`cauchy_stress`]); with J = 1, F diagonal and traction-free lateral faces
//!   it is λ times the nominal stress.

use crate::energy::{positive, StrainEnergy};
use crate::invariants::{Kinematics, FULL};
use crate::material::Muscle;
use crate::response::Order;
use crate::roots::newton_bisection;
use crate::{Error, Result};
use nalgebra::{Matrix3, SVector, Vector3};

/// One point of a uniaxial test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UniaxialPoint {
    /// Applied stretch λ [-].
    pub lambda: f64,
    /// Nominal stress along the stretch \[kPa\].
    pub stress: f64,
    /// Cauchy (true) stress along the stretch, σ = J⁻¹ P Fᵀ \[kPa\].
    pub cauchy: f64,
    /// Activation γ at the point [-].
    pub gamma: f64,
    /// Fibre stretch λ_f [-] (= λ along the fibres).
    pub fibre_stretch: f64,
    /// The two lateral stretches [-] (along the fibres: both λ^-½; across: the fibre stretch
    /// and the other lateral stretch).
    pub lateral: [f64; 2],
}

/// Direction of a uniaxial test relative to the fibres (in a scene: `direction = "along" | "across"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Direction {
    /// Stretch along the fibres ([`along_fibres`]).
    #[default]
    Along,
    /// Stretch across the fibres, lateral faces traction free ([`across_fibres`]).
    Across,
}

impl Direction {
    /// `along` or `across`.
    pub fn name(self) -> &'static str {
        match self {
            Direction::Along => "along",
            Direction::Across => "across",
        }
    }

    /// The uniaxial test of `muscle` at stretch `lambda` in this direction.
    pub fn point<E: StrainEnergy>(self, muscle: &Muscle<E>, lambda: f64) -> Result<UniaxialPoint> {
        match self {
            Direction::Along => along_fibres(muscle, lambda),
            Direction::Across => across_fibres(muscle, lambda),
        }
    }
}

fn fibre() -> Vector3<f64> {
    Vector3::new(1.0, 0.0, 0.0)
}

/// The homogeneous state along the fibres (m = e₁): F = diag(λ, λ^-½, λ^-½).
pub fn fibre_kinematics(lambda: f64) -> Result<Kinematics> {
    positive("lambda", lambda)?;
    let t = lambda.sqrt().recip();
    Kinematics::new(
        &Matrix3::from_diagonal(&Vector3::new(lambda, t, t)),
        &fibre(),
    )
}

/// Nominal stress along the fibres from ∂Ψ/∂F (entries row by row) in that state:
/// P₁₁ − p/λ with the lateral pressure p = F₂₂ ∂Ψ/∂F₂₂.
pub(crate) fn nominal_along(p: &SVector<f64, 9>, lambda: f64) -> f64 {
    p[0] - p[4] * lambda.sqrt().recip() / lambda
}

/// The Cauchy stress σ = J⁻¹ P Fᵀ \[kPa\] of the total nominal stress P = ∂Ψ/∂F − p F⁻ᵀ, from
/// ∂Ψ/∂F (`dpsi_df`, row by row), the pressure p \[kPa\] and F: σ = J⁻¹ (∂Ψ/∂F) Fᵀ − p I.
/// Rejects det F ≤ 0.
pub fn cauchy_stress(
    dpsi_df: &SVector<f64, 9>,
    pressure: f64,
    f: &Matrix3<f64>,
) -> Result<Matrix3<f64>> {
    let j = f.determinant();
    if j <= 0.0 || !j.is_finite() {
        return Err(Error::NonPositiveJacobian {
            det: j,
            f: [
                [f[(0, 0)], f[(0, 1)], f[(0, 2)]],
                [f[(1, 0)], f[(1, 1)], f[(1, 2)]],
                [f[(2, 0)], f[(2, 1)], f[(2, 2)]],
            ],
        });
    }
    let p = Matrix3::from_row_slice(dpsi_df.as_slice());
    Ok(p * f.transpose() / j - Matrix3::identity() * pressure)
}

/// Uniaxial tension along the fibres.
pub fn along_fibres<E: StrainEnergy>(muscle: &Muscle<E>, lambda: f64) -> Result<UniaxialPoint> {
    let kin = fibre_kinematics(lambda)?;
    let t = lambda.sqrt().recip();
    let r = muscle.respond(&kin, Order::Stress, &FULL)?;
    let p = r.stress.unwrap_or_default();
    let f = Matrix3::from_diagonal(&Vector3::new(lambda, t, t));
    Ok(UniaxialPoint {
        lambda,
        stress: nominal_along(&p, lambda),
        cauchy: cauchy_stress(&p, p[4] * t, &f)?[(0, 0)],
        gamma: r.gamma,
        fibre_stretch: r.fibre_stretch,
        lateral: [t, t],
    })
}

/// Uniaxial tension across the fibres (stretch along e₂, fibres along e₁).
pub fn across_fibres<E: StrainEnergy>(muscle: &Muscle<E>, lambda: f64) -> Result<UniaxialPoint> {
    positive("lambda", lambda)?;
    let state = |a: f64| -> Result<(Kinematics, f64)> {
        let f33 = 1.0 / (a * lambda);
        Ok((
            Kinematics::new(
                &Matrix3::from_diagonal(&Vector3::new(a, lambda, f33)),
                &fibre(),
            )?,
            f33,
        ))
    };
    // r(a) = a P₁₁ − F₃₃ P₃₃ and its exact derivative.
    let residual = |a: f64| -> (f64, f64) {
        let Ok((kin, f33)) = state(a) else {
            return (f64::NAN, f64::NAN);
        };
        let Ok(r) = muscle.respond(&kin, Order::Tangent, &FULL) else {
            return (f64::NAN, f64::NAN);
        };
        let (p, k) = (r.stress.unwrap_or_default(), r.tangent.unwrap_or_default());
        let df33 = -f33 / a;
        let dp11 = k[(0, 0)] + k[(0, 8)] * df33;
        let dp33 = k[(8, 0)] + k[(8, 8)] * df33;
        (
            a * p[0] - f33 * p[8],
            p[0] + a * dp11 - df33 * p[8] - f33 * dp33,
        )
    };
    let guess = lambda.sqrt().recip();
    let (mut lo, mut hi) = (guess, guess);
    let mut expanded = 0;
    // Expand [lo, hi] geometrically until r(lo) < 0 < r(hi) (a NaN counts as not yet).
    let below = |a: f64| residual(a).0 < 0.0;
    let above = |a: f64| residual(a).0 > 0.0;
    while !below(lo) || !above(hi) {
        if !below(lo) {
            lo *= 0.8;
        }
        if !above(hi) {
            hi *= 1.25;
        }
        expanded += 1;
        if expanded > 60 {
            return Err(Error::NoSolution {
                equation: format!("lateral equilibrium across the fibres at lambda = {lambda}"),
                reason: format!(
                    "no sign change of a P11 - F33 P33 for fibre stretch in [{lo}, {hi}]"
                ),
            });
        }
    }
    let a =
        newton_bisection(residual, lo, hi, 1e-15 * guess).map_err(|reason| Error::NoSolution {
            equation: format!("lateral equilibrium across the fibres at lambda = {lambda}"),
            reason,
        })?;
    let (kin, f33) = state(a)?;
    let r = muscle.respond(&kin, Order::Stress, &FULL)?;
    let p = r.stress.unwrap_or_default();
    let pressure = p[8] * f33;
    let f = Matrix3::from_diagonal(&Vector3::new(a, lambda, f33));
    Ok(UniaxialPoint {
        lambda,
        stress: p[4] - pressure / lambda,
        cauchy: cauchy_stress(&p, pressure, &f)?[(1, 1)],
        gamma: r.gamma,
        fibre_stretch: r.fibre_stretch,
        lateral: [a, f33],
    })
}
