//! The model choice of a study: an activation approach, law, coupling and damage by name
//! ([`ModelChoice`]), and their product over a study's lists.

pub use crate::active::{Approach, CouplingKind, LawKind};
use serde::{Deserialize, Serialize};

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

/// One activation model: approach, law, coupling, damage. An approach without a law (active
/// stress) reads neither `law` nor `coupling` (they hold the defaults): tables and labels take
/// them through [`ModelChoice::activation_law`], which says so.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelChoice {
    /// Activation approach.
    pub approach: Approach,
    /// Activation law (of an approach that has one).
    pub law: LawKind,
    /// Coupling (of an approach that has a law).
    pub coupling: CouplingKind,
    /// Damage d ∈ [0, 1].
    pub damage: f64,
}

impl ModelChoice {
    /// The model of an approach without a law, at damage d: one per damage.
    pub fn lawless(approach: Approach, damage: f64) -> Self {
        Self {
            approach,
            law: LawKind::default(),
            coupling: CouplingKind::default(),
            damage,
        }
    }

    /// Its law and coupling; `None` for an approach that has no law.
    pub fn activation_law(&self) -> Option<(LawKind, CouplingKind)> {
        (!self.approach.laws().is_empty()).then_some((self.law, self.coupling))
    }

    /// The law's name as a table writes it (`None`: the approach has no law).
    pub fn law_name(&self) -> Option<&'static str> {
        self.activation_law().map(|(l, _)| l.name())
    }

    /// The coupling's name as a table writes it (`None`: the approach has no law).
    pub fn coupling_name(&self) -> Option<&'static str> {
        self.activation_law().map(|(_, c)| c.name())
    }
}

/// Every approach × law × coupling × damage, in that order of nesting; an approach without a
/// law gives one model per damage. The laws and couplings are those of the approaches that have
/// one (the studies refuse, at their keys, a law an approach does not list).
pub fn product(
    approaches: &[Approach],
    laws: &[LawKind],
    couplings: &[CouplingKind],
    damages: &[f64],
) -> Vec<ModelChoice> {
    let mut models = Vec::new();
    for &approach in approaches {
        if approach.laws().is_empty() {
            models.extend(damages.iter().map(|&d| ModelChoice::lawless(approach, d)));
            continue;
        }
        for &law in laws {
            for &coupling in couplings {
                for &damage in damages {
                    models.push(ModelChoice {
                        approach,
                        law,
                        coupling,
                        damage,
                    });
                }
            }
        }
    }
    models
}
