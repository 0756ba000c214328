//! Homogeneous (0D) states beyond uniaxial tension, with the faces normal to e₃ traction free:
//! simple shear and planar biaxial stretch.
//!
//! The in-plane part of F is prescribed, F = [[a, b, 0], [c, d, 0], [0, 0, λ₃]]:
//!
//! - simple shear: a = d = 1, b = k (the amount of shear), c = 0, F = I + k e₁⊗e₂;
//! - planar biaxial: F = diag(λ₁, λ₂, λ₃).
//!
//! Exactly incompressible (the chapter's constraint): λ₃ = 1/(ad − bc) and the pressure follows
//! from σ₃₃ = 0, p = (∂Ψ/∂F Fᵀ)₃₃, so σ = ∂Ψ/∂F Fᵀ − p I and P = ∂Ψ/∂F − p F⁻ᵀ. Nearly
//! incompressible (a volumetric energy U(J)): P = ∂Ψ/∂F + U′(J) cof F, and λ₃ solves P₃₃ = 0 by
//! safeguarded Newton with dP₃₃/dλ₃ = ∂²Ψ/∂F₃₃² + U″(J) (cof F)₃₃² (cof F)₃₃ = ad − bc does not
//! depend on λ₃); σ = J⁻¹ P Fᵀ.
//!
//! The fibre direction m lies in the plane: m = (cos θ, sin θ, 0).

use crate::energy::StrainEnergy;
use crate::invariants::{Kinematics, FULL};
use crate::material::Muscle;
use crate::response::Order;
use crate::roots::newton_bisection;
use crate::volumetric::Volumetric;
use crate::{Error, Result};
use nalgebra::{Matrix2, Matrix3, Vector3};

/// A homogeneous state with traction-free faces normal to e₃.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanarState {
    /// The deformation gradient, λ₃ = F₃₃ included.
    pub f: Matrix3<f64>,
    /// Activation γ (or ω) [-].
    pub gamma: f64,
    /// Fibre stretch λ_f = |F m| [-].
    pub fibre_stretch: f64,
    /// First Piola–Kirchhoff (nominal) stress, pressure or volumetric term included \[kPa\].
    pub nominal: Matrix3<f64>,
    /// Cauchy stress σ = J⁻¹ P Fᵀ \[kPa\] (σ₃₃ = 0 to rounding).
    pub cauchy: Matrix3<f64>,
}

/// The in-plane fibre direction at angle `degrees` to e₁.
pub fn in_plane_fibre(degrees: f64) -> Vector3<f64> {
    let t = degrees.to_radians();
    Vector3::new(t.cos(), t.sin(), 0.0)
}

/// F with in-plane part `g` and F₃₃ = `lambda_3`.
fn deformation(g: &Matrix2<f64>, lambda_3: f64) -> Matrix3<f64> {
    Matrix3::new(
        g[(0, 0)],
        g[(0, 1)],
        0.0,
        g[(1, 0)],
        g[(1, 1)],
        0.0,
        0.0,
        0.0,
        lambda_3,
    )
}

/// ∂Ψ/∂F (a 3×3 matrix), γ and the fibre stretch of `muscle` at F, and ∂²Ψ/∂F₃₃² if `tangent`.
fn respond<E: StrainEnergy>(
    muscle: &Muscle<E>,
    f: &Matrix3<f64>,
    m: &Vector3<f64>,
    tangent: bool,
) -> Result<(Matrix3<f64>, f64, f64, f64)> {
    let kin = Kinematics::new(f, m)?;
    let order = if tangent {
        Order::Tangent
    } else {
        Order::Stress
    };
    let r = muscle.respond(&kin, order, &FULL)?;
    let p = r.stress.unwrap_or_default();
    let dpsi = Matrix3::from_row_slice(p.as_slice());
    let a33 = r.tangent.map_or(0.0, |t| t[(8, 8)]);
    Ok((dpsi, r.gamma, r.fibre_stretch, a33))
}

/// The state of `muscle` with the in-plane deformation `g` and the fibre `m` (in the plane),
/// exactly incompressible (`volumetric` = `None`) or with the volumetric energy.
pub fn planar<E: StrainEnergy>(
    muscle: &Muscle<E>,
    volumetric: Option<&Volumetric>,
    g: &Matrix2<f64>,
    m: &Vector3<f64>,
) -> Result<PlanarState> {
    let det2 = g.determinant();
    if !(det2.is_finite() && det2 > 0.0) {
        return Err(Error::NonPositiveJacobian {
            det: det2,
            f: deformation(g, 1.0).into(),
        });
    }
    match volumetric {
        None => planar_exact(muscle, g, m, det2),
        Some(v) => planar_near(muscle, v, g, m, det2),
    }
}

/// [`planar`] exactly incompressible: λ₃ = 1/det₂, the pressure from σ₃₃ = 0.
fn planar_exact<E: StrainEnergy>(
    muscle: &Muscle<E>,
    g: &Matrix2<f64>,
    m: &Vector3<f64>,
    det2: f64,
) -> Result<PlanarState> {
    let f = deformation(g, 1.0 / det2);
    let (dpsi, gamma, fibre_stretch, _) = respond(muscle, &f, m, false)?;
    let sigma_hat = dpsi * f.transpose();
    let p = sigma_hat[(2, 2)];
    let cauchy = sigma_hat - Matrix3::identity() * p;
    let f_inv_t = f
        .try_inverse()
        .ok_or(Error::NonPositiveJacobian {
            det: 0.0,
            f: f.into(),
        })?
        .transpose();
    Ok(PlanarState {
        f,
        gamma,
        fibre_stretch,
        nominal: dpsi - f_inv_t * p,
        cauchy,
    })
}

/// [`planar`] with the volumetric energy `v`: λ₃ from zero traction P₃₃ = 0.
fn planar_near<E: StrainEnergy>(
    muscle: &Muscle<E>,
    v: &Volumetric,
    g: &Matrix2<f64>,
    m: &Vector3<f64>,
    det2: f64,
) -> Result<PlanarState> {
    // P₃₃(λ₃) = ∂Ψ/∂F₃₃ + U′(J) det₂ with J = det₂ λ₃, increasing in λ₃.
    let residual = |l3: f64| -> (f64, f64) {
        let f = deformation(g, l3);
        match (respond(muscle, &f, m, true), v.derivatives(det2 * l3)) {
            (Ok((dpsi, _, _, a33)), Ok([_, du, ddu])) => {
                (dpsi[(2, 2)] + du * det2, a33 + ddu * det2 * det2)
            }
            _ => (f64::NAN, f64::NAN),
        }
    };
    let start = 1.0 / det2;
    let (mut lo, mut hi) = (start, start);
    for _ in 0..60 {
        if residual(lo).0 < 0.0 {
            break;
        }
        lo *= 0.8;
    }
    for _ in 0..60 {
        if residual(hi).0 > 0.0 {
            break;
        }
        hi *= 1.25;
    }
    let l3 = newton_bisection(residual, lo, hi, 1e-15).map_err(|reason| Error::NoSolution {
        equation: format!(
            "zero traction on the faces normal to e3 (P33 = 0) at det F_plane = {det2}"
        ),
        reason,
    })?;
    let f = deformation(g, l3);
    let (dpsi, gamma, fibre_stretch, _) = respond(muscle, &f, m, false)?;
    let j = f.determinant();
    let [_, du, _] = v.derivatives(j)?;
    let cof = f
        .try_inverse()
        .ok_or(Error::NonPositiveJacobian {
            det: j,
            f: f.into(),
        })?
        .transpose()
        * j;
    let nominal = dpsi + cof * du;
    Ok(PlanarState {
        f,
        gamma,
        fibre_stretch,
        nominal,
        cauchy: nominal * f.transpose() / j,
    })
}

/// Simple shear F = I + k e₁⊗e₂ with the fibre in the shear plane at `angle` degrees to e₁.
pub fn simple_shear<E: StrainEnergy>(
    muscle: &Muscle<E>,
    volumetric: Option<&Volumetric>,
    k: f64,
    angle: f64,
) -> Result<PlanarState> {
    let g = Matrix2::new(1.0, k, 0.0, 1.0);
    planar(muscle, volumetric, &g, &in_plane_fibre(angle))
}

/// Planar biaxial stretch F = diag(λ₁, λ₂, λ₃), λ₁ along the fibres (m = e₁), λ₂ across.
pub fn planar_biaxial<E: StrainEnergy>(
    muscle: &Muscle<E>,
    volumetric: Option<&Volumetric>,
    lambda_1: f64,
    lambda_2: f64,
) -> Result<PlanarState> {
    crate::energy::positive("lambda1", lambda_1)?;
    crate::energy::positive("lambda2", lambda_2)?;
    let g = Matrix2::new(lambda_1, 0.0, 0.0, lambda_2);
    planar(muscle, volumetric, &g, &Vector3::x())
}
