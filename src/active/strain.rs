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
    let inv = lambda.recip();
    let j = [
        lambda * lambda + inv * 2.0,
        lambda * lambda,
        inv * inv + lambda * 2.0,
        inv * inv,
        T::one(),
    ];
    active_energy(energy, &j, gamma)
}

/// The active-strain map as matrices at a fixed γ: Ie = A j, and its γ-derivatives.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StrainMap {
    /// 1 − γ.
    pub c: f64,
    /// A(γ).
    pub a: SMatrix<f64, 5, 5>,
    /// dA/dγ.
    pub a_gamma: SMatrix<f64, 5, 5>,
    /// d²A/dγ².
    pub a_gamma2: SMatrix<f64, 5, 5>,
}

impl StrainMap {
    /// ds/dγ = s², d(s²)/dγ = 2s³, d(2s³)/dγ = 6s⁴; d(c²)/dγ = −2c, d(−2c)/dγ = 2.
    pub fn new(gamma: f64) -> Self {
        let c = 1.0 - gamma;
        let s = 1.0 / c;
        let (s2, s3, s4) = (s * s, s * s * s, s * s * s * s);
        let mut a = SMatrix::<f64, 5, 5>::zeros();
        let mut a_gamma = SMatrix::<f64, 5, 5>::zeros();
        let mut a_gamma2 = SMatrix::<f64, 5, 5>::zeros();
        a[(0, 0)] = 1.0;
        a[(0, 1)] = s2 - 1.0;
        a[(1, 1)] = s2;
        a[(2, 2)] = 1.0;
        a[(2, 3)] = c * c - 1.0;
        a[(3, 3)] = c * c;
        a[(4, 4)] = s2;
        for (r, col) in [(0, 1), (1, 1), (4, 4)] {
            a_gamma[(r, col)] = 2.0 * s3;
            a_gamma2[(r, col)] = 6.0 * s4;
        }
        for (r, col) in [(2, 3), (3, 3)] {
            a_gamma[(r, col)] = -2.0 * c;
            a_gamma2[(r, col)] = 2.0;
        }
        Self {
            c,
            a,
            a_gamma,
            a_gamma2,
        }
    }

    /// Ie = A j.
    pub fn apply(&self, j: &SVector<f64, 5>) -> SVector<f64, 5> {
        self.a * j
    }
}
