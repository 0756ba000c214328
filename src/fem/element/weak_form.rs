//! The element residual and tangent of the mixed u–p weak form, for any
//! [`ReferenceElement`]: what the assembly evaluates cell by cell.

use super::reference::{zeroed, PointGeometry, ReferenceElement};
use crate::fem::kinematics::{jacobian, jacobian_gradient, jacobian_hessian};
use crate::fem::material::{AxiF, AxisymmetricMaterial};
use crate::volumetric::Volumetric;
use nalgebra::{SMatrix, SVector};
use std::ops::AddAssign;

/// Element vector (`ND` dofs).
pub type ElementVector<const ND: usize> = SVector<f64, ND>;
/// Element matrix (column-major, as nalgebra stores it).
pub type ElementMatrix<const ND: usize> = SMatrix<f64, ND, ND>;

/// K[0..NU, 0..NU] += Bᵀ D B (`K` of any size R ≥ NU = 2 `NN`), column by column. Column j of B
/// (node b = j/2, its u_r or u_z) gives c = D B_j (five numbers), and column j of Bᵀ D B is
///
/// Bᵀ c = (∂N_a/∂r c₀ + ∂N_a/∂z c₁ + N_a/r c₄,  ∂N_a/∂r c₂ + ∂N_a/∂z c₃)  for every node a,
///
/// written over the interleaved rows (u_r⁰, u_z⁰, u_r¹, …) as one expression
/// `dr2 · (c₀ | c₂) + dz2 · (c₁ | c₃) + nr2 · c₄` with `dr2` = (∂N₀/∂r, ∂N₀/∂r, ∂N₁/∂r, …),
/// `dz2` likewise and `nr2` = (N₀/r, 0, N₁/r, 0, …): a loop over contiguous rows, which
/// vectorises (a u_z row adds nr2 · c₄ = 0, so its value is the same as without that term).
/// With `lower`, only the node blocks a ≥ b (for a symmetric D; see [`mirror_node_blocks`]).
#[inline(always)]
fn add_btdb<const NN: usize, const NU: usize, const R: usize>(
    k: &mut SMatrix<f64, R, R>,
    g: &PointGeometry<NN>,
    d: &SMatrix<f64, 5, 5>,
    lower: bool,
) {
    let dr2: [f64; NU] = std::array::from_fn(|i| g.dn_dr[i / 2]);
    let dz2: [f64; NU] = std::array::from_fn(|i| g.dn_dz[i / 2]);
    let nr2: [f64; NU] = std::array::from_fn(|i| if i % 2 == 0 { g.n_over_r[i / 2] } else { 0.0 });
    for j in 0..NU {
        let b = j / 2;
        let (dr, dz, nr) = (g.dn_dr[b], g.dn_dz[b], g.n_over_r[b]);
        let c: [f64; 5] = if j % 2 == 0 {
            std::array::from_fn(|i| d[(i, 0)] * dr + d[(i, 1)] * dz + d[(i, 4)] * nr)
        } else {
            std::array::from_fn(|i| d[(i, 2)] * dr + d[(i, 3)] * dz)
        };
        let even: [f64; NU] = std::array::from_fn(|i| if i % 2 == 0 { c[0] } else { c[2] });
        let odd: [f64; NU] = std::array::from_fn(|i| if i % 2 == 0 { c[1] } else { c[3] });
        let first = if lower { 2 * b } else { 0 };
        let column = &mut k.as_mut_slice()[j * R..j * R + NU];
        for i in first..NU {
            column[i] += dr2[i] * even[i] + dz2[i] * odd[i] + nr2[i] * c[4];
        }
    }
}

/// Completes a matrix of 2 × 2 node blocks of which [`add_btdb`] filled the blocks a ≥ b:
/// block (b, a) = block (a, b)ᵀ.
fn mirror_node_blocks<const NU: usize>(k: &mut SMatrix<f64, NU, NU>) {
    for nb in 0..NU / 2 {
        for na in nb + 1..NU / 2 {
            for i in 0..2 {
                for j in 0..2 {
                    k[(2 * nb + i, 2 * na + j)] = k[(2 * na + j, 2 * nb + i)];
                }
            }
        }
    }
}

/// (J − J̃(p), 1/U″(J̃)) at J and the pressure p: (J − 1, 0) for the exact constraint
/// (`volumetric` None).
#[inline(always)]
fn constraint(volumetric: Option<&Volumetric>, j: f64, p: f64) -> crate::Result<(f64, f64)> {
    match volumetric {
        None => Ok((j - 1.0, 0.0)),
        Some(v) => {
            let (jt, compliance) = v.dilatation(p)?;
            Ok((j - jt, compliance))
        }
    }
}

/// One quadrature point's share of the residual, added to `residual`:
/// R_u += Bᵀ (P − p ∂J/∂F) dV and R_p += −M c(J, p) dV (c of [`constraint`]), its stress scale
/// noted in `scale`. Returns ∂J/∂F and the constraint's compliance, which the tangent reuses.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn add_point_residual<const NN: usize, const NU: usize, const NP: usize, const ND: usize>(
    g: &PointGeometry<NN>,
    m: &SVector<f64, NP>,
    f: &AxiF,
    pq: f64,
    pk: &AxiF,
    volumetric: Option<&Volumetric>,
    residual: &mut ElementVector<ND>,
    scale: &mut ElementScale,
) -> crate::Result<(AxiF, f64)> {
    let dj = jacobian_gradient(f);
    let s = pk - dj * pq;
    scale.stress = scale.stress.max(pk.amax()).max(s.amax());
    let ru = g.transpose_mul::<NU>(&s, g.dv);
    residual.fixed_rows_mut::<NU>(0).add_assign(&ru);
    let (c, compliance) = constraint(volumetric, jacobian(f), pq)?;
    let rp = m * (-c * g.dv);
    residual.fixed_rows_mut::<NP>(NU).add_assign(&rp);
    Ok((dj, compliance))
}

/// What one element evaluation returns besides its vectors: the stress scale max |P_ij|, |p ∂J/∂F_ij| \[kPa\].
#[derive(Debug, Clone, Copy, Default)]
pub struct ElementScale {
    /// Largest stress magnitude met at the element's quadrature points.
    pub stress: f64,
}

impl<const NN: usize, const NU: usize, const NP: usize, const ND: usize, const NQ: usize>
    ReferenceElement<NN, NU, NP, ND, NQ>
{
    /// Residual and (optionally) tangent of one element, added to `residual` and `tangent`
    /// (which the caller zeroes: [`zeroed`]).
    ///
    /// Weak form (Π(u, p) = ∫ [Ψ(F) − p (J − 1)] dV, dV = 2π r dr dz, q and δu test functions):
    ///
    /// R_u(δu) = ∫ (P(F) − p ∂J/∂F) : δF dV,      δF = B δu,
    /// R_p(q)  = −∫ q (J − 1) dV,
    ///
    /// and its linearisation (A = ∂P/∂F, possibly non-symmetric; H = ∂²J/∂F∂F):
    ///
    /// K_uu = ∫ Bᵀ (A − p H) B dV,   K_up = −∫ Bᵀ ∂J/∂F M dV,   K_pu = −∫ M (∂J/∂F)ᵀ B dV,   K_pp = 0.
    ///
    /// For Q1/P0 the only M is 1 on the cell, so R_p = −∫_e (J − 1) dV: incompressibility in
    /// the mean per cell. `geometry` is the cell's mapped geometry ([`Self::cell_geometry`]).
    ///
    /// Nearly incompressible (`volumetric` = U(J), strictly convex): the perturbed Lagrangian
    /// with the Legendre transform Φ(p) = sup_J [−p (J − 1) − U(J)] of U,
    ///
    /// Π(u, p) = ∫ [Ψ(F) − p (J − 1) − Φ(p)] dV,
    ///
    /// whose stationarity in p, J = J̃(p) := (U′)⁻¹(−p), gives back ∫ [Ψ + U(J)] dV. The
    /// displacement equations are those of the exact constraint; the pressure equation and block
    /// become ([`crate::volumetric::Volumetric::dilatation`]: Φ′ = 1 − J̃, Φ″ = 1/U″(J̃))
    ///
    /// R_p(q) = −∫ q [J − J̃(p)] dV,   K_pp = −∫ M Mᵀ / U″(J̃(p)) dV,
    ///
    /// for U = (κ/2)(J − 1)²: R_p = −∫ q [(J − 1) + p/κ] dV, K_pp = −∫ M Mᵀ/κ dV, and κ = ∞ is the
    /// exact constraint. U is evaluated at the interpolated pressure, never at the pointwise J of
    /// the displacement (which the mixed element keeps close to J̃ only weakly): a stiff,
    /// non-quadratic U (4C's J^(−2κ)) then stays as well conditioned as the quadratic one.
    ///
    /// Compiled twice, for the baseline target and with AVX2, and chosen at run time
    /// (`is_x86_feature_detected!`): the same operations in the same order, so the same numbers;
    /// AVX2 vectorises the loops over an element's rows ([`add_btdb`]).
    #[allow(clippy::too_many_arguments)]
    pub fn residual_tangent<M: AxisymmetricMaterial + ?Sized>(
        &self,
        geometry: &[PointGeometry<NN>; NQ],
        u: &SVector<f64, NU>,
        p: &SVector<f64, NP>,
        material: &M,
        volumetric: Option<&Volumetric>,
        residual: &mut ElementVector<ND>,
        tangent: Option<&mut ElementMatrix<ND>>,
    ) -> crate::Result<ElementScale> {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2 (checked just above).
            return unsafe {
                self.residual_tangent_avx2(geometry, u, p, material, volumetric, residual, tangent)
            };
        }
        self.residual_tangent_plain(geometry, u, p, material, volumetric, residual, tangent)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[allow(clippy::too_many_arguments)]
    fn residual_tangent_avx2<M: AxisymmetricMaterial + ?Sized>(
        &self,
        geometry: &[PointGeometry<NN>; NQ],
        u: &SVector<f64, NU>,
        p: &SVector<f64, NP>,
        material: &M,
        volumetric: Option<&Volumetric>,
        residual: &mut ElementVector<ND>,
        tangent: Option<&mut ElementMatrix<ND>>,
    ) -> crate::Result<ElementScale> {
        self.residual_tangent_plain(geometry, u, p, material, volumetric, residual, tangent)
    }

    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn residual_tangent_plain<M: AxisymmetricMaterial + ?Sized>(
        &self,
        geometry: &[PointGeometry<NN>; NQ],
        u: &SVector<f64, NU>,
        p: &SVector<f64, NP>,
        material: &M,
        volumetric: Option<&Volumetric>,
        residual: &mut ElementVector<ND>,
        tangent: Option<&mut ElementMatrix<ND>>,
    ) -> crate::Result<ElementScale> {
        match tangent {
            None => self.add_residual(geometry, u, p, material, volumetric, residual),
            Some(k) => self.add_residual_tangent(geometry, u, p, material, volumetric, residual, k),
        }
    }

    /// The residual alone (R_u, R_p of [`Self::residual_tangent`]), added to `residual`.
    #[inline(always)]
    fn add_residual<M: AxisymmetricMaterial + ?Sized>(
        &self,
        geometry: &[PointGeometry<NN>; NQ],
        u: &SVector<f64, NU>,
        p: &SVector<f64, NP>,
        material: &M,
        volumetric: Option<&Volumetric>,
        residual: &mut ElementVector<ND>,
    ) -> crate::Result<ElementScale> {
        let mut scale = ElementScale::default();
        for (g, m) in geometry.iter().zip(&self.m) {
            let f = g.deformation(u);
            let pq = m.dot(p);
            let pk = material.stress_at(&f, [g.r, g.z])?;
            add_point_residual::<NN, NU, NP, ND>(
                g, m, &f, pq, &pk, volumetric, residual, &mut scale,
            )?;
        }
        Ok(scale)
    }

    /// The residual and the tangent K of [`Self::residual_tangent`], added to `residual` and `k`.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn add_residual_tangent<M: AxisymmetricMaterial + ?Sized>(
        &self,
        geometry: &[PointGeometry<NN>; NQ],
        u: &SVector<f64, NU>,
        p: &SVector<f64, NP>,
        material: &M,
        volumetric: Option<&Volumetric>,
        residual: &mut ElementVector<ND>,
        k: &mut ElementMatrix<ND>,
    ) -> crate::Result<ElementScale> {
        let mut scale = ElementScale::default();
        // The node blocks below the diagonal of the points with a symmetric D, if any.
        let mut kuu_lower = None;
        for (g, m) in geometry.iter().zip(&self.m) {
            let f = g.deformation(u);
            let pq = m.dot(p);
            let (pk, a) = material.stress_tangent_at(&f, [g.r, g.z])?;
            let (dj, compliance) = add_point_residual::<NN, NU, NP, ND>(
                g, m, &f, pq, &pk, volumetric, residual, &mut scale,
            )?;
            if volumetric.is_some() {
                k.fixed_view_mut::<NP, NP>(NU, NU)
                    .add_assign(&(m * m.transpose() * (-compliance * g.dv)));
            }
            // K_uu += Bᵀ D B with D = (A − p H) dV; for a symmetric D (a hyperelastic
            // material) only the node blocks below the diagonal, mirrored at the end.
            let d = (a - jacobian_hessian(&f) * pq) * g.dv;
            if (1..5).all(|i| (0..i).all(|j| d[(i, j)] == d[(j, i)])) {
                let lower = kuu_lower.get_or_insert_with(zeroed::<NU, NU>);
                add_btdb::<NN, NU, NU>(lower, g, &d, true);
            } else {
                add_btdb::<NN, NU, ND>(k, g, &d, false);
            }
            // K_up = −Bᵀ ∂J/∂F Mᵀ dV, K_pu = −M (∂J/∂F)ᵀ B dV.
            let bdj = g.transpose_mul::<NU>(&dj, -g.dv);
            let kup = bdj * m.transpose();
            k.fixed_view_mut::<NU, NP>(0, NU).add_assign(&kup);
        }
        // K_pu = K_upᵀ, copied once rather than accumulated point by point.
        for i in 0..NP {
            for j in 0..NU {
                k[(NU + i, j)] = k[(j, NU + i)];
            }
        }
        if let Some(mut lower) = kuu_lower {
            mirror_node_blocks(&mut lower);
            k.fixed_view_mut::<NU, NU>(0, 0).add_assign(&lower);
        }
        Ok(scale)
    }
}
