//! The model choice of a study: an activation law, a coupling and a damage by name
//! ([`ModelChoice`]), and their product over a study's lists.

use serde::{Deserialize, Serialize};

/// An activation law by name (`law = "implicit"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum LawKind {
    /// The chapter's exact fit, eq. (13) solved numerically ([`ImplicitLaw`]).
    #[default]
    Implicit,
    /// The chapter's closed form, eq. (14) ([`ExplicitLaw`]).
    Explicit,
    /// The energy-consistent fit ([`EnergyLaw`]).
    Energy,
}

impl LawKind {
    /// Name in scene files and outputs.
    pub fn name(self) -> &'static str {
        match self {
            LawKind::Implicit => "implicit",
            LawKind::Explicit => "explicit",
            LawKind::Energy => "energy",
        }
    }
}

/// A coupling by name (`coupling = "frozen"`); the frozen model's tangent is the scene's
/// `frozen_tangent`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CouplingKind {
    /// The chapter's model: γ held in the stress ([`Coupling::Frozen`]).
    #[default]
    Frozen,
    /// Truly hyperelastic: Ψ(F) = Ŵ(F, g(λ_f(F))) ([`Coupling::Consistent`]).
    Consistent,
}

impl CouplingKind {
    /// Name in scene files and outputs.
    pub fn name(self) -> &'static str {
        match self {
            CouplingKind::Frozen => "frozen",
            CouplingKind::Consistent => "consistent",
        }
    }
}

/// How the laws that solve an equation for γ (implicit, energy) are evaluated
/// (`representation = "tabulated"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RepresentationKind {
    /// Solved at every evaluation.
    #[default]
    Exact,
    /// From a table built once per damage and checked against the exact solve
    /// ([`crate::active::TabulatedLaw`]): |Δγ| ≤ 1e-12, fibre stress within 1e-9 kPa + 1e-13 |P|.
    Tabulated,
}

/// One activation model: law, coupling, damage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelChoice {
    /// Activation law.
    pub law: LawKind,
    /// Coupling.
    pub coupling: CouplingKind,
    /// Damage d ∈ [0, 1].
    pub damage: f64,
}

/// Every law × coupling × damage, in that order of nesting.
pub fn product(laws: &[LawKind], couplings: &[CouplingKind], damages: &[f64]) -> Vec<ModelChoice> {
    let mut models = Vec::with_capacity(laws.len() * couplings.len() * damages.len());
    for &law in laws {
        for &coupling in couplings {
            for &damage in damages {
                models.push(ModelChoice {
                    law,
                    coupling,
                    damage,
                });
            }
        }
    }
    models
}
