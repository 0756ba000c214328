//! Test materials shared by the FE tests.

use activemuscle::fem::material::axial_stretch;
use activemuscle::fem::{AxiF, AxisymmetricMaterial};
use nalgebra::{SMatrix, SVector};

/// Neo-Hookean plus a stress that is not the gradient of any energy: P_rr += c F_zz².
/// Its exact tangent has ∂P_rr/∂F_zz = 2c F_zz but ∂P_zz/∂F_rr = 0: non-symmetric.
pub struct NonSymmetric {
    pub mu: f64,
    pub c: f64,
    /// If true, `stress_tangent` drops the non-symmetric part (an approximated tangent).
    pub approximate: bool,
}

impl AxisymmetricMaterial for NonSymmetric {
    fn stress(&self, f: &AxiF) -> activemuscle::Result<SVector<f64, 5>> {
        let mut p = f * self.mu;
        p[0] += self.c * f[3] * f[3];
        Ok(p)
    }
    fn stress_tangent(
        &self,
        f: &AxiF,
    ) -> activemuscle::Result<(SVector<f64, 5>, SMatrix<f64, 5, 5>)> {
        let mut a = SMatrix::<f64, 5, 5>::identity() * self.mu;
        if !self.approximate {
            a[(0, 3)] += 2.0 * self.c * f[3];
        }
        Ok((self.stress(f)?, a))
    }
    fn point_fields(&self, f: &AxiF) -> activemuscle::Result<(f64, f64)> {
        Ok((0.0, axial_stretch(f)))
    }
}
