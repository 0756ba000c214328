//! Energies whose parameters can be fitted: [`Parametric`] (defined with the energies, whose
//! parameter tables it reads) and the default bounds of a fit, the parameters' admissible ranges.

use super::Bounds;
pub use crate::energy::Parametric;

/// The default fit bounds of each parameter of `energy` (its admissible range, or narrower).
pub fn parameter_bounds<E: Parametric>(energy: &E) -> Vec<Bounds> {
    energy
        .parameters()
        .iter()
        .map(|p| Bounds::new(p.bounds.0, p.bounds.1))
        .collect()
}
