use super::ShippedApproach;
use crate::active::coupling::CouplingKind;
use crate::active::curve::ActiveCurve;
use crate::active::drive::Drive;
use crate::active::law::LawKind;
use crate::active::map::ActivationMap;
use crate::energy::StrainEnergy;

/// Active stress (FEBio's prescribed active contraction, Blemker's muscle): the target stress
/// added along the fibres, Ψ = W(C) + E(λ_f) with dE/dλ = T(λ) = (1 − d)·a·f_v·P_act(λ), so that
/// P = ∂W/∂F + T(λ_f) F M/λ_f (− p F⁻ᵀ under the constraint). No activation variable, hence no
/// law and no coupling: the target is met by construction along the fibres, and without
/// force–velocity Ψ is hyperelastic.
#[derive(Debug, Clone, Copy)]
pub struct ActiveStress;

impl ShippedApproach for ActiveStress {
    const NAME: &'static str = "active-stress";
    const VARIABLE: Option<&'static str> = None;
    const LAWS: &'static [LawKind] = &[];
    const COUPLINGS: &'static [CouplingKind] = &[];
    const MAPS: &'static [ActivationMap] = &[];
    const NO_LAW: &'static str = "active stress has no activation variable, hence no law and no coupling: P = ∂W/∂F + T(λ_f) F M/λ_f meets the target along the fibres by construction";
    const NO_MAP: &'static str = "active stress activates no energy, so it has no activation map";
    const FIBRE_ENERGY: bool = true;

    /// The identity at γ = 0: the passive energy is not activated.
    fn map<E: StrainEnergy>(_energy: &E, _named: ActivationMap) -> Result<ActivationMap, String> {
        Ok(ActivationMap::Chapter)
    }

    /// E(c) with λ = √c and dE/dλ = T(λ), as (E, dE/dc, d²E/dc²) with dE/dc = T/(2λ) and
    /// d²E/dc² = (T′ − T/λ)/(4λ²). E itself is the active work (1 − d)·a·f_v ∫P_act
    /// ([`Drive::work`]); with a stretch rate E is not a potential of the stress (f_v′ is not in
    /// dE/dλ), as in every code that writes active stress with force–velocity.
    fn fibre_energy(drive: &Drive, curve: &ActiveCurve, c_m: f64) -> (f64, f64, f64) {
        let lambda = c_m.sqrt();
        if drive.is_off() || lambda <= curve.lambda_min() {
            return (0.0, 0.0, 0.0);
        }
        let (t, t_l) = num_dual::first_derivative(|l| drive.target(curve, l), lambda);
        let work = drive.work(curve, lambda);
        let d_c = t / (2.0 * lambda);
        let d_cc = (t_l - t / lambda) / (4.0 * lambda * lambda);
        (work, d_c, d_cc)
    }

    fn words(_map: ActivationMap) -> &'static str {
        "active stress, "
    }

    fn row(_map: ActivationMap) -> [&'static str; 3] {
        [
            "active stress",
            "Ψ = W_pas(C) + (1 − d) ∫_{λ_min}^{λ_f} P_act, P = ∂W_pas/∂F + (1 − d) P_act(λ_f) F M/λ_f (FEBio, Blemker): no activation variable, no law; hyperelastic",
            "not in the chapter",
        ]
    }
}
