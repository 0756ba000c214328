//! Active strain: F = F_e F_a with F_a = I − γ M, and Ŵ(F, γ) = det F_a · W(F_a⁻ᵀ C F_a⁻¹).
//!
//! With c = 1 − γ and s = 1/c, the invariants of C_e are linear in those of C:
//!
//! | invariant of C_e | in terms of C |
//! |---|---|
//! | tr C_e | tr C + (s² − 1) C:M |
//! | C_e : M | s² C:M |
//! | tr C_e⁻¹ | tr C⁻¹ + (c² − 1) C⁻¹:M |
//! | C_e⁻¹ : M | c² C⁻¹:M |
//! | det C_e | s² det C |
//!
//! and Ŵ = c · W(C_e). This map is owned by the framework: any energy plugs in unchanged.

use crate::energy::{Invariants, StrainEnergy};
use crate::{Error, Result, Scalar};
use nalgebra::{SMatrix, SVector};

/// Rejects γ ∉ [0, 1) (and non-finite γ).
pub fn check_activation(gamma: f64) -> Result<f64> {
    if (0.0..1.0).contains(&gamma) {
        Ok(gamma)
    } else {
        Err(Error::ActivationOutOfRange { gamma })
    }
}

/// Invariants of C_e from the invariants `j` = [tr C, C:M, tr C⁻¹, C⁻¹:M, det C] of C.
pub fn elastic_invariants<T: Scalar>(j: &[T; 5], gamma: T) -> [T; 5] {
    let c = -gamma + 1.0;
    let c2 = c * c;
    let s2 = c2.recip();
    [
        j[0] + j[1] * (s2 - 1.0),
        j[1] * s2,
        j[2] + j[3] * (c2 - 1.0),
        j[3] * c2,
        j[4] * s2,
    ]
}

/// Ŵ(j, γ) = (1 − γ) W(C_e): the active-strain energy as a generic function of the invariants
/// of C and of γ (no range check: callers check γ once).
pub fn active_energy<E: StrainEnergy, T: Scalar>(energy: &E, j: &[T; 5], gamma: T) -> T {
    let elastic = Invariants::from_array(elastic_invariants(j, gamma));
    (-gamma + 1.0) * energy.energy(&elastic)
}

/// Ŵ along the incompressible uniaxial path along the fibres, F = diag(λ, λ^-½, λ^-½), m = e₁:
/// j = [λ² + 2/λ, λ², λ⁻² + 2λ, λ⁻², 1] (eq. D:Wattgamma). Its λ-derivative is P_tot
/// (eq. D:Ptotcalcolato).
pub fn fibre_path_energy<E: StrainEnergy, T: Scalar>(energy: &E, lambda: T, gamma: T) -> T {
    active_energy(energy, &fibre_path_invariants(lambda), gamma)
}

/// The invariants j = [tr C, C:M, tr C⁻¹, C⁻¹:M, det C] = [λ² + 2/λ, λ², λ⁻² + 2λ, λ⁻², 1] of the
/// incompressible uniaxial path along the fibres, F = diag(λ, λ^-½, λ^-½), m = e₁.
pub fn fibre_path_invariants<T: Scalar>(lambda: T) -> [T; 5] {
    let inv = lambda.recip();
    [
        lambda * lambda + inv * 2.0,
        lambda * lambda,
        inv * inv + lambda * 2.0,
        inv * inv,
        T::one(),
    ]
}

/// The active-strain map at a fixed γ, Ie = A(γ) j, applied by its seven non-zero entries:
///
/// A = [[1, s²−1, 0, 0, 0], [0, s², 0, 0, 0], [0, 0, 1, c²−1, 0], [0, 0, 0, c², 0], [0, 0, 0, 0, s²]],
///
/// with ds/dγ = s², d(s²)/dγ = 2s³, d(2s³)/dγ = 6s⁴; d(c²)/dγ = −2c, d(−2c)/dγ = 2.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StrainMap {
    /// 1 − γ.
    pub c: f64,
    c2: f64,
    s2: f64,
    s3: f64,
    s4: f64,
}

impl StrainMap {
    #[inline]
    pub fn new(gamma: f64) -> Self {
        let c = 1.0 - gamma;
        let s = 1.0 / c;
        let s2 = s * s;
        Self {
            c,
            c2: c * c,
            s2,
            s3: s2 * s,
            s4: s2 * s2,
        }
    }

    /// Ie = A j.
    #[inline]
    pub fn apply(&self, j: &SVector<f64, 5>) -> SVector<f64, 5> {
        SVector::from([
            j[0] + (self.s2 - 1.0) * j[1],
            self.s2 * j[1],
            j[2] + (self.c2 - 1.0) * j[3],
            self.c2 * j[3],
            self.s2 * j[4],
        ])
    }

    /// (A X)_rk for the rows r of X (one per invariant): the gradients of the elastic
    /// invariants from those of the invariants of C.
    #[inline(always)]
    pub fn row<const N: usize>(&self, r: usize, x: &SMatrix<f64, 5, N>, k: usize) -> f64 {
        match r {
            0 => x[(0, k)] + (self.s2 - 1.0) * x[(1, k)],
            1 => self.s2 * x[(1, k)],
            2 => x[(2, k)] + (self.c2 - 1.0) * x[(3, k)],
            3 => self.c2 * x[(3, k)],
            _ => self.s2 * x[(4, k)],
        }
    }

    /// Aᵀ y.
    #[inline]
    pub fn transpose_apply(&self, y: &SVector<f64, 5>) -> SVector<f64, 5> {
        SVector::from([
            y[0],
            (self.s2 - 1.0) * y[0] + self.s2 * y[1],
            y[2],
            (self.c2 - 1.0) * y[2] + self.c2 * y[3],
            self.s2 * y[4],
        ])
    }

    /// dIe/dγ = (dA/dγ) j.
    #[inline]
    pub fn rate(&self, j: &SVector<f64, 5>) -> SVector<f64, 5> {
        let (a, b) = (2.0 * self.s3, -2.0 * self.c);
        SVector::from([a * j[1], a * j[1], b * j[3], b * j[3], a * j[4]])
    }

    /// d²Ie/dγ² = (d²A/dγ²) j.
    #[inline]
    pub fn rate2(&self, j: &SVector<f64, 5>) -> SVector<f64, 5> {
        let a = 6.0 * self.s4;
        SVector::from([a * j[1], a * j[1], 2.0 * j[3], 2.0 * j[3], a * j[4]])
    }

    /// (dA/dγ)ᵀ y.
    #[inline]
    pub fn rate_transpose_apply(&self, y: &SVector<f64, 5>) -> SVector<f64, 5> {
        let (a, b) = (2.0 * self.s3, -2.0 * self.c);
        SVector::from([0.0, a * (y[0] + y[1]), 0.0, b * (y[2] + y[3]), a * y[4]])
    }

    /// X A, by columns.
    #[inline(always)]
    fn right(&self, x: &SMatrix<f64, 5, 5>) -> SMatrix<f64, 5, 5> {
        let mut y = *x;
        for r in 0..5 {
            y[(r, 1)] = (self.s2 - 1.0) * x[(r, 0)] + self.s2 * x[(r, 1)];
            y[(r, 3)] = (self.c2 - 1.0) * x[(r, 2)] + self.c2 * x[(r, 3)];
            y[(r, 4)] = self.s2 * x[(r, 4)];
        }
        y
    }

    /// Aᵀ H A for a symmetric H.
    #[inline(always)]
    pub fn congruence(&self, h: &SMatrix<f64, 5, 5>) -> SMatrix<f64, 5, 5> {
        self.right(&self.right(h).transpose())
    }
}
