//! The representative material point every constitutive benchmark uses (see BENCHMARKS.md).

use activemuscle::invariants::axisymmetric_f;
use nalgebra::{Matrix3, SVector};

/// γ at the point.
pub const GAMMA: f64 = 0.15;

/// Axisymmetric entries [F_rr, F_rz, F_zr, F_zz, F_θθ]: axial stretch 1.1, lateral contraction
/// 1/√1.1, shear 0.05 / 0.02 (det F ≈ 1).
pub fn axi_entries() -> SVector<f64, 5> {
    let l = 1.0 / 1.1_f64.sqrt();
    SVector::from([l, 0.05, 0.02, 1.1, l])
}

/// 3D F: the axisymmetric point plus an out-of-plane shear, so that no entry is structurally zero.
pub fn full_f() -> Matrix3<f64> {
    let mut f = axisymmetric_f(&axi_entries());
    f[(0, 1)] = 0.03;
    f[(1, 2)] = -0.02;
    f[(2, 1)] = 0.01;
    f
}
