//! Homogeneous (0D) tests of an incompressible muscle: uniaxial tension along and across the fibres
//! with traction-free lateral faces. Fibres along e₁.
//!
//! - Along: F = diag(λ, λ^-½, λ^-½); the pressure follows from P₂₂ = 0, p = F₂₂ ∂Ψ/∂F₂₂, and the
//!   nominal stress is P₁₁ = ∂Ψ/∂F₁₁ − p/λ. With γ = g(λ) this is P_tot(λ, g(λ)) (frozen) or
//!   dΨ/dλ (consistent).
//! - Across (stretch along e₂): F = diag(a, λ, 1/(aλ)) with the fibre stretch a unknown; both
//!   lateral faces traction free: a ∂Ψ/∂F₁₁ = F₃₃ ∂Ψ/∂F₃₃ (= p), solved for a by safeguarded Newton
//!   with the exact tangent. Nominal stress P₂₂ = ∂Ψ/∂F₂₂ − p/λ.

use crate::energy::{positive, StrainEnergy};
use crate::invariants::{Kinematics, FULL};
use crate::material::Muscle;
use crate::response::Order;
use crate::roots::newton_bisection;
use crate::volumetric::Volumetric;
use crate::{Error, Result};
use nalgebra::{Matrix3, SVector, Vector3};

/// One point of a uniaxial test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UniaxialPoint {
    /// Applied stretch λ [-].
    pub lambda: f64,
    /// Nominal stress along the stretch \[kPa\].
    pub stress: f64,
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

/// Uniaxial tension along the fibres.
pub fn along_fibres<E: StrainEnergy>(muscle: &Muscle<E>, lambda: f64) -> Result<UniaxialPoint> {
    let kin = fibre_kinematics(lambda)?;
    let t = lambda.sqrt().recip();
    let r = muscle.respond(&kin, Order::Stress, &FULL)?;
    Ok(UniaxialPoint {
        lambda,
        stress: nominal_along(&r.stress.unwrap_or_default(), lambda),
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
    Ok(UniaxialPoint {
        lambda,
        stress: p[4] - pressure / lambda,
        gamma: r.gamma,
        fibre_stretch: r.fibre_stretch,
        lateral: [a, f33],
    })
}

/// Newton iterations allowed for the lateral equilibrium of the nearly incompressible test.
pub const MAX_LATERAL_ITERATIONS: usize = 60;

/// The passive stress s₀ at F = I of `energy`, which must be hydrostatic (s₀ I, fibres along
/// e₁) \[kPa\]: what a volumetric energy must cancel for a stress-free reference
/// ([`crate::volumetric::Volumetric::new`]). 0 for the chapter's energies, μ for the
/// neo-Hookean μ/2 (tr C − 3).
pub fn reference_stress<E: StrainEnergy + Clone>(energy: &E) -> Result<f64> {
    let muscle = Muscle::passive(energy.clone());
    let kin = Kinematics::new(&Matrix3::identity(), &fibre())?;
    let p = muscle
        .respond(&kin, Order::Stress, &FULL)?
        .stress
        .unwrap_or_default();
    let s0 = p[0];
    let off = [1, 2, 3, 5, 6, 7]
        .iter()
        .map(|&i| p[i].abs())
        .fold(0.0, f64::max);
    let spread = (p[4] - s0).abs().max((p[8] - s0).abs());
    if off.max(spread) > 1e-12 * (1.0 + s0.abs()) {
        return Err(Error::NoSolution {
            equation: "stress-free reference of the nearly incompressible material".into(),
            reason: format!(
                "the passive stress at F = I is not hydrostatic (diagonal {}, {}, {} kPa), so no U(J) cancels it",
                p[0], p[4], p[8]
            ),
        });
    }
    Ok(s0)
}

/// Uniaxial tension of the nearly incompressible muscle, energy Ŵ(F, γ) + U(J), in `direction`
/// (fibres along e₁, stretch along e₁ or e₂): F = diag(F₁₁, F₂₂, F₃₃) with the applied stretch λ
/// on the loaded axis k and the two lateral stretches unknown, solved from zero lateral traction
///
/// P_ii = ∂Ŵ/∂F_ii + U′(J) J/F_ii = 0 (both lateral i; cof F = J F⁻ᵀ),
///
/// by Newton with the exact 2 × 2 tangent (∂²Ŵ/∂F_ii∂F_jj from the dual-number route, plus
/// U″ (J/F_ii)(J/F_jj) and, for i ≠ j, U′ J/(F_ii F_jj)), backtracking on |r|, from the
/// incompressible solution, at most [`MAX_LATERAL_ITERATIONS`] iterations (an error saying so
/// otherwise). The nominal stress is P_kk = ∂Ŵ/∂F_kk + U′(J) J/F_kk; `lateral` holds the two
/// lateral stretches (along: e₂, e₃; across: e₁ (the fibre), e₃).
pub fn nearly_incompressible<E: StrainEnergy>(
    muscle: &Muscle<E>,
    volumetric: &Volumetric,
    direction: Direction,
    lambda: f64,
) -> Result<UniaxialPoint> {
    positive("lambda", lambda)?;
    let start = direction.point(muscle, lambda)?;
    let (axis, lat) = match direction {
        Direction::Along => (0usize, [1usize, 2usize]),
        Direction::Across => (1, [0, 2]),
    };
    let diagonal = |x: [f64; 2]| {
        let mut d = Vector3::zeros();
        d[axis] = lambda;
        d[lat[0]] = x[0];
        d[lat[1]] = x[1];
        d
    };
    // Residual (P_ii of both lateral axes), its Jacobian, the loaded axis' P_kk, γ and λ_f.
    type Lateral = ([f64; 2], [[f64; 2]; 2], f64, f64, f64);
    let evaluate = |x: [f64; 2], tangent: bool| -> Result<Lateral> {
        let d = diagonal(x);
        let kin = Kinematics::new(&Matrix3::from_diagonal(&d), &fibre())?;
        let order = if tangent {
            Order::Tangent
        } else {
            Order::Stress
        };
        let r = muscle.respond(&kin, order, &FULL)?;
        let p = r.stress.unwrap_or_default();
        let j = d[0] * d[1] * d[2];
        let [_, du, ddu] = volumetric.derivatives(j)?;
        let cof = |i: usize| j / d[i];
        let res = [
            p[4 * lat[0]] + du * cof(lat[0]),
            p[4 * lat[1]] + du * cof(lat[1]),
        ];
        let mut jac = [[0.0; 2]; 2];
        if let Some(k) = r.tangent {
            for (a, &i) in lat.iter().enumerate() {
                for (b, &m) in lat.iter().enumerate() {
                    let cross = if i == m { 0.0 } else { du * j / (d[i] * d[m]) };
                    jac[a][b] = k[(4 * i, 4 * m)] + ddu * cof(i) * cof(m) + cross;
                }
            }
        }
        let nominal = p[4 * axis] + du * cof(axis);
        Ok((res, jac, nominal, r.gamma, r.fibre_stretch))
    };
    let failure = |reason: String| {
        Error::NoSolution {
        equation: format!(
            "lateral equilibrium of the nearly incompressible test {} the fibres at lambda = {lambda}",
            direction.name()
        ),
        reason,
    }
    };
    let norm = |r: [f64; 2]| r[0].abs().max(r[1].abs());
    let mut x = start.lateral;
    for iteration in 0..MAX_LATERAL_ITERATIONS {
        let (r, jac, _, _, _) = evaluate(x, true)?;
        let det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
        if !(det.is_finite() && det != 0.0) {
            return Err(failure(format!(
                "singular lateral tangent (det = {det}) at lateral stretches {x:?}, iteration {iteration}"
            )));
        }
        let dx = [
            -(jac[1][1] * r[0] - jac[0][1] * r[1]) / det,
            -(-jac[1][0] * r[0] + jac[0][0] * r[1]) / det,
        ];
        // Backtracking: stay at positive stretches and do not increase |r| (beyond rounding).
        let mut step = 1.0;
        let mut next = [x[0] + dx[0], x[1] + dx[1]];
        for _ in 0..30 {
            let ok = next[0] > 0.0
                && next[1] > 0.0
                && evaluate(next, false).is_ok_and(|(rn, ..)| norm(rn) <= norm(r) * (1.0 + 1e-12));
            if ok {
                break;
            }
            step *= 0.5;
            next = [x[0] + step * dx[0], x[1] + step * dx[1]];
        }
        let moved = (next[0] - x[0]).abs().max((next[1] - x[1]).abs());
        x = next;
        if moved <= 4.0 * f64::EPSILON * x[0].abs().max(x[1].abs()) {
            let (_, _, stress, gamma, fibre_stretch) = evaluate(x, false)?;
            return Ok(UniaxialPoint {
                lambda,
                stress,
                gamma,
                fibre_stretch,
                lateral: x,
            });
        }
    }
    Err(failure(format!(
        "no convergence in {MAX_LATERAL_ITERATIONS} Newton iterations (last lateral stretches {x:?})"
    )))
}
