use super::{positive, Invariants, Parameter, ScalarWith, Shipped, StrainEnergy};
use crate::Result;
use crate::Scalar;

/// Incompressible neo-Hookean reference: W(C) = μ/2 (tr C − 3). Isotropic; the fibre direction
/// enters only through active strain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NeoHookean {
    mu: f64,
}

impl NeoHookean {
    /// Shear modulus μ \[kPa\] > 0.
    pub fn new(mu: f64) -> Result<Self> {
        Ok(Self {
            mu: positive("mu", mu)?,
        })
    }

    /// Shear modulus μ \[kPa\].
    pub fn mu(&self) -> f64 {
        self.mu
    }

    /// The formula, written once: W \[kPa\] from μ \[kPa\] (`f64` or a dual number) and tr C.
    pub fn energy_with<P: Scalar, T: ScalarWith<P>>(mu: P, c: &Invariants<T>) -> T {
        (c.tr_c - 3.0) * (mu / 2.0)
    }
}

impl StrainEnergy for NeoHookean {
    fn energy<T: Scalar>(&self, c: &Invariants<T>) -> T {
        Self::energy_with(self.mu, c)
    }

    fn name(&self) -> &str {
        Self::NAME
    }

    fn uses_det_c(&self) -> bool {
        false
    }
}

impl Shipped for NeoHookean {
    const NAME: &'static str = "neo-hookean";
    const W: Option<&'static str> = Some("mu/2*(I1 - 3)");
    const FORMULA: &'static str = "neo-Hookean reference, W = μ/2 (tr C − 3)";
    const CHAPTER: &'static str = "not in the chapter";
    /// μ has no chapter value: a scene must give it.
    const PARAMETERS: &'static [Parameter] = &[Parameter::positive("mu", "μ", "kPa", None)];
    fn values(&self) -> Vec<f64> {
        vec![self.mu]
    }
    fn from_values(v: &[f64]) -> Result<Self> {
        Self::new(v[0])
    }
    fn energy_of<T: Scalar>(p: &[T], invariants: &Invariants<T>) -> T {
        Self::energy_with(p[0], invariants)
    }
}
