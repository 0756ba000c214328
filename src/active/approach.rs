//! The three ways to activate a fibre-reinforced energy, all calibrated to the same uniaxial
//! target P_pas + T(λ), T = (1 − d)·a·f_v·P_act ([`crate::active::drive`]) (in a scene:
//! `[activation] approach = "active-strain" | "active-stress" | "structural"`):
//!
//! | approach | energy | activation | law, coupling |
//! |---|---|---|---|
//! | active strain (the chapter's) | Ŵ(F, γ) = φ(γ) W(C_e), F = F_e F_a | γ = g(λ_f) ∈ [0, 1), `map = "chapter" \| "volume-preserving"` | any law, frozen or consistent |
//! | active stress (FEBio, Blemker) | Ψ = W_pas(C) + (1 − d)·a ∫_{λ_min}^{λ_f} P_act | none | none: P = ∂W_pas/∂F + T(λ_f) F M/λ_f is hyperelastic (f_v = 1) |
//! | structural (Ehret, Böl & Itskov 2011; 4C's MAT_Muscle_Weickenmeier) | W with I = C:(L + ωM) | ω = g(λ_f) ≥ 0 | any law but the explicit one, frozen or consistent |
//!
//! They agree along the fibres by construction and differ elsewhere (Giantesio, Musesti &
//! Riccobelli 2019: in simple shear along the fibres λ_f stays 1, so active stress only adds
//! σ₁₁ while active strain changes the shear stiffness).

use crate::active::curve::ActiveCurve;
use crate::active::drive::Drive;

/// An activation approach by name (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Approach {
    /// Active strain F = F_e F_a with the scene's `map`.
    #[default]
    ActiveStrain,
    /// Active stress: the target stress added along the fibres, no activation variable.
    ActiveStress,
    /// The activation ω in the structural tensor, I = C:(L + ωM).
    Structural,
}

impl Approach {
    /// Every approach, in the order of the enum.
    pub const ALL: [Approach; 3] = [
        Approach::ActiveStrain,
        Approach::ActiveStress,
        Approach::Structural,
    ];

    /// Name in scene files and outputs: active-strain, active-stress, structural.
    pub fn name(self) -> &'static str {
        match self {
            Approach::ActiveStrain => "active-strain",
            Approach::ActiveStress => "active-stress",
            Approach::Structural => "structural",
        }
    }

    /// Whether the approach has an activation variable, hence a law and a coupling.
    pub fn has_law(self) -> bool {
        self != Approach::ActiveStress
    }
}

/// The active-stress term of the energy as a function of c = C:M = λ_f²: E(c) with λ = √c and
/// dE/dλ = T(λ) (so that P = T(λ_f) F M/λ_f), returned as (E, dE/dc, d²E/dc²) with
/// dE/dc = T/(2λ) and d²E/dc² = (T′ − T/λ)/(4λ²). E itself is the active work
/// (1 − d)·a·f_v ∫P_act ([`Drive::work`]); with a stretch rate E is not a potential of the stress
/// (f_v′ is not in dE/dλ), as in every code that writes active stress with force–velocity.
pub fn active_stress_terms(drive: &Drive, curve: &ActiveCurve, c_m: f64) -> (f64, f64, f64) {
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
