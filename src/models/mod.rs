//! Models from choices: the scene's material and activation ([`Models`]) build the activation
//! map, law, coupling and muscle of a [`ModelChoice`] (approach × law × coupling × damage); an
//! [`EnergySpec`] (a shipped energy by name, parameters by name) builds an [`Energy`] from the
//! registry [`crate::energy::SHIPPED`]. The scene and every study build their models here.
//!
//! | module | what |
//! |---|---|
//! | [`choice`] | an approach, a law, a coupling and a damage by name |
//! | [`factory`] | [`Models`]: maps, laws, couplings and muscles from a material and an activation |
//! | [`activation`] | the scene's `[activation]` table, each key declared once |
//! | [`spec`] | the scene's `[material]` and `[incompressibility]` tables, and [`Models::from_spec`] |
//!
//! [`Energy`]: crate::energy::Energy

pub mod activation;
pub mod choice;
pub mod factory;
pub mod formula;
pub mod spec;

pub use activation::{curve_parameter_names, ActivationSpec, ExplicitSpec, ModelDefaults};
pub use choice::{product, Approach, CouplingKind, LawKind, ModelChoice, RepresentationKind};
pub use factory::Models;
pub use formula::{DeclaredSpec, FormulaSpec};
pub use spec::{EnergySpec, IncompressibilityKind, IncompressibilitySpec, MaterialSpec};
