use super::ShippedApproach;
use crate::active::coupling::CouplingKind;
use crate::active::law::LawKind;
use crate::active::map::ActivationMap;
use crate::energy::StrainEnergy;

/// The activation in the structural tensor (Ehret, Böl & Itskov 2011; 4C's
/// MAT_Muscle_Weickenmeier): W with I = C:(L + ωM), L = (w0/3) I + (1 − w0) M, ω = g(λ_f) ≥ 0,
/// for an energy that depends on C:M only through I = C:L ([`ActivationMap::structural`]). The
/// implicit and the energy law give ω, frozen or consistent.
#[derive(Debug, Clone, Copy)]
pub struct Structural;

impl ShippedApproach for Structural {
    const NAME: &'static str = "structural";
    const VARIABLE: Option<&'static str> = Some("ω");
    const LAWS: &'static [LawKind] = &[LawKind::Implicit, LawKind::Energy];
    const COUPLINGS: &'static [CouplingKind] = &CouplingKind::ALL;
    const MAPS: &'static [ActivationMap] = &[];
    const NO_LAW: &'static str =
        "the explicit law (eq. (14)) is fitted for active strain; the structural approach's ω is given by the implicit or the energy law";
    const NO_MAP: &'static str = "the structural approach activates the energy's own structural invariant I = C:(L + ωM): its map is not chosen";

    fn map<E: StrainEnergy>(energy: &E, _named: ActivationMap) -> Result<ActivationMap, String> {
        ActivationMap::structural(energy).ok_or_else(|| {
            format!(
                "the structural approach activates the structural invariant I = C:(L + ωM) of an \
                 energy that depends on C:M only through I = C:L (giantesio-musesti, \
                 ehret-bol-itskov, 4c-passive); material.energy is {}",
                energy.name()
            )
        })
    }

    fn words(_map: ActivationMap) -> &'static str {
        "structural, "
    }

    fn row(_map: ActivationMap) -> [&'static str; 3] {
        [
            "ω, activation",
            "activation in the structural tensor (Ehret, Böl & Itskov 2011; 4C's MAT_Muscle_Weickenmeier): W with I = C:(L + ωM), L = (w0/3) I + (1 − w0) M, ω = g(λ_f)",
            "not in the chapter",
        ]
    }
}
