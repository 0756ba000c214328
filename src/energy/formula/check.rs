//! The formula at the reference configuration F = I (invariants j₀ = [3, 1, 3, 1, 1]), checked
//! with its parameters whenever they change.
//!
//! At F = I the stress of any energy of the five invariants is, with g = ∂W/∂j at j₀ and M = m⊗m,
//!
//! P(I) = 2 (g_{tr C} − g_{tr C⁻¹} + g_{det C}) I + 2 (g_{C:M} − g_{C⁻¹:M}) M
//!
//! (∂tr C/∂F = 2F, ∂(C:M)/∂F = 2FM, ∂tr C⁻¹/∂F = −2C⁻¹F⁻ᵀ, ∂(C⁻¹:M)/∂F = −2F⁻ᵀMC⁻¹,
//! ∂det C/∂F = 2 det C F⁻ᵀ, all at F = I). The rules:
//!
//! - W, ∂W/∂j and ∂²W/∂j² are finite at j₀ (`sqrt(I1 - 3)`, whose slope is infinite there, is
//!   refused);
//! - W(I) = 0: under active strain Ŵ = (1 − γ) W(C_e), so a constant in W would change ∂Ŵ/∂γ,
//!   the activation laws and the consistent coupling;
//! - the fibre part of P(I) vanishes: a pressure balances a hydrostatic stress at the reference,
//!   not a uniaxial one. The hydrostatic part s₀ = 2 (g_{tr C} − g_{tr C⁻¹} + g_{det C}) is
//!   admitted, as for the neo-Hookean energy μ/2 (I₁ − 3) (s₀ = μ): under exact
//!   incompressibility the pressure absorbs it, and a volumetric energy adds the linear term that
//!   cancels it ([`crate::volumetric::Volumetric::new`]).

use super::program::Program;
use super::FormulaError;
use crate::energy::Invariants;
use nalgebra::SVector;
use num_dual::{gradient, hessian, Dual2SVec64, DualSVec64};

/// The invariants at F = I.
pub const REFERENCE: [f64; 5] = [3.0, 1.0, 3.0, 1.0, 1.0];

/// Relative tolerance of W(I) = 0 and of the fibre stress at I, against the size of the terms.
const TOLERANCE: f64 = 1e-10;

/// Checks the program with constants `c` at F = I; returns the hydrostatic stress s₀ \[kPa\].
pub fn reference(program: &Program, c: &[f64], values: &str) -> Result<f64, FormulaError> {
    let j0 = SVector::from(REFERENCE);
    let (w, g, h) = hessian(
        |v: SVector<Dual2SVec64<5>, 5>| {
            program.energy(c, &Invariants::from_array([v[0], v[1], v[2], v[3], v[4]]))
        },
        &j0,
    );
    let at = |what: &str| {
        format!("{what} at F = I (invariants tr C = 3, C:M = 1, tr C⁻¹ = 3, C⁻¹:M = 1, det C = 1), with {values}")
    };
    if !(w.is_finite() && g.iter().all(|x| x.is_finite()) && h.iter().all(|x| x.is_finite())) {
        return Err(FormulaError::formula(
            format!("W = {w}, ∂W/∂j = [{}]", list(g.as_slice())),
            format!(
                "{}: W and its first and second derivatives in the invariants must be finite there (sqrt(I1 - 3) or (I1 - 3)^1.5 have an infinite slope or curvature at I1 = 3; integer powers such as (I1 - 3)^2, or expm1 forms, do not)",
                at("W or a derivative is not finite")
            ),
        ));
    }
    let size = 1.0
        + g.iter()
            .zip(REFERENCE)
            .map(|(g, j)| (g * j).abs())
            .sum::<f64>();
    if w.abs() > TOLERANCE * size {
        return Err(FormulaError::formula(
            format!("W(I) = {w}"),
            format!(
                "{}: the reference must store no energy (under active strain Ŵ = (1 − γ) W(C_e), so a constant in W changes ∂Ŵ/∂γ, the activation laws and the consistent coupling); subtract the constant from W",
                at("not 0")
            ),
        ));
    }
    let fibre = 2.0 * (g[1] - g[3]);
    if fibre.abs() > TOLERANCE * size {
        return Err(FormulaError::formula(
            format!("2(∂W/∂c_m − ∂W/∂c_inv_m) = {fibre} kPa"),
            format!(
                "{}: the stress there is P(I) = s₀ I + 2(∂W/∂c_m − ∂W/∂c_inv_m) M, and a pressure balances the hydrostatic part s₀ only, not a stress along the fibres; write the fibre terms so that they are stress free at I4 = 1 (e.g. (I4 - 1)^2, not I4 - 1)",
                at("a stress along the fibres")
            ),
        ));
    }
    Ok(2.0 * (g[0] - g[2] + g[4]))
}

/// States (invariants, not all of one deformation: W is a function of five numbers) at which
/// [`structural_weight`] reads W's gradient.
const SAMPLES: [[f64; 5]; 3] = [
    [3.2, 1.3, 3.1, 0.8, 1.0],
    [2.9, 0.7, 3.4, 1.5, 1.0],
    [3.6, 1.7, 3.2, 0.6, 1.2],
];

/// The weight f of C:M in a structural invariant I = ((1 − f)/3) tr C + f C:M through which
/// alone W depends on tr C and C:M, if it has one (what the structural activation of Ehret,
/// Böl & Itskov needs, [`crate::energy::StrainEnergy::structural_fibre_weight`]): then
/// ∂W/∂(C:M) / ∂W/∂(tr C) = 3f/(1 − f) everywhere, i.e. f = g_{C:M}/(3 g_{tr C} + g_{C:M}). Read
/// at [`SAMPLES`] and accepted if the same there to 1e-9 (relative) and in (0, 1]: a formula
/// written in I_p = (w0/3) tr C + (1 − w0) C:M gives f = 1 − w0 to rounding; one with a fibre
/// term of its own (e.g. (I4 − 1)²) gives different ratios and no structural invariant.
pub fn structural_weight(program: &Program, c: &[f64]) -> Option<f64> {
    let mut weight: Option<f64> = None;
    for s in SAMPLES {
        let (_, g) = gradient(
            |v: SVector<DualSVec64<5>, 5>| {
                program.energy(c, &Invariants::from_array([v[0], v[1], v[2], v[3], v[4]]))
            },
            &SVector::from(s),
        );
        let here = g[1] / (3.0 * g[0] + g[1]);
        if !here.is_finite() {
            return None;
        }
        match weight {
            None => weight = Some(here),
            Some(f) if (here - f).abs() <= 1e-9 * f.abs() => {}
            Some(_) => return None,
        }
    }
    weight.filter(|f| *f > 0.0 && *f <= 1.0)
}

fn list(v: &[f64]) -> String {
    v.iter()
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}
