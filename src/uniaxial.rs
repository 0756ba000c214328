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
use crate::text::shortest;
use crate::volumetric::Volumetric;
use crate::{Error, Result};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

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

/// dP/dλ along the homogeneous path along the fibres, exact from ∂Ψ/∂F (`p`) and its tangent
/// (`k`, entries row by row) at F = diag(λ, λ^-½, λ^-½). With t = λ^-½ and P = P₁₁ − P₂₂ t/λ:
/// dP/dλ = dP₁₁/dλ − λ^{-3/2} dP₂₂/dλ + (3/2) λ^{-5/2} P₂₂, dF/dλ = diag(1, −t/(2λ), −t/(2λ)).
pub(crate) fn slope_along(p: &SVector<f64, 9>, k: &SMatrix<f64, 9, 9>, lambda: f64) -> f64 {
    let t = lambda.sqrt().recip();
    let df = [(0, 1.0), (4, -t / (2.0 * lambda)), (8, -t / (2.0 * lambda))];
    let rate = |row: usize| df.iter().map(|&(b, v)| k[(row, b)] * v).sum::<f64>();
    rate(0) - lambda.powf(-1.5) * rate(4) + 1.5 * lambda.powf(-2.5) * p[4]
}

/// The uniaxial test of `muscle` at stretch `lambda` in `direction`: exactly incompressible
/// (`volumetric` = `None`, [`Direction::point`]) or nearly incompressible with the lateral
/// stretches in equilibrium ([`nearly_incompressible`]).
pub fn point<E: StrainEnergy>(
    muscle: &Muscle<E>,
    volumetric: Option<&Volumetric>,
    direction: Direction,
    lambda: f64,
) -> Result<UniaxialPoint> {
    match volumetric {
        None => direction.point(muscle, lambda),
        Some(v) => nearly_incompressible(muscle, v, direction, lambda),
    }
}

/// Free contraction along the fibres, exactly incompressible (`volumetric` = `None`,
/// [`free_contraction`]) or nearly incompressible ([`nearly_incompressible_free_contraction`]).
pub fn zero_load_point<E: StrainEnergy>(
    muscle: &Muscle<E>,
    volumetric: Option<&Volumetric>,
) -> Result<UniaxialPoint> {
    match volumetric {
        None => free_contraction(muscle),
        Some(v) => nearly_incompressible_free_contraction(muscle, v),
    }
}

/// Free contraction along the fibres: the stretch at which the nominal stress along the fibres
/// vanishes (zero axial load, lateral faces traction free), P(λ) = 0. An active muscle shortens:
/// P(1) = (1 − d)·a·P_act(1) > 0 for the exact laws, and the root taken is the largest one at or
/// below λ = 1 (the first met when contracting from rest), bracketed by stretches 1 − 0.005·2^k
/// and refined by safeguarded Newton with the exact slope ([`slope_along`]) to 1e-15. If P(1) < 0
/// (e.g. a passive muscle whose P(1) is −1e-17) the root is bracketed above 1 the same way. For the
/// chapter's implicit law the root solves P_pas(λ) + (1 − d)·a·P_act(λ) = 0, unique on
/// (λ_min, 1) since both terms increase there. Errors if no sign change is found in [0.05, 10],
/// or if the root is a jump of P (a law discontinuous in λ), not a zero.
pub fn free_contraction<E: StrainEnergy>(muscle: &Muscle<E>) -> Result<UniaxialPoint> {
    let stress = |l: f64| -> (f64, f64) {
        let Ok(kin) = fibre_kinematics(l) else {
            return (f64::NAN, f64::NAN);
        };
        match muscle.respond(&kin, Order::Tangent, &FULL) {
            Ok(r) => {
                let (p, k) = (r.stress.unwrap_or_default(), r.tangent.unwrap_or_default());
                (nominal_along(&p, l), slope_along(&p, &k, l))
            }
            Err(_) => (f64::NAN, f64::NAN),
        }
    };
    zero_load(
        "free contraction P(lambda) = 0 along the fibres",
        0.0,
        stress,
        |l| along_fibres(muscle, l),
    )
}

/// Free contraction of the nearly incompressible muscle (energy Ŵ + U(J), [`Volumetric`]): the
/// stretch λ along the fibres at which P₁₁(λ) = 0 with both lateral stretches solved from zero
/// lateral traction ([`nearly_incompressible`]), the same bracketing and safeguarded Newton as
/// [`free_contraction`]. The slope is the exact one of the constrained curve, the Schur
/// complement dP₁₁/dλ = H₁₁ − H₁ₗ H_ll⁻¹ Hₗ₁ of the diagonal Hessian H (ℓ: the lateral axes).
pub fn nearly_incompressible_free_contraction<E: StrainEnergy>(
    muscle: &Muscle<E>,
    volumetric: &Volumetric,
) -> Result<UniaxialPoint> {
    let stress = |l: f64| match nearly_incompressible_with_slope(
        muscle,
        volumetric,
        Direction::Along,
        l,
        true,
    ) {
        Ok((point, slope)) => (point.stress, slope),
        Err(_) => (f64::NAN, f64::NAN),
    };
    zero_load(
        "free contraction P(lambda) = 0 along the fibres of the nearly incompressible block",
        64.0 * f64::EPSILON * volumetric.bulk_modulus(),
        stress,
        |l| nearly_incompressible(muscle, volumetric, Direction::Along, l),
    )
}

/// The zero of the nominal stress P(λ) nearest below λ = 1 (above, if P(1) < 0), from
/// `stress(λ) = (P, dP/dλ)`; `point(λ)` gives the state at the root. See [`free_contraction`].
/// `noise` \[kPa\] is the rounding level of P on top of |slope| × 1e-15 (a nearly incompressible
/// block's P carries U″ × J's rounding error, ≈ κ ε).
fn zero_load(
    equation: &str,
    noise: f64,
    stress: impl Fn(f64) -> (f64, f64),
    point: impl Fn(f64) -> Result<UniaxialPoint>,
) -> Result<UniaxialPoint> {
    let at_rest = stress(1.0).0;
    if at_rest == 0.0 {
        return point(1.0);
    }
    let (mut lo, mut hi) = (1.0, 1.0);
    let mut offset = 0.005;
    loop {
        let trial = if at_rest > 0.0 {
            1.0 - offset
        } else {
            1.0 + offset
        };
        if !(0.05..=10.0).contains(&trial) {
            return Err(Error::NoSolution {
                equation: equation.to_string(),
                reason: format!(
                    "P(1) = {at_rest} kPa and no sign change of P for lambda in [0.05, 10]"
                ),
            });
        }
        let p = stress(trial).0;
        if at_rest > 0.0 && p < 0.0 {
            lo = trial;
            break;
        }
        if at_rest < 0.0 && p > 0.0 {
            hi = trial;
            break;
        }
        if at_rest > 0.0 && p > 0.0 {
            hi = trial;
        } else if at_rest < 0.0 && p < 0.0 {
            lo = trial;
        }
        offset *= 2.0;
    }
    let lambda = newton_bisection(&stress, lo, hi, 1e-15).map_err(|reason| Error::NoSolution {
        equation: equation.to_string(),
        reason,
    })?;
    let state = point(lambda)?;
    // A zero of P has |P| ≲ |slope| × 1e-15 + noise; a jump leaves |P| at the size of the jump.
    let (_, slope) = stress(lambda);
    if state.stress.abs() > 1e-9 * (1.0 + slope.abs()) + noise {
        return Err(Error::NoSolution {
            equation: equation.to_string(),
            reason: format!(
                "P changes sign at lambda = {} without vanishing (P = {} kPa there): the activation law jumps",
                shortest(lambda),
                shortest(state.stress)
            ),
        });
    }
    Ok(state)
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
                equation: format!(
                    "lateral equilibrium across the fibres at lambda = {}",
                    shortest(lambda)
                ),
                reason: format!(
                    "no sign change of a P11 - F33 P33 for fibre stretch in [{}, {}]",
                    shortest(lo),
                    shortest(hi)
                ),
            });
        }
    }
    let a =
        newton_bisection(residual, lo, hi, 1e-15 * guess).map_err(|reason| Error::NoSolution {
            equation: format!(
                "lateral equilibrium across the fibres at lambda = {}",
                shortest(lambda)
            ),
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

/// The initial modulus of the passive `energy` along the fibres, E₀ = dP/dλ at λ = 1 \[kPa\] of
/// exactly incompressible uniaxial tension (a central difference of step 1e-4: the stiffness a
/// volumetric energy is compared with, not a result).
pub fn initial_modulus<E: StrainEnergy + Clone>(energy: &E) -> Result<f64> {
    let muscle = Muscle::passive(energy.clone());
    let h = 1e-4;
    let p = |lambda: f64| along_fibres(&muscle, lambda).map(|q| q.stress);
    Ok((p(1.0 + h)? - p(1.0 - h)?) / (2.0 * h))
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
    Ok(nearly_incompressible_with_slope(muscle, volumetric, direction, lambda, false)?.0)
}

/// [`nearly_incompressible`], and with `slope` the derivative of the nominal stress along the
/// loaded axis k with the lateral stretches in equilibrium, dP_kk/dλ = H_kk − H_kℓ H_ℓℓ⁻¹ H_ℓk
/// \[kPa\], H_ab = ∂P_aa/∂F_bb of the diagonal state (NaN without `slope`; one more tangent
/// evaluation with it).
pub fn nearly_incompressible_with_slope<E: StrainEnergy>(
    muscle: &Muscle<E>,
    volumetric: &Volumetric,
    direction: Direction,
    lambda: f64,
    slope: bool,
) -> Result<(UniaxialPoint, f64)> {
    positive("lambda", lambda)?;
    let start = direction.point(muscle, lambda)?;
    let (axis, lat) = match direction {
        Direction::Along => (0usize, [1usize, 2usize]),
        Direction::Across => (1, [0, 2]),
    };
    let test = LateralTest {
        muscle,
        volumetric,
        direction,
        lambda,
        axis,
        lat,
    };
    let mut x = start.lateral;
    for iteration in 0..MAX_LATERAL_ITERATIONS {
        let state = test.evaluate(x, true)?;
        let dx = test.newton_step(&state, x, iteration)?;
        let next = test.backtrack(x, dx, state.residual);
        let moved = (next[0] - x[0]).abs().max((next[1] - x[1]).abs());
        x = next;
        if moved <= 4.0 * f64::EPSILON * x[0].abs().max(x[1].abs()) {
            return test.point(x, slope);
        }
    }
    Err(test.failure(format!(
        "no convergence in {MAX_LATERAL_ITERATIONS} Newton iterations (last lateral stretches {x:?})"
    )))
}

/// One nearly incompressible uniaxial test: the loaded axis k (`axis`) held at `lambda`, the
/// two lateral axes `lat` free.
struct LateralTest<'a, E> {
    muscle: &'a Muscle<E>,
    volumetric: &'a Volumetric,
    direction: Direction,
    lambda: f64,
    axis: usize,
    lat: [usize; 2],
}

/// The state at lateral stretches x: the residual (P_ii of both lateral axes), the diagonal
/// Hessian H_ab = ∂P_aa/∂F_bb (all three axes; zero without the tangent), the loaded axis' P_kk,
/// γ and λ_f.
struct LateralState {
    residual: [f64; 2],
    hessian: [[f64; 3]; 3],
    nominal: f64,
    gamma: f64,
    fibre_stretch: f64,
}

impl<E: StrainEnergy> LateralTest<'_, E> {
    /// diag(F): λ on the loaded axis, `x` on the lateral ones.
    fn diagonal(&self, x: [f64; 2]) -> Vector3<f64> {
        let mut d = Vector3::zeros();
        d[self.axis] = self.lambda;
        d[self.lat[0]] = x[0];
        d[self.lat[1]] = x[1];
        d
    }

    /// P_ii = ∂Ŵ/∂F_ii + U′(J) J/F_ii and, with `tangent`,
    /// H_im = ∂²Ŵ/∂F_ii∂F_mm + U″ (J/F_ii)(J/F_mm) + (i ≠ m) U′ J/(F_ii F_mm).
    fn evaluate(&self, x: [f64; 2], tangent: bool) -> Result<LateralState> {
        let (axis, lat) = (self.axis, self.lat);
        let d = self.diagonal(x);
        let kin = Kinematics::new(&Matrix3::from_diagonal(&d), &fibre())?;
        let order = if tangent {
            Order::Tangent
        } else {
            Order::Stress
        };
        let r = self.muscle.respond(&kin, order, &FULL)?;
        let p = r.stress.unwrap_or_default();
        let j = d[0] * d[1] * d[2];
        let [_, du, ddu] = self.volumetric.derivatives(j)?;
        let cof = |i: usize| j / d[i];
        let residual = [
            p[4 * lat[0]] + du * cof(lat[0]),
            p[4 * lat[1]] + du * cof(lat[1]),
        ];
        let mut hessian = [[0.0; 3]; 3];
        if let Some(k) = r.tangent {
            for (i, row) in hessian.iter_mut().enumerate() {
                for (m, h) in row.iter_mut().enumerate() {
                    let cross = if i == m { 0.0 } else { du * j / (d[i] * d[m]) };
                    *h = k[(4 * i, 4 * m)] + ddu * cof(i) * cof(m) + cross;
                }
            }
        }
        let nominal = p[4 * axis] + du * cof(axis);
        Ok(LateralState {
            residual,
            hessian,
            nominal,
            gamma: r.gamma,
            fibre_stretch: r.fibre_stretch,
        })
    }

    /// The Newton step dx = −J⁻¹ r with the 2 × 2 lateral block J of the Hessian (Cramer's
    /// rule); an error if J is singular.
    fn newton_step(&self, state: &LateralState, x: [f64; 2], iteration: usize) -> Result<[f64; 2]> {
        let r = state.residual;
        let jac = lateral_block(&state.hessian, self.lat);
        let det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
        if !(det.is_finite() && det != 0.0) {
            return Err(self.failure(format!(
                "singular lateral tangent (det = {det}) at lateral stretches {x:?}, iteration {iteration}"
            )));
        }
        Ok([
            -(jac[1][1] * r[0] - jac[0][1] * r[1]) / det,
            -(-jac[1][0] * r[0] + jac[0][0] * r[1]) / det,
        ])
    }

    /// Backtracking from `x` along `dx`: halve the step (at most 30 times) until the stretches
    /// are positive and |r| does not increase (beyond rounding).
    fn backtrack(&self, x: [f64; 2], dx: [f64; 2], r: [f64; 2]) -> [f64; 2] {
        let norm = |r: [f64; 2]| r[0].abs().max(r[1].abs());
        let mut step = 1.0;
        let mut next = [x[0] + dx[0], x[1] + dx[1]];
        for _ in 0..30 {
            let ok = next[0] > 0.0
                && next[1] > 0.0
                && self
                    .evaluate(next, false)
                    .is_ok_and(|s| norm(s.residual) <= norm(r) * (1.0 + 1e-12));
            if ok {
                break;
            }
            step *= 0.5;
            next = [x[0] + step * dx[0], x[1] + step * dx[1]];
        }
        next
    }

    /// The converged point at lateral stretches `x`, and with `slope` dP_kk/dλ (else NaN).
    fn point(&self, x: [f64; 2], slope: bool) -> Result<(UniaxialPoint, f64)> {
        let state = self.evaluate(x, slope)?;
        let point = UniaxialPoint {
            lambda: self.lambda,
            stress: state.nominal,
            // σ = J⁻¹ P Fᵀ on the diagonal: σ_kk = P_kk λ / (λ x₀ x₁).
            cauchy: state.nominal / (x[0] * x[1]),
            gamma: state.gamma,
            fibre_stretch: state.fibre_stretch,
            lateral: x,
        };
        let slope = if slope {
            schur_slope(&state.hessian, self.axis, self.lat)
        } else {
            f64::NAN
        };
        Ok((point, slope))
    }

    /// The error of a lateral solve that failed, saying why.
    fn failure(&self, reason: String) -> Error {
        Error::NoSolution {
            equation: format!(
                "lateral equilibrium of the nearly incompressible test {} the fibres at lambda = {}",
                self.direction.name(),
                shortest(self.lambda)
            ),
            reason,
        }
    }
}

/// The 2 × 2 block of the diagonal Hessian on the lateral axes `lat`.
fn lateral_block(h: &[[f64; 3]; 3], lat: [usize; 2]) -> [[f64; 2]; 2] {
    [
        [h[lat[0]][lat[0]], h[lat[0]][lat[1]]],
        [h[lat[1]][lat[0]], h[lat[1]][lat[1]]],
    ]
}

/// dP_kk/dλ with the lateral stretches in equilibrium: H_kk − H_kℓ H_ℓℓ⁻¹ H_ℓk.
fn schur_slope(h: &[[f64; 3]; 3], axis: usize, lat: [usize; 2]) -> f64 {
    let jac = lateral_block(h, lat);
    let det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
    let (c0, c1) = (h[lat[0]][axis], h[lat[1]][axis]);
    // H_ℓℓ⁻¹ H_ℓk by Cramer's rule.
    let y0 = (jac[1][1] * c0 - jac[0][1] * c1) / det;
    let y1 = (-jac[1][0] * c0 + jac[0][0] * c1) / det;
    h[axis][axis] - h[axis][lat[0]] * y0 - h[axis][lat[1]] * y1
}
