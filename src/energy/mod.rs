//! Strain-energy densities, written once as generic scalar functions of the invariants of C.
//!
//! A model implements [`StrainEnergy::energy`] for any scalar `T: DualNum<Primitive = f64> + Copy`;
//! `f64` gives the value, dual numbers give exact derivatives. The framework owns the invariants
//! and their derivatives with respect to F (see [`crate::invariants`]), so a model never writes a
//! derivative by hand.

mod ehret_bol_itskov;
mod giantesio_musesti;
mod neo_hookean;

pub use ehret_bol_itskov::EhretBolItskov;
pub use giantesio_musesti::GiantesioMusesti;
pub use neo_hookean::NeoHookean;

use crate::Scalar;
use crate::{Error, Result};

/// A scalar `T` that combines with model parameters of type `P` (`T op P -> T`): `P = f64` for
/// fixed parameters (the fast path every response takes, no zero derivatives carried) or
/// `P = T` for parameters carried as dual numbers (derivatives in the parameters, for fitting).
/// Lets each model write its formula once for both.
pub trait ScalarWith<P>:
    Scalar
    + std::ops::Add<P, Output = Self>
    + std::ops::Sub<P, Output = Self>
    + std::ops::Mul<P, Output = Self>
    + std::ops::Div<P, Output = Self>
{
}

impl<P, T> ScalarWith<P> for T where
    T: Scalar
        + std::ops::Add<P, Output = T>
        + std::ops::Sub<P, Output = T>
        + std::ops::Mul<P, Output = T>
        + std::ops::Div<P, Output = T>
{
}

/// The invariants of a right Cauchy–Green tensor C with respect to the fibre direction m
/// (M = m ⊗ m) that energies may use.
///
/// | field | definition | at C = I |
/// |---|---|---|
/// | `tr_c` | tr C | 3 |
/// | `c_m` | C : M = λ_f² | 1 |
/// | `tr_c_inv` | tr C⁻¹ | 3 |
/// | `c_inv_m` | C⁻¹ : M | 1 |
/// | `det_c` | det C = J² | 1 |
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Invariants<T> {
    /// tr C.
    pub tr_c: T,
    /// C : M, the squared fibre stretch.
    pub c_m: T,
    /// tr C⁻¹.
    pub tr_c_inv: T,
    /// C⁻¹ : M.
    pub c_inv_m: T,
    /// det C.
    pub det_c: T,
}

impl<T: Copy> Invariants<T> {
    /// Number of invariants.
    pub const COUNT: usize = 5;

    /// From `[tr C, C:M, tr C⁻¹, C⁻¹:M, det C]`.
    pub fn from_array(v: [T; 5]) -> Self {
        Self {
            tr_c: v[0],
            c_m: v[1],
            tr_c_inv: v[2],
            c_inv_m: v[3],
            det_c: v[4],
        }
    }

    /// As `[tr C, C:M, tr C⁻¹, C⁻¹:M, det C]`.
    pub fn to_array(self) -> [T; 5] {
        [self.tr_c, self.c_m, self.tr_c_inv, self.c_inv_m, self.det_c]
    }
}

/// A hyperelastic strain-energy density W(C) \[kPa\], transversely isotropic about the fibre direction.
///
/// Implement [`energy`](Self::energy) once, generically; every response (stress, tangent, dP/dγ,
/// activation, both couplings, the FE solver) follows from it. Under the incompressibility
/// constraint det C = 1 the energy need not vanish with det C; with active strain the *elastic*
/// C_e has det C_e = (1 − γ)⁻², so an energy that uses `det_c` sees it.
pub trait StrainEnergy: Clone + Send + Sync {
    /// W(C) in kPa from the invariants of C. Must be 0 at C = I for a stress-free reference.
    fn energy<T: Scalar>(&self, invariants: &Invariants<T>) -> T;

    /// Short name for logs and output files.
    fn name(&self) -> &str {
        "user-defined"
    }

    /// Whether W depends on `det_c`. An energy that does not may return `false`: the responses
    /// then differentiate over four invariants instead of five (about 1.5× faster tangents).
    /// Returning `false` for an energy that does use `det_c` gives wrong derivatives.
    fn uses_det_c(&self) -> bool {
        true
    }
}

/// Checks that `value` is finite and strictly positive.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            rule: "must be finite and > 0",
        })
    }
}

/// Checks that `value` lies in the open interval (0, 1).
pub(crate) fn open_unit(name: &'static str, value: f64) -> Result<f64> {
    if value > 0.0 && value < 1.0 {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            rule: "must lie in (0, 1)",
        })
    }
}

/// Any of the shipped energies, chosen at run time (e.g. from a scene file).
#[derive(Debug, Clone, PartialEq)]
pub enum Energy {
    /// The chapter's passive energy, eq. D:Wpassiva.
    GiantesioMusesti(GiantesioMusesti),
    /// The Ehret–Böl–Itskov energy, eq. D:Webi.
    EhretBolItskov(EhretBolItskov),
    /// Incompressible neo-Hookean reference.
    NeoHookean(NeoHookean),
}

impl StrainEnergy for Energy {
    fn energy<T: Scalar>(&self, invariants: &Invariants<T>) -> T {
        match self {
            Energy::GiantesioMusesti(w) => w.energy(invariants),
            Energy::EhretBolItskov(w) => w.energy(invariants),
            Energy::NeoHookean(w) => w.energy(invariants),
        }
    }

    fn name(&self) -> &str {
        match self {
            Energy::GiantesioMusesti(w) => w.name(),
            Energy::EhretBolItskov(w) => w.name(),
            Energy::NeoHookean(w) => w.name(),
        }
    }

    fn uses_det_c(&self) -> bool {
        match self {
            Energy::GiantesioMusesti(w) => w.uses_det_c(),
            Energy::EhretBolItskov(w) => w.uses_det_c(),
            Energy::NeoHookean(w) => w.uses_det_c(),
        }
    }
}
