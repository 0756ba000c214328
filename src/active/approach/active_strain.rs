use super::ShippedApproach;
use crate::active::coupling::CouplingKind;
use crate::active::law::LawKind;
use crate::active::map::ActivationMap;
use crate::energy::StrainEnergy;

/// Active strain, the chapter's (eqs. (5)–(6)): F = F_e F_a, Ŵ(F, γ) = φ(γ) W(C_e) with
/// C_e = F_a⁻ᵀ C F_a⁻¹ and γ = g(λ_f) ∈ [0, 1), F_a the scene's `map`: the chapter's
/// F_a = I − γ M (φ = 1 − γ) or the volume-preserving F_a = (1 − γ) M + (1 − γ)^(−½)(I − M)
/// (φ = 1; Weickenmeier et al. 2014, 4C's MAT_Muscle_Giantesio). Any energy, any law, either
/// coupling (see [`crate::active::strain`]).
#[derive(Debug, Clone, Copy)]
pub struct ActiveStrain;

impl ShippedApproach for ActiveStrain {
    const NAME: &'static str = "active-strain";
    const VARIABLE: Option<&'static str> = Some("γ");
    const LAWS: &'static [LawKind] = &LawKind::ALL;
    const COUPLINGS: &'static [CouplingKind] = &CouplingKind::ALL;
    const MAPS: &'static [ActivationMap] = &ActivationMap::NAMED;
    const NO_LAW: &'static str = "";
    const NO_MAP: &'static str = "";

    fn map<E: StrainEnergy>(_energy: &E, named: ActivationMap) -> Result<ActivationMap, String> {
        Ok(named)
    }

    fn words(map: ActivationMap) -> &'static str {
        match map {
            ActivationMap::VolumePreserving => "volume-preserving active strain, ",
            _ => "",
        }
    }

    fn row(map: ActivationMap) -> [&'static str; 3] {
        match map {
            ActivationMap::VolumePreserving => [
                "γ, activation",
                "active strain F = F_e F_a with the volume-preserving F_a = (1 − γ) m⊗m + (1 − γ)^(−½)(I − m⊗m) (Weickenmeier et al. 2014; 4C's MAT_Muscle_Giantesio), Ŵ(F, γ) = W(C_e)",
                "eqs. (5)–(6) with another F_a",
            ],
            _ => [
                "γ, activation",
                "active strain F = F_e F_a, F_a = I − γ m⊗m, Ŵ(F, γ) = (1 − γ) W(C_e)",
                "eqs. (5)–(6)",
            ],
        }
    }
}
