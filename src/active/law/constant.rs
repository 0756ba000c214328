use super::{ActivationLaw, LawValue};
use crate::active::drive::Drive;
use crate::active::strain::check_activation;
use crate::Result;

/// γ fixed, independent of the stretch and of the damage (the chapter's Fig. D:gamma-s-s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConstantLaw {
    gamma: f64,
}

impl ConstantLaw {
    /// γ ∈ [0, 1).
    pub fn new(gamma: f64) -> Result<Self> {
        Ok(Self {
            gamma: check_activation(gamma)?,
        })
    }
}

impl ActivationLaw for ConstantLaw {
    fn evaluate(&self, _lambda: f64, _drive: impl Into<Drive>) -> Result<LawValue> {
        Ok(LawValue {
            gamma: self.gamma,
            slope: 0.0,
            curvature: 0.0,
        })
    }
}
