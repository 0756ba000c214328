//! Derivative routes at a material point, as [`AxisymmetricMaterial`] wrappers the FE solver can
//! run unchanged.
//!
//! - The fast route is [`Muscle`]'s own implementation (dual numbers over the invariants only).
//! - [`OracleRoute`]: dual numbers over F's nine entries and γ ([`crate::oracle::full_response`],
//!   a 10×10 hyper-dual Hessian per point) plus the activation law's slopes: the slow,
//!   independent reference. Trades ≈ 50× the time per point for nothing but independence.
//! - [`FiniteDifferenceTangent`]: the stress of any material, its tangent by central differences
//!   of that stress. Trades 10 stress evaluations per tangent and ≈ 1e-10 relative accuracy for
//!   not needing second derivatives.

use crate::active::{Coupling, FrozenTangent};
use crate::energy::StrainEnergy;
use crate::fem::{AxiF, AxisymmetricMaterial};
use crate::invariants::{axial_fibre, axisymmetric_f, Kinematics};
use crate::oracle::full_response;
use crate::{Error, Muscle, Result};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Row-major indices in F's nine entries of the axisymmetric entries [F_rr, F_rz, F_zr, F_zz, F_θθ]
/// with (r, θ, z) = (0, 1, 2).
const AXI_IN_FULL: [usize; 5] = [0, 2, 6, 8, 4];

/// The oracle route for a muscle: Ŵ's derivatives by one 10-variable hyper-dual Hessian over F
/// and γ, coupled to the law γ = g(λ_f) by the chain rule written out in full 3×3 form:
///
/// - frozen: P = ∂Ŵ/∂F; exact tangent ∂²Ŵ/∂F² + (∂P/∂γ) ⊗ g′ ∂λ_f/∂F with ∂λ_f/∂F = F M / λ_f
///   (M = m ⊗ m); the symmetric variant drops the second term;
/// - consistent: P = ∂Ŵ/∂F + Ŵ_γ g′ ∂λ_f/∂F; tangent ∂²Ŵ/∂F² + (∂P/∂γ ⊗ g′∂λ_f/∂F +
///   transpose) + (Ŵ_γγ g′² + Ŵ_γ g″) ∂λ_f/∂F ⊗ ∂λ_f/∂F + Ŵ_γ g′ ∂²λ_f/∂F², with
///   ∂²λ_f/∂F_iJ∂F_kL = δ_ik M_JL / λ_f − (F m)_i m_J (F m)_k m_L / λ_f³.
///
/// Stress \[kPa\], tangent \[kPa\]; the same quantities as the fast route, computed independently of
/// the invariant calculus and the active-strain map.
#[derive(Debug, Clone, Copy)]
pub struct OracleRoute<'a, E> {
    muscle: &'a Muscle<E>,
}

impl<'a, E: StrainEnergy> OracleRoute<'a, E> {
    /// The oracle route for `muscle` (its energy, law, damage and coupling).
    pub fn new(muscle: &'a Muscle<E>) -> Self {
        Self { muscle }
    }

    /// Full 3×3 stress (row-major 9-vector) and, if `tangent`, the 9×9 tangent at `f`.
    pub fn full(
        &self,
        f: &Matrix3<f64>,
        m: &Vector3<f64>,
        tangent: bool,
    ) -> Result<(SVector<f64, 9>, Option<SMatrix<f64, 9, 9>>)> {
        let fm = f * m;
        let lambda = fm.norm();
        let law = self.muscle.activation(lambda)?;
        let r = full_response(self.muscle.energy(), f, m, law.gamma)?;
        // ∂λ_f/∂F_iJ = (F m)_i m_J / λ_f.
        let dl = SVector::<f64, 9>::from_fn(|k, _| fm[k / 3] * m[k % 3] / lambda);
        let g1 = law.slope;
        let coupling = self.muscle.coupling();
        let mut p = r.stress;
        if coupling == Coupling::Consistent {
            p += dl * (r.denergy_dgamma * g1);
        }
        if !tangent {
            return Ok((p, None));
        }
        let mut k = r.tangent;
        match coupling {
            Coupling::Frozen(FrozenTangent::Symmetric) => {}
            Coupling::Frozen(FrozenTangent::Exact) => {
                k += r.dstress_dgamma * (dl.transpose() * g1);
            }
            Coupling::Consistent => {
                let cross = r.dstress_dgamma * (dl.transpose() * g1);
                k += cross + cross.transpose();
                k += dl
                    * dl.transpose()
                    * (r.d2energy_dgamma2 * g1 * g1 + r.denergy_dgamma * law.curvature);
                let w = r.denergy_dgamma * g1;
                for a in 0..9 {
                    for b in 0..9 {
                        let (i, jj, kk, l) = (a / 3, a % 3, b / 3, b % 3);
                        let delta = if i == kk { m[jj] * m[l] / lambda } else { 0.0 };
                        let d2 = delta - fm[i] * m[jj] * fm[kk] * m[l] / lambda.powi(3);
                        k[(a, b)] += w * d2;
                    }
                }
            }
        }
        Ok((p, Some(k)))
    }

    fn axisymmetric(
        &self,
        f: &AxiF,
        tangent: bool,
    ) -> Result<(SVector<f64, 5>, SMatrix<f64, 5, 5>)> {
        let full = axisymmetric_f(f);
        // Rejects det F ≤ 0 with the offending F, as the fast route does.
        Kinematics::new(&full, &axial_fibre())?;
        let (p9, k9) = self.full(&full, &axial_fibre(), tangent)?;
        let p = SVector::<f64, 5>::from_fn(|a, _| p9[AXI_IN_FULL[a]]);
        let k = match k9 {
            Some(k9) => SMatrix::<f64, 5, 5>::from_fn(|a, b| k9[(AXI_IN_FULL[a], AXI_IN_FULL[b])]),
            None => SMatrix::zeros(),
        };
        Ok((p, k))
    }
}

impl<E: StrainEnergy + Sync> AxisymmetricMaterial for OracleRoute<'_, E> {
    fn stress(&self, f: &AxiF) -> Result<SVector<f64, 5>> {
        Ok(self.axisymmetric(f, false)?.0)
    }

    fn stress_tangent(&self, f: &AxiF) -> Result<(SVector<f64, 5>, SMatrix<f64, 5, 5>)> {
        self.axisymmetric(f, true)
    }

    fn point_fields(&self, f: &AxiF) -> Result<(f64, f64)> {
        self.muscle.point_fields(f)
    }
}

/// Any material's stress with its tangent by central differences of that stress:
/// ∂P/∂F_j ≈ (P(F + h_j e_j) − P(F − h_j e_j)) / (2 h_j), h_j = `step` · max(1, |F_j|).
///
/// Costs 10 stress evaluations per tangent (plus one for P). Truncation error O(h²) and
/// round-off O(ε |P| / h): with h = 10⁻⁵ the tangent is good to ≈ 10⁻⁹–10⁻¹⁰ relative.
#[derive(Debug, Clone, Copy)]
pub struct FiniteDifferenceTangent<'a, M: ?Sized> {
    inner: &'a M,
    step: f64,
}

impl<'a, M: AxisymmetricMaterial + ?Sized> FiniteDifferenceTangent<'a, M> {
    /// Central differences of `inner`'s stress with relative step `step` (finite, in (0, 0.1]).
    pub fn new(inner: &'a M, step: f64) -> Result<Self> {
        if !(step.is_finite() && step > 0.0 && step <= 0.1) {
            return Err(Error::InvalidParameter {
                name: "step",
                value: step,
                rule: "finite-difference step must be finite and in (0, 0.1]",
            });
        }
        Ok(Self { inner, step })
    }

    /// The relative step h.
    pub fn step(&self) -> f64 {
        self.step
    }
}

impl<M: AxisymmetricMaterial + ?Sized> AxisymmetricMaterial for FiniteDifferenceTangent<'_, M> {
    fn stress(&self, f: &AxiF) -> Result<SVector<f64, 5>> {
        self.inner.stress(f)
    }

    fn stress_tangent(&self, f: &AxiF) -> Result<(SVector<f64, 5>, SMatrix<f64, 5, 5>)> {
        let p = self.inner.stress(f)?;
        let mut k = SMatrix::<f64, 5, 5>::zeros();
        for j in 0..5 {
            let h = self.step * f[j].abs().max(1.0);
            let (mut fp, mut fm) = (*f, *f);
            fp[j] += h;
            fm[j] -= h;
            let dp = self.inner.stress(&fp)? - self.inner.stress(&fm)?;
            k.set_column(j, &(dp / (fp[j] - fm[j])));
        }
        Ok((p, k))
    }

    fn point_fields(&self, f: &AxiF) -> Result<(f64, f64)> {
        self.inner.point_fields(f)
    }
}
