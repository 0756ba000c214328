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
//! evaluates that sum directly, entry by entry, only for the entries of F the problem has.

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
}

impl Kinematics {
    /// Prepares F for differentiation. Rejects det F ≤ 0 (and non-finite F).
    /// `m` must be a unit vector (the caller validates it once, not per point).
    pub fn new(f: &Matrix3<f64>, m: &Vector3<f64>) -> Result<Self> {
        let det_f = f.determinant();
        let rejected = || Error::NonPositiveJacobian {
            det: det_f,
            f: f.transpose().into(),
        };
        if det_f.is_nan() || det_f <= 0.0 || !f.iter().all(|x| x.is_finite()) {
            return Err(rejected());
        }
        let b = f.try_inverse().ok_or_else(rejected)?;
        let c_inv = b * b.transpose();
        let b_t_b = b.transpose() * b;
        let f_m = f * m;
        let b_t_m = b.transpose() * m;
        let c_inv_m = c_inv * m;
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
            g_identity: b_t_b * b.transpose(),
            invariants,
        })
    }

    /// Fibre stretch λ_f = sqrt(C : M).
    pub fn fibre_stretch(&self) -> f64 {
        self.invariants[1].sqrt()
    }

    /// D_ja = ∂j/∂F_a for the five invariants j (rows) and the entries a of F (columns).
    /// With g_M = Bᵀ M C⁻¹ = (Bᵀm)(C⁻¹m)ᵀ and F M = (Fm) mᵀ.
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

    /// Σ_j w_j ∂²j/∂F_a∂F_b over the entries of F (symmetric N×N), for weights w over the
    /// five invariants (see the module table).
    pub fn curvature<const N: usize>(
        &self,
        w: &SVector<f64, 5>,
        entries: &Entries<N>,
    ) -> SMatrix<f64, N, N> {
        let (b, c_inv, m) = (&self.b, &self.c_inv, &self.m);
        // C⁻¹ : A with A = w₃ I + w₄ M: g = Bᵀ A C⁻¹, Q = Bᵀ A B.
        let g = self.g_identity * w[2] + self.b_t_m * self.c_inv_m.transpose() * w[3];
        let q = self.b_t_b * w[2] + self.b_t_m * self.b_t_m.transpose() * w[3];
        let j2w = self.det_f * self.det_f * w[4];
        let mut t = SMatrix::<f64, N, N>::zeros();
        for (x, &(k, l)) in entries.index.iter().enumerate() {
            for (y, &(i, jj)) in entries.index.iter().enumerate().skip(x) {
                let mut v = 2.0
                    * (b[(jj, k)] * g[(i, l)]
                        + q[(k, i)] * c_inv[(jj, l)]
                        + g[(k, jj)] * b[(l, i)]);
                if k == i {
                    v += 2.0 * (w[1] * m[l] * m[jj] + if l == jj { w[0] } else { 0.0 });
                }
                if j2w != 0.0 {
                    v += j2w * (4.0 * b[(jj, i)] * b[(l, k)] - 2.0 * b[(l, i)] * b[(jj, k)]);
                }
                t[(x, y)] = v;
                t[(y, x)] = v;
            }
        }
        t
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
