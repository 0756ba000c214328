//! Material stability: strong ellipticity of an incompressible material and the slope of the
//! uniaxial curve.
//!
//! Strong ellipticity (Legendre–Hadamard) under the constraint det F = 1: for every unit reference
//! normal N and every unit direction a tangent to the constraint, a ⊥ n with n = F⁻ᵀN,
//!
//! a · Q(N) a > 0,  Q_ik(N) = A_iJkL N_J N_L,  A = ∂P/∂F.
//!
//! The pressure term −p F⁻ᵀ contributes p (n·a)² = 0 on a ⊥ n, so the tangent of Ψ alone decides.
//! Only the symmetric part of Q enters the quadratic form, so the same check serves the frozen
//! model's non-symmetric tangent. N is sampled on a Fibonacci half-sphere (Q(−N) = Q(N)); for
//! each N the smallest eigenvalue of the 2×2 restriction of Q to the plane ⊥ n is exact.

use crate::energy::StrainEnergy;
use crate::invariants::{axial_fibre, axisymmetric_f, Kinematics, FULL};
use crate::material::Muscle;
use crate::response::Order;
use crate::uniaxial::{fibre_kinematics, nominal_along, slope_along};
use crate::{Error, Result};
use nalgebra::{Matrix2, Matrix3, SMatrix, SVector, Vector3};

/// The least value of a·Q(N)a over the sampled normals.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ellipticity {
    /// min a·Q(N)a \[kPa\].
    pub least: f64,
    /// The same divided by the Frobenius norm of the tangent [-]: negative means not elliptic.
    pub relative: f64,
    /// The reference normal N where it is least.
    pub normal: Vector3<f64>,
    /// The direction a where it is least.
    pub direction: Vector3<f64>,
}

impl Ellipticity {
    /// Strongly elliptic up to a relative tolerance of 1e-12.
    pub fn holds(&self) -> bool {
        self.relative > -1e-12
    }
}

/// Unit vectors on the half-sphere z ≥ 0, Fibonacci lattice.
fn half_sphere(samples: usize) -> impl Iterator<Item = Vector3<f64>> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..samples).map(move |i| {
        let z = (i as f64 + 0.5) / samples as f64;
        let r = (1.0 - z * z).sqrt();
        let phi = golden * i as f64;
        Vector3::new(r * phi.cos(), r * phi.sin(), z)
    })
}

/// Two unit vectors spanning the plane orthogonal to the unit vector `n`.
fn plane_basis(n: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let helper = if n.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let e1 = n.cross(&helper).normalize();
    (e1, n.cross(&e1))
}

/// Strong ellipticity of the tangent A = ∂P/∂F (9×9, entries of F row by row) at F, over
/// `samples` reference normals.
pub fn strong_ellipticity(
    tangent: &SMatrix<f64, 9, 9>,
    f: &Matrix3<f64>,
    samples: usize,
) -> Result<Ellipticity> {
    let f_inv_t = f
        .try_inverse()
        .ok_or(Error::NonPositiveJacobian {
            det: f.determinant(),
            f: f.transpose().into(),
        })?
        .transpose();
    let scale = tangent.norm().max(f64::MIN_POSITIVE);
    let mut best = Ellipticity {
        least: f64::INFINITY,
        relative: f64::INFINITY,
        normal: Vector3::z(),
        direction: Vector3::x(),
    };
    for normal in half_sphere(samples.max(1)) {
        let q = Matrix3::from_fn(|i, k| {
            let mut s = 0.0;
            for jj in 0..3 {
                for l in 0..3 {
                    s += tangent[(3 * i + jj, 3 * k + l)] * normal[jj] * normal[l];
                }
            }
            s
        });
        let n = (f_inv_t * normal).normalize();
        let (e1, e2) = plane_basis(&n);
        let sym = |a: &Vector3<f64>, b: &Vector3<f64>| 0.5 * (a.dot(&(q * b)) + b.dot(&(q * a)));
        let m = Matrix2::new(sym(&e1, &e1), sym(&e1, &e2), sym(&e2, &e1), sym(&e2, &e2));
        let eig = m.symmetric_eigen();
        let (idx, least) = if eig.eigenvalues[0] <= eig.eigenvalues[1] {
            (0, eig.eigenvalues[0])
        } else {
            (1, eig.eigenvalues[1])
        };
        if least < best.least {
            let v = eig.eigenvectors.column(idx);
            best = Ellipticity {
                least,
                relative: least / scale,
                normal,
                direction: e1 * v[0] + e2 * v[1],
            };
        }
    }
    Ok(best)
}

/// Stability of one point of the uniaxial curve along the fibres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UniaxialStability {
    /// Stretch λ [-].
    pub lambda: f64,
    /// Nominal stress \[kPa\].
    pub stress: f64,
    /// Cauchy stress along the fibres σ₁₁ = J⁻¹ (P Fᵀ)₁₁ \[kPa\] (= λ P).
    pub cauchy: f64,
    /// dP/dλ \[kPa\] along the homogeneous path (exact, from the tangent).
    pub slope: f64,
    /// Strong ellipticity at the point.
    pub ellipticity: Ellipticity,
}

/// Slope and strong ellipticity of the homogeneous uniaxial state along the fibres at λ (fibres
/// along e₁, F = diag(λ, λ^-½, λ^-½)); the slope is [`crate::uniaxial`]'s exact dP/dλ.
pub fn along_fibres_stability<E: StrainEnergy>(
    muscle: &Muscle<E>,
    lambda: f64,
    samples: usize,
) -> Result<UniaxialStability> {
    let kin = fibre_kinematics(lambda)?;
    let f = kin.f;
    let r = muscle.respond(&kin, Order::Tangent, &FULL)?;
    let (p, k) = (r.stress.unwrap_or_default(), r.tangent.unwrap_or_default());
    Ok(UniaxialStability {
        lambda,
        stress: nominal_along(&p, lambda),
        // The lateral faces are traction free: p = ∂Ψ/∂F₂₂ F₂₂ with F₂₂ = λ^-½.
        cauchy: crate::uniaxial::cauchy_stress(&p, p[4] * lambda.sqrt().recip(), &f)?[(0, 0)],
        slope: slope_along(&p, &k, lambda),
        ellipticity: strong_ellipticity(&k, &f, samples)?,
    })
}

/// The largest stretch along the fibres (λ ≥ 1, uniaxial F = diag(λ, λ^-½, λ^-½)) at which the
/// response of `muscle` to the given order is representable in f64, found by bisection to
/// 1e-10 relative between 1 and 1e4 (≈ 47 halvings; at most 200). Beyond it the response is a typed
/// [`Error::NonFinite`] (exp overflow: the Hessian leaves f64 first, then the gradient, then
/// the energy), never inf or NaN.
pub fn representable_stretch<E: StrainEnergy>(muscle: &Muscle<E>, order: Order) -> Result<f64> {
    let ok = |l: f64| -> bool {
        fibre_kinematics(l)
            .and_then(|kin| muscle.respond(&kin, order, &FULL))
            .is_ok()
    };
    if !ok(1.0) {
        return Err(Error::NoSolution {
            equation: "representable stretch".into(),
            reason: "the response is not representable even at lambda = 1".into(),
        });
    }
    let (mut lo, mut hi) = (1.0, 1e4);
    if ok(hi) {
        return Ok(hi);
    }
    for _ in 0..200 {
        if hi - lo <= 1e-10 * lo {
            break;
        }
        let mid = 0.5 * (lo + hi);
        if ok(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(lo)
}

/// What the material says about the quadrature points of a state the FE solver could not
/// converge to: strong ellipticity at each point (with the 9×9 tangent of the coupled model) and
/// whether the body straddles a discontinuity of the activation law.
#[derive(Debug, Clone, PartialEq)]
pub struct FailureDiagnosis {
    /// Quadrature points examined.
    pub points: usize,
    /// Points where strong ellipticity fails.
    pub not_elliptic: usize,
    /// Least relative value of a·Q(N)a/‖A‖ over all points, and the fibre stretch there.
    pub least: (f64, f64),
    /// Range of fibre stretches over the points.
    pub fibre_stretch: (f64, f64),
    /// The law's discontinuity (see [`crate::active::Law::jump`]) and how many points lie at or below it.
    pub jump: Option<(f64, usize)>,
    /// Points where the material itself refused the state (e.g. exp overflow).
    pub refused: usize,
}

impl std::fmt::Display for FailureDiagnosis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "of {} quadrature points of the failed trial state, {} are not strongly elliptic (least a·Q(N)a/|A| = {:.3e} at fibre stretch {:.4}); fibre stretches span [{:.4}, {:.4}]",
            self.points, self.not_elliptic, self.least.0, self.least.1, self.fibre_stretch.0, self.fibre_stretch.1
        )?;
        if let Some((at, below)) = self.jump {
            if below > 0 && below < self.points {
                write!(f, "; {below} points lie at or below lambda_min = {at}, where the activation law jumps, so the energy Psi is discontinuous inside the body")?;
            } else if below == 0 && self.fibre_stretch.0 - at < 0.01 {
                write!(
                    f,
                    "; the smallest fibre stretch is {:.2e} above lambda_min = {at}, where the activation law jumps: the next stretch puts part of the body across a discontinuity of the energy Psi",
                    self.fibre_stretch.0 - at
                )?;
            }
        }
        if self.refused > 0 {
            write!(f, "; the material refused {} points", self.refused)?;
        }
        Ok(())
    }
}

/// Diagnoses the quadrature points (axisymmetric F entries [F_rr, F_rz, F_zr, F_zz, F_θθ], fibres
/// along z) of a failed FE trial state, with `samples` normals per point.
pub fn diagnose_axisymmetric<E: StrainEnergy>(
    muscle: &Muscle<E>,
    points: &[SVector<f64, 5>],
    samples: usize,
) -> FailureDiagnosis {
    let mut d = FailureDiagnosis {
        points: points.len(),
        not_elliptic: 0,
        least: (f64::INFINITY, f64::NAN),
        fibre_stretch: (f64::INFINITY, f64::NEG_INFINITY),
        jump: muscle.law().jump().map(|at| (at, 0)),
        refused: 0,
    };
    for f in points {
        let full = axisymmetric_f(f);
        let check = Kinematics::new(&full, &axial_fibre()).and_then(|kin| {
            let r = muscle.respond(&kin, Order::Tangent, &FULL)?;
            Ok((
                kin.fibre_stretch(),
                strong_ellipticity(&r.tangent.unwrap_or_default(), &full, samples)?,
            ))
        });
        let Ok((lambda, e)) = check else {
            d.refused += 1;
            continue;
        };
        d.fibre_stretch = (d.fibre_stretch.0.min(lambda), d.fibre_stretch.1.max(lambda));
        if !e.holds() {
            d.not_elliptic += 1;
        }
        if e.relative < d.least.0 {
            d.least = (e.relative, lambda);
        }
        if let Some((at, below)) = d.jump.as_mut() {
            if lambda <= *at {
                *below += 1;
            }
        }
    }
    d
}
