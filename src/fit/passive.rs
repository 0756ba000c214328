//! Fit 1: passive parameters of any [`Parametric`] energy to uniaxial (λ, P) data.
//!
//! Along the fibres (F = diag(λ, λ^-½, λ^-½), m = e₁) the nominal stress is the derivative of the
//! energy along the path (eq. (11)),
//!
//! P(λ; θ) = d/dλ W(j(λ); θ),  j(λ) = [λ² + 2/λ, λ², λ⁻² + 2λ, λ⁻², 1],
//!
//! evaluated with λ as a dual number nested over the parameter dual (`Dual<T>`), so the same
//! formula gives P and ∂P/∂θ.
//!
//! Across the fibres (stretch λ along e₂, F = diag(a, λ, 1/(aλ))) the reduced energy
//! w(a, λ; θ) = W(j(a, λ); θ) with j = [a² + λ² + (aλ)⁻², a², a⁻² + λ⁻² + (aλ)², a⁻², 1] gives the
//! lateral equilibrium ∂w/∂a = 0 (traction-free lateral faces) and the stress P = ∂w/∂λ at that a.
//! The fibre stretch a*(θ) is solved in f64 by [`crate::uniaxial::across_fibres`]; its parameter
//! derivatives follow from the implicit-function theorem by one Newton step taken in dual
//! arithmetic from the converged root, a = a* − w_a/w_aa (exact first derivatives, since
//! w_a(a*) = 0).

use super::{
    parameter_bounds, Data, FitError, FitReport, FitSetup, Parametric, Residuals, Selection,
};
use crate::active::fibre_path_invariants;
use crate::energy::Invariants;
use crate::material::Muscle;
use crate::uniaxial::{across_fibres, Direction};
use crate::Scalar;
use num_dual::{Dual, Dual2};

/// A fitted energy and its report.
#[derive(Debug, Clone, PartialEq)]
pub struct PassiveFit<E> {
    /// The energy with the fitted parameters.
    pub energy: E,
    /// Statistics of the fit.
    pub report: FitReport,
}

/// The passive nominal stress along the fibres, P(λ) = dW/dλ \[kPa\], with all parameters of
/// `energy` given as scalars `parameters` (dual numbers differentiate in them).
pub fn fibre_stress_with<E: Parametric, T: Scalar>(energy: &E, parameters: &[T], lambda: f64) -> T {
    let lifted: Vec<Dual<T>> = parameters.iter().map(|&p| Dual::from_re(p)).collect();
    let l = Dual::from_re(T::from(lambda)).derivative();
    let j = Invariants::from_array(fibre_path_invariants(l));
    energy.energy_with(&lifted, &j).eps
}

/// Invariants of C = diag(a², λ², (aλ)⁻²) with m = e₁.
fn across_invariants<T: Scalar>(a: T, lambda: T) -> Invariants<T> {
    let (a2, l2) = (a * a, lambda * lambda);
    let (ia2, il2) = (a2.recip(), l2.recip());
    Invariants::from_array([a2 + l2 + ia2 * il2, a2, ia2 + il2 + a2 * l2, ia2, T::one()])
}

/// The passive nominal stress across the fibres \[kPa\] at the lateral equilibrium a*, with all
/// parameters of `energy` given as scalars: a* is solved in f64, then lifted to the parameter
/// scalar by one dual Newton step (exact first derivatives, see the module docs).
pub fn across_stress_with<E: Parametric, T: Scalar>(
    energy: &E,
    parameters: &[T],
    lambda: f64,
) -> crate::Result<T> {
    let values: Vec<f64> = parameters.iter().map(|p| p.re()).collect();
    let a_star = across_fibres(&Muscle::passive(energy.rebuilt(&values)?), lambda)?.lateral[0];
    // w_a and w_aa at a*, parameters as T.
    let lifted2: Vec<Dual2<T>> = parameters.iter().map(|&p| Dual2::from_re(p)).collect();
    let a2 = Dual2::from_re(T::from(a_star)).derivative();
    let w = energy.energy_with(
        &lifted2,
        &across_invariants(a2, Dual2::from_re(T::from(lambda))),
    );
    let a = T::from(a_star) - w.v1 / w.v2;
    // P = ∂w/∂λ at (a, λ).
    let lifted: Vec<Dual<T>> = parameters.iter().map(|&p| Dual::from_re(p)).collect();
    let l = Dual::from_re(T::from(lambda)).derivative();
    Ok(energy
        .energy_with(&lifted, &across_invariants(Dual::from_re(a), l))
        .eps)
}

struct PassiveProblem<'a, E> {
    energy: &'a E,
    selection: &'a Selection,
    sets: &'a [(Direction, &'a Data)],
}

impl<E: Parametric> Residuals for PassiveProblem<'_, E> {
    fn count(&self) -> usize {
        self.sets.iter().map(|(_, d)| d.len()).sum()
    }

    fn residuals<T: Scalar>(&self, theta: &[T]) -> crate::Result<Vec<T>> {
        let params = self.selection.assemble(theta);
        // Parameters the energy's constructor refuses (e.g. w0 = 1) are outside the model.
        self.energy
            .rebuilt(&params.iter().map(|p| p.re()).collect::<Vec<_>>())?;
        let mut out = Vec::with_capacity(self.count());
        for (direction, data) in self.sets {
            for (&l, &p) in data.lambda().iter().zip(data.stress()) {
                let model = match direction {
                    Direction::Along => fibre_stress_with(self.energy, &params, l),
                    Direction::Across => across_stress_with(self.energy, &params, l)?,
                };
                out.push(model - p);
            }
        }
        Ok(out)
    }
}

/// The parameters a passive fit frees by default: all but μ (the chapter's practice), or all if
/// μ is the only one.
pub fn default_passive_free<'a>(names: &[&'a str]) -> Vec<&'a str> {
    let free: Vec<&str> = names.iter().copied().filter(|n| *n != "mu").collect();
    if free.is_empty() {
        names.to_vec()
    } else {
        free
    }
}

/// Fits the parameters of `energy` chosen in `setup` (default: all but μ, as the chapter does)
/// to uniaxial data sets: each `(direction, data)` contributes its residuals
/// P_model(λ_i) − P_i \[kPa\]. The model's other parameters stay at their values.
pub fn fit_passive<E: Parametric>(
    energy: &E,
    sets: &[(Direction, &Data)],
    setup: &FitSetup,
) -> Result<PassiveFit<E>, FitError> {
    fit_energy(energy, setup, |selection| {
        let problem = PassiveProblem {
            energy,
            selection,
            sets,
        };
        let observed: Vec<f64> = sets.iter().flat_map(|(_, d)| d.stress().to_vec()).collect();
        selection.solve(&problem, setup, &observed)
    })
}

/// The frame of every passive fit: the parameters of `energy` chosen in `setup` (default: all
/// but μ), solved by `solve` on that selection, and the energy rebuilt at the fitted values.
pub(crate) fn fit_energy<E: Parametric>(
    energy: &E,
    setup: &FitSetup,
    solve: impl FnOnce(&Selection) -> Result<super::FitReport, FitError>,
) -> Result<PassiveFit<E>, FitError> {
    let names = energy.parameter_names();
    let selection = setup.resolve(
        &names,
        &energy.parameter_values(),
        &parameter_bounds(energy),
        &default_passive_free(&names),
    )?;
    let report = solve(&selection)?;
    let energy = energy.rebuilt(&selection.assemble_values(&report.values))?;
    Ok(PassiveFit { energy, report })
}
