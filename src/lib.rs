//! # activemuscle
//!
//! Mechanics of active skeletal muscle after Giantesio & Musesti, "A continuum model of skeletal
//! muscle tissue with loss of activation": a transversely isotropic, incompressible, polyconvex
//! passive energy; activation by active strain F = F_e F_a with F_a = I − γ m⊗m; γ fitted as a
//! function of the fibre stretch; loss of activation through a damage d scaling the active stress.
//!
//! - [`energy`]: energies written once, generically ([`StrainEnergy`]); [`parameter`]: their
//!   (and the active curves') named, validated parameters.
//! - [`invariants`]: the invariants of C and their exact derivatives in F (framework-owned).
//! - [`response`]: the one place that seeds dual numbers.
//! - [`active`]: active strain, active curve, activation laws, frozen/consistent coupling.
//! - [`material`]: a muscle answering at a point.
//! - [`uniaxial`]: homogeneous tests along and across the fibres; [`homogeneous`]: simple shear
//!   and planar biaxial stretch.
//! - [`oracle`]: the slow reference route (dual numbers over F's nine entries).
//! - [`fem`]: the axisymmetric mixed finite-element solver.
//! - [`fit`]: least squares with dual-number Jacobians.
//! - [`tangent_check`]: Taylor tests of any material's tangent, at a point and assembled.
//!
//! The application layer, imports in one direction: [`models`] (laws, couplings, muscles and
//! energies from choices) → [`studies`] (uniaxial, cylinder, fit, stability, tradeoff: spec,
//! validation, run, typed results) → [`scene`] (scene files: parse, resolve, run) → [`output`]
//! (CSV, figures, report); [`app_error`] is the errors of all four.

pub mod active;
pub mod app_error;
pub mod energy;
pub mod error;
pub mod fem;
pub mod fit;
pub mod fixed_length;
pub mod homogeneous;
pub mod invariants;
pub mod material;
pub mod models;
pub mod oracle;
pub mod output;
pub mod parameter;
pub mod plot;
pub mod random;
pub mod response;
pub mod roots;
pub mod scalar;
pub mod scene;
pub mod stability;
pub mod studies;
pub mod tangent_check;
pub mod testing;
pub mod text;
pub mod uniaxial;
pub mod user_file;
pub mod volumetric;

pub use app_error::AppError;
pub use energy::{Energy, StrainEnergy};
pub use error::{Error, Result};
pub use material::Muscle;
/// Re-exported for [`energy_test_battery!`] in users' crates.
pub use nalgebra;
/// Re-exported for [`energy_test_battery!`] in users' crates.
pub use num_dual;
pub use scalar::Scalar;
