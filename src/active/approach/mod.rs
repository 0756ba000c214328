//! The ways to activate a fibre-reinforced energy, all calibrated to the same uniaxial target
//! P_pas + T(λ), T = (1 − d)·a·f_v·P_act ([`crate::active::drive`]) (in a scene:
//! `[activation] approach = "..."`, or a shear or biaxial study's `approaches = [...]`):
//!
//! | approach | energy | activation | laws, couplings, maps |
//! |---|---|---|---|
//! | `active-strain` ([`ActiveStrain`], the chapter's) | Ŵ(F, γ) = φ(γ) W(C_e), F = F_e F_a | γ = g(λ_f) ∈ [0, 1) | any law, frozen or consistent; `map = "chapter" \| "volume-preserving"` |
//! | `active-stress` ([`ActiveStress`]: FEBio, Blemker) | Ψ = W_pas(C) + (1 − d)·a ∫_{λ_min}^{λ_f} P_act | none | none: P = ∂W_pas/∂F + T(λ_f) F M/λ_f is hyperelastic (f_v = 1) |
//! | `structural` ([`Structural`]: Ehret, Böl & Itskov 2011; 4C's MAT_Muscle_Weickenmeier) | W with I = C:(L + ωM) | ω = g(λ_f) ≥ 0 | the implicit and energy laws, frozen or consistent; its own map |
//!
//! They agree along the fibres by construction and differ elsewhere (Giantesio, Musesti &
//! Riccobelli 2019: in simple shear along the fibres λ_f stays 1, so active stress only adds
//! σ₁₁ while active strain changes the shear stiffness).
//!
//! An approach declares what applies to it ([`ShippedApproach`]): its activation variable, the
//! laws that give it, the couplings of a law to the energy, the maps a scene may choose, the
//! curves; the scene refuses every other key at the key, with the approach's reason. It builds
//! its activation map, may add an energy of the fibre stretch of its own (active stress), and says
//! how labels and the report's models table name it. A new approach is its file in this directory
//! (`impl ShippedApproach`) and one line in `shipped_approaches!` below: the scene, the studies,
//! the labels, the report and Python take it from [`Approach`].

use crate::active::coupling::CouplingKind;
use crate::active::curve::ActiveCurve;
use crate::active::drive::Drive;
use crate::active::law::LawKind;
use crate::active::map::ActivationMap;
use crate::energy::StrainEnergy;

/// What an approach is, declares and builds (see the module docs).
pub trait ShippedApproach {
    /// Name in scene files and outputs (`active-strain`).
    const NAME: &'static str;
    /// Symbol of its activation variable, which a law gives (`None`: it has none).
    const VARIABLE: Option<&'static str>;
    /// The laws that can give its variable (none without a variable).
    const LAWS: &'static [LawKind];
    /// The couplings of its law to the energy (none without a law).
    const COUPLINGS: &'static [CouplingKind];
    /// The maps `[activation] map = "..."` chooses among (none: its map is its own).
    const MAPS: &'static [ActivationMap];
    /// The shipped curves (by name) it is calibrated to; `None`: every one.
    const CURVES: Option<&'static [&'static str]> = None;
    /// Why a law or a coupling it does not list does not apply (the rule a refusal states).
    const NO_LAW: &'static str;
    /// Why `map` does not apply, if [`MAPS`](Self::MAPS) is empty.
    const NO_MAP: &'static str;

    /// Its activation map on `energy`, `named` being the scene's `map` (one of
    /// [`MAPS`](Self::MAPS) where it has any), or why `energy` cannot be activated this way.
    fn map<E: StrainEnergy>(energy: &E, named: ActivationMap) -> Result<ActivationMap, String>;

    /// Whether it adds an energy of the fibre stretch of its own ([`fibre_energy`](Self::fibre_energy)).
    const FIBRE_ENERGY: bool = false;

    /// The energy of c = C:M it adds to φ(γ) W(A(γ) j), as (E, dE/dc, d²E/dc²) under `drive`
    /// with `curve` (0 unless [`FIBRE_ENERGY`](Self::FIBRE_ENERGY): its activation is the map's).
    fn fibre_energy(_drive: &Drive, _curve: &ActiveCurve, _c_m: f64) -> (f64, f64, f64) {
        (0.0, 0.0, 0.0)
    }

    /// The approach in a model's label, before its law (`structural, ` in
    /// `giantesio-musesti, structural, implicit law, frozen coupling, d = 0`; empty for the
    /// chapter's).
    fn words(map: ActivationMap) -> &'static str;

    /// Its row of the report's models table: name, what it is, where the chapter has it.
    fn row(map: ActivationMap) -> [&'static str; 3];
}

/// The shipped approaches: `shipped_approaches! { file::Type => Variant, ... }` declares each
/// approach's module (`src/active/approach/file.rs`), re-exports its type and generates
/// [`Approach`] (one variant per type) with its dispatch.
macro_rules! shipped_approaches {
    ($($(#[$doc:meta])* $file:ident::$approach:ident => $variant:ident),* $(,)?) => {
        $(mod $file;
        pub use $file::$approach;)*

        /// An activation approach by name (see the module docs); the first is the default.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum Approach {
            $($(#[$doc])* $variant,)*
        }

        impl Approach {
            /// Every approach, in the order of the registry.
            pub const ALL: &'static [Approach] = &[$(Approach::$variant,)*];

            /// Every approach's name, in the order of the registry.
            pub const NAMES: &'static [&'static str] = &[$($approach::NAME,)*];

            /// Name in scene files and outputs.
            pub fn name(self) -> &'static str {
                match self { $(Approach::$variant => $approach::NAME,)* }
            }
            /// Symbol of its activation variable (`None`: it has none).
            pub fn variable(self) -> Option<&'static str> {
                match self { $(Approach::$variant => $approach::VARIABLE,)* }
            }
            /// The laws that can give its variable.
            pub fn laws(self) -> &'static [LawKind] {
                match self { $(Approach::$variant => $approach::LAWS,)* }
            }
            /// The couplings of its law to the energy.
            pub fn couplings(self) -> &'static [CouplingKind] {
                match self { $(Approach::$variant => $approach::COUPLINGS,)* }
            }
            /// The maps a scene may choose for it.
            pub fn maps(self) -> &'static [ActivationMap] {
                match self { $(Approach::$variant => $approach::MAPS,)* }
            }
            /// The curves it is calibrated to (`None`: every shipped curve).
            pub fn curves(self) -> Option<&'static [&'static str]> {
                match self { $(Approach::$variant => $approach::CURVES,)* }
            }
            /// Why a law or a coupling it does not list does not apply.
            pub fn no_law(self) -> &'static str {
                match self { $(Approach::$variant => $approach::NO_LAW,)* }
            }
            /// Why `map` does not apply to it.
            pub fn no_map(self) -> &'static str {
                match self { $(Approach::$variant => $approach::NO_MAP,)* }
            }
            /// Its activation map on `energy` with the scene's `map`, or why there is none.
            pub fn map<E: StrainEnergy>(self, energy: &E, named: ActivationMap) -> Result<ActivationMap, String> {
                match self { $(Approach::$variant => $approach::map(energy, named),)* }
            }
            /// Whether it adds an energy of the fibre stretch of its own.
            pub fn adds_fibre_energy(self) -> bool {
                match self { $(Approach::$variant => $approach::FIBRE_ENERGY,)* }
            }
            /// The energy of C:M it adds ([`ShippedApproach::fibre_energy`]).
            #[inline]
            pub fn fibre_energy(self, drive: &Drive, curve: &ActiveCurve, c_m: f64) -> (f64, f64, f64) {
                match self { $(Approach::$variant => $approach::fibre_energy(drive, curve, c_m),)* }
            }
            /// The approach in a model's label, before its law.
            pub fn words(self, map: ActivationMap) -> &'static str {
                match self { $(Approach::$variant => $approach::words(map),)* }
            }
            /// Its row of the report's models table.
            pub fn row(self, map: ActivationMap) -> [&'static str; 3] {
                match self { $(Approach::$variant => $approach::row(map),)* }
            }
        }
    };
}

// A new approach: its file in this directory (`impl ShippedApproach`) and one line here.
shipped_approaches! {
    /// Active strain F = F_e F_a with the scene's `map` (the chapter's).
    active_strain::ActiveStrain => ActiveStrain,
    /// Active stress: the target stress added along the fibres, no activation variable.
    active_stress::ActiveStress => ActiveStress,
    /// The activation ω in the structural tensor, I = C:(L + ωM).
    structural::Structural => Structural,
}

impl Default for Approach {
    fn default() -> Self {
        Approach::ALL[0]
    }
}

impl Approach {
    /// The approach called `name`.
    pub fn find(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|a| a.name() == name)
    }
}

/// Written by its name.
impl serde::Serialize for Approach {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}

/// Read by name, one of [`Approach::NAMES`].
impl<'de> serde::Deserialize<'de> for Approach {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let name = String::deserialize(deserializer)?;
        Self::find(&name).ok_or_else(|| serde::de::Error::unknown_variant(&name, Self::NAMES))
    }
}
