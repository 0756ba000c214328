//! Energies whose parameters can be fitted: [`Parametric`] (defined with the energies, whose
//! parameter tables it reads) and the default bounds of a fit, the parameters' admissible ranges.

use super::Bounds;
pub use crate::energy::Parametric;

/// The admissible range of each parameter of `energy`, as fit bounds.
pub fn parameter_bounds<E: Parametric>(energy: &E) -> Vec<Bounds> {
    energy
        .parameters()
        .iter()
        .map(|p| Bounds::new(p.range.0, p.range.1))
        .collect()
}
