//! The interface between the FE solver and any constitutive model.
//!
//! The solver only ever sees [`AxisymmetricMaterial`]: the nominal stress P = ∂Ψ/∂F on the five
//! nonzero entries of an axisymmetric, torsion-free deformation gradient, its tangent, and two
//! scalar output fields. The incompressibility pressure −p ∂J/∂F is added by the solver.
//!
//! [`NeoHookean`] is a verification material (not a muscle model): Ψ = μ/2 (tr C − 3), whose
//! restriction to the five entries is exact because tr C = F_rr² + F_rz² + F_zr² + F_zz² + F_θθ².

use nalgebra::{SMatrix, SVector};

/// The five nonzero entries of an axisymmetric deformation gradient, ordered [F_rr, F_rz, F_zr, F_zz, F_θθ].
pub type AxiF = nalgebra::SVector<f64, 5>;

/// What the FE solver asks of a constitutive model at one quadrature point. The pressure term is the solver's.
pub trait AxisymmetricMaterial: Sync {
    /// P = ∂Ψ/∂F restricted to the five entries (same order as AxiF), without the pressure term.
    fn stress(&self, f: &AxiF) -> crate::Result<nalgebra::SVector<f64, 5>>;
    /// P and its tangent ∂P/∂F (5×5; row = P entry, column = F entry). May be NON-symmetric (frozen activation model): never assume symmetry.
    fn stress_tangent(
        &self,
        f: &AxiF,
    ) -> crate::Result<(nalgebra::SVector<f64, 5>, nalgebra::SMatrix<f64, 5, 5>)>;
    /// Scalar fields for output at a point: (activation γ, fibre stretch λ_f). A passive material returns (0, sqrt(C_zz)).
    fn point_fields(&self, f: &AxiF) -> crate::Result<(f64, f64)>;
}

/// Index of each entry in [`AxiF`].
pub mod entry {
    /// F_rr.
    pub const RR: usize = 0;
    /// F_rz.
    pub const RZ: usize = 1;
    /// F_zr.
    pub const ZR: usize = 2;
    /// F_zz.
    pub const ZZ: usize = 3;
    /// F_θθ.
    pub const TT: usize = 4;
}

/// Axial right Cauchy–Green entry C_zz = F_rz² + F_zz² (fibres along z), so λ_f = sqrt(C_zz).
pub fn axial_stretch(f: &AxiF) -> f64 {
    (f[entry::RZ] * f[entry::RZ] + f[entry::ZZ] * f[entry::ZZ]).sqrt()
}

/// Incompressible neo-Hookean verification material, Ψ = μ/2 (tr C − 3).
///
/// P = μ F on the five entries and ∂P/∂F = μ I (5×5), exactly. Used by the FE tests and the
/// scaling example; the solver never names it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NeoHookean {
    /// Shear modulus μ \[kPa\].
    pub mu: f64,
}

impl NeoHookean {
    /// A neo-Hookean material with shear modulus `mu` \[kPa\] (> 0, finite).
    pub fn new(mu: f64) -> crate::Result<Self> {
        if mu.is_finite() && mu > 0.0 {
            Ok(Self { mu })
        } else {
            Err(crate::Error::InvalidParameter {
                name: "mu",
                value: mu,
                rule: "must be finite and > 0",
            })
        }
    }
}

impl AxisymmetricMaterial for NeoHookean {
    fn stress(&self, f: &AxiF) -> crate::Result<SVector<f64, 5>> {
        Ok(f * self.mu)
    }

    fn stress_tangent(&self, f: &AxiF) -> crate::Result<(SVector<f64, 5>, SMatrix<f64, 5, 5>)> {
        Ok((f * self.mu, SMatrix::<f64, 5, 5>::identity() * self.mu))
    }

    fn point_fields(&self, f: &AxiF) -> crate::Result<(f64, f64)> {
        Ok((0.0, axial_stretch(f)))
    }
}
