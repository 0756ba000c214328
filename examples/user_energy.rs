//! A user-defined energy: implement one generic method and get stress, tangent, activation laws,
//! both couplings and the FE solver for free.
//!
//! Run with `cargo run --release --example user_energy`. It ends with the Taylor test of the
//! tangents the solver would use for this energy (`activemuscle::tangent_check`).
//!
//! The energy here is a transversely isotropic Mooney–Rivlin-type material with an exponential
//! fibre term (Holzapfel-like):
//! W = c₁ (tr C − 3) + c₂ (tr C⁻¹ − 3) + k₁/(2k₂) [e^{k₂ (C:M − 1)²} − 1].

use activemuscle::active::{ActiveCurve, Coupling, FrozenTangent, ImplicitLaw, Law};
use activemuscle::energy::Invariants;
use activemuscle::tangent_check::{halvings, taylor_test, MusclePoint};
use activemuscle::uniaxial::along_fibres;
use activemuscle::{Muscle, Scalar, StrainEnergy};
use nalgebra::{Matrix3, Vector3};

/// Parameters in kPa (c₁, c₂, k₁) and dimensionless (k₂).
#[derive(Debug, Clone)]
struct FibreReinforced {
    c1: f64,
    c2: f64,
    k1: f64,
    k2: f64,
}

impl StrainEnergy for FibreReinforced {
    fn energy<T: Scalar>(&self, c: &Invariants<T>) -> T {
        let fibre = c.c_m - 1.0;
        (c.tr_c - 3.0) * self.c1
            + (c.tr_c_inv - 3.0) * self.c2
            + (fibre * fibre * self.k2).exp_m1() * (self.k1 / (2.0 * self.k2))
    }

    fn name(&self) -> &str {
        "fibre-reinforced Mooney-Rivlin"
    }
}

fn main() -> activemuscle::Result<()> {
    let energy = FibreReinforced {
        c1: 0.5,
        c2: 0.2,
        k1: 2.0,
        k2: 3.0,
    };
    // The chapter's activation fit, now for this energy: the implicit law picks γ(λ) so that the
    // stress at frozen γ equals the target P_pas(λ) + P_act(λ) (d = 0).
    let curve = ActiveCurve::paper();
    let law = Law::Implicit(ImplicitLaw::new(energy.clone(), curve));
    let passive = Muscle::passive(energy.clone());
    let frozen = Muscle::new(
        energy.clone(),
        law.clone(),
        0.0,
        Coupling::Frozen(FrozenTangent::Exact),
    )?;
    let consistent = Muscle::new(energy.clone(), law, 0.0, Coupling::Consistent)?;
    println!("{} along the fibres (kPa)", energy.name());
    println!(
        "{:>6} {:>10} {:>13} {:>10} {:>10} {:>12}",
        "lambda", "P_pas", "P_pas+P_act", "gamma", "P frozen", "P consistent"
    );
    for i in 0..=8 {
        let l = 0.8 + 0.1 * i as f64;
        let p = along_fibres(&passive, l)?;
        let (f, c) = (along_fibres(&frozen, l)?, along_fibres(&consistent, l)?);
        println!(
            "{l:6.2} {:10.4} {:13.4} {:10.6} {:10.4} {:12.4}",
            p.stress,
            p.stress + curve.value(l),
            f.gamma,
            f.stress,
            c.stress
        );
    }
    // Frozen coupling reproduces the target by construction. The consistent model's stress is the
    // derivative of the energy along the law, d/dλ W(λ, γ(λ)) = ∂W/∂λ + (∂W/∂γ) γ′(λ): it differs
    // from the target by (∂W/∂γ) γ′(λ), which vanishes only where γ does not change with λ.
    check_tangents(&frozen, &consistent)
}

/// The Taylor test of both models' tangents at a sheared stretch along the fibre e₁: the
/// remainder r₁(h) = |P(F + hΔF) − P(F) − h A:ΔF| falls as h² (order 2) where A is the
/// derivative of P; central differences of P agree with A; the frozen tangent is not symmetric
/// (its stress is not a gradient), and how far its symmetric approximation is from it.
fn check_tangents(
    frozen: &Muscle<FibreReinforced>,
    consistent: &Muscle<FibreReinforced>,
) -> activemuscle::Result<()> {
    let f = Matrix3::new(1.15, 0.05, -0.02, 0.03, 0.94, 0.04, -0.01, 0.02, 0.93);
    let df = Matrix3::new(0.3, -0.2, 0.1, 0.25, -0.35, 0.15, -0.1, 0.2, 0.4);
    let h = halvings(2f64.powi(-6), 2f64.powi(-20))?;
    println!("\nTaylor test at a sheared stretch of 1.15 along the fibres, h = 2^-6 ... 2^-20");
    for (name, muscle) in [("frozen", frozen), ("consistent", consistent)] {
        let point = MusclePoint::new(muscle.clone(), Vector3::x())?;
        let report = taylor_test(&point, &f, &df, &h)?;
        let (r, s) = (&report.remainders, &report.state);
        let order = |o: Option<f64>| o.map_or("-".to_string(), |o| format!("{o:.3}"));
        println!(
            "{name:>10}: order of r0 {}, of r1 {}; central differences {:.1e}; asymmetry {:.3}{}",
            order(r.order_0),
            order(r.order_1),
            s.fd_error.unwrap_or(f64::NAN),
            s.asymmetry,
            s.asymmetry_reason
                .as_ref()
                .map_or(String::new(), |why| format!(" ({why})"))
        );
        for (approximation, error) in &s.approximations {
            println!(
                "{:>10}  the {approximation} tangent: |A_approx − A|/|A| = {error:.3}",
                ""
            );
        }
        if let Some(flag) = &r.flag {
            println!("{:>10}  flagged: {}", "", flag.reason());
        }
    }
    Ok(())
}
