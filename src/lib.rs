//! # activemuscle
//!
//! Mechanics of active skeletal muscle after G. Giantesio and A. Musesti, *A continuum model of
//! skeletal muscle tissue with loss of activation* (LNCSE 122, Springer 2017; arXiv:1701.07823):
//! a transversely isotropic, incompressible, polyconvex passive energy; activation by active
//! strain F = F_e F_a with F_a = I − γ m⊗m, γ fitted as a function of the fibre stretch; loss of
//! activation through a damage d scaling the active stress; and the formulations other codes ship
//! (active stress, structural activation, volumetric energies, activation in time).
//!
//! The user guide is the repository's README.md and its `docs/` pages; this documentation is the
//! API.
//!
//! ## A material point
//!
//! An energy is one generic method over the invariants of C ([`StrainEnergy`]); dual numbers give
//! its stress, tangent and dP/dγ, and a [`Muscle`] combines it with an activation law, a damage
//! and a coupling:
//!
//! ```
//! use activemuscle::active::{ActiveCurve, Coupling, FrozenTangent, ImplicitLaw, Law};
//! use activemuscle::energy::Invariants;
//! use activemuscle::uniaxial::along_fibres;
//! use activemuscle::{Muscle, Scalar, StrainEnergy};
//!
//! /// W = c₁ (tr C − 3) + k₁/(2k₂) [e^{k₂ (C:M − 1)²} − 1], in kPa.
//! #[derive(Clone)]
//! struct FibreReinforced { c1: f64, k1: f64, k2: f64 }
//!
//! impl StrainEnergy for FibreReinforced {
//!     fn energy<T: Scalar>(&self, c: &Invariants<T>) -> T {
//!         let fibre = c.c_m - 1.0;
//!         let matrix = (c.tr_c - 3.0) * self.c1;
//!         matrix + (fibre * fibre * self.k2).exp_m1() * (self.k1 / (2.0 * self.k2))
//!     }
//! }
//!
//! // The chapter's implicit law makes the frozen model reproduce P_pas + (1 − d) P_act
//! // along the fibres, for any energy.
//! let energy = FibreReinforced { c1: 0.5, k1: 2.0, k2: 3.0 };
//! let curve = ActiveCurve::paper();
//! let law = Law::Implicit(ImplicitLaw::new(energy.clone(), curve));
//! let frozen = Coupling::Frozen(FrozenTangent::Exact);
//! let muscle = Muscle::new(energy.clone(), law, 0.0, frozen)?; // damage d = 0
//! let passive = Muscle::passive(energy);
//! let (active, rest) = (along_fibres(&muscle, 1.1)?, along_fibres(&passive, 1.1)?);
//! assert!((active.stress - (rest.stress + curve.value(1.1))).abs() < 1e-8);
//! # Ok::<(), activemuscle::Error>(())
//! ```
//!
//! ## A scene, without files
//!
//! The command line's studies from a TOML text: [`scene::Scene::parse`] validates it and
//! resolves every default, [`scene::Scene::run`] computes each study into a typed
//! [`studies::Outcome`]:
//!
//! ```
//! use activemuscle::scene::{RunOptions, Scene};
//! use activemuscle::studies::StudyResult;
//!
//! let scene = Scene::parse(
//!     r#"
//!     [activation]
//!     damage = [0.0, 0.5]
//!
//!     [[study]]
//!     kind = "uniaxial"
//!     stretch = [0.9, 1.0, 1.17]
//!     "#,
//!     "example.toml",
//! )?;
//! let results = scene.run(&RunOptions::default());
//! assert!(results.complete());
//! let StudyResult::Uniaxial(uniaxial) = &results.studies[0].result else {
//!     unreachable!("a uniaxial study")
//! };
//! assert_eq!(uniaxial.curves.len(), 3); // the passive curve and one per damage
//! # Ok::<(), activemuscle::scene::SceneError>(())
//! ```
//!
//! ## The modules
//!
//! - [`energy`]: energies written once, generically ([`StrainEnergy`]), and the shipped ones'
//!   registry; [`parameter`]: their (and the active curves') named, validated parameters.
//! - [`invariants`]: the invariants of C and their exact derivatives in F.
//! - [`response`]: the one place that seeds dual numbers.
//! - [`active`]: active-strain maps, active curves, activation laws and approaches, couplings,
//!   activation in time.
//! - [`material`]: a muscle answering at a point; [`volumetric`]: near incompressibility.
//! - [`uniaxial`]: homogeneous tests along and across the fibres; [`homogeneous`]: simple shear
//!   and planar biaxial stretch; [`stability`]: strong ellipticity.
//! - [`oracle`]: the slow reference route (dual numbers over F's nine entries).
//! - [`fem`]: the axisymmetric mixed finite-element solver.
//! - [`fit`]: least squares with dual-number Jacobians.
//! - [`tangent_check`]: Taylor tests of any material's tangent, at a point and assembled.
//!
//! The application layer, imports in one direction: [`models`] (laws, couplings, muscles and
//! energies from choices) → [`studies`] (one module per study kind: spec, validation, run, typed
//! results, tables, figures, report section) → [`scene`] (scene files: parse, resolve, run; the
//! generated scene reference) → [`output`] (CSV, `datapackage.json`, figures, report);
//! [`app_error`] is the errors of all four.

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
pub mod threads;
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
