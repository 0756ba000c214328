//! Active strain: F = F_e F_a, and Ŵ(F, γ) = det F_a · W(F_a⁻ᵀ C F_a⁻¹), for either active-strain
//! map of [`ActiveStrainMap`]. Both are F_a = a M + b (I − M), so F_a⁻¹ = (1/a) M + (1/b)(I − M)
//! and the invariants of C_e are linear in those of C:
//!
//! | invariant of C_e | in terms of C | chapter (a = c, b = 1) | volume-preserving (a = c, b = √s) |
//! |---|---|---|---|
//! | tr C_e | b⁻² tr C + (a⁻² − b⁻²) C:M | tr C + (s² − 1) C:M | c tr C + (s² − c) C:M |
//! | C_e : M | a⁻² C:M | s² C:M | s² C:M |
//! | tr C_e⁻¹ | b² tr C⁻¹ + (a² − b²) C⁻¹:M | tr C⁻¹ + (c² − 1) C⁻¹:M | s tr C⁻¹ + (c² − s) C⁻¹:M |
//! | C_e⁻¹ : M | a² C⁻¹:M | c² C⁻¹:M | c² C⁻¹:M |
//! | det C_e | a⁻² b⁻⁴ det C | s² det C | det C |
//!
//! with c = 1 − γ, s = 1/c, and Ŵ = φ W(C_e), φ = det F_a = a b² (c for the chapter's map, 1 for
//! the volume-preserving one). This map is owned by the framework: any energy plugs in unchanged.

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

/// Which active-strain map F_a(γ) a muscle uses (in a scene: `[activation] map = "chapter" |
/// "volume-preserving"`). Both are F_a = a M + b (I − M) with a = 1 − γ along the fibres.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ActiveStrainMap {
    /// The chapter's F_a = I − γ M (b = 1): the fibres shorten, the cross-section does not
    /// change, det F_a = 1 − γ (Giantesio & Musesti).
    #[default]
    Chapter,
    /// F_a = (1 − γ) M + (1 − γ)^(−½) (I − M) (b = (1 − γ)^(−½)): the fibres shorten and the
    /// cross-section widens so that det F_a = 1 (Weickenmeier et al. 2014; 4C's
    /// MAT_Muscle_Giantesio and MAT_Muscle_Weickenmeier).
    VolumePreserving,
}

impl ActiveStrainMap {
    /// Name used in scenes, logs and output files: chapter, volume-preserving.
    pub fn name(&self) -> &'static str {
        match self {
            ActiveStrainMap::Chapter => "chapter",
            ActiveStrainMap::VolumePreserving => "volume-preserving",
        }
    }

    /// Invariants of C_e from the invariants `j` = [tr C, C:M, tr C⁻¹, C⁻¹:M, det C] of C (the
    /// table of the module docs).
    pub fn elastic_invariants<T: Scalar>(&self, j: &[T; 5], gamma: T) -> [T; 5] {
        let c = -gamma + 1.0;
        let c2 = c * c;
        let s2 = c2.recip();
        match self {
            ActiveStrainMap::Chapter => [
                j[0] + j[1] * (s2 - 1.0),
                j[1] * s2,
                j[2] + j[3] * (c2 - 1.0),
                j[3] * c2,
                j[4] * s2,
            ],
            ActiveStrainMap::VolumePreserving => {
                let s = c.recip();
                [
                    j[0] * c + j[1] * (s2 - c),
                    j[1] * s2,
                    j[2] * s + j[3] * (c2 - s),
                    j[3] * c2,
                    j[4],
                ]
            }
        }
    }

    /// Ŵ(j, γ) = det F_a · W(C_e): the active-strain energy as a generic function of the
    /// invariants of C and of γ (no range check: callers check γ once).
    pub fn active_energy<E: StrainEnergy, T: Scalar>(&self, energy: &E, j: &[T; 5], gamma: T) -> T {
        let w = energy.energy(&Invariants::from_array(self.elastic_invariants(j, gamma)));
        match self {
            ActiveStrainMap::Chapter => (-gamma + 1.0) * w,
            ActiveStrainMap::VolumePreserving => w,
        }
    }

    /// Ŵ along the incompressible uniaxial path along the fibres, F = diag(λ, λ^-½, λ^-½),
    /// m = e₁ (eq. D:Wattgamma for the chapter's map). Its λ-derivative is P_tot
    /// (eq. D:Ptotcalcolato).
    pub fn fibre_path_energy<E: StrainEnergy, T: Scalar>(
        &self,
        energy: &E,
        lambda: T,
        gamma: T,
    ) -> T {
        self.active_energy(energy, &fibre_path_invariants(lambda), gamma)
    }
}

/// [`ActiveStrainMap::elastic_invariants`] of the chapter's map.
pub fn elastic_invariants<T: Scalar>(j: &[T; 5], gamma: T) -> [T; 5] {
    ActiveStrainMap::Chapter.elastic_invariants(j, gamma)
}

/// [`ActiveStrainMap::active_energy`] of the chapter's map: Ŵ = (1 − γ) W(C_e).
pub fn active_energy<E: StrainEnergy, T: Scalar>(energy: &E, j: &[T; 5], gamma: T) -> T {
    ActiveStrainMap::Chapter.active_energy(energy, j, gamma)
}

/// [`ActiveStrainMap::fibre_path_energy`] of the chapter's map (eq. D:Wattgamma).
pub fn fibre_path_energy<E: StrainEnergy, T: Scalar>(energy: &E, lambda: T, gamma: T) -> T {
    ActiveStrainMap::Chapter.fibre_path_energy(energy, lambda, gamma)
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

/// The active-strain map at a fixed γ, Ie = A(γ) j, applied by its seven non-zero entries
///
/// A = [[p, q, 0, 0, 0], [0, r, 0, 0, 0], [0, 0, u, v, 0], [0, 0, 0, w, 0], [0, 0, 0, 0, z]],
///
/// with the factor φ = det F_a, and their first and second γ-derivatives (c = 1 − γ, s = 1/c,
/// ds/dγ = s², d(s²)/dγ = 2s³, d(2s³)/dγ = 6s⁴, d(c²)/dγ = −2c):
///
/// | | p | q | r | u | v | w | z | φ |
/// |---|---|---|---|---|---|---|---|---|
/// | chapter | 1 | s² − 1 | s² | 1 | c² − 1 | c² | s² | c |
/// | ′ | 0 | 2s³ | 2s³ | 0 | −2c | −2c | 2s³ | −1 |
/// | ″ | 0 | 6s⁴ | 6s⁴ | 0 | 2 | 2 | 6s⁴ | 0 |
/// | volume-preserving | c | s² − c | s² | s | c² − s | c² | 1 | 1 |
/// | ′ | −1 | 2s³ + 1 | 2s³ | s² | −2c − s² | −2c | 0 | 0 |
/// | ″ | 0 | 6s⁴ | 6s⁴ | 2s³ | 2 − 2s³ | 2 | 0 | 0 |
#[derive(Debug, Clone, Copy)]
pub(crate) struct StrainMap {
    /// [p, q, r, u, v, w, z].
    a: [f64; 7],
    /// Their γ-derivatives.
    a1: [f64; 7],
    /// Their second γ-derivatives.
    a2: [f64; 7],
    /// φ = det F_a.
    pub det: f64,
    /// dφ/dγ.
    pub det_rate: f64,
    /// d²φ/dγ².
    pub det_rate2: f64,
}

impl StrainMap {
    #[inline]
    pub fn new(map: ActiveStrainMap, gamma: f64) -> Self {
        let c = 1.0 - gamma;
        let s = 1.0 / c;
        let s2 = s * s;
        let (s3, s4, c2) = (s2 * s, s2 * s2, c * c);
        match map {
            ActiveStrainMap::Chapter => Self {
                a: [1.0, s2 - 1.0, s2, 1.0, c2 - 1.0, c2, s2],
                a1: [0.0, 2.0 * s3, 2.0 * s3, 0.0, -2.0 * c, -2.0 * c, 2.0 * s3],
                a2: [0.0, 6.0 * s4, 6.0 * s4, 0.0, 2.0, 2.0, 6.0 * s4],
                det: c,
                det_rate: -1.0,
                det_rate2: 0.0,
            },
            ActiveStrainMap::VolumePreserving => Self {
                a: [c, s2 - c, s2, s, c2 - s, c2, 1.0],
                a1: [
                    -1.0,
                    2.0 * s3 + 1.0,
                    2.0 * s3,
                    s2,
                    -2.0 * c - s2,
                    -2.0 * c,
                    0.0,
                ],
                a2: [0.0, 6.0 * s4, 6.0 * s4, 2.0 * s3, 2.0 - 2.0 * s3, 2.0, 0.0],
                det: 1.0,
                det_rate: 0.0,
                det_rate2: 0.0,
            },
        }
    }

    /// B j for the map B with entries `b` = [p, q, r, u, v, w, z].
    #[inline(always)]
    fn times(b: &[f64; 7], j: &SVector<f64, 5>) -> SVector<f64, 5> {
        SVector::from([
            b[0] * j[0] + b[1] * j[1],
            b[2] * j[1],
            b[3] * j[2] + b[4] * j[3],
            b[5] * j[3],
            b[6] * j[4],
        ])
    }

    /// Bᵀ y for the map B with entries `b`.
    #[inline(always)]
    fn transpose_times(b: &[f64; 7], y: &SVector<f64, 5>) -> SVector<f64, 5> {
        SVector::from([
            b[0] * y[0],
            b[1] * y[0] + b[2] * y[1],
            b[3] * y[2],
            b[4] * y[2] + b[5] * y[3],
            b[6] * y[4],
        ])
    }

    /// Ie = A j.
    #[inline]
    pub fn apply(&self, j: &SVector<f64, 5>) -> SVector<f64, 5> {
        Self::times(&self.a, j)
    }

    /// (A X)_rk for the rows r of X (one per invariant): the gradients of the elastic
    /// invariants from those of the invariants of C.
    #[inline(always)]
    pub fn row<const N: usize>(&self, r: usize, x: &SMatrix<f64, 5, N>, k: usize) -> f64 {
        let a = &self.a;
        match r {
            0 => a[0] * x[(0, k)] + a[1] * x[(1, k)],
            1 => a[2] * x[(1, k)],
            2 => a[3] * x[(2, k)] + a[4] * x[(3, k)],
            3 => a[5] * x[(3, k)],
            _ => a[6] * x[(4, k)],
        }
    }

    /// Aᵀ y.
    #[inline]
    pub fn transpose_apply(&self, y: &SVector<f64, 5>) -> SVector<f64, 5> {
        Self::transpose_times(&self.a, y)
    }

    /// dIe/dγ = (dA/dγ) j.
    #[inline]
    pub fn rate(&self, j: &SVector<f64, 5>) -> SVector<f64, 5> {
        Self::times(&self.a1, j)
    }

    /// d²Ie/dγ² = (d²A/dγ²) j.
    #[inline]
    pub fn rate2(&self, j: &SVector<f64, 5>) -> SVector<f64, 5> {
        Self::times(&self.a2, j)
    }

    /// (dA/dγ)ᵀ y.
    #[inline]
    pub fn rate_transpose_apply(&self, y: &SVector<f64, 5>) -> SVector<f64, 5> {
        Self::transpose_times(&self.a1, y)
    }

    /// X A, by columns.
    #[inline(always)]
    fn right(&self, x: &SMatrix<f64, 5, 5>) -> SMatrix<f64, 5, 5> {
        let a = &self.a;
        let mut y = *x;
        for r in 0..5 {
            y[(r, 0)] = a[0] * x[(r, 0)];
            y[(r, 1)] = a[1] * x[(r, 0)] + a[2] * x[(r, 1)];
            y[(r, 2)] = a[3] * x[(r, 2)];
            y[(r, 3)] = a[4] * x[(r, 2)] + a[5] * x[(r, 3)];
            y[(r, 4)] = a[6] * x[(r, 4)];
        }
        y
    }

    /// Aᵀ H A for a symmetric H.
    #[inline(always)]
    pub fn congruence(&self, h: &SMatrix<f64, 5, 5>) -> SMatrix<f64, 5, 5> {
        self.right(&self.right(h).transpose())
    }
}
