//! How the activation variable enters the invariants: Ŵ(j, γ) = φ(γ) W(A(γ) j), a linear map A
//! of the invariants j = [tr C, C:M, tr C⁻¹, C⁻¹:M, det C] of C and a factor φ, for each approach
//! that activates the energy itself:
//!
//! | [`ActivationMap`] | approach | variable | Ie = A j | φ |
//! |---|---|---|---|---|
//! | `Chapter` | active strain, F_a = I − γ M (the chapter's) | γ ∈ [0, 1) | invariants of C_e = F_a⁻ᵀ C F_a⁻¹ | 1 − γ |
//! | `VolumePreserving` | active strain, F_a = (1 − γ) M + (1 − γ)^(−½)(I − M) | γ ∈ [0, 1) | invariants of C_e | 1 |
//! | `Structural` | Ehret, Böl & Itskov (2011): I = C:(L + ω M) | ω ≥ 0 | C:M ↦ (1 + ω/f) C:M | 1 |
//!
//! The active-strain maps are tabulated in [`crate::active::strain`]; a scene chooses between
//! them with `[activation] map = "chapter" | "volume-preserving"` (the structural map is the
//! structural approach's own, [`crate::active::approach`]). The structural one acts on
//! an energy whose only dependence on C:M is through I = C:L, L = (w0/3) I + (1 − w0) M (the
//! chapter's, Ehret–Böl–Itskov's and 4C's energies; [`StrainEnergy::structural_fibre_weight`]
//! returns f = 1 − w0): then C:(L + ωM) = I + ω C:M = (w0/3) tr C + f (1 + ω/f) C:M. It changes
//! neither J = cof C : L (4C's MAT_Muscle_Weickenmeier) nor K_p. The map is owned by the
//! framework: any energy plugs in unchanged.

use crate::energy::{Invariants, StrainEnergy};
use crate::{Error, Result, Scalar};
use nalgebra::{SMatrix, SVector};

/// How a muscle's activation variable enters its energy (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum ActivationMap {
    /// The chapter's active strain F_a = I − γ M.
    #[default]
    Chapter,
    /// The volume-preserving active strain of Weickenmeier et al. (2014) (4C's
    /// MAT_Muscle_Giantesio).
    VolumePreserving,
    /// Ehret, Böl & Itskov's activation in the structural tensor (4C's MAT_Muscle_Weickenmeier),
    /// for an energy whose weight of C:M in I = C:L is `fibre_weight` = 1 − w0.
    Structural {
        /// f = 1 − w0 ∈ (0, 1].
        fibre_weight: f64,
    },
}

impl ActivationMap {
    /// The maps a scene chooses by name (`map = "..."`): the active-strain maps.
    pub const NAMED: [ActivationMap; 2] = [ActivationMap::Chapter, ActivationMap::VolumePreserving];

    /// Name used in scenes, logs and output files: chapter, volume-preserving, structural.
    pub fn name(&self) -> &'static str {
        match self {
            ActivationMap::Chapter => "chapter",
            ActivationMap::VolumePreserving => "volume-preserving",
            ActivationMap::Structural { .. } => "structural",
        }
    }

    /// The structural map of `energy`, if the energy has a structural invariant I = C:L.
    pub fn structural<E: StrainEnergy>(energy: &E) -> Option<Self> {
        energy
            .structural_fibre_weight()
            .filter(|f| *f > 0.0 && *f <= 1.0)
            .map(|fibre_weight| ActivationMap::Structural { fibre_weight })
    }

    /// The (open) upper end of the variable's range: 1 for γ, ∞ for ω.
    pub fn upper_bound(&self) -> f64 {
        match self {
            ActivationMap::Structural { .. } => f64::INFINITY,
            _ => 1.0,
        }
    }

    /// Rejects γ ∉ [0, 1) for active strain, ω ∉ [0, ∞) for the structural map (and any
    /// non-finite value).
    pub fn check(&self, value: f64) -> Result<f64> {
        if value >= 0.0 && value < self.upper_bound() {
            Ok(value)
        } else {
            Err(Error::ActivationOutOfRange { gamma: value })
        }
    }

    /// Invariants of the activated material, Ie = A(γ) j, from the invariants `j` of C.
    pub fn elastic_invariants<T: Scalar>(&self, j: &[T; 5], gamma: T) -> [T; 5] {
        match self {
            ActivationMap::Chapter => {
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
            ActivationMap::VolumePreserving => {
                let c = -gamma + 1.0;
                let c2 = c * c;
                let s2 = c2.recip();
                let s = c.recip();
                [
                    j[0] * c + j[1] * (s2 - c),
                    j[1] * s2,
                    j[2] * s + j[3] * (c2 - s),
                    j[3] * c2,
                    j[4],
                ]
            }
            ActivationMap::Structural { fibre_weight } => {
                [j[0], j[1] * (gamma / *fibre_weight + 1.0), j[2], j[3], j[4]]
            }
        }
    }

    /// Ŵ(j, γ) = φ(γ) W(A(γ) j) as a generic function of the invariants of C and of the
    /// activation (no range check: callers check it once).
    pub fn active_energy<E: StrainEnergy, T: Scalar>(&self, energy: &E, j: &[T; 5], gamma: T) -> T {
        let w = energy.energy(&Invariants::from_array(self.elastic_invariants(j, gamma)));
        match self {
            ActivationMap::Chapter => (-gamma + 1.0) * w,
            _ => w,
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

/// Written by its name.
impl serde::Serialize for ActivationMap {
    fn serialize<S: serde::Serializer>(
        &self,
        serializer: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}

/// Read by name, one of [`ActivationMap::NAMED`].
impl<'de> serde::Deserialize<'de> for ActivationMap {
    fn deserialize<D: serde::Deserializer<'de>>(
        deserializer: D,
    ) -> std::result::Result<Self, D::Error> {
        let name = String::deserialize(deserializer)?;
        Self::NAMED
            .into_iter()
            .find(|m| m.name() == name)
            .ok_or_else(|| {
                serde::de::Error::unknown_variant(&name, &["chapter", "volume-preserving"])
            })
    }
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

/// The activation map at a fixed activation γ (or ω), Ie = A(γ) j, applied by its seven entries
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
/// | structural (ω, f = fibre weight) | 1 | 0 | 1 + ω/f | 1 | 0 | 1 | 1 | 1 |
/// | ′ | 0 | 0 | 1/f | 0 | 0 | 0 | 0 | 0 |
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
    pub fn new(map: ActivationMap, gamma: f64) -> Self {
        match map {
            ActivationMap::Structural { fibre_weight } => {
                // C:M ↦ (1 + ω/f) C:M, nothing else: Ie = C:(L + ωM) for I = C:L.
                let r1 = 1.0 / fibre_weight;
                return Self {
                    a: [1.0, 0.0, 1.0 + gamma * r1, 1.0, 0.0, 1.0, 1.0],
                    a1: [0.0, 0.0, r1, 0.0, 0.0, 0.0, 0.0],
                    a2: [0.0; 7],
                    det: 1.0,
                    det_rate: 0.0,
                    det_rate2: 0.0,
                };
            }
            ActivationMap::Chapter | ActivationMap::VolumePreserving => {}
        }
        let c = 1.0 - gamma;
        let s = 1.0 / c;
        let s2 = s * s;
        let (s3, s4, c2) = (s2 * s, s2 * s2, c * c);
        if map == ActivationMap::Chapter {
            Self {
                a: [1.0, s2 - 1.0, s2, 1.0, c2 - 1.0, c2, s2],
                a1: [0.0, 2.0 * s3, 2.0 * s3, 0.0, -2.0 * c, -2.0 * c, 2.0 * s3],
                a2: [0.0, 6.0 * s4, 6.0 * s4, 0.0, 2.0, 2.0, 6.0 * s4],
                det: c,
                det_rate: -1.0,
                det_rate2: 0.0,
            }
        } else {
            Self {
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
            }
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
