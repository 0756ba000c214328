//! Activation: the active curves, what drives them (damage, level, force–velocity), the
//! activation maps (active strain, structural), the activation laws γ = g(λ_f, drive), the
//! coupling (frozen or consistent) of a law to the energy, and the registry of approaches that
//! choose among them ([`Approach`]: active strain, active stress, structural).

pub mod approach;
pub mod coupling;
pub mod curve;
pub mod drive;
pub mod law;
pub mod map;
pub mod strain;
pub mod time;

pub use approach::{Approach, ShippedApproach};
pub use coupling::{Coupling, CouplingKind, FrozenTangent};
pub use curve::{ActiveCurve, CurveEntry, CURVES};
pub use drive::{Drive, ForceVelocity, StretchRate};
pub use law::{
    ActivationLaw, BelowMinimum, ConstantLaw, Domain, EnergyLaw, ExplicitLaw, ImplicitLaw, Law,
    LawKind, LawRepresentation, LawValue, OutsideDomain, SolvedLaw, TableComparison, TableReport,
    TableSpec, TabulatedLaw,
};
pub use map::{fibre_path_invariants, ActivationMap};
pub use strain::{active_energy, check_activation, fibre_path_energy};
