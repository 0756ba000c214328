//! Activation: the active-strain map, the active curve, the activation laws γ = g(λ_f, d) and the
//! coupling (frozen or consistent) of a law to the energy.

pub mod coupling;
pub mod curve;
pub mod law;
pub mod strain;
pub mod time;

pub use coupling::{Coupling, FrozenTangent};
pub use curve::ActiveCurve;
pub use law::{
    effective_damage, ActivationLaw, BelowMinimum, ConstantLaw, EnergyLaw, ExplicitLaw,
    ImplicitLaw, Law, LawRepresentation, LawValue, SolvedLaw, TableComparison, TableReport,
    TableSpec, TabulatedLaw,
};
pub use strain::{
    active_energy, check_activation, fibre_path_energy, fibre_path_invariants, ActiveStrainMap,
};
