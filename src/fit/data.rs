//! Stress–stretch data: (λ, P) pairs, λ dimensionless and strictly increasing, P the nominal
//! stress in kPa, and optionally each point's standard deviation σ \[kPa\] (what weighted fits
//! divide the residuals by, [`super::Weights`]). Read from CSV with the header `lambda,P` or
//! `lambda,P,sigma`, at most [`MAX_DATA_BYTES`] bytes and [`MAX_DATA_POINTS`] points (a file
//! beyond either is refused, read no further than the limit).

use super::FitError;
use std::io::Read;
use std::path::Path;

/// The largest data file a fit reads: 64 MiB (a measured curve takes a few kB; `/dev/zero` or a
/// wrong file must not fill the memory).
pub const MAX_DATA_BYTES: u64 = 64 * 1024 * 1024;

/// The most points a fit takes: 100 000 (each point costs one model evaluation per residual,
/// and a Jacobian takes one per free parameter).
pub const MAX_DATA_POINTS: usize = 100_000;

/// Validated stress–stretch data: λ_i > 0 strictly increasing, all values finite, σ_i > 0.
#[derive(Debug, Clone, PartialEq)]
pub struct Data {
    lambda: Vec<f64>,
    stress: Vec<f64>,
    sigma: Option<Vec<f64>>,
}

impl Data {
    /// From columns λ [-] and P \[kPa\]; errors name the 1-based point.
    pub fn new(lambda: Vec<f64>, stress: Vec<f64>) -> Result<Self, FitError> {
        if lambda.len() != stress.len() {
            return Err(FitError::LengthMismatch {
                stretches: lambda.len(),
                stresses: stress.len(),
            });
        }
        let locations: Vec<String> = (1..=lambda.len()).map(|i| format!("point {i}")).collect();
        validate(&lambda, &stress, &locations)?;
        Ok(Self {
            lambda,
            stress,
            sigma: None,
        })
    }

    /// The same data with each point's standard deviation σ_i \[kPa\] (finite, > 0).
    pub fn with_sigma(self, sigma: Vec<f64>) -> Result<Self, FitError> {
        if sigma.len() != self.len() {
            return Err(FitError::LengthMismatch {
                stretches: self.len(),
                stresses: sigma.len(),
            });
        }
        let locations: Vec<String> = (1..=sigma.len()).map(|i| format!("point {i}")).collect();
        check_sigma(&sigma, &locations)?;
        Ok(Self {
            sigma: Some(sigma),
            ..self
        })
    }

    /// Samples `model` at the given stretches (for synthetic data and reference curves).
    pub fn sampled(
        lambda: Vec<f64>,
        model: impl Fn(f64) -> crate::Result<f64>,
    ) -> Result<Self, FitError> {
        let stress = lambda
            .iter()
            .map(|&l| model(l))
            .collect::<crate::Result<Vec<f64>>>()?;
        Self::new(lambda, stress)
    }

    /// Reads a CSV file with header `lambda,P` (λ [-], P \[kPa\]).
    pub fn from_csv_path(path: impl AsRef<Path>) -> Result<Self, FitError> {
        let path = path.as_ref();
        Self::from_csv_reader(open(path)?, &path.display().to_string())
    }

    /// Reads CSV with header `lambda,P` or `lambda,P,sigma` from any reader; `source_name`
    /// appears in errors. Reads at most [`MAX_DATA_BYTES`] + 1 bytes and refuses more than
    /// [`MAX_DATA_POINTS`] points ([`FitError::DataTooLarge`]).
    pub fn from_csv_reader(reader: impl Read, source_name: &str) -> Result<Self, FitError> {
        let (mut columns, locations) =
            read_columns(reader, source_name, &["lambda", "P"], &["sigma"])?;
        let sigma = (columns.len() == 3).then(|| columns.pop().unwrap_or_default());
        let stress = columns.pop().unwrap_or_default();
        let lambda = columns.pop().unwrap_or_default();
        validate(&lambda, &stress, &locations)?;
        if let Some(s) = &sigma {
            check_sigma(s, &locations)?;
        }
        Ok(Self {
            lambda,
            stress,
            sigma,
        })
    }

    /// Writes the data as CSV with header `lambda,P` (`lambda,P,sigma` with standard deviations).
    pub fn to_csv(&self) -> String {
        let mut out = String::from(if self.sigma.is_some() {
            "lambda,P,sigma\n"
        } else {
            "lambda,P\n"
        });
        for (i, (l, p)) in self.lambda.iter().zip(&self.stress).enumerate() {
            match &self.sigma {
                Some(s) => out.push_str(&format!("{l},{p},{}\n", s[i])),
                None => out.push_str(&format!("{l},{p}\n")),
            }
        }
        out
    }

    /// Each point's standard deviation σ_i \[kPa\], if the data have them.
    pub fn sigma(&self) -> Option<&[f64]> {
        self.sigma.as_deref()
    }

    /// Stretches λ_i [-].
    pub fn lambda(&self) -> &[f64] {
        &self.lambda
    }

    /// Nominal stresses P_i \[kPa\].
    pub fn stress(&self) -> &[f64] {
        &self.stress
    }

    /// The points (λ_i, P_i).
    pub fn points(&self) -> Vec<(f64, f64)> {
        self.lambda
            .iter()
            .copied()
            .zip(self.stress.iter().copied())
            .collect()
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.lambda.len()
    }

    /// True if there are no points.
    pub fn is_empty(&self) -> bool {
        self.lambda.is_empty()
    }

    /// The same stretches (and standard deviations) with stresses `stress` (for residual data
    /// after a subtraction).
    pub(crate) fn with_stress(&self, stress: Vec<f64>) -> Result<Self, FitError> {
        Ok(Self {
            sigma: self.sigma.clone(),
            ..Self::new(self.lambda.clone(), stress)?
        })
    }
}

/// Opens a data file (a regular file: a FIFO would block); an error names it (line 0: the file as a whole).
pub(crate) fn open(path: &Path) -> Result<std::fs::File, FitError> {
    crate::user_file::open(path).map_err(|e| FitError::Csv {
        source_name: path.display().to_string(),
        line: 0,
        message: e.to_string(),
    })
}

/// The columns of a CSV file whose header is `header`, optionally followed by `optional`
/// (names compared without regard to ASCII case), as numbers, with the location of each row
/// ("FILE, line n"). Reads at most [`MAX_DATA_BYTES`] + 1 bytes and refuses more than
/// [`MAX_DATA_POINTS`] rows.
pub(crate) fn read_columns(
    reader: impl Read,
    source_name: &str,
    header: &[&str],
    optional: &[&str],
) -> Result<(Vec<Vec<f64>>, Vec<String>), FitError> {
    let csv_error = |line: u64, message: String| FitError::Csv {
        source_name: source_name.to_string(),
        line,
        message,
    };
    let too_large = |what: String| FitError::DataTooLarge {
        source_name: source_name.to_string(),
        what,
        limits: (MAX_DATA_BYTES, MAX_DATA_POINTS),
    };
    let mut bytes = Vec::new();
    reader
        .take(MAX_DATA_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| csv_error(0, e.to_string()))?;
    if bytes.len() as u64 > MAX_DATA_BYTES {
        return Err(too_large(format!("more than {MAX_DATA_BYTES} bytes")));
    }
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(true)
        .trim(csv::Trim::All)
        .from_reader(bytes.as_slice());
    let found = rdr
        .headers()
        .map_err(|e| csv_error(1, e.to_string()))?
        .clone();
    let names: Vec<&str> = found.iter().collect();
    let full: Vec<&str> = header.iter().chain(optional).copied().collect();
    let matches = |h: &[&str]| {
        names.len() == h.len() && names.iter().zip(h).all(|(n, h)| n.eq_ignore_ascii_case(h))
    };
    let header: &[&str] = if !optional.is_empty() && matches(&full) {
        &full
    } else if matches(header) {
        header
    } else {
        let or = if optional.is_empty() {
            String::new()
        } else {
            format!(" or `{}`", full.join(","))
        };
        return Err(csv_error(
            1,
            format!(
                "header must be `{}`{or}, found `{}`",
                header.join(","),
                names.join(",")
            ),
        ));
    };
    let mut columns = vec![Vec::new(); header.len()];
    let mut locations = Vec::new();
    for record in rdr.records() {
        if locations.len() == MAX_DATA_POINTS {
            return Err(too_large(format!("more than {MAX_DATA_POINTS} points")));
        }
        let record = record.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line());
            csv_error(line, e.to_string())
        })?;
        let line = record.position().map_or(0, |p| p.line());
        for (i, column) in header.iter().enumerate() {
            let text = record.get(i).unwrap_or("");
            let value = text
                .parse::<f64>()
                .map_err(|_| csv_error(line, format!("{column} = {text:?} is not a number")))?;
            columns[i].push(value);
        }
        locations.push(format!("{source_name}, line {line}"));
    }
    Ok((columns, locations))
}

/// Each σ_i finite and > 0.
fn check_sigma(sigma: &[f64], locations: &[String]) -> Result<(), FitError> {
    match sigma.iter().position(|s| !(s.is_finite() && *s > 0.0)) {
        Some(i) => Err(FitError::NonPositiveSigma {
            location: locations[i].clone(),
            sigma: sigma[i],
        }),
        None => Ok(()),
    }
}

fn validate(lambda: &[f64], stress: &[f64], locations: &[String]) -> Result<(), FitError> {
    for i in 0..lambda.len() {
        let location = || locations[i].clone();
        let (l, p) = (lambda[i], stress[i]);
        if !l.is_finite() {
            return Err(FitError::NonFiniteData {
                location: location(),
                column: "lambda",
                value: l,
            });
        }
        if !p.is_finite() {
            return Err(FitError::NonFiniteData {
                location: location(),
                column: "P",
                value: p,
            });
        }
        if l <= 0.0 {
            return Err(FitError::NonPositiveStretch {
                location: location(),
                lambda: l,
            });
        }
        if i > 0 {
            let previous = lambda[i - 1];
            if l == previous {
                return Err(FitError::DuplicateStretch {
                    location: location(),
                    lambda: l,
                });
            }
            if l < previous {
                return Err(FitError::DecreasingStretch {
                    location: location(),
                    lambda: l,
                    previous,
                });
            }
        }
    }
    Ok(())
}
