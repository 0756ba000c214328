//! Models from choices: the scene's material and activation ([`Models`]) build the activation
//! law, the coupling and the muscle of a [`ModelChoice`] (law × coupling × damage); an
//! [`EnergySpec`] (a shipped energy by name, parameters by name) builds an [`Energy`] from the
//! registry [`crate::energy::SHIPPED`]. The scene and every study build their models here.
//!
//! | module | what |
//! |---|---|
//! | [`choice`] | a law, a coupling and a damage by name |
//! | [`factory`] | [`Models`]: laws, couplings and muscles from a material and an activation |
//! | [`spec`] | the scene's `[material]`, `[activation]`, `[incompressibility]` tables as written |
//!
//! [`Energy`]: crate::energy::Energy

pub mod choice;
pub mod factory;
pub mod formula;
pub mod spec;

pub use choice::{product, CouplingKind, LawKind, ModelChoice, RepresentationKind};
pub use factory::Models;
pub use formula::{DeclaredSpec, FormulaSpec};
pub use spec::{
    curve_parameter_names, ActivationSpec, EnergySpec, ExplicitSpec, IncompressibilitySpec,
    MaterialSpec,
};
