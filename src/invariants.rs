//! The invariants of C = FᵀF used by the energies, and their exact first and second derivatives
//! with respect to F, in closed form. This is the framework's half of "write the energy once":
//! the energy is differentiated (by dual numbers) only with respect to these five numbers.
//!
//! With B = F⁻¹ (so C⁻¹ = B Bᵀ), J = det F, M = m ⊗ m, and for a symmetric A the invariant
//! j_A = C⁻¹ : A (so tr C⁻¹ = j_I and C⁻¹ : M = j_M):
//!
//! | invariant | ∂/∂F_kL | ∂²/∂F_kL ∂F_iJ |
//! |---|---|---|
//! | tr C | 2 F_kL | 2 δ_ki δ_LJ |
//! | C : M | 2 (F M)_kL | 2 δ_ki M_LJ |
//! | C⁻¹ : A | −2 g_kL, g = Bᵀ A C⁻¹ | 2 [B_Jk g_iL + Q_ki C⁻¹_JL + g_kJ B_Li], Q = Bᵀ A B |
//! | det C | 2 J² B_Lk | J² (4 B_Ji B_Lk − 2 B_Li B_Jk) |
//!
//! The second-derivative term of a response, Σ_j w_j ∂²j/∂F², is linear in the weights w, and
//! the two C⁻¹ invariants combine into one j_A with A = w₃ I + w₄ M: [`Kinematics::curvature`]
//! evaluates that sum directly, only for the entries of F the problem has.

use crate::{Error, Result};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Which entries (k, L) of F a problem varies: all nine in 3D, five in axisymmetry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Entries<const N: usize> {
    /// (row, column) of each varied entry of F, in the order used by stress and tangent vectors.
    pub index: [(usize, usize); N],
}

/// All nine entries of F, row by row: (0,0), (0,1), …, (2,2).
pub const FULL: Entries<9> = Entries {
    index: [
        (0, 0),
        (0, 1),
        (0, 2),
        (1, 0),
        (1, 1),
        (1, 2),
        (2, 0),
        (2, 1),
        (2, 2),
    ],
};

/// Axisymmetric entries with coordinates ordered (r, θ, z) = (0, 1, 2) and fibres along z:
/// [F_rr, F_rz, F_zr, F_zz, F_θθ].
pub const AXISYMMETRIC: Entries<5> = Entries {
    index: [(0, 0), (0, 2), (2, 0), (2, 2), (1, 1)],
};

/// F with the quantities every derivative of the invariants needs, computed once per point.
#[derive(Debug, Clone)]
pub struct Kinematics {
    /// Deformation gradient F.
    pub f: Matrix3<f64>,
    /// Unit fibre direction m (reference configuration).
    pub m: Vector3<f64>,
    /// J = det F.
    pub det_f: f64,
    /// B = F⁻¹.
    b: Matrix3<f64>,
    /// C⁻¹ = B Bᵀ.
    c_inv: Matrix3<f64>,
    /// Bᵀ B = b⁻¹ (inverse left Cauchy–Green).
    b_t_b: Matrix3<f64>,
    /// F m.
    f_m: Vector3<f64>,
    /// Bᵀ m = F⁻ᵀ m.
    b_t_m: Vector3<f64>,
    /// C⁻¹ m.
    c_inv_m: Vector3<f64>,
    /// Bᵀ C⁻¹ = Bᵀ B Bᵀ (g of j_I).
    g_identity: Matrix3<f64>,
    /// [tr C, C:M, tr C⁻¹, C⁻¹:M, det C].
    pub invariants: [f64; 5],
    /// F and m do not couple θ with (r, z) (see [`Kinematics::new`]).
    axisymmetric: bool,
}

/// X Y for 3×3 matrices, by its nine dot products (no zero fill, fully unrolled).
#[inline(always)]
fn product(x: &Matrix3<f64>, y: &Matrix3<f64>) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| x[(i, 0)] * y[(0, j)] + x[(i, 1)] * y[(1, j)] + x[(i, 2)] * y[(2, j)])
}

/// X Y for block-diagonal 3×3 matrices (a (0, 2) block and the (1, 1) entry).
#[inline(always)]
fn block_product(x: &Matrix3<f64>, y: &Matrix3<f64>) -> Matrix3<f64> {
    let e = |i: usize, j: usize| x[(i, 0)] * y[(0, j)] + x[(i, 2)] * y[(2, j)];
    Matrix3::new(
        e(0, 0),
        0.0,
        e(0, 2),
        0.0,
        x[(1, 1)] * y[(1, 1)],
        0.0,
        e(2, 0),
        0.0,
        e(2, 2),
    )
}

/// X v for a block-diagonal 3×3 X and v in the (0, 2) plane.
#[inline(always)]
fn block_apply(x: &Matrix3<f64>, v: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(
        x[(0, 0)] * v[0] + x[(0, 2)] * v[2],
        0.0,
        x[(2, 0)] * v[0] + x[(2, 2)] * v[2],
    )
}

/// F and m leave θ = index 1 uncoupled from (r, z) = (0, 2): F_rθ = F_θr = F_zθ = F_θz = 0
/// and m_θ = 0, so that B, C⁻¹, g and Q are block diagonal.
#[inline(always)]
fn uncouples_theta(f: &Matrix3<f64>, m: &Vector3<f64>) -> bool {
    f[(0, 1)] == 0.0 && f[(1, 0)] == 0.0 && f[(1, 2)] == 0.0 && f[(2, 1)] == 0.0 && m[1] == 0.0
}

impl Kinematics {
    /// Prepares F for differentiation. Rejects det F ≤ 0 (and non-finite F).
    /// `m` must be a unit vector (the caller validates it once, not per point).
    ///
    /// B = F⁻¹ = adj F / J by cofactors, with J = det F expanded along the first row of F. When F
    /// and m do not couple θ = index 1 with (r, z) = (0, 2) (the axisymmetric problem), every
    /// tensor is block diagonal and only the 2×2 (r, z) block and the θθ entry are computed:
    /// B_θθ = 1/F_θθ, the block of B by the 2×2 inverse.
    #[inline(always)]
    pub fn new(f: &Matrix3<f64>, m: &Vector3<f64>) -> Result<Self> {
        let axisymmetric = uncouples_theta(f, m);
        let (det_f, b) = if axisymmetric {
            let (a, c, d, e, t) = (f[(0, 0)], f[(0, 2)], f[(2, 0)], f[(2, 2)], f[(1, 1)]);
            let det2 = a * e - c * d;
            let det_f = det2 * t;
            let k = 1.0 / det2;
            let b = Matrix3::new(e * k, 0.0, -c * k, 0.0, 1.0 / t, 0.0, -d * k, 0.0, a * k);
            (det_f, b)
        } else {
            let x = |i: usize, j: usize| f[(i, j)];
            // adj F (the transposed cofactor matrix), row-major.
            let adj = Matrix3::new(
                x(1, 1) * x(2, 2) - x(1, 2) * x(2, 1),
                x(0, 2) * x(2, 1) - x(0, 1) * x(2, 2),
                x(0, 1) * x(1, 2) - x(0, 2) * x(1, 1),
                x(1, 2) * x(2, 0) - x(1, 0) * x(2, 2),
                x(0, 0) * x(2, 2) - x(0, 2) * x(2, 0),
                x(0, 2) * x(1, 0) - x(0, 0) * x(1, 2),
                x(1, 0) * x(2, 1) - x(1, 1) * x(2, 0),
                x(0, 1) * x(2, 0) - x(0, 0) * x(2, 1),
                x(0, 0) * x(1, 1) - x(0, 1) * x(1, 0),
            );
            let det_f = x(0, 0) * adj[(0, 0)] + x(0, 1) * adj[(1, 0)] + x(0, 2) * adj[(2, 0)];
            (det_f, adj * (1.0 / det_f))
        };
        if det_f.is_nan() || det_f <= 0.0 || !f.iter().all(|x| x.is_finite()) {
            return Err(Error::NonPositiveJacobian {
                det: det_f,
                f: f.transpose().into(),
            });
        }
        let product = |x: &Matrix3<f64>, y: &Matrix3<f64>| {
            if axisymmetric {
                block_product(x, y)
            } else {
                product(x, y)
            }
        };
        let b_t = b.transpose();
        let c_inv = product(&b, &b_t);
        let b_t_b = product(&b_t, &b);
        let apply = |x: &Matrix3<f64>, v: &Vector3<f64>| {
            if axisymmetric {
                block_apply(x, v)
            } else {
                x * v
            }
        };
        let f_m = apply(f, m);
        let b_t_m = apply(&b_t, m);
        let c_inv_m = apply(&b, &b_t_m);
        let invariants = [
            f.norm_squared(),
            f_m.norm_squared(),
            b.norm_squared(),
            b_t_m.norm_squared(),
            det_f * det_f,
        ];
        Ok(Self {
            f: *f,
            m: *m,
            det_f,
            b,
            c_inv,
            b_t_b,
            f_m,
            b_t_m,
            c_inv_m,
            g_identity: product(&b_t_b, &b_t),
            invariants,
            axisymmetric,
        })
    }

    /// Fibre stretch λ_f = sqrt(C : M).
    pub fn fibre_stretch(&self) -> f64 {
        self.invariants[1].sqrt()
    }

    /// D_ja = ∂j/∂F_a for the five invariants j (rows) and the entries a of F (columns).
    /// With g_M = Bᵀ M C⁻¹ = (Bᵀm)(C⁻¹m)ᵀ and F M = (Fm) mᵀ.
    #[inline(always)]
    pub fn gradients<const N: usize>(&self, entries: &Entries<N>) -> SMatrix<f64, 5, N> {
        let j2 = self.det_f * self.det_f;
        let mut d = SMatrix::<f64, 5, N>::zeros();
        for (a, &(k, l)) in entries.index.iter().enumerate() {
            d[(0, a)] = 2.0 * self.f[(k, l)];
            d[(1, a)] = 2.0 * self.f_m[k] * self.m[l];
            d[(2, a)] = -2.0 * self.g_identity[(k, l)];
            d[(3, a)] = -2.0 * self.b_t_m[k] * self.c_inv_m[l];
            d[(4, a)] = 2.0 * j2 * self.b[(l, k)];
        }
        d
    }

    /// Σ_j w_j ∂²j/∂F_a∂F_b over the entries of F (symmetric N×N), with w₁ … w₅ the weights of
    /// tr C, C:M, tr C⁻¹, C⁻¹:M and det C (the module table, summed):
    ///
    /// T_kL,iJ = 2 [B_Jk g_iL + Q_ki C⁻¹_JL + g_kJ B_Li + δ_ki E_LJ]
    ///         + w₅ J² (4 B_Ji B_Lk − 2 B_Li B_Jk),
    ///
    /// g = Bᵀ A C⁻¹ and Q = Bᵀ A B with A = w₃ I + w₄ M (the two C⁻¹ invariants in one), and
    /// E = w₁ I + w₂ M. One formula, evaluated three ways: all nine entries by constant-bound
    /// loops; the axisymmetric entries, when F and m do not couple θ with (r, z), on the 2×2
    /// (r, z) block plus the θθ entry; any other entry set entry by entry.
    #[inline(always)]
    pub fn curvature<const N: usize>(
        &self,
        w: &SVector<f64, 5>,
        entries: &Entries<N>,
    ) -> SMatrix<f64, N, N> {
        let mut t = SMatrix::zeros();
        self.curvature_into(w, entries, &mut t);
        t
    }

    /// [`curvature`](Self::curvature) written into `t` (every entry is overwritten): the
    /// routes build their tangent in place, without copying it.
    #[inline(always)]
    pub fn curvature_into<const N: usize>(
        &self,
        w: &SVector<f64, 5>,
        entries: &Entries<N>,
        t: &mut SMatrix<f64, N, N>,
    ) {
        if entries.index[..] == FULL.index[..] {
            self.weighted(w, [0, 1, 2]).fill(t);
        } else if entries.index[..] == AXISYMMETRIC.index[..] && self.is_axisymmetric() {
            self.axisymmetric_curvature(w, t);
        } else {
            let c = self.weighted(w, [0, 1, 2]);
            for x in 0..N {
                for y in 0..N {
                    let (a, b) = (entries.index[x], entries.index[y]);
                    t[(x, y)] = c.entry(a, b) + c.det_entry(a, b);
                }
            }
        }
    }

    /// F and m do not couple θ with (r, z): B, C⁻¹, g and Q are block diagonal.
    fn is_axisymmetric(&self) -> bool {
        self.axisymmetric
    }

    /// The curvature over [F_rr, F_rz, F_zr, F_zz, F_θθ] for block-diagonal F and m in the
    /// (r, z) plane. With β = B_θθ = 1/F_θθ (so C⁻¹_θθ = β², g_θθ = w₃ β³, Q_θθ = w₃ β²), the
    /// formula splits into the (r, z) block, its coupling with θθ through the det C term
    /// alone, T_kL,θθ = 4 w₅ J² β B_Lk, and T_θθ,θθ = 6 w₃ β⁴ + 2 w₁ + 2 w₅ J² β².
    #[inline(always)]
    fn axisymmetric_curvature<const N: usize>(
        &self,
        w: &SVector<f64, 5>,
        t: &mut SMatrix<f64, N, N>,
    ) {
        let c = self.weighted(w, [0, 2]);
        let beta = self.b[(1, 1)];
        let beta2 = beta * beta;
        // Entry order of AXISYMMETRIC: (k, L) = 2 k + L in (r, z) block indices r = 0, z = 1,
        // then θθ.
        c.fill(t);
        for k in 0..2 {
            for l in 0..2 {
                let v = 4.0 * c.j2w * beta * c.b[l][k];
                t[(2 * k + l, 4)] = v;
                t[(4, 2 * k + l)] = v;
            }
        }
        t[(4, 4)] = 6.0 * w[2] * beta2 * beta2 + 2.0 * w[0] + 2.0 * c.j2w * beta2;
    }

    /// The ingredients of the curvature restricted to the rows and columns `idx` of the 3×3
    /// tensors (all three, or the (r, z) block).
    #[inline(always)]
    fn weighted<const D: usize>(&self, w: &SVector<f64, 5>, idx: [usize; D]) -> Weighted<D> {
        let (bm, cm, m) = (&self.b_t_m, &self.c_inv_m, &self.m);
        let sub = |x: &Matrix3<f64>| idx.map(|i| idx.map(|j| x[(i, j)]));
        Weighted {
            b: sub(&self.b),
            c_inv: sub(&self.c_inv),
            g: idx.map(|i| idx.map(|j| w[2] * self.g_identity[(i, j)] + w[3] * bm[i] * cm[j])),
            q: idx.map(|i| idx.map(|j| w[2] * self.b_t_b[(i, j)] + w[3] * bm[i] * bm[j])),
            e: idx.map(|i| idx.map(|j| w[1] * m[i] * m[j] + if i == j { w[0] } else { 0.0 })),
            j2w: self.det_f * self.det_f * w[4],
        }
    }
}

/// B, C⁻¹, g = Bᵀ A C⁻¹, Q = Bᵀ A B (A = w₃ I + w₄ M), E = w₁ I + w₂ M and w₅ J²: what the
/// curvature formula reads, on a D×D block of the 3×3 tensors.
struct Weighted<const D: usize> {
    b: [[f64; D]; D],
    c_inv: [[f64; D]; D],
    g: [[f64; D]; D],
    q: [[f64; D]; D],
    e: [[f64; D]; D],
    j2w: f64,
}

impl<const D: usize> Weighted<D> {
    /// The tr C, C:M and C⁻¹ terms of T_kL,iJ (indices into the block):
    /// 2 [B_Jk g_iL + Q_ki C⁻¹_JL + g_kJ B_Li + δ_ki E_LJ].
    #[inline(always)]
    fn entry(&self, (k, l): (usize, usize), (i, jj): (usize, usize)) -> f64 {
        let (b, g) = (&self.b, &self.g);
        let v = b[jj][k] * g[i][l] + self.q[k][i] * self.c_inv[jj][l] + g[k][jj] * b[l][i];
        2.0 * if k == i { v + self.e[l][jj] } else { v }
    }

    /// The det C term of T_kL,iJ: w₅ J² (4 B_Ji B_Lk − 2 B_Li B_Jk).
    #[inline(always)]
    fn det_entry(&self, (k, l): (usize, usize), (i, jj): (usize, usize)) -> f64 {
        let b = &self.b;
        self.j2w * (4.0 * b[jj][i] * b[l][k] - 2.0 * b[l][i] * b[jj][k])
    }

    /// Rows and columns (k, L) = D k + L < D² of `t`. The formula is symmetric under
    /// (k, L) ↔ (i, J), so only the upper triangle is evaluated and mirrored: entry by entry
    /// for the 2×2 block (16 entries, all loops unrolled), by the D×D sub-blocks (k, i) with
    /// i ≥ k for all nine entries (81 entries: the loops over (k, i) stay loops, those over
    /// (L, J) are unrolled). The det C term in the same pass, its weight 0 for energies that
    /// ignore det C.
    #[inline(always)]
    fn fill<const N: usize>(&self, t: &mut SMatrix<f64, N, N>) {
        for k in 0..D {
            for i in 0..D {
                if D == 3 && i < k {
                    continue;
                }
                for l in 0..D {
                    for jj in 0..D {
                        let (a, b) = (D * k + l, D * i + jj);
                        if D == 2 && b < a {
                            continue;
                        }
                        let mut v = self.entry((k, l), (i, jj));
                        if self.j2w != 0.0 {
                            v += self.det_entry((k, l), (i, jj));
                        }
                        t[(a, b)] = v;
                        t[(b, a)] = v;
                    }
                }
            }
        }
    }
}

/// Builds the full F from the five axisymmetric entries [F_rr, F_rz, F_zr, F_zz, F_θθ].
pub fn axisymmetric_f(f: &SVector<f64, 5>) -> Matrix3<f64> {
    Matrix3::new(f[0], 0.0, f[1], 0.0, f[4], 0.0, f[2], 0.0, f[3])
}

/// The axis e_z, the fibre direction of the axisymmetric problem.
pub fn axial_fibre() -> Vector3<f64> {
    Vector3::new(0.0, 0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::{Invariants, StrainEnergy};
    use crate::oracle::full_response;
    use crate::testing::Sampler;
    use crate::Scalar;

    /// W = Σ w_j j: at γ = 0 the oracle's Hessian over F (matrix products, no invariant calculus)
    /// is then exactly the curvature Σ w_j ∂²j/∂F².
    #[derive(Clone)]
    struct Weights([f64; 5]);

    impl StrainEnergy for Weights {
        fn energy<T: Scalar>(&self, c: &Invariants<T>) -> T {
            let w = &self.0;
            c.tr_c * w[0] + c.c_m * w[1] + c.tr_c_inv * w[2] + c.c_inv_m * w[3] + c.det_c * w[4]
        }
    }

    fn weights(s: &mut Sampler, det_c: bool) -> [f64; 5] {
        let mut w = [0.0; 5].map(|_| s.range(-2.0, 2.0));
        if !det_c {
            w[4] = 0.0;
        }
        w
    }

    fn rel<const R: usize, const C: usize>(a: &SMatrix<f64, R, C>, b: &SMatrix<f64, R, C>) -> f64 {
        (a - b).amax() / b.amax()
    }

    /// T restricted to `entries`, read off the nine-entry matrix.
    fn restrict<const N: usize>(
        t: &SMatrix<f64, 9, 9>,
        entries: &Entries<N>,
    ) -> SMatrix<f64, N, N> {
        let at = |(k, l): (usize, usize)| 3 * k + l;
        SMatrix::from_fn(|x, y| t[(at(entries.index[x]), at(entries.index[y]))])
    }

    #[test]
    fn curvature_is_the_hessian_of_the_weighted_invariants_to_1e_12() {
        let mut s = Sampler::new(0xC0_5A7);
        for n in 0..40 {
            let (f, m) = (s.deformation(0.3), s.unit_vector());
            let w = weights(&mut s, n % 2 == 0);
            let reference = full_response(&Weights(w), &f, &m, 0.0).unwrap();
            let kin = Kinematics::new(&f, &m).unwrap();
            let t = kin.curvature(&SVector::from(w), &FULL);
            assert!(rel(&t, &reference.tangent) <= 1e-12, "sample {n}");
            let p = kin.gradients(&FULL).tr_mul(&SVector::from(w));
            assert!(rel(&p, &reference.stress) <= 1e-12, "sample {n}");
        }
    }

    /// The axisymmetric block evaluation (F and m not coupling θ with (r, z)), the same entries
    /// at a general F (entry by entry), and an arbitrary entry set all read the nine-entry matrix.
    #[test]
    fn every_entry_set_reads_the_nine_entry_curvature() {
        const SOME: Entries<4> = Entries {
            index: [(2, 1), (0, 0), (1, 2), (2, 2)],
        };
        let mut s = Sampler::new(0xB10C);
        for n in 0..40 {
            let w = SVector::from(weights(&mut s, n % 2 == 0));
            let axi = SVector::from([0.0; 5].map(|_| s.range(-0.3, 0.3)))
                + SVector::from([1.0, 0.0, 0.0, 1.0, 1.0]);
            let (block, general) = (axisymmetric_f(&axi), s.deformation(0.3));
            let in_plane = Vector3::new(s.range(-1.0, 1.0), 0.0, 1.0).normalize();
            let kin = Kinematics::new(&block, &in_plane).unwrap();
            assert!(kin.is_axisymmetric());
            let full = kin.curvature(&w, &FULL);
            assert!(
                rel(
                    &kin.curvature(&w, &AXISYMMETRIC),
                    &restrict(&full, &AXISYMMETRIC)
                ) <= 1e-14
            );
            for kin in [kin, Kinematics::new(&general, &s.unit_vector()).unwrap()] {
                let full = kin.curvature(&w, &FULL);
                if !kin.is_axisymmetric() {
                    let axi = kin.curvature(&w, &AXISYMMETRIC);
                    assert!(
                        rel(&axi, &restrict(&full, &AXISYMMETRIC)) <= 1e-14,
                        "sample {n}"
                    );
                }
                assert!(rel(&kin.curvature(&w, &SOME), &restrict(&full, &SOME)) <= 1e-14);
            }
        }
    }
}
