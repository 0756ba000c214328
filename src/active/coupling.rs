//! Frozen versus consistent coupling of an activation law γ = g(λ_f) to the energy Ŵ(F, γ).
//!
//! Writing γ as a function of the invariant j₂ = C:M = λ_f², γ = G(j₂) = g(√j₂) with
//! G′ = g′/(2λ), G″ = (g″ − g′/λ)/(4λ²), both couplings live in the space of the five
//! invariants j (e₂ is the unit vector of j₂):
//!
//! - **Frozen** (the chapter's model): P = ∂Ŵ/∂F at γ = G(j₂), γ held. Not a gradient. Its exact
//!   linearisation has the invariant-space Hessian K = Ŵ_jj + Ŵ_jγ ⊗ G′e₂, not symmetric;
//!   [`FrozenTangent::Symmetric`] drops the second term (symmetric, inexact: Newton converges
//!   linearly).
//! - **Consistent** (truly hyperelastic): Ψ(F) = Ŵ(F, G(j₂)), gradient Ŵ_j + Ŵ_γ G′ e₂ and
//!   Hessian K = Ŵ_jj + Ŵ_jγ ⊗ G′e₂ + G′e₂ ⊗ Ŵ_jγ + (Ŵ_γγ G′² + Ŵ_γ G″) e₂ ⊗ e₂, symmetric.
//!
//! The stress and tangent in F then follow by the chain rule of [`crate::invariants`]:
//! P = Dᵀ Ψ_j, ∂P/∂F = Dᵀ K D + Σ_j Ψ_j ∂²j/∂F².

use super::law::LawValue;
use crate::response::InvariantDerivatives;
use nalgebra::{SMatrix, SVector};

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

/// dγ/dj₂ and d²γ/dj₂² from dγ/dλ and d²γ/dλ² at λ = √j₂.
pub fn invariant_slopes(law: &LawValue, fibre_stretch: f64) -> (f64, f64) {
    let l = fibre_stretch;
    (
        law.slope / (2.0 * l),
        (law.curvature - law.slope / l) / (4.0 * l * l),
    )
}

/// Invariant-space gradient Ψ_j and (if `d` carries second derivatives) Hessian K of the coupled
/// response, see the module docs.
pub fn couple(
    coupling: Coupling,
    d: &InvariantDerivatives,
    law: &LawValue,
    fibre_stretch: f64,
) -> (SVector<f64, 5>, Option<SMatrix<f64, 5, 5>>) {
    let (g1, g2) = invariant_slopes(law, fibre_stretch);
    let mut gradient = d.d_j;
    if coupling == Coupling::Consistent {
        gradient[1] += d.d_gamma * g1;
    }
    let hessian = d.second.as_ref().map(|s| {
        let mut k = s.d_jj;
        match coupling {
            Coupling::Frozen(FrozenTangent::Symmetric) => {}
            Coupling::Frozen(FrozenTangent::Exact) => {
                for r in 0..5 {
                    k[(r, 1)] += s.d_jgamma[r] * g1;
                }
            }
            Coupling::Consistent => {
                for r in 0..5 {
                    k[(r, 1)] += s.d_jgamma[r] * g1;
                    k[(1, r)] += s.d_jgamma[r] * g1;
                }
                k[(1, 1)] += s.d_gammagamma * g1 * g1 + d.d_gamma * g2;
            }
        }
        k
    });
    (gradient, hessian)
}
