//! Axisymmetric kinematics at a quadrature point: F from the strain–displacement operator and
//! the element displacements, and the volume ratio J with its first and second derivatives.
//!
//! F = I + B u on the five entries [F_rr, F_rz, F_zr, F_zz, F_θθ], J = F_θθ (F_rr F_zz − F_rz F_zr).

use super::material::AxiF;
use nalgebra::{SMatrix, SVector};

/// F = I + B u on the five entries [F_rr, F_rz, F_zr, F_zz, F_θθ] (`NU` element displacement dofs).
#[inline]
pub fn deformation<const NU: usize>(b: &SMatrix<f64, 5, NU>, u: &SVector<f64, NU>) -> AxiF {
    let mut f = b * u;
    f[0] += 1.0;
    f[3] += 1.0;
    f[4] += 1.0;
    f
}

/// J = F_θθ (F_rr F_zz − F_rz F_zr).
#[inline]
pub fn jacobian(f: &AxiF) -> f64 {
    f[4] * (f[0] * f[3] - f[1] * f[2])
}

/// ∂J/∂F on the five entries.
#[inline]
pub fn jacobian_gradient(f: &AxiF) -> AxiF {
    AxiF::new(
        f[4] * f[3],
        -f[4] * f[2],
        -f[4] * f[1],
        f[4] * f[0],
        f[0] * f[3] - f[1] * f[2],
    )
}

/// ∂²J/∂F∂F on the five entries (symmetric).
#[inline]
pub fn jacobian_hessian(f: &AxiF) -> SMatrix<f64, 5, 5> {
    let mut h = SMatrix::<f64, 5, 5>::zeros();
    let mut set = |i: usize, j: usize, v: f64| {
        h[(i, j)] = v;
        h[(j, i)] = v;
    };
    set(0, 3, f[4]);
    set(0, 4, f[3]);
    set(1, 2, -f[4]);
    set(1, 4, -f[2]);
    set(2, 4, -f[1]);
    set(3, 4, f[0]);
    h
}
