//! Frozen versus consistent coupling of an activation law γ = g(λ_f) to the energy Ŵ(F, γ).
//!
//! Writing γ as a function of the invariant j₂ = C:M = λ_f², γ = G(j₂) = g(√j₂) with
//! G′ = g′/(2λ), G″ = (g″ − g′/λ)/(4λ²), and D₂ = ∂j₂/∂F (so ∂γ/∂F = G′ D₂), with P, ∂P/∂F and
//! dP/dγ those of Ŵ at γ held ([`crate::response`]):
//!
//! - **Frozen** (the chapter's model): P at γ = G(j₂), γ held. Not a gradient. Its exact
//!   linearisation is ∂P/∂F + (dP/dγ) ⊗ G′D₂, not symmetric; [`FrozenTangent::Symmetric`] drops
//!   the second term (symmetric, inexact: Newton converges linearly).
//! - **Consistent** (truly hyperelastic): Ψ(F) = Ŵ(F, G(j₂)), stress P + Ŵ_γ G′ D₂ and tangent
//!   ∂P/∂F + (dP/dγ) ⊗ G′D₂ + G′D₂ ⊗ (dP/dγ) + (Ŵ_γγ G′² + Ŵ_γ G″) D₂ ⊗ D₂ + Ŵ_γ G′ ∂²j₂/∂F²,
//!   symmetric. The first and last terms are those of Ŵ with ∂Ŵ/∂j₂ raised by Ŵ_γ G′ (see
//!   [`crate::response`]'s F-space assembly).

use super::law::LawValue;

/// Which linearisation the frozen model uses (in a scene: `frozen_tangent = "exact" | "symmetric"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FrozenTangent {
    /// The exact (non-symmetric) linearisation: quadratic Newton convergence.
    #[default]
    Exact,
    /// ∂²Ŵ/∂F² at frozen γ only: symmetric, inexact, linear Newton convergence.
    Symmetric,
}

/// How the activation law enters the stress.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coupling {
    /// The chapter's model: P = ∂Ŵ/∂F with γ = g(λ_f) held fixed.
    Frozen(FrozenTangent),
    /// The hyperelastic model Ψ(F) = Ŵ(F, g(λ_f(F))).
    Consistent,
}

impl Coupling {
    /// Name used in logs and output files: frozen, consistent.
    pub fn name(&self) -> &'static str {
        match self {
            Coupling::Frozen(_) => "frozen",
            Coupling::Consistent => "consistent",
        }
    }

    /// Whether the tangent this coupling produces is major-symmetric.
    pub fn symmetric_tangent(&self) -> bool {
        !matches!(self, Coupling::Frozen(FrozenTangent::Exact))
    }
}

/// A coupling by name (`coupling = "frozen"`); the frozen model's tangent is the scene's
/// `frozen_tangent`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CouplingKind {
    /// The chapter's model: γ held in the stress ([`Coupling::Frozen`]).
    #[default]
    Frozen,
    /// Truly hyperelastic: Ψ(F) = Ŵ(F, g(λ_f(F))) ([`Coupling::Consistent`]).
    Consistent,
}

impl CouplingKind {
    /// Every coupling, in the order of the enum.
    pub const ALL: [CouplingKind; 2] = [CouplingKind::Frozen, CouplingKind::Consistent];

    /// Name in scene files and outputs.
    pub fn name(self) -> &'static str {
        match self {
            CouplingKind::Frozen => "frozen",
            CouplingKind::Consistent => "consistent",
        }
    }
}

/// dγ/dj₂ and d²γ/dj₂² from dγ/dλ and d²γ/dλ² at λ = √j₂.
pub fn invariant_slopes(law: &LawValue, fibre_stretch: f64) -> (f64, f64) {
    let l = fibre_stretch;
    (
        law.slope / (2.0 * l),
        (law.curvature - law.slope / l) / (4.0 * l * l),
    )
}
