//! Work bounded before it starts: the memory a solve needs, estimated from the mesh's counts
//! before anything large is allocated, and the limit it is checked against.
//!
//! With n free dofs, z nonzeros of the tangent, f values of the LDLᵀ factor (supernodal, so
//! dense diagonal blocks included), c cells of d dofs (p of them pressures) with q quadrature
//! points, N nodes and a process baseline of [`BASELINE`] bytes, the resident memory of a sweep
//! is estimated as (bytes):
//!
//! - element buffers of the assembly: 8 d² c (tangents) + 4 (d² − p²) c (gather list) + 24 d c
//!   (Q2/Q1: 12 m² c for the condensed cell matrices, m = d − 2, and 8 (4 + 4m) c for the centre
//!   nodes' data, [`super::condensation`]);
//! - the tangent: 4 z (pattern) + 8 z (values) + 4 z (gather pointers); its symmetric part
//!   and transpose map: 12 z;
//! - the factors: 8 f (LDLᵀ) + 16 f + 8 z (LU on the LDLᵀ's pattern, for non-symmetric
//!   tangents) + [`FACTOR_SCRATCH`] n (faer's workspace); [`LinearSolver::Lu`]: faer's LU
//!   instead, [`LU_FILL`] times the LDLᵀ's values;
//! - vectors: 40 vectors of n (Krylov basis, Newton, predictor, rates, 20 stretches' results);
//! - quadrature-point fields for results and diagnostics: 104 q c;
//! - the cells' mapped geometry, computed once per mesh ([`super::element::PointGeometry`]):
//!   8 q (3 k + 3) c for cells of k nodes (2 160 bytes per Q2/Q1 cell, 480 per Q1/P0 cell);
//! - the mesh and dof map: 28 N + 8 d c.
//!
//! Before the symbolic factorisation f is modelled as [`FILL`] · n (log₂ n)² (a 2D mesh under the
//! dissection order of [`super::dissection`]); after it, f is exact. Measured (clamped cylinder R = 1, L = 4,
//! 20 stretches, `cargo run --release --example fem_memory`): the estimate from the counts is
//! above the peak resident memory (VmHWM) at every size, by 1.41× at 9.4k dofs, 1.55× at 37k and
//! 1.71× at 148k (frozen muscle, Q2/Q1; after the symbolic factorisation 1.15–1.35×); see
//! BENCHMARKS.md, "The cost curve".

use super::element::{Element, PressureLayout};
use super::error::{FemError, FemResult};
use super::linear_solver::LinearSolver;

/// Limit used when the available memory cannot be read (no `/proc/meminfo`): 4 GiB.
pub const FALLBACK_LIMIT: u64 = 4 << 30;

/// Factor values per n (log₂ n)² of the LDLᵀ of the clamped cylinder meshes (n the free dofs)
/// under the dissection order: measured 0.39 for Q2/Q1 (9.4k–148k dofs), 0.52–0.55 for Q1/P0
/// (3.1k–49k dofs). (Under the minimum-degree order used before: 0.38 and 0.48–0.50.)
pub const FILL: f64 = 0.56;

/// Bytes per dof of faer's workspace for the numeric supernodal LDLᵀ (measured 465–479 from
/// 9.4k to 148k dofs).
pub const FACTOR_SCRATCH: f64 = 480.0;

/// Resident memory of the process before the solve \[bytes\] (measured 2.7 MiB).
pub const BASELINE: f64 = 3.0 * 1024.0 * 1024.0;

/// faer's partial-pivoting LU against the LDLᵀ: its fill is bounded by the Cholesky factor of
/// KᵀK (measured ≈ 3× the LDLᵀ's values on the cylinder meshes).
pub const LU_FILL: f64 = 3.0;

/// The default memory limit: half the memory the kernel reports available (`MemAvailable` in
/// `/proc/meminfo`), so that two solves in parallel still fit, or [`FALLBACK_LIMIT`].
pub fn default_limit() -> u64 {
    available_memory().map_or(FALLBACK_LIMIT, |a| a / 2)
}

/// `MemAvailable` from `/proc/meminfo`, in bytes.
pub fn available_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib.saturating_mul(1024))
}

/// What a solve on a mesh needs, from counts.
#[derive(Debug, Clone, PartialEq)]
pub struct MemoryEstimate {
    /// The mesh, in words (cells, element).
    pub mesh: String,
    /// Free dofs (estimated from the node count: all displacement and pressure dofs).
    pub dofs: f64,
    /// Nonzeros of the tangent.
    pub nonzeros: f64,
    /// Values of the LDLᵀ factor.
    pub factor_values: f64,
    /// The estimate \[bytes\].
    pub bytes: f64,
    counts: Counts,
    linear: LinearSolver,
}

/// Counts of a mesh with the element's cells.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Counts {
    /// Nodes.
    pub nodes: f64,
    /// Cells.
    pub cells: f64,
    /// Pressure dofs (corner nodes for Q2/Q1, cells for Q1/P0: [`PressureLayout`]).
    pub pressures: f64,
    /// The element of the cells.
    pub element: Element,
}

impl MemoryEstimate {
    /// The estimate for the structured nr × nz mesh of [`super::mesh::Mesh::structured`] with `element`'s
    /// cells, from the counts alone (nothing is allocated).
    pub fn structured(nr: usize, nz: usize, element: Element, linear: LinearSolver) -> Self {
        let (r, z) = (nr as f64, nz as f64);
        // k nodes along a cell side: ((k − 1) nr + 1)((k − 1) nz + 1) nodes.
        let k = (element.node_layout().per_side() - 1) as f64;
        let cells = r * z;
        let counts = Counts {
            nodes: (k * r + 1.0) * (k * z + 1.0),
            cells,
            pressures: match element.pressure_layout() {
                PressureLayout::AtCorners => (r + 1.0) * (z + 1.0),
                PressureLayout::PerCell => element.pressures() as f64 * cells,
            },
            element,
        };
        Self::of_counts(counts, &format!("{nr} × {nz} {element} cells"), linear)
    }

    /// The estimate from the counts `c` of a mesh described as `mesh` (in words), e.g.
    /// [`super::mesh::Mesh::memory_estimate`]'s.
    pub fn of_counts(c: Counts, mesh: &str, linear: LinearSolver) -> Self {
        let dofs = 2.0 * c.nodes + c.pressures;
        let d = (2 * c.element.nodes() + c.element.pressures()) as f64;
        let p = c.element.pressures() as f64;
        // Distinct couplings per cell: every entry of the element matrix but the
        // pressure–pressure block, shared with the neighbours on edges and corners.
        let nonzeros = (d * d - p * p) * c.cells * SHARED;
        let fill = FILL * dofs * dofs.max(2.0).log2().powi(2);
        let mut e = Self {
            mesh: mesh.to_string(),
            dofs,
            nonzeros,
            factor_values: fill,
            bytes: 0.0,
            counts: c,
            linear,
        };
        e.bytes = e.total();
        e
    }

    /// The estimate with the exact free dofs, tangent nonzeros and (if known: after the
    /// symbolic factorisation) LDLᵀ factor values.
    pub fn with_counts(&self, dofs: usize, nonzeros: usize, factor_values: Option<usize>) -> Self {
        let mut e = Self {
            dofs: dofs as f64,
            nonzeros: nonzeros as f64,
            factor_values: factor_values.map_or(self.factor_values, |f| f as f64),
            ..self.clone()
        };
        e.bytes = e.total();
        e
    }

    fn total(&self) -> f64 {
        let (c, linear) = (self.counts, self.linear);
        let d = (2 * c.element.nodes() + c.element.pressures()) as f64;
        let p = c.element.pressures() as f64;
        let q = c.element.quadrature_points() as f64;
        let (n, z, f) = (self.dofs, self.nonzeros, self.factor_values);
        let element_buffers = match c.element.condensed_node() {
            // The condensed cell matrix (m = d − 2, pressure block included) and the condensed
            // node's data for the expansion.
            Some(_) => {
                let m = d - 2.0;
                (12.0 * m * m + 8.0 * (4.0 + 4.0 * m) + 24.0 * d) * c.cells
            }
            None => (8.0 * d * d + 4.0 * (d * d - p * p) + 24.0 * d) * c.cells,
        };
        let tangent = 28.0 * z;
        let factors = match linear {
            LinearSolver::SymmetricPartGmres => 24.0 * f + 8.0 * z + FACTOR_SCRATCH * n,
            LinearSolver::Lu => 8.0 * LU_FILL * f,
        };
        let vectors = 40.0 * 8.0 * n;
        let fields = 104.0 * q * c.cells;
        let geometry = 8.0 * q * (3.0 * c.element.nodes() as f64 + 3.0) * c.cells;
        let mesh = 28.0 * c.nodes + 8.0 * d * c.cells;
        BASELINE + element_buffers + tangent + factors + vectors + fields + geometry + mesh
    }

    /// Refuses with [`FemError::MemoryLimit`] an estimate above `limit` bytes.
    pub fn check(&self, limit: u64) -> FemResult<()> {
        if self.bytes <= limit as f64 {
            Ok(())
        } else {
            Err(FemError::MemoryLimit {
                mesh: self.mesh.clone(),
                dofs: self.dofs,
                estimate: self.bytes,
                limit,
            })
        }
    }
}

/// Fraction of an element matrix's couplings that are distinct in the assembled tangent of a
/// structured mesh (the rest are shared with neighbouring cells).
const SHARED: f64 = 0.75;
