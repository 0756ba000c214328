//! Energies whose parameters can be fitted: named parameters that can be read, rebuilt from
//! numbers (validated) and passed to the energy's one formula as dual numbers.

use super::Bounds;
use crate::energy::{EhretBolItskov, Energy, GiantesioMusesti, Invariants, NeoHookean};
use crate::{Result, Scalar, StrainEnergy};

/// A [`StrainEnergy`] with named parameters that a fit may free. The three shipped energies
/// implement it; a user's energy opts in by implementing these five methods (the formula itself
/// stays written once: `energy` calls `energy_with` with its own `f64` parameters).
pub trait Parametric: StrainEnergy + Sized {
    /// Parameter names, as in the docs (e.g. `["mu", "alpha", "w0"]`).
    fn parameter_names(&self) -> &'static [&'static str];

    /// Current values, in the order of [`parameter_names`](Self::parameter_names).
    fn parameter_values(&self) -> Vec<f64>;

    /// Admissible ranges (default fit bounds), in the same order.
    fn parameter_bounds(&self) -> Vec<Bounds>;

    /// The same model with new parameter values, validated by its constructor.
    fn rebuilt(&self, values: &[f64]) -> Result<Self>;

    /// W(C) \[kPa\] with the parameters given as scalars (dual numbers differentiate in them).
    fn energy_with<T: Scalar>(&self, parameters: &[T], invariants: &Invariants<T>) -> T;
}

impl Parametric for GiantesioMusesti {
    fn parameter_names(&self) -> &'static [&'static str] {
        &["mu", "alpha", "w0"]
    }
    fn parameter_values(&self) -> Vec<f64> {
        vec![self.mu(), self.alpha(), self.w0()]
    }
    fn parameter_bounds(&self) -> Vec<Bounds> {
        vec![Bounds::POSITIVE, Bounds::POSITIVE, Bounds::UNIT]
    }
    fn rebuilt(&self, v: &[f64]) -> Result<Self> {
        GiantesioMusesti::new(v[0], v[1], v[2])
    }
    fn energy_with<T: Scalar>(&self, p: &[T], invariants: &Invariants<T>) -> T {
        GiantesioMusesti::energy_with(p[0], p[1], p[2], invariants)
    }
}

impl Parametric for EhretBolItskov {
    fn parameter_names(&self) -> &'static [&'static str] {
        &["mu", "alpha", "beta", "w0"]
    }
    fn parameter_values(&self) -> Vec<f64> {
        vec![self.mu(), self.alpha(), self.beta(), self.w0()]
    }
    fn parameter_bounds(&self) -> Vec<Bounds> {
        vec![
            Bounds::POSITIVE,
            Bounds::POSITIVE,
            Bounds::POSITIVE,
            Bounds::UNIT,
        ]
    }
    fn rebuilt(&self, v: &[f64]) -> Result<Self> {
        EhretBolItskov::new(v[0], v[1], v[2], v[3])
    }
    fn energy_with<T: Scalar>(&self, p: &[T], invariants: &Invariants<T>) -> T {
        EhretBolItskov::energy_with(p[0], p[1], p[2], p[3], invariants)
    }
}

impl Parametric for NeoHookean {
    fn parameter_names(&self) -> &'static [&'static str] {
        &["mu"]
    }
    fn parameter_values(&self) -> Vec<f64> {
        vec![self.mu()]
    }
    fn parameter_bounds(&self) -> Vec<Bounds> {
        vec![Bounds::POSITIVE]
    }
    fn rebuilt(&self, v: &[f64]) -> Result<Self> {
        NeoHookean::new(v[0])
    }
    fn energy_with<T: Scalar>(&self, p: &[T], invariants: &Invariants<T>) -> T {
        NeoHookean::energy_with(p[0], invariants)
    }
}

impl Parametric for Energy {
    fn parameter_names(&self) -> &'static [&'static str] {
        match self {
            Energy::GiantesioMusesti(w) => w.parameter_names(),
            Energy::EhretBolItskov(w) => w.parameter_names(),
            Energy::NeoHookean(w) => w.parameter_names(),
        }
    }
    fn parameter_values(&self) -> Vec<f64> {
        match self {
            Energy::GiantesioMusesti(w) => w.parameter_values(),
            Energy::EhretBolItskov(w) => w.parameter_values(),
            Energy::NeoHookean(w) => w.parameter_values(),
        }
    }
    fn parameter_bounds(&self) -> Vec<Bounds> {
        match self {
            Energy::GiantesioMusesti(w) => w.parameter_bounds(),
            Energy::EhretBolItskov(w) => w.parameter_bounds(),
            Energy::NeoHookean(w) => w.parameter_bounds(),
        }
    }
    fn rebuilt(&self, v: &[f64]) -> Result<Self> {
        Ok(match self {
            Energy::GiantesioMusesti(w) => Energy::GiantesioMusesti(w.rebuilt(v)?),
            Energy::EhretBolItskov(w) => Energy::EhretBolItskov(w.rebuilt(v)?),
            Energy::NeoHookean(w) => Energy::NeoHookean(w.rebuilt(v)?),
        })
    }
    fn energy_with<T: Scalar>(&self, p: &[T], invariants: &Invariants<T>) -> T {
        match self {
            Energy::GiantesioMusesti(w) => Parametric::energy_with(w, p, invariants),
            Energy::EhretBolItskov(w) => Parametric::energy_with(w, p, invariants),
            Energy::NeoHookean(w) => Parametric::energy_with(w, p, invariants),
        }
    }
}
