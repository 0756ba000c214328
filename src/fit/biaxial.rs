//! Passive parameters of any [`Parametric`] energy fitted to planar biaxial data, the test that
//! soft-tissue labs report: rows (λ₁, λ₂, P₁₁, P₂₂), λ₁ along the fibres and λ₂ across, the faces
//! normal to e₃ traction free, exactly incompressible.
//!
//! With C = diag(λ₁², λ₂², λ₃²), λ₃ = 1/(λ₁λ₂) and m = e₁ the energy reduces to
//!
//! w(λ₁, λ₂; θ) = W(j(λ₁, λ₂); θ),  j = [λ₁² + λ₂² + λ₃², λ₁², λ₁⁻² + λ₂⁻² + λ₃⁻², λ₁⁻², 1],
//!
//! and zero traction on the e₃ faces gives the nominal stresses P₁₁ = ∂w/∂λ₁, P₂₂ = ∂w/∂λ₂
//! (the pressure drops out with λ₃). Each is one dual number in its stretch nested over the
//! parameter scalar, so the same formula gives P and ∂P/∂θ. Residuals: P₁₁ − P₁₁ᵢ and
//! P₂₂ − P₂₂ᵢ for every row \[kPa\].

use super::data::{open, read_columns};
use super::passive::fit_energy;
use super::{FitError, FitSetup, Parametric, PassiveFit, Residuals, Selection};
use crate::energy::Invariants;
use crate::Scalar;
use num_dual::Dual;
use std::io::Read;
use std::path::Path;

/// The CSV header of biaxial data.
pub const BIAXIAL_HEADER: [&str; 4] = ["lambda1", "lambda2", "P11", "P22"];

/// Validated planar biaxial data: stretches positive, every value finite. The rows may follow
/// any path (equibiaxial, strip, several protocols one after the other).
#[derive(Debug, Clone, PartialEq)]
pub struct BiaxialData {
    stretches: Vec<[f64; 2]>,
    stresses: Vec<[f64; 2]>,
}

impl BiaxialData {
    /// From rows (λ₁, λ₂) [-] and (P₁₁, P₂₂) \[kPa\]; errors name the 1-based point.
    pub fn new(stretches: Vec<[f64; 2]>, stresses: Vec<[f64; 2]>) -> Result<Self, FitError> {
        if stretches.len() != stresses.len() {
            return Err(FitError::LengthMismatch {
                stretches: stretches.len(),
                stresses: stresses.len(),
            });
        }
        let locations: Vec<String> = (1..=stretches.len())
            .map(|i| format!("point {i}"))
            .collect();
        Self::validated(stretches, stresses, &locations)
    }

    fn validated(
        stretches: Vec<[f64; 2]>,
        stresses: Vec<[f64; 2]>,
        locations: &[String],
    ) -> Result<Self, FitError> {
        for (i, (l, p)) in stretches.iter().zip(&stresses).enumerate() {
            let values = [l[0], l[1], p[0], p[1]];
            for (&value, column) in values.iter().zip(BIAXIAL_HEADER) {
                if !value.is_finite() {
                    return Err(FitError::NonFiniteData {
                        location: locations[i].clone(),
                        column,
                        value,
                    });
                }
            }
            if let Some(&lambda) = l.iter().find(|&&x| x <= 0.0) {
                return Err(FitError::NonPositiveStretch {
                    location: locations[i].clone(),
                    lambda,
                });
            }
        }
        Ok(Self {
            stretches,
            stresses,
        })
    }

    /// Reads a CSV file with header `lambda1,lambda2,P11,P22`.
    pub fn from_csv_path(path: impl AsRef<Path>) -> Result<Self, FitError> {
        let path = path.as_ref();
        Self::from_csv_reader(open(path)?, &path.display().to_string())
    }

    /// Reads CSV with header `lambda1,lambda2,P11,P22` from any reader, within the limits of
    /// [`super::MAX_DATA_BYTES`] and [`super::MAX_DATA_POINTS`].
    pub fn from_csv_reader(reader: impl Read, source_name: &str) -> Result<Self, FitError> {
        let (c, locations) = read_columns(reader, source_name, &BIAXIAL_HEADER, &[])?;
        let rows = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(&x, &y)| [x, y]).collect();
        Self::validated(rows(&c[0], &c[1]), rows(&c[2], &c[3]), &locations)
    }

    /// The stretches (λ₁, λ₂) of each row [-].
    pub fn stretches(&self) -> &[[f64; 2]] {
        &self.stretches
    }

    /// The nominal stresses (P₁₁, P₂₂) of each row \[kPa\].
    pub fn stresses(&self) -> &[[f64; 2]] {
        &self.stresses
    }

    /// Number of rows (each gives two residuals).
    pub fn len(&self) -> usize {
        self.stretches.len()
    }

    /// True if there are no rows.
    pub fn is_empty(&self) -> bool {
        self.stretches.is_empty()
    }
}

/// The invariants j(λ₁, λ₂) of C = diag(λ₁², λ₂², (λ₁λ₂)⁻²) with m = e₁.
fn biaxial_invariants<T: Scalar>(l1: T, l2: T) -> Invariants<T> {
    let (a, b) = (l1 * l1, l2 * l2);
    let c = (a * b).recip();
    let (ia, ib) = (a.recip(), b.recip());
    Invariants::from_array([a + b + c, a, ia + ib + a * b, ia, T::one()])
}

/// The passive nominal stresses (P₁₁, P₂₂) \[kPa\] of planar biaxial stretch (λ₁, λ₂), exactly
/// incompressible, e₃ faces traction free, with all parameters of `energy` as scalars (dual
/// numbers differentiate in them).
pub fn biaxial_stress_with<E: Parametric, T: Scalar>(
    energy: &E,
    parameters: &[T],
    [l1, l2]: [f64; 2],
) -> [T; 2] {
    let lifted: Vec<Dual<T>> = parameters.iter().map(|&p| Dual::from_re(p)).collect();
    let fixed = |x: f64| Dual::from_re(T::from(x));
    let moving = |x: f64| Dual::from_re(T::from(x)).derivative();
    let p11 = energy.energy_with(&lifted, &biaxial_invariants(moving(l1), fixed(l2)));
    let p22 = energy.energy_with(&lifted, &biaxial_invariants(fixed(l1), moving(l2)));
    [p11.eps, p22.eps]
}

struct BiaxialProblem<'a, E> {
    energy: &'a E,
    selection: &'a Selection,
    data: &'a BiaxialData,
}

impl<E: Parametric> Residuals for BiaxialProblem<'_, E> {
    fn count(&self) -> usize {
        2 * self.data.len()
    }

    fn residuals<T: Scalar>(&self, theta: &[T]) -> crate::Result<Vec<T>> {
        let params = self.selection.assemble(theta);
        // Parameters the energy's constructor refuses (e.g. w0 = 1) are outside the model.
        self.energy
            .rebuilt(&params.iter().map(|p| p.re()).collect::<Vec<_>>())?;
        let mut out = Vec::with_capacity(self.count());
        for (&l, p) in self.data.stretches().iter().zip(self.data.stresses()) {
            let [p11, p22] = biaxial_stress_with(self.energy, &params, l);
            out.push(p11 - p[0]);
            out.push(p22 - p[1]);
        }
        Ok(out)
    }
}

/// Fits the parameters of `energy` chosen in `setup` (default: all but μ, as for uniaxial data)
/// to planar biaxial data; the other parameters stay at their values.
pub fn fit_passive_biaxial<E: Parametric>(
    energy: &E,
    data: &BiaxialData,
    setup: &FitSetup,
) -> Result<PassiveFit<E>, FitError> {
    fit_energy(energy, setup, |selection| {
        let problem = BiaxialProblem {
            energy,
            selection,
            data,
        };
        let observed: Vec<f64> = data.stresses().iter().flat_map(|p| [p[0], p[1]]).collect();
        selection.solve(&problem, setup, &observed)
    })
}
