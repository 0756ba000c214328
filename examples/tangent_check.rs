//! Checking a tangent ported from another code: a material written for the FE solver
//! (`AxisymmetricMaterial`) with its stress and tangent derived by hand, as users port them,
//! passed through the Taylor test of `activemuscle::tangent_check`; then the same material with
//! a slip in its tangent (a factor 4 written as 2), which the test reports with order 1 and why.
//!
//! Run with `cargo run --release --example tangent_check`. To check a scene's own material with
//! defaults, no code: `activemuscle tangent SCENE.toml` (docs/tangent-check.md).
//!
//! The material, fibres along the cylinder's axis z, over the five axisymmetric entries
//! [F_rr, F_rz, F_zr, F_zz, F_θθ]:
//! W = μ/2 (tr C − 3) + k₁/(2k₂) [e^{k₂ (C_zz − 1)²} − 1], C_zz = F_rz² + F_zz²,
//! P = μ F + 2 g(C_zz) (0, F_rz, 0, F_zz, 0), g(c) = k₁ (c − 1) e^{k₂ (c − 1)²},
//! ∂P_a/∂F_b = μ δ_ab + 2 g δ_ab + 4 g′ F_a F_b (a, b ∈ {rz, zz}), g′(c) = k₁ e^{k₂ (c − 1)²} [1 + 2k₂ (c − 1)²].

use activemuscle::fem::material::axial_stretch;
use activemuscle::fem::{AxiF, AxisymmetricMaterial};
use activemuscle::tangent_check::{halvings, taylor_test};
use nalgebra::{Matrix3, SMatrix, SVector};

/// The ported material; `slip` is the factor of its tangent's g′ term (4 is right).
struct Ported {
    mu: f64,
    k1: f64,
    k2: f64,
    slip: f64,
}

impl Ported {
    /// g(C_zz) and g′(C_zz).
    fn fibre(&self, f: &AxiF) -> (f64, f64) {
        let c = f[1] * f[1] + f[3] * f[3] - 1.0;
        let e = (self.k2 * c * c).exp();
        (self.k1 * c * e, self.k1 * e * (1.0 + 2.0 * self.k2 * c * c))
    }
}

impl AxisymmetricMaterial for Ported {
    fn stress(&self, f: &AxiF) -> activemuscle::Result<SVector<f64, 5>> {
        let (g, _) = self.fibre(f);
        let mut p = f * self.mu;
        p[1] += 2.0 * g * f[1];
        p[3] += 2.0 * g * f[3];
        Ok(p)
    }

    fn stress_tangent(
        &self,
        f: &AxiF,
    ) -> activemuscle::Result<(SVector<f64, 5>, SMatrix<f64, 5, 5>)> {
        let (g, dg) = self.fibre(f);
        let mut a = SMatrix::<f64, 5, 5>::identity() * self.mu;
        for x in [1, 3] {
            a[(x, x)] += 2.0 * g;
            for y in [1, 3] {
                a[(x, y)] += self.slip * dg * f[x] * f[y];
            }
        }
        Ok((self.stress(f)?, a))
    }

    fn point_fields(&self, f: &AxiF) -> activemuscle::Result<(f64, f64)> {
        Ok((0.0, axial_stretch(f)))
    }
}

fn main() -> activemuscle::Result<()> {
    // A state of the cylinder in (r, θ, z): stretched along z, sheared in the r–z plane.
    let f = Matrix3::new(0.95, 0.0, 0.08, 0.0, 0.97, 0.0, -0.05, 0.0, 1.12);
    let df = Matrix3::new(0.2, 0.0, -0.3, 0.0, 0.4, 0.0, 0.1, 0.0, 0.5);
    let h = halvings(2f64.powi(-6), 2f64.powi(-20))?;
    for slip in [4.0, 2.0] {
        let material = Ported {
            mu: 3.0,
            k1: 2.0,
            k2: 5.0,
            slip,
        };
        let report = taylor_test(&material, &f, &df, &h)?;
        let r = &report.remainders;
        println!("tangent with {slip} g′ F_a F_b:");
        println!("  h          r0          r1");
        for (k, step) in r.h.iter().enumerate().step_by(2) {
            let show = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3e}"));
            println!("  {step:.3e}  {}   {}", show(r.r0[k]), show(r.r1[k]));
        }
        println!(
            "  order of r0 {:.3}, of r1 {:.3}; central differences differ by {:.2e}",
            r.order_0.unwrap_or(f64::NAN),
            r.order_1.unwrap_or(f64::NAN),
            report.state.fd_error.unwrap_or(f64::NAN)
        );
        match &r.flag {
            None => println!("  no flag: the tangent is the derivative of the stress"),
            Some(flag) => println!("  flagged {}: {}", flag.kind(), flag.reason()),
        }
    }
    Ok(())
}
