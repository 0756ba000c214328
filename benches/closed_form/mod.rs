//! Hand-derived closed form of the chapter's active model, written ONLY as the benchmark's
//! yardstick (and as an independent check of the AD routes in `tests/it/closed_form.rs`).
//!
//! Passive energy (eq. (1)) W(C) = μ/4 { (e^{α(I−1)} − 1)/α + K − 1 } with
//! I = A : C, K = A : C⁻¹, A = a I + b M, a = w0/3, b = 1 − w0, M = m ⊗ m.
//! Active strain F_a = I − γ M, N = F_a⁻¹ = I + (s − 1) M with c = 1 − γ, s = 1/c, and
//! Ŵ(F, γ) = c W(C_e), C_e = N C N.
//!
//! Pulling A through N and F_a (N M = s M, F_a M = c M):
//!
//! - I_e = A : C_e = F : (F Â),   Â = N A N   = a I + â M,  â = a (s² − 1) + b s²,
//! - K_e = A : C_e⁻¹ = Ǎ : C⁻¹,   Ǎ = F_a A F_a = a I + ǎ M,  ǎ = a (c² − 1) + b c²,
//!
//! so with B = F⁻¹, C⁻¹ = B Bᵀ, e = e^{α(I_e − 1)} and κ = c μ/2:
//!
//! - P = κ (e F Â − g),  g = Bᵀ Ǎ C⁻¹ (this is eq. (7) without the pressure:
//!   F_e {e A − C_e⁻¹ A C_e⁻¹} F_a⁻¹ = e F Â − Bᵀ Ǎ C⁻¹),
//! - ∂P_kL/∂F_iJ = κ { 2α e (FÂ)_kL (FÂ)_iJ + e δ_ki Â_LJ + B_Jk g_iL + Q_ki C⁻¹_JL + g_kJ B_Li },
//!   Q = Bᵀ Ǎ B (from ∂B_ab/∂F_iJ = −B_ai B_Jb); major-symmetric,
//! - dP/dγ = −μ/2 (e F Â − g) + κ { â′ e (α |F m|² F Â + (F m) ⊗ m) − ǎ′ (Bᵀ m) ⊗ (C⁻¹ m) },
//!   â′ = 2 (a + b) s³, ǎ′ = −2 (a + b) c.
//!
//! Axisymmetric (entries [F_rr, F_rz, F_zr, F_zz, F_θθ], m = e_z): F is block diagonal
//! (2×2 (r, z) block and F_θθ), so are B, C⁻¹, g and Q, and the formulas split into the 2×2 block
//! plus the θθ entry: (FÂ)_θθ = a F_θθ, g_θθ = a/F_θθ³, Q_θθ = a/F_θθ², and the only coupling of
//! θθ with the block is the exponential term 2α e (FÂ)_kL a F_θθ.
//!
//! Fixed-size arrays only, no allocation.
#![allow(dead_code)]

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// The chapter's passive parameters (μ [kPa], α, w0).
#[derive(Debug, Clone, Copy)]
pub struct ClosedForm {
    pub mu: f64,
    pub alpha: f64,
    pub w0: f64,
}

/// Energy, first Piola stress (no pressure), tangent ∂P/∂F and dP/dγ over N entries of F.
#[derive(Debug, Clone, Copy)]
pub struct ClosedResponse<const N: usize> {
    pub energy: f64,
    pub stress: SVector<f64, N>,
    pub tangent: SMatrix<f64, N, N>,
    pub dstress_dgamma: SVector<f64, N>,
}

/// γ-dependent scalars shared by both dimensions.
struct Coefficients {
    /// a = w0/3.
    a: f64,
    /// â: Â = a I + â M.
    a_hat: f64,
    /// ǎ: Ǎ = a I + ǎ M.
    a_check: f64,
    /// dâ/dγ.
    a_hat_prime: f64,
    /// dǎ/dγ.
    a_check_prime: f64,
    /// κ = (1 − γ) μ / 2.
    kappa: f64,
    /// 1 − γ.
    c: f64,
}

impl ClosedForm {
    pub fn new(mu: f64, alpha: f64, w0: f64) -> Self {
        Self { mu, alpha, w0 }
    }

    #[inline(always)]
    fn coefficients(&self, gamma: f64) -> Coefficients {
        let a = self.w0 / 3.0;
        let b = 1.0 - self.w0;
        let c = 1.0 - gamma;
        let s = 1.0 / c;
        let s2 = s * s;
        let c2 = c * c;
        Coefficients {
            a,
            a_hat: a * (s2 - 1.0) + b * s2,
            a_check: a * (c2 - 1.0) + b * c2,
            a_hat_prime: 2.0 * (a + b) * s2 * s,
            a_check_prime: -2.0 * (a + b) * c,
            kappa: 0.5 * c * self.mu,
            c,
        }
    }

    /// 3D: the nine entries of F row by row, any unit m. `None` if det F ≤ 0.
    pub fn full(
        &self,
        f: &Matrix3<f64>,
        m: &Vector3<f64>,
        gamma: f64,
    ) -> Option<ClosedResponse<9>> {
        let k = self.coefficients(gamma);
        let (a, alpha) = (k.a, self.alpha);
        let f = [
            [f[(0, 0)], f[(0, 1)], f[(0, 2)]],
            [f[(1, 0)], f[(1, 1)], f[(1, 2)]],
            [f[(2, 0)], f[(2, 1)], f[(2, 2)]],
        ];
        let m = [m[0], m[1], m[2]];

        // Cofactor inverse B = F⁻¹.
        let cof = |i: usize, j: usize| {
            let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            f[i1][j1] * f[i2][j2] - f[i1][j2] * f[i2][j1]
        };
        let det = f[0][0] * cof(0, 0) + f[0][1] * cof(0, 1) + f[0][2] * cof(0, 2);
        if det.is_nan() || det <= 0.0 {
            return None;
        }
        let inv_det = 1.0 / det;
        let mut b = [[0.0; 3]; 3];
        for (i, row) in b.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x = cof(j, i) * inv_det;
            }
        }

        // F m, F Â = a F + â (F m) ⊗ m, I_e = F : F Â.
        let mut fm = [0.0; 3];
        for i in 0..3 {
            fm[i] = f[i][0] * m[0] + f[i][1] * m[1] + f[i][2] * m[2];
        }
        let fm2 = fm[0] * fm[0] + fm[1] * fm[1] + fm[2] * fm[2];
        let mut fa = [[0.0; 3]; 3];
        let mut tr_c = 0.0;
        for i in 0..3 {
            for j in 0..3 {
                fa[i][j] = a * f[i][j] + k.a_hat * fm[i] * m[j];
                tr_c += f[i][j] * f[i][j];
            }
        }
        let i_e = a * tr_c + k.a_hat * fm2;

        // C⁻¹ = B Bᵀ, BᵀB, Bᵀm, C⁻¹m.
        let mut c_inv = [[0.0; 3]; 3];
        let mut btb = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in i..3 {
                let x = b[i][0] * b[j][0] + b[i][1] * b[j][1] + b[i][2] * b[j][2];
                let y = b[0][i] * b[0][j] + b[1][i] * b[1][j] + b[2][i] * b[2][j];
                c_inv[i][j] = x;
                c_inv[j][i] = x;
                btb[i][j] = y;
                btb[j][i] = y;
            }
        }
        let mut bm = [0.0; 3];
        for i in 0..3 {
            bm[i] = b[0][i] * m[0] + b[1][i] * m[1] + b[2][i] * m[2];
        }
        let mut cm = [0.0; 3];
        for i in 0..3 {
            cm[i] = b[i][0] * bm[0] + b[i][1] * bm[1] + b[i][2] * bm[2];
        }
        // g = Bᵀ Ǎ C⁻¹ = a (BᵀB) Bᵀ + ǎ (Bᵀm) ⊗ (C⁻¹m); Q = Bᵀ Ǎ B = a BᵀB + ǎ (Bᵀm) ⊗ (Bᵀm).
        let mut g = [[0.0; 3]; 3];
        let mut q = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                let btbbt = btb[i][0] * b[j][0] + btb[i][1] * b[j][1] + btb[i][2] * b[j][2];
                g[i][j] = a * btbbt + k.a_check * bm[i] * cm[j];
                q[i][j] = a * btb[i][j] + k.a_check * bm[i] * bm[j];
            }
        }
        let k_e = a * (c_inv[0][0] + c_inv[1][1] + c_inv[2][2])
            + k.a_check * (m[0] * cm[0] + m[1] * cm[1] + m[2] * cm[2]);

        let em1 = (alpha * (i_e - 1.0)).exp_m1();
        let e = em1 + 1.0;
        let energy = 0.5 * k.kappa * (em1 / alpha + k_e - 1.0);

        let mut stress = SVector::<f64, 9>::zeros();
        let mut dstress = SVector::<f64, 9>::zeros();
        let dk = -0.5 * self.mu;
        let ee = e * k.a_hat_prime;
        for i in 0..3 {
            for j in 0..3 {
                let p = e * fa[i][j] - g[i][j];
                stress[3 * i + j] = k.kappa * p;
                dstress[3 * i + j] = dk * p
                    + k.kappa
                        * (ee * (alpha * fm2 * fa[i][j] + fm[i] * m[j])
                            - k.a_check_prime * bm[i] * cm[j]);
            }
        }

        // Tangent: constant-bound loops (fully unrolled by the compiler), all 81 entries (the
        // symmetric half with a mirror costs more in index arithmetic than it saves).
        let two_alpha_e = 2.0 * alpha * e;
        let mut ea = [[0.0; 3]; 3];
        for l in 0..3 {
            for j in 0..3 {
                ea[l][j] = e * (k.a_hat * m[l] * m[j] + if l == j { a } else { 0.0 });
            }
        }
        let mut t = [[0.0; 9]; 9];
        for kk in 0..3 {
            for l in 0..3 {
                let row = &mut t[3 * kk + l];
                let tf = two_alpha_e * fa[kk][l];
                for i in 0..3 {
                    for jj in 0..3 {
                        let mut v = tf * fa[i][jj]
                            + b[jj][kk] * g[i][l]
                            + q[kk][i] * c_inv[jj][l]
                            + g[kk][jj] * b[l][i];
                        if kk == i {
                            v += ea[l][jj];
                        }
                        row[3 * i + jj] = k.kappa * v;
                    }
                }
            }
        }
        let t = SMatrix::<f64, 9, 9>::from_fn(|x, y| t[x][y]);
        Some(ClosedResponse {
            energy,
            stress,
            tangent: t,
            dstress_dgamma: dstress,
        })
    }

    /// Axisymmetric: entries [F_rr, F_rz, F_zr, F_zz, F_θθ], m = e_z. `None` if det F ≤ 0.
    pub fn axisymmetric(&self, f5: &SVector<f64, 5>, gamma: f64) -> Option<ClosedResponse<5>> {
        let k = self.coefficients(gamma);
        let (a, alpha) = (k.a, self.alpha);
        // 2×2 (r, z) block, 2D indices r = 0, z = 1; m = (0, 1) in the block.
        let f = [[f5[0], f5[1]], [f5[2], f5[3]]];
        let ft = f5[4];
        let det2 = f[0][0] * f[1][1] - f[0][1] * f[1][0];
        if (det2 * ft).is_nan() || det2 * ft <= 0.0 {
            return None;
        }
        let id = 1.0 / det2;
        let b = [[f[1][1] * id, -f[0][1] * id], [-f[1][0] * id, f[0][0] * id]];
        let bt = 1.0 / ft;
        let bt2 = bt * bt;

        // F Â: column r scaled by a, column z by a + â.
        let az = a + k.a_hat;
        let fa = [[a * f[0][0], az * f[0][1]], [a * f[1][0], az * f[1][1]]];
        let fa_t = a * ft;
        let fm2 = f[0][1] * f[0][1] + f[1][1] * f[1][1];
        let i_e = a * (f[0][0] * f[0][0] + f[1][0] * f[1][0] + ft * ft) + az * fm2;

        // C⁻¹ = B Bᵀ, BᵀB, Bᵀm (row z of B), C⁻¹m.
        let c_inv = [
            [
                b[0][0] * b[0][0] + b[0][1] * b[0][1],
                b[0][0] * b[1][0] + b[0][1] * b[1][1],
            ],
            [
                b[0][0] * b[1][0] + b[0][1] * b[1][1],
                b[1][0] * b[1][0] + b[1][1] * b[1][1],
            ],
        ];
        let btb = [
            [
                b[0][0] * b[0][0] + b[1][0] * b[1][0],
                b[0][0] * b[0][1] + b[1][0] * b[1][1],
            ],
            [
                b[0][0] * b[0][1] + b[1][0] * b[1][1],
                b[0][1] * b[0][1] + b[1][1] * b[1][1],
            ],
        ];
        let bm = [b[1][0], b[1][1]];
        let cm = [
            b[0][0] * bm[0] + b[0][1] * bm[1],
            b[1][0] * bm[0] + b[1][1] * bm[1],
        ];
        let mut g = [[0.0; 2]; 2];
        let mut q = [[0.0; 2]; 2];
        for i in 0..2 {
            for j in 0..2 {
                g[i][j] =
                    a * (btb[i][0] * b[j][0] + btb[i][1] * b[j][1]) + k.a_check * bm[i] * cm[j];
                q[i][j] = a * btb[i][j] + k.a_check * bm[i] * bm[j];
            }
        }
        let g_t = a * bt2 * bt;
        let k_e = a * (c_inv[0][0] + c_inv[1][1] + bt2) + k.a_check * cm[1];

        let em1 = (alpha * (i_e - 1.0)).exp_m1();
        let e = em1 + 1.0;
        let energy = 0.5 * k.kappa * (em1 / alpha + k_e - 1.0);

        // Entry order: (r,r), (r,z), (z,r), (z,z) of the block, then θθ.
        const IDX: [(usize, usize); 4] = [(0, 0), (0, 1), (1, 0), (1, 1)];
        let dk = -0.5 * self.mu;
        let ee = e * k.a_hat_prime;
        let mut stress = SVector::<f64, 5>::zeros();
        let mut dstress = SVector::<f64, 5>::zeros();
        for (x, &(i, j)) in IDX.iter().enumerate() {
            let p = e * fa[i][j] - g[i][j];
            stress[x] = k.kappa * p;
            // (F m) ⊗ m: only column z, F m = column z of F.
            let fmm = if j == 1 { f[i][1] } else { 0.0 };
            dstress[x] = dk * p
                + k.kappa * (ee * (alpha * fm2 * fa[i][j] + fmm) - k.a_check_prime * bm[i] * cm[j]);
        }
        let p_t = e * fa_t - g_t;
        stress[4] = k.kappa * p_t;
        dstress[4] = dk * p_t + k.kappa * ee * alpha * fm2 * fa_t;

        let two_alpha_e = 2.0 * alpha * e;
        let mut t = SMatrix::<f64, 5, 5>::zeros();
        for (x, &(kk, l)) in IDX.iter().enumerate() {
            for (y, &(i, jj)) in IDX.iter().enumerate().skip(x) {
                let mut v = two_alpha_e * fa[kk][l] * fa[i][jj]
                    + b[jj][kk] * g[i][l]
                    + q[kk][i] * c_inv[jj][l]
                    + g[kk][jj] * b[l][i];
                if kk == i && l == jj {
                    v += e * if l == 1 { az } else { a };
                }
                let v = k.kappa * v;
                t[(x, y)] = v;
                t[(y, x)] = v;
            }
            let v = k.kappa * two_alpha_e * fa[kk][l] * fa_t;
            t[(x, 4)] = v;
            t[(4, x)] = v;
        }
        t[(4, 4)] = k.kappa * (two_alpha_e * fa_t * fa_t + e * a + 3.0 * a * bt2 * bt2);
        Some(ClosedResponse {
            energy,
            stress,
            tangent: t,
            dstress_dgamma: dstress,
        })
    }
}
