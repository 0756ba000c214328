//! Axisymmetric kinematics at a quadrature point: the volume ratio J with its first and second
//! derivatives (F = I + B u itself: [`super::element::PointGeometry::deformation`]).
//!
//! J = F_θθ (F_rr F_zz − F_rz F_zr) on the five entries [F_rr, F_rz, F_zr, F_zz, F_θθ].

use super::material::AxiF;
use nalgebra::SMatrix;

/// J = F_θθ (F_rr F_zz − F_rz F_zr).
#[inline(always)]
pub fn jacobian(f: &AxiF) -> f64 {
    f[4] * (f[0] * f[3] - f[1] * f[2])
}

/// ∂J/∂F on the five entries.
#[inline(always)]
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
#[inline(always)]
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
