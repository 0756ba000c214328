//! Least-squares fitting of the model's parameters to stress–stretch data, the way the chapter
//! obtained them: (α, w0) of the passive energy with μ fixed (Table 1), (λ_min, λ_opt, k)
//! of the active curve with P_opt fixed (Table 2), (a, b) of the explicit law (eq. (14)),
//! and — read backwards — the damage d of a weakened muscle (section "Loss of activation").
//!
//! | fit | model of the data | default free parameters |
//! |---|---|---|
//! | [`fit_passive`] | P(λ) = dW(λ)/dλ along (or across) the fibres, any [`Parametric`] energy | all but μ |
//! | [`fit_active_curve`] | P_act(λ) of eq. (8) (data: active stress, or total minus passive via [`active_from_total`]) | λ_min, λ_opt, k |
//! | [`fit_explicit_law`] | γ_expl(λ; a, b) against the implicit γ, or the stress P_tot(λ, γ_expl) against P_pas + P_act | a, b |
//! | [`fit_damage`] | P_pas(λ) + (1 − d) P_act(λ) | d |
//!
//! Units: λ dimensionless, P in kPa (CSV header `lambda,P`, see [`Data`]).
//!
//! All residuals are written once for a generic scalar; the Jacobian comes from dual numbers
//! (one evaluation per free parameter, exact), see [`solver`]. Results are [`FitReport`]s with
//! the parameters, residual norm, RMS error, standard errors s²(JᵀJ)⁻¹, the correlation matrix,
//! iterations and the convergence flag; a fit that does not converge is an error
//! ([`FitError::NotConverged`]) carrying the best point found, never a result. A minimum on a
//! bound is a result, with the parameter marked [`AtBound`] ([`bounded`]). Residuals may be
//! weighted ([`Weights`]: relative, or by each point's standard deviation).

mod active;
mod biaxial;
mod bounded;
mod damage;
mod data;
mod error;
mod explicit;
mod levenberg;
mod parametric;
mod passive;
mod problem;
pub mod solver;
mod weights;

pub use crate::uniaxial::Direction;
pub use active::{active_from_total, fit_active_curve, ActiveFit};
pub use biaxial::{biaxial_stress_with, fit_passive_biaxial, BiaxialData, BIAXIAL_HEADER};
pub use bounded::{least_squares, AtBound};
pub use damage::{fit_damage, DamageFit};
pub use data::{Data, MAX_DATA_BYTES, MAX_DATA_POINTS};
pub use error::{FitError, NotConverged};
pub use explicit::{
    explicit_law_errors, fit_explicit_law, ExplicitFit, ExplicitTarget, COEFFICIENT_BOUNDS,
};
pub use levenberg::MAX_TRIES;
pub use parametric::{parameter_bounds, Parametric};
pub use passive::{
    across_stress_with, default_passive_free, fibre_stress_with, fit_passive, PassiveFit,
};
pub use problem::{residuals_and_jacobian, Bounds, Residuals};
pub use solver::{FitOptions, Method};
pub use weights::Weights;

use crate::Scalar;
use std::fmt;

/// The outcome of a least-squares fit, at the best point found.
#[derive(Debug, Clone, PartialEq)]
pub struct FitReport {
    /// Names of the free parameters, in order.
    pub names: Vec<String>,
    /// Fitted values.
    pub values: Vec<f64>,
    /// Standard errors σ_j = √(s² (JᵀJ)⁻¹_jj), s² = ‖r‖²/(m − p) (NaN if JᵀJ is singular).
    pub standard_errors: Vec<f64>,
    /// Correlation of the parameter estimates, ρ_ij = (JᵀJ)⁻¹_ij / √((JᵀJ)⁻¹_ii (JᵀJ)⁻¹_jj).
    pub correlation: Vec<Vec<f64>>,
    /// Residuals r_i = model − data at the fitted values (units of the data).
    pub residuals: Vec<f64>,
    /// ‖r‖₂.
    pub residual_norm: f64,
    /// RMS error √(‖r‖²/m).
    pub rms: f64,
    /// Solver iterations (Nelder–Mead plus Levenberg–Marquardt).
    pub iterations: u64,
    /// True only if the final Gauss–Newton step is negligible (see [`solver`]), the parameters
    /// held at a bound aside ([`bounded`]).
    pub converged: bool,
    /// How the solver(s) stopped.
    pub termination: String,
    /// Per parameter: the bound it is held at, if the minimum lies beyond it (its standard error
    /// and correlations are then NaN: it is not estimated).
    pub at_bound: Vec<Option<AtBound>>,
    /// The scale σ_i each residual was divided by in the fit (`None`: equal weights); the
    /// residuals, their norm and RMS above are in the data's unit, the standard errors from
    /// the weighted residuals ([`Weights`]).
    pub sigma: Option<Vec<f64>>,
}

impl FitReport {
    /// Fitted value of parameter `name`.
    pub fn value(&self, name: &str) -> Option<f64> {
        self.index(name).map(|i| self.values[i])
    }

    /// Standard error of parameter `name`.
    pub fn standard_error(&self, name: &str) -> Option<f64> {
        self.index(name).map(|i| self.standard_errors[i])
    }

    fn index(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }
}

impl fmt::Display for FitReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{:<12} {:>14} {:>12}",
            "parameter", "value", "std. error"
        )?;
        for i in 0..self.names.len() {
            match self.at_bound.get(i).copied().flatten() {
                Some(b) => writeln!(
                    f,
                    "{:<12} {:>14.6} at its bound {} (the minimum lies beyond, at {})",
                    self.names[i],
                    self.values[i],
                    crate::text::shortest(b.bound),
                    crate::text::significant(b.beyond, 6)
                )?,
                None => writeln!(
                    f,
                    "{:<12} {:>14.6} {:>12.3e}",
                    self.names[i], self.values[i], self.standard_errors[i]
                )?,
            }
        }
        if self.names.len() > 1 {
            write!(f, "correlation:")?;
            for row in &self.correlation {
                write!(f, " [")?;
                for c in row {
                    write!(f, "{c:>7.3}")?;
                }
                write!(f, " ]")?;
            }
            writeln!(f)?;
        }
        write!(
            f,
            "residual norm {:.4e}, RMS {:.4e}, {} points, {} iterations, {}",
            self.residual_norm,
            self.rms,
            self.residuals.len(),
            self.iterations,
            if self.converged {
                "converged"
            } else {
                "NOT converged"
            }
        )
    }
}

/// Which parameters are free, where they start and within which bounds; unnamed parameters keep
/// the model's values, starts default to the model's values, bounds to the model's admissible
/// ranges.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FitSetup {
    free: Option<Vec<String>>,
    start: Vec<(String, f64)>,
    bounds: Vec<(String, Bounds)>,
    /// Solver settings.
    pub options: FitOptions,
    /// How the residuals are weighted (default: equally).
    pub weights: Weights,
}

impl FitSetup {
    /// The fit's default free parameters, starts and bounds.
    pub fn new() -> Self {
        Self::default()
    }

    /// Frees exactly these parameters (the others are held at the model's values).
    pub fn free(mut self, names: &[&str]) -> Self {
        self.free = Some(names.iter().map(|s| s.to_string()).collect());
        self
    }

    /// Starting value of a free parameter.
    pub fn start(mut self, name: &str, value: f64) -> Self {
        self.start.push((name.to_string(), value));
        self
    }

    /// Bounds of a free parameter.
    pub fn bounds(mut self, name: &str, bounds: Bounds) -> Self {
        self.bounds.push((name.to_string(), bounds));
        self
    }

    /// Solver settings.
    pub fn options(mut self, options: FitOptions) -> Self {
        self.options = options;
        self
    }

    /// How the residuals are weighted.
    pub fn weights(mut self, weights: Weights) -> Self {
        self.weights = weights;
        self
    }

    /// Resolves the selection against a model's parameters.
    pub(crate) fn resolve(
        &self,
        names: &[&str],
        values: &[f64],
        bounds: &[Bounds],
        default_free: &[&str],
    ) -> Result<Selection, FitError> {
        let unknown = |name: &str| FitError::UnknownParameter {
            name: name.to_string(),
            available: names.iter().map(|n| n.to_string()).collect(),
        };
        let free: Vec<String> = match &self.free {
            Some(f) => f.clone(),
            None => default_free.iter().map(|s| s.to_string()).collect(),
        };
        if free.is_empty() {
            return Err(FitError::NoFreeParameter);
        }
        let mut indices = Vec::new();
        for name in &free {
            let i = names
                .iter()
                .position(|n| n == name)
                .ok_or_else(|| unknown(name))?;
            if indices.contains(&i) {
                return Err(unknown(name));
            }
            indices.push(i);
        }
        let mut start: Vec<f64> = indices.iter().map(|&i| values[i]).collect();
        let mut free_bounds: Vec<Bounds> = indices.iter().map(|&i| bounds[i]).collect();
        for (name, value) in &self.start {
            let k = free
                .iter()
                .position(|n| n == name)
                .ok_or_else(|| unknown(name))?;
            start[k] = *value;
        }
        for (name, b) in &self.bounds {
            let k = free
                .iter()
                .position(|n| n == name)
                .ok_or_else(|| unknown(name))?;
            free_bounds[k] = *b;
        }
        Ok(Selection {
            all: values.to_vec(),
            indices,
            names: free,
            start,
            bounds: free_bounds,
        })
    }
}

/// A resolved parameter selection: all values, which are free, their names, starts and bounds.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Selection {
    pub all: Vec<f64>,
    pub indices: Vec<usize>,
    pub names: Vec<String>,
    pub start: Vec<f64>,
    pub bounds: Vec<Bounds>,
}

impl Selection {
    /// Fits `problem` over the selected free parameters from their starts within their bounds,
    /// its residuals weighted as `setup` says (`observed`: the data, one per residual, which
    /// relative weights divide by).
    pub fn solve<R: Residuals>(
        &self,
        problem: &R,
        setup: &FitSetup,
        observed: &[f64],
    ) -> Result<FitReport, FitError> {
        let (names, start, bounds) = (&self.names, &self.start, &self.bounds);
        match setup.weights.scales(observed)? {
            None => least_squares(problem, names, start, bounds, &setup.options),
            Some(sigma) => {
                let weighted = weights::Weighted {
                    problem,
                    sigma: &sigma,
                };
                least_squares(&weighted, names, start, bounds, &setup.options)
                    .map(|r| weights::unweighted(r, &sigma))
                    .map_err(|e| weights::unweighted_error(e, &sigma))
            }
        }
    }

    /// All parameters as scalars: the free ones from θ, the others fixed.
    pub fn assemble<T: Scalar>(&self, theta: &[T]) -> Vec<T> {
        let mut all: Vec<T> = self.all.iter().map(|&v| T::from(v)).collect();
        for (k, &i) in self.indices.iter().enumerate() {
            all[i] = theta[k];
        }
        all
    }

    /// All parameters as numbers, with the free ones from `values`.
    pub fn assemble_values(&self, values: &[f64]) -> Vec<f64> {
        self.assemble(values)
    }
}
