//! A user-defined energy: implement one generic method and get stress, tangent, activation laws,
//! both couplings and the FE solver for free.
//!
//! Run with `cargo run --release --example user_energy`.
//!
//! The energy here is a transversely isotropic Mooney–Rivlin-type material with an exponential
//! fibre term (Holzapfel-like):
//! W = c₁ (tr C − 3) + c₂ (tr C⁻¹ − 3) + k₁/(2k₂) [e^{k₂ (C:M − 1)²} − 1].

use activemuscle::active::{ActiveCurve, Coupling, ImplicitLaw, Law};
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
    // The chapter's activation fit, now for this energy: γ(λ) solves P_tot = P_pas + P_act.
    let law = Law::Implicit(ImplicitLaw::new(energy.clone(), ActiveCurve::paper()));
    let passive = Muscle::passive(energy.clone());
    let active = Muscle::new(energy.clone(), law, 0.0, Coupling::Consistent)?;
    println!("{} along the fibres (kPa)", energy.name());
    println!(
        "{:>6} {:>10} {:>10} {:>10}",
        "lambda", "P_pas", "gamma", "P"
    );
    for i in 0..=8 {
        let l = 0.8 + 0.1 * i as f64;
        let (p, a) = (along_fibres(&passive, l)?, along_fibres(&active, l)?);
        println!(
            "{l:6.2} {:10.4} {:10.6} {:10.4}",
            p.stress, a.gamma, a.stress
        );
    }
    Ok(())
}
