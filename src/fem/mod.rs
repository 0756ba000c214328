//! Axisymmetric mixed displacement–pressure finite elements for the muscle cylinder.
//!
//! A cylinder of radius R and length L, fibres along z, is meshed in its meridian half plane
//! (r, z) ∈ [0, R] × [0, L] with quadrilaterals of the user's [`Element`]: Taylor–Hood Q2/Q1
//! (default, inf–sup stable) or the cheaper Q1/P0 (incompressibility in the mean per cell),
//! chosen in [`SolverOptions::element`]. The solver minimises
//! (finds the saddle point of) Π(u, p) = ∫ [Ψ(F) − p (J − 1)] dV with
//!
//! F = [[1 + ∂u_r/∂r, 0, ∂u_r/∂z], [0, 1 + u_r/r, 0], [∂u_z/∂r, 0, 1 + ∂u_z/∂z]],
//! J = F_θθ (F_rr F_zz − F_rz F_zr),  dV = 2π r dr dz,
//!
//! for any constitutive model behind [`AxisymmetricMaterial`]. Boundary conditions: u_r = 0 on
//! the axis, u_z = 0 at z = 0, u_z = (λ − 1) L at z = L, lateral surface traction free, bases
//! [`Bases::Sliding`] or [`Bases::Clamped`]. See [`solver::AxisymmetricSolver`].
//!
//! Layers: [`mesh`], [`dofs`], [`element`] and [`assembly`] build the discrete problem;
//! [`problem`] makes it a [`NonlinearSystem`]; [`continuation`] drives any such system through
//! the load path (load stepping, Newton, line search); [`tangent_solver`] solves the Newton
//! systems by [`gmres`] preconditioned with [`ldlt`] or [`pattern_lu`] (both in the elimination
//! order of [`ordering`]), or by faer's LU ([`linear`]), as [`linear_solver`] chooses; [`vtk`]
//! writes fields; [`memory`] bounds the work before it starts; [`timings`] records the time spent.

pub mod assembly;
pub mod condensation;
pub mod continuation;
pub mod dofs;
pub mod element;
pub mod error;
pub mod gmres;
pub mod kinematics;
pub mod ldlt;
pub mod linear;
pub mod linear_solver;
pub mod material;
pub mod memory;
pub mod mesh;
pub mod ordering;
pub mod pattern_lu;
pub mod problem;
pub mod solver;
pub mod tangent_solver;
pub mod timings;
pub mod vtk;

pub use assembly::QuadraturePoint;
pub use continuation::{Cancel, NonlinearSystem};
pub use dofs::Bases;
pub use element::Element;
pub use error::{FemError, FemResult, StepFailure};
pub use material::{AxiF, AxisymmetricMaterial, NeoHookean, Region, Regions};
pub use memory::MemoryEstimate;
pub use mesh::{Boundary, Mesh};
pub use solver::{
    AxisymmetricSolver, IterationRecord, LinearSolver, Progress, SolverOptions, State, StepRecord,
    Stepping, StretchResult, Sweep, Timings, VtkOutput,
};
