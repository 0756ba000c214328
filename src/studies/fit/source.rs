//! Where a fit's data come from: a data file named relative to the scene file, or synthetic
//! data sampled from a model with seeded Gaussian noise ([`DataSource`]).

use super::{CaseData, FitCase, FitKind};
use crate::app_error::SpecError;
use crate::fit::{BiaxialData, Data, FitError, BIAXIAL_HEADER};
use crate::random::Sampler;
use crate::studies::rules::required;
use std::io::{BufRead, BufReader};
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
    /// be given), with the source in words (`data file <path><what>`); errors name `data`. A
    /// file with the biaxial header holds planar biaxial rows, which only a passive fit takes.
    pub(super) fn file(
        &self,
        kind: FitKind,
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
        let unusable = |e: FitError| {
            SpecError::new(
                "data",
                format!("{name:?}"),
                format!("unusable data file: {e}"),
            )
        };
        // Opened and read once: the header, peeked at, says which data the file holds.
        let source_name = path.display().to_string();
        let file = crate::user_file::open(&path).map_err(|e| {
            unusable(FitError::Csv {
                source_name: source_name.clone(),
                line: 0,
                message: e.to_string(),
            })
        })?;
        let mut reader = BufReader::new(file);
        if !starts_with_header(&mut reader, &BIAXIAL_HEADER) {
            let data = Data::from_csv_reader(reader, &source_name).map_err(unusable)?;
            return Ok((
                vec![case(name, CaseData::Uniaxial(data), reference)],
                format!("data file {}{what}", path.display()),
            ));
        }
        if kind != FitKind::Passive {
            return Err(SpecError::new(
                "data",
                format!("{name:?}"),
                format!(
                    "a planar biaxial file ({}), which passive fits take; a {} fit takes lambda,P",
                    BIAXIAL_HEADER.join(","),
                    kind.name()
                ),
            ));
        }
        let data = BiaxialData::from_csv_reader(reader, &source_name).map_err(unusable)?;
        Ok((
            vec![case(name, CaseData::Biaxial(data), reference)],
            format!(
                "planar biaxial data file {} (λ₁ along the fibres, λ₂ across, λ₃ = 1/(λ₁λ₂), the e₃ faces traction free){what}",
                path.display()
            ),
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
    required(
        stretches,
        "stretch",
        format!("{what} needs the stretches at which to sample it"),
    )
}

/// A fit with two sources of data given both or neither.
pub(super) fn one_source(fit: &str, other: &str) -> SpecError {
    SpecError::new(
        "",
        "",
        format!("a {fit} fit needs exactly one of data = \"file.csv\" and {other}"),
    )
}

/// The first line of `reader` is `header` (names compared without regard to ASCII case and
/// surrounding spaces, as the CSV readers compare them), peeked at without consuming it.
fn starts_with_header(reader: &mut impl BufRead, header: &[&str]) -> bool {
    let Ok(buffer) = reader.fill_buf() else {
        return false;
    };
    let line = buffer.split(|&b| b == b'\n').next().unwrap_or_default();
    let Ok(line) = std::str::from_utf8(line) else {
        return false;
    };
    let names: Vec<&str> = line
        .trim_start_matches('\u{feff}')
        .split(',')
        .map(str::trim)
        .collect();
    names.len() == header.len()
        && names
            .iter()
            .zip(header)
            .all(|(n, h)| n.eq_ignore_ascii_case(h))
}

pub(super) fn case(label: &str, data: CaseData, reference: Option<Vec<f64>>) -> FitCase {
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
