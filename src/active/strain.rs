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

use crate::active::map::ActivationMap;
use crate::energy::StrainEnergy;
use crate::{Error, Result, Scalar};

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
        ActivationMap::from(*self).elastic_invariants(j, gamma)
    }

    /// Ŵ(j, γ) = det F_a · W(C_e): the active-strain energy as a generic function of the
    /// invariants of C and of γ (no range check: callers check γ once).
    pub fn active_energy<E: StrainEnergy, T: Scalar>(&self, energy: &E, j: &[T; 5], gamma: T) -> T {
        ActivationMap::from(*self).active_energy(energy, j, gamma)
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
        ActivationMap::from(*self).fibre_path_energy(energy, lambda, gamma)
    }
}

impl From<ActiveStrainMap> for ActivationMap {
    fn from(map: ActiveStrainMap) -> Self {
        match map {
            ActiveStrainMap::Chapter => ActivationMap::Chapter,
            ActiveStrainMap::VolumePreserving => ActivationMap::VolumePreserving,
        }
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
