//! Where a fit's data come from: a data file named relative to the scene file, or synthetic
//! data sampled from a model with seeded Gaussian noise ([`DataSource`]).

use super::FitCase;
use crate::app_error::SpecError;
use crate::fit::Data;
use crate::random::Sampler;
use std::path::{Path, PathBuf};

/// Where a fit's data come from: the scene file's directory for data files, and the seeded
/// noise of synthetic data.
pub struct DataSource<'a> {
    pub(super) base: &'a Path,
    pub(super) noise: Option<(f64, Sampler)>,
    pub(super) noise_text: String,
}

impl DataSource<'_> {
    /// The one case of a data file named relative to the scene file (then `stretch` must not
    /// be given), with the source in words (`data file <path><what>`); errors name `data`.
    pub(super) fn file(
        &self,
        name: &str,
        stretches: Option<&[f64]>,
        reference: Option<Vec<f64>>,
        what: &str,
    ) -> Result<(Vec<FitCase>, String), SpecError> {
        if stretches.is_some() {
            return Err(SpecError::new(
                "stretch",
                "(given)",
                "the data file gives the stretches: remove stretch",
            ));
        }
        let path: PathBuf = if Path::new(name).is_absolute() {
            PathBuf::from(name)
        } else {
            self.base.join(name)
        };
        let data = Data::from_csv_path(&path).map_err(|e| {
            SpecError::new(
                "data",
                format!("{name:?}"),
                format!("unusable data file: {e}"),
            )
        })?;
        Ok((
            vec![case(name, data, reference)],
            format!("data file {}{what}", path.display()),
        ))
    }

    /// Samples `model` at `lambdas`, adding the noise; errors name `stretch`.
    pub(super) fn synthetic(
        &mut self,
        lambdas: &[f64],
        model: impl Fn(f64) -> crate::Result<f64>,
    ) -> Result<Data, SpecError> {
        let mut stress = Vec::with_capacity(lambdas.len());
        for &l in lambdas {
            let p = model(l).map_err(|e| {
                SpecError::new(
                    "stretch",
                    l,
                    format!("the synthetic data cannot be computed at this stretch: {e}"),
                )
            })?;
            stress.push(match &mut self.noise {
                Some((sigma, rng)) => p + *sigma * rng.normal(),
                None => p,
            });
        }
        Data::new(lambdas.to_vec(), stress)
            .map_err(|e| SpecError::new("stretch", "", e.to_string()))
    }
}

pub(super) fn need<'a>(stretches: Option<&'a [f64]>, what: &str) -> Result<&'a [f64], SpecError> {
    stretches.ok_or_else(|| {
        SpecError::new(
            "stretch",
            "(missing)",
            format!("{what} needs the stretches at which to sample it"),
        )
    })
}

/// A fit with two sources of data given both or neither.
pub(super) fn one_source(fit: &str, other: &str) -> SpecError {
    SpecError::new(
        "",
        "",
        format!("a {fit} fit needs exactly one of data = \"file.csv\" and {other}"),
    )
}

pub(super) fn case(label: &str, data: Data, reference: Option<Vec<f64>>) -> FitCase {
    FitCase {
        label: label.to_string(),
        data,
        damage: None,
        reference,
    }
}

pub(super) fn sample(lambdas: &[f64], f: impl Fn(f64) -> crate::Result<f64>) -> Vec<(f64, f64)> {
    lambdas
        .iter()
        .filter_map(|&l| f(l).ok().filter(|y| y.is_finite()).map(|y| (l, y)))
        .collect()
}
