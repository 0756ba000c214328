//! Speed versus accuracy, measured on both axes at once.
//!
//! Every option a user can turn to trade accuracy for speed (activation law, derivative route,
//! frozen tangent, mesh, Newton tolerance, 0D versus FE) is run at each of its variants, timed
//! (wall time \[s\], median of repeats for anything short, see [`measure::time_median`]) and compared
//! with a reference computed at the accurate end of the same option, on what a user reads off a
//! run: the nominal stress P(λ) over the sweep \[kPa\] (max abs and max rel error), the activation γ
//! [-] (0D) or the centre γ (FE). The error machinery ([`measure`]) is independent of the options
//! and is tested on cases with a known answer.
//!
//! - [`measure`]: timing, curve errors, speed-up and error ratio, the Pareto front.
//! - [`routes`]: derivative routes as [`crate::fem::AxisymmetricMaterial`] wrappers (the 9-entry
//!   oracle route and a central-difference tangent).
//! - [`study`]: the options and their variants for a scene.
//! - [`report`]: `tradeoff.csv`, log–log error-versus-time figures, `tradeoff.html`.

pub mod measure;
pub mod report;
pub mod routes;
pub mod study;

pub use measure::{curve_error, pareto_front, time_median, CurveError, Measurement};
pub use routes::{FiniteDifferenceTangent, OracleRoute};
pub use study::{run, TradeoffOptions, TradeoffResults};
