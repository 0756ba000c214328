//! Tangents by central differences of the stress: at a point of any [`TangentMaterial`]
//! ([`central_differences`]), and as a material the FE solver can use ([`CentralDifferences`]:
//! its stress, with the tangent by differences at every quadrature point), so that a user sees
//! what a tangent that is not derived costs the Newton solver.
//!
//! Column j of the tangent is (P(x + δ_j e_j) − P(x − δ_j e_j))/(2δ_j) with
//! δ_j = ε^⅓ max(1, |x_j|): truncation δ²|P‴|/6 and rounding ε|P|/δ balance there, ≈ 1e-10
//! relative for a stress of unit-size terms. Two stress evaluations per entry of F.

use super::material::TangentMaterial;
use crate::fem::{AxiF, AxisymmetricMaterial};
use crate::Result;
use nalgebra::{Matrix3, SMatrix, SVector};

/// The step of entry value `x`: ε^⅓ max(1, |x|).
fn step(x: f64) -> f64 {
    f64::EPSILON.cbrt() * x.abs().max(1.0)
}

/// The tangent of `stress` at `x` by central differences, one column per entry.
pub fn differences<const N: usize>(
    stress: impl Fn(&SVector<f64, N>) -> Result<SVector<f64, N>>,
    x: &SVector<f64, N>,
) -> Result<SMatrix<f64, N, N>> {
    let mut tangent = SMatrix::<f64, N, N>::zeros();
    for j in 0..N {
        let delta = step(x[j]);
        let (mut plus, mut minus) = (*x, *x);
        plus[j] += delta;
        minus[j] -= delta;
        // The step actually taken (x ± δ rounds).
        let taken = plus[j] - minus[j];
        let column = (stress(&plus)? - stress(&minus)?) / taken;
        tangent.set_column(j, &column);
    }
    Ok(tangent)
}

/// The tangent of `material` at F by central differences of its stress, over its entries.
pub fn central_differences<const N: usize, M: TangentMaterial<N> + ?Sized>(
    material: &M,
    f: &Matrix3<f64>,
) -> Result<SMatrix<f64, N, N>> {
    let entries = material.entries();
    let x = SVector::<f64, N>::from_fn(|a, _| {
        let (i, j) = entries.index[a];
        f[(i, j)]
    });
    differences(
        |y| {
            let mut g = *f;
            for (a, &(i, j)) in entries.index.iter().enumerate() {
                g[(i, j)] = y[a];
            }
            material.stress_of(&g)
        },
        &x,
    )
}

/// A material of the FE solver whose tangent is taken by central differences of the inner
/// material's stress at every quadrature point (10 stress evaluations for the five entries);
/// stress and output fields are the inner material's.
#[derive(Debug, Clone, Copy)]
pub struct CentralDifferences<'m, M: ?Sized>(pub &'m M);

impl<M: AxisymmetricMaterial + ?Sized> AxisymmetricMaterial for CentralDifferences<'_, M> {
    fn stress(&self, f: &AxiF) -> Result<SVector<f64, 5>> {
        self.0.stress(f)
    }

    fn stress_tangent(&self, f: &AxiF) -> Result<(SVector<f64, 5>, SMatrix<f64, 5, 5>)> {
        Ok((self.0.stress(f)?, differences(|g| self.0.stress(g), f)?))
    }

    fn point_fields(&self, f: &AxiF) -> Result<(f64, f64)> {
        self.0.point_fields(f)
    }

    fn stress_at(&self, f: &AxiF, at: [f64; 2]) -> Result<SVector<f64, 5>> {
        self.0.stress_at(f, at)
    }

    fn stress_tangent_at(
        &self,
        f: &AxiF,
        at: [f64; 2],
    ) -> Result<(SVector<f64, 5>, SMatrix<f64, 5, 5>)> {
        let tangent = differences(|g| self.0.stress_at(g, at), f)?;
        Ok((self.0.stress_at(f, at)?, tangent))
    }

    fn point_fields_at(&self, f: &AxiF, at: [f64; 2]) -> Result<(f64, f64)> {
        self.0.point_fields_at(f, at)
    }

    fn damage_activation_at(&self, at: [f64; 2]) -> Option<(f64, f64)> {
        self.0.damage_activation_at(at)
    }

    /// Differences of a stress that is not a gradient are not symmetric either.
    fn symmetric_tangent(&self) -> bool {
        self.0.symmetric_tangent()
    }
}
