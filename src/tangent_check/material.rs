//! What a tangent check asks of a material ([`TangentMaterial`]: the stress and its tangent over
//! the entries of F it varies) and what a material may add about itself ([`Known`]): why its
//! tangent need not be symmetric, the approximate tangents a solver can use instead, the fibre
//! stretches where it is not smooth, strong ellipticity.
//!
//! Every [`AxisymmetricMaterial`] — the trait the FE solver uses, so any material a user ports
//! with a hand-derived tangent — is a `TangentMaterial<5>` over the axisymmetric entries
//! [F_rr, F_rz, F_zr, F_zz, F_θθ] (coordinates (r, θ, z)); a material of all nine entries
//! implements `TangentMaterial<9>` ([`super::MusclePoint`] for a [`crate::Muscle`]).

use crate::fem::{AxiF, AxisymmetricMaterial};
use crate::invariants::{Entries, AXISYMMETRIC};
use crate::stability::Ellipticity;
use crate::{Error, Result};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// What a tangent check asks of a material at one state F.
pub trait TangentMaterial<const N: usize> {
    /// The entries (row, column) of F the stress and the tangent are over, in their order.
    fn entries(&self) -> Entries<N>;

    /// P = ∂Ψ/∂F over [`entries`](Self::entries) \[kPa\] (without a pressure term the solver
    /// adds).
    fn stress_of(&self, f: &Matrix3<f64>) -> Result<SVector<f64, N>>;

    /// P and the tangent A = ∂P/∂F the solver uses (row: P entry, column: F entry) \[kPa\].
    fn stress_and_tangent(&self, f: &Matrix3<f64>)
        -> Result<(SVector<f64, N>, SMatrix<f64, N, N>)>;

    /// What the material knows of itself at F with tangent `tangent`; by default nothing.
    fn known(&self, _f: &Matrix3<f64>, _tangent: &SMatrix<f64, N, N>) -> Result<Known<N>> {
        Ok(Known::default())
    }
}

/// What a material knows of itself at a state.
#[derive(Debug, Clone, Default)]
pub struct Known<const N: usize> {
    /// Why A is not major-symmetric there, where it need not be (the frozen coupling's exact
    /// tangent); `None`: it should be.
    pub asymmetry: Option<String>,
    /// Why A itself is an approximation, where it is one by choice (the frozen model's
    /// symmetric tangent): an order 1 of r₁ is then its cause.
    pub approximate: Option<String>,
    /// Approximate tangents a solver can use instead of A.
    pub approximations: Vec<Approximation<N>>,
    /// Fibre stretches where the stress is not smooth.
    pub edges: Vec<Edge>,
    /// The reference fibre direction m (unit), which the edges are fibre stretches |F m| of.
    pub fibre: Option<Vector3<f64>>,
    /// Strong ellipticity at the state, where the material can tell.
    pub ellipticity: Option<Ellipticity>,
    /// What else a user should know of this state.
    pub notes: Vec<String>,
}

/// An approximate tangent a solver can use.
#[derive(Debug, Clone)]
pub struct Approximation<const N: usize> {
    /// What it is (`symmetric frozen`, `tabulated law`).
    pub name: String,
    /// Its matrix, over the same entries as A.
    pub tangent: SMatrix<f64, N, N>,
}

/// A fibre stretch at which a material's stress is not smooth.
#[derive(Debug, Clone, PartialEq)]
pub struct Edge {
    /// The fibre stretch λ_f = |F m| [-].
    pub fibre_stretch: f64,
    /// A short key for tables (`lambda-min-kink`, `lambda-min-jump`, `table-end`, ...).
    pub kind: &'static str,
    /// What happens there, in words.
    pub what: String,
}

/// The axisymmetric entries of F (coordinates (r, θ, z)); refuses an F that couples θ with
/// (r, z).
pub fn axisymmetric_entries(f: &Matrix3<f64>) -> Result<AxiF> {
    let coupling = [f[(0, 1)], f[(1, 0)], f[(1, 2)], f[(2, 1)]];
    if let Some(&v) = coupling.iter().find(|v| **v != 0.0) {
        return Err(Error::InvalidParameter {
            name: "F",
            value: v,
            rule: "an axisymmetric material takes F with F_rθ = F_θr = F_zθ = F_θz = 0 (coordinates (r, θ, z))",
        });
    }
    Ok(SVector::from([
        f[(0, 0)],
        f[(0, 2)],
        f[(2, 0)],
        f[(2, 2)],
        f[(1, 1)],
    ]))
}

/// Any material of the FE solver, over its five entries.
impl<M: AxisymmetricMaterial + ?Sized> TangentMaterial<5> for M {
    fn entries(&self) -> Entries<5> {
        AXISYMMETRIC
    }

    fn stress_of(&self, f: &Matrix3<f64>) -> Result<SVector<f64, 5>> {
        AxisymmetricMaterial::stress(self, &axisymmetric_entries(f)?)
    }

    fn stress_and_tangent(
        &self,
        f: &Matrix3<f64>,
    ) -> Result<(SVector<f64, 5>, SMatrix<f64, 5, 5>)> {
        AxisymmetricMaterial::stress_tangent(self, &axisymmetric_entries(f)?)
    }
}
