//! A user-defined energy: implement one generic method and get stress, tangent, activation laws,
//! both couplings and the FE solver for free.
//!
//! Run with `cargo run --release --example user_energy`.
//!
//! The energy here is a transversely isotropic Mooney–Rivlin-type material with an exponential
//! fibre term (Holzapfel-like):
//! W = c₁ (tr C − 3) + c₂ (tr C⁻¹ − 3) + k₁/(2k₂) [e^{k₂ (C:M − 1)²} − 1].

use activemuscle::active::{ActiveCurve, Coupling, FrozenTangent, ImplicitLaw, Law};
use activemuscle::energy::Invariants;
use activemuscle::uniaxial::along_fibres;
use activemuscle::{Muscle, Scalar, StrainEnergy};

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
    Ok(())
}
