//! The same battery on every shipped energy, passive (γ = 0) and inside the active-strain wrapper.

use activemuscle::energy::{EhretBolItskov, FourCPassive, GiantesioMusesti, NeoHookean};
use activemuscle::energy_test_battery;

energy_test_battery!(
    giantesio_musesti_passive,
    GiantesioMusesti::paper(),
    gamma = 0.0
);
energy_test_battery!(
    giantesio_musesti_active,
    GiantesioMusesti::paper(),
    gamma = 0.3
);
energy_test_battery!(
    ehret_bol_itskov_passive,
    EhretBolItskov::paper(),
    gamma = 0.0
);
energy_test_battery!(
    ehret_bol_itskov_active,
    EhretBolItskov::paper(),
    gamma = 0.2
);
energy_test_battery!(four_c_passive_passive, FourCPassive::paper(), gamma = 0.0);
energy_test_battery!(four_c_passive_active, FourCPassive::paper(), gamma = 0.25);
energy_test_battery!(
    neo_hookean_passive,
    NeoHookean::new(1.0).unwrap(),
    gamma = 0.0
);
energy_test_battery!(
    neo_hookean_active,
    NeoHookean::new(1.0).unwrap(),
    gamma = 0.25
);

/// A user-defined energy that uses all five invariants, so that every invariant's derivatives are
/// exercised (the shipped energies do not use det C).
#[derive(Debug, Clone)]
struct AllInvariants;

impl activemuscle::StrainEnergy for AllInvariants {
    fn energy<T: activemuscle::Scalar>(&self, c: &activemuscle::energy::Invariants<T>) -> T {
        (c.tr_c - 3.0) * 0.5
            + (c.c_m - 1.0).powi(2) * 0.7
            + (c.tr_c_inv - 3.0) * 0.3
            + (c.c_inv_m - 1.0).powi(2) * 0.2
            - c.det_c.ln() * 0.4
            + (c.det_c - 1.0).powi(2) * 1.3
            + (((c.c_m - 1.0) * 0.5).exp_m1() - (c.c_m - 1.0) * 0.5) * c.det_c.sqrt()
    }
}

energy_test_battery!(all_invariants_passive, AllInvariants, gamma = 0.0);
energy_test_battery!(all_invariants_active, AllInvariants, gamma = 0.35);

/// [`AllInvariants`] written as a formula (a parameter-free one: numbers only).
fn all_invariants_formula() -> activemuscle::energy::FormulaEnergy {
    activemuscle::energy::FormulaEnergy::new(
        "0.5*(tr_c - 3) + 0.7*(c_m - 1)^2 + 0.3*(tr_c_inv - 3) + 0.2*(c_inv_m - 1)^2 \
         - 0.4*ln(det_c) + 1.3*(det_c - 1)^2 + (expm1((c_m - 1)*0.5) - (c_m - 1)*0.5)*sqrt(det_c)",
        Vec::new(),
    )
    .unwrap()
}

energy_test_battery!(
    formula_yeoh_fibres_passive,
    crate::formula_energy::yeoh_fibres(),
    gamma = 0.0
);
energy_test_battery!(
    formula_yeoh_fibres_active,
    crate::formula_energy::yeoh_fibres(),
    gamma = 0.25
);
energy_test_battery!(
    formula_all_invariants_active,
    all_invariants_formula(),
    gamma = 0.35
);
