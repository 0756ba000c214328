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
    /// [`stress`](Self::stress) at the quadrature point of reference coordinates `at` = (r, z)
    /// (the mesh's length unit): a material varying in space ([`Regions`]) answers per point;
    /// every other material is the same everywhere.
    fn stress_at(&self, f: &AxiF, _at: [f64; 2]) -> crate::Result<SVector<f64, 5>> {
        self.stress(f)
    }
    /// [`stress_tangent`](Self::stress_tangent) at reference (r, z) = `at`.
    fn stress_tangent_at(
        &self,
        f: &AxiF,
        _at: [f64; 2],
    ) -> crate::Result<(SVector<f64, 5>, SMatrix<f64, 5, 5>)> {
        self.stress_tangent(f)
    }
    /// [`point_fields`](Self::point_fields) at reference (r, z) = `at`.
    fn point_fields_at(&self, f: &AxiF, _at: [f64; 2]) -> crate::Result<(f64, f64)> {
        self.point_fields(f)
    }
    /// (damage d, activation level a) at reference (r, z) = `at` for a material varying in
    /// space, written as VTK cell fields; `None` (the default) for a uniform material.
    fn damage_activation_at(&self, _at: [f64; 2]) -> Option<(f64, f64)> {
        None
    }
    /// False when the tangent is known to be non-symmetric (the frozen model's exact tangent):
    /// the solver then factorises it by LU from the first Newton iteration, instead of first
    /// finding out that GMRES on the LDLᵀ of its symmetric part does not converge. True (the
    /// default) only says that the LDLᵀ is worth trying; the solver still checks.
    fn symmetric_tangent(&self) -> bool {
        true
    }
}

/// A material varying in space by regions: `base` outside every region, and in each
/// rectangle [r0, r1] × [z0, z1] of the reference meridian section (the mesh's length unit) its
/// own material; a later region overrides an earlier one where they overlap. Each region's
/// (damage, activation) is carried for output only. The lookup is a scan of the regions
/// (a few comparisons per quadrature point).
#[derive(Debug, Clone)]
pub struct Regions<M> {
    base: M,
    base_fields: (f64, f64),
    regions: Vec<Region<M>>,
}

/// One region of [`Regions`].
#[derive(Debug, Clone)]
pub struct Region<M> {
    /// [r0, r1] (reference, the mesh's length unit).
    pub r: [f64; 2],
    /// [z0, z1] (reference, the mesh's length unit).
    pub z: [f64; 2],
    /// The material inside.
    pub material: M,
    /// (damage d, activation level a) inside, for output.
    pub fields: (f64, f64),
}

impl<M> Regions<M> {
    /// `base` (with its (damage, activation) `base_fields`) outside `regions`.
    pub fn new(base: M, base_fields: (f64, f64), regions: Vec<Region<M>>) -> Self {
        Self {
            base,
            base_fields,
            regions,
        }
    }

    /// The material and its (damage, activation) at reference (r, z): the last region holding
    /// the point, else the base.
    pub fn at(&self, at: [f64; 2]) -> (&M, (f64, f64)) {
        self.regions
            .iter()
            .rev()
            .find(|g| g.r[0] <= at[0] && at[0] <= g.r[1] && g.z[0] <= at[1] && at[1] <= g.z[1])
            .map_or((&self.base, self.base_fields), |g| (&g.material, g.fields))
    }
}

/// Without a point, a [`Regions`] material answers as its base (the solver always asks with the
/// point: [`AxisymmetricMaterial::stress_at`]).
impl<M: AxisymmetricMaterial> AxisymmetricMaterial for Regions<M> {
    fn stress(&self, f: &AxiF) -> crate::Result<SVector<f64, 5>> {
        self.base.stress(f)
    }
    fn stress_tangent(&self, f: &AxiF) -> crate::Result<(SVector<f64, 5>, SMatrix<f64, 5, 5>)> {
        self.base.stress_tangent(f)
    }
    fn point_fields(&self, f: &AxiF) -> crate::Result<(f64, f64)> {
        self.base.point_fields(f)
    }
    fn stress_at(&self, f: &AxiF, at: [f64; 2]) -> crate::Result<SVector<f64, 5>> {
        self.at(at).0.stress(f)
    }
    fn stress_tangent_at(
        &self,
        f: &AxiF,
        at: [f64; 2],
    ) -> crate::Result<(SVector<f64, 5>, SMatrix<f64, 5, 5>)> {
        self.at(at).0.stress_tangent(f)
    }
    fn point_fields_at(&self, f: &AxiF, at: [f64; 2]) -> crate::Result<(f64, f64)> {
        self.at(at).0.point_fields(f)
    }
    fn damage_activation_at(&self, at: [f64; 2]) -> Option<(f64, f64)> {
        Some(self.at(at).1)
    }
    fn symmetric_tangent(&self) -> bool {
        self.base.symmetric_tangent() && self.regions.iter().all(|g| g.material.symmetric_tangent())
    }
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
