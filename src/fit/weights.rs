//! Weighted residuals: each residual r_i divided by a scale σ_i before the least squares, so that
//! a fit minimises Σ (r_i/σ_i)². With σ_i each point's standard deviation this is the
//! maximum-likelihood fit of Gaussian noise, and the standard errors s²(JᵀJ)⁻¹ (J of the weighted
//! residuals) are those of the estimates; with σ_i = |P_i| (relative residuals) it is the fit of
//! noise proportional to the data, which an unweighted fit misreads (its standard errors assume
//! the same noise at every point).

use super::problem::Residuals;
use super::{FitError, FitReport};
use crate::Scalar;

/// How the residuals of a fit are weighted.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Weights {
    /// σ_i = 1: residuals in the data's unit, every point alike.
    #[default]
    Equal,
    /// σ_i = |y_i|, the datum itself: relative residuals (model − y_i)/|y_i|.
    Relative,
    /// σ_i given, one per residual (e.g. a data file's `sigma` column).
    Sigma(Vec<f64>),
}

impl Weights {
    /// The scales σ_i of the residuals of the data `observed` (one per residual), `None` for
    /// equal weights; each must be finite and > 0.
    pub fn scales(&self, observed: &[f64]) -> Result<Option<Vec<f64>>, FitError> {
        let sigma = match self {
            Weights::Equal => return Ok(None),
            Weights::Relative => observed.iter().map(|y| y.abs()).collect::<Vec<f64>>(),
            Weights::Sigma(s) => s.clone(),
        };
        if sigma.len() != observed.len() {
            return Err(FitError::BadScales {
                given: sigma.len(),
                residuals: observed.len(),
                index: 0,
                value: f64::NAN,
            });
        }
        match sigma.iter().position(|s| !(s.is_finite() && *s > 0.0)) {
            Some(i) => Err(FitError::BadScales {
                given: sigma.len(),
                residuals: observed.len(),
                index: i + 1,
                value: sigma[i],
            }),
            None => Ok(Some(sigma)),
        }
    }
}

/// The residuals of `problem` divided by `sigma`.
pub(super) struct Weighted<'a, R> {
    pub problem: &'a R,
    pub sigma: &'a [f64],
}

impl<R: Residuals> Residuals for Weighted<'_, R> {
    fn count(&self) -> usize {
        self.problem.count()
    }

    fn residuals<T: Scalar>(&self, theta: &[T]) -> crate::Result<Vec<T>> {
        let mut r = self.problem.residuals(theta)?;
        for (x, s) in r.iter_mut().zip(self.sigma) {
            *x /= *s;
        }
        Ok(r)
    }
}

/// The report of a fit of residuals weighted by `sigma`, its residuals, their norm and RMS back
/// in the data's unit (the standard errors and correlations stay those of the weighted fit).
pub(super) fn unweighted(mut report: FitReport, sigma: &[f64]) -> FitReport {
    for (r, s) in report.residuals.iter_mut().zip(sigma) {
        *r *= s;
    }
    report.residual_norm = super::levenberg::norm(&report.residuals);
    report.rms = report.residual_norm / (report.residuals.len().max(1) as f64).sqrt();
    report.sigma = Some(sigma.to_vec());
    report
}

/// [`unweighted`] for the best point an error carries.
pub(super) fn unweighted_error(e: FitError, sigma: &[f64]) -> FitError {
    match e {
        FitError::NotConverged { reason, step, best } => FitError::NotConverged {
            reason,
            step,
            best: Box::new(unweighted(*best, sigma)),
        },
        other => other,
    }
}
