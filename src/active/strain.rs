//! Active strain: F = F_e F_a, and Ŵ(F, γ) = det F_a · W(F_a⁻ᵀ C F_a⁻¹), for either active-strain
//! map of [`ActivationMap`] (`Chapter`, `VolumePreserving`). Both are F_a = a M + b (I − M), so F_a⁻¹ = (1/a) M + (1/b)(I − M)
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

/// [`ActivationMap::elastic_invariants`] of the chapter's map.
pub fn elastic_invariants<T: Scalar>(j: &[T; 5], gamma: T) -> [T; 5] {
    ActivationMap::Chapter.elastic_invariants(j, gamma)
}

/// [`ActivationMap::active_energy`] of the chapter's map: Ŵ = (1 − γ) W(C_e).
pub fn active_energy<E: StrainEnergy, T: Scalar>(energy: &E, j: &[T; 5], gamma: T) -> T {
    ActivationMap::Chapter.active_energy(energy, j, gamma)
}

/// [`ActivationMap::fibre_path_energy`] of the chapter's map (eq. D:Wattgamma).
pub fn fibre_path_energy<E: StrainEnergy, T: Scalar>(energy: &E, lambda: T, gamma: T) -> T {
    ActivationMap::Chapter.fibre_path_energy(energy, lambda, gamma)
}
