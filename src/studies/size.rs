//! Bounded work and output: what a scene will compute and write, estimated from its studies when
//! it is read, before anything runs, and refused beyond bounds no real study meets.
//!
//! Each list of a scene has its own cap (stretches, damages: [`super::spec`]); their product
//! and the number of studies do not: one 12-line study (9 001 stretches × 3 laws × 2 couplings ×
//! 16 damages) wrote 918 102 rows (148 MB of curves.csv), twenty of them aborted on a 2.9 GB
//! allocation while writing, 3 000 one-point studies wrote a 534 MB report.html and 6 004 files.
//! Per study, [`Size`] counts the rows of its tables, its figures, its VTK files and the work
//! and memory of its FE sweeps ([`size_of`]: one arm per kind, which a new kind must add); the
//! scene's sum is checked against [`LIMITS`]. The paper's scene is far inside every one of
//! them: it writes 6 894 rows, 18 figures, 72 files, 17.1 MB with a 6.4 MB report.html (the
//! estimate: 6 894 rows, 19 figures, 72 files, 17.5 MB, 6.3 MB).

use super::Study;
use crate::app_error::SpecError;
use crate::fem::{Element, MemoryEstimate, SolverOptions};
use crate::models::LawKind;
use crate::text::{bytes, grouped};

/// Wall time of an FE solve per unknown and target stretch \[s\] on 2 cores: 5.6 µs at 16 × 64
/// (9 400 unknowns) and 6.4–8.7 µs at 32 × 128 (37 152), clamped sweeps of 20 stretches
/// (BENCHMARKS.md).
pub const FE_SECONDS: f64 = 7e-6;

/// Bytes a row takes in a CSV file: 199 in curves.csv (173 446 527 bytes for 873 097 rows).
pub const ROW_BYTES: u64 = 200;
/// Bytes a row holds in memory from the solve to the written CSV: 1.14 KiB (the peak resident
/// memory of an 873 097-row uniaxial run less that of an 87 397-row one, per row).
pub const ROW_MEMORY: u64 = 1_200;
/// Bytes a figure takes in report.html (base64 PNG and caption; the paper's report: 6.4 MB for 20
/// figures) and, as PNG and SVG files, on the disk.
pub const FIGURE_BYTES: u64 = 330_000;
/// Figures shared by all the studies of a kind (transverse isotropy, FE against 0D).
const SHARED_FIGURES: u64 = 2;
/// Bytes of a VTK file per node (ASCII: coordinates, displacement, pressure) and per cell
/// (connectivity, J, γ, λ_f, P_zz, the nominal and Cauchy stress tensors, the hydrostatic
/// pressure): a 6 × 24 mesh of Q2/Q1 cells (637 nodes, 144 cells) writes 119–121 kB, the
/// estimate 150 kB.
const VTK_NODE_BYTES: u64 = 110;
const VTK_CELL_BYTES: u64 = 560;

/// What a study (or a scene: their sum) will compute and write.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Size {
    /// Rows of the CSV tables.
    pub rows: u64,
    /// Figures, at most (each a PNG, an SVG and a picture in report.html).
    pub figures: u64,
    /// CSV files besides the shared tables (one table per study and kind).
    pub tables: u64,
    /// VTK files (the cylinder's fields at the stretches asked for, and a series per sweep).
    pub vtk_files: u64,
    /// Their bytes.
    pub vtk_bytes: u64,
    /// FE sweeps.
    pub sweeps: u64,
    /// Unknowns × target stretches over the FE sweeps: the work of the FE solves.
    pub fe_work: f64,
    /// The memory of the largest FE solve \[bytes\] (a scene: the largest of its studies).
    pub fe_memory: f64,
}

impl std::ops::Add for Size {
    type Output = Size;
    fn add(self, o: Size) -> Size {
        Size {
            rows: self.rows + o.rows,
            figures: self.figures + o.figures,
            tables: self.tables + o.tables,
            vtk_files: self.vtk_files + o.vtk_files,
            vtk_bytes: self.vtk_bytes + o.vtk_bytes,
            sweeps: self.sweeps + o.sweeps,
            fe_work: self.fe_work + o.fe_work,
            fe_memory: self.fe_memory.max(o.fe_memory),
        }
    }
}

impl Size {
    /// Files written: the figures' PNG and SVG, the tables, the VTK files, and curves.csv,
    /// scene.toml, datapackage.json and report.html.
    pub fn files(&self) -> u64 {
        2 * self.figures + self.tables + self.vtk_files + 4
    }

    /// Bytes of report.html.
    pub fn report_bytes(&self) -> u64 {
        self.figures * FIGURE_BYTES
    }

    /// Bytes written: the tables, the figures (as files and in the report), the VTK files.
    pub fn output_bytes(&self) -> u64 {
        self.rows * ROW_BYTES + 2 * self.report_bytes() + self.vtk_bytes
    }

    /// Memory at the peak \[bytes\]: the rows held until written, the report, and the FE solves
    /// running at the same time on `threads` threads.
    pub fn memory(&self, threads: usize) -> u64 {
        let solves = self.sweeps.min(threads as u64) as f64;
        self.rows * ROW_MEMORY + self.report_bytes() + (self.fe_memory * solves) as u64
    }
}

/// The bounds a scene is checked against (documented in docs/running.md).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Rows of all its tables.
    pub rows: u64,
    /// Figures.
    pub figures: u64,
    /// Files.
    pub files: u64,
    /// Bytes written.
    pub output_bytes: u64,
    /// Unknowns × target stretches over its FE sweeps.
    pub fe_work: f64,
}

/// The limits: 500 000 rows (≈ 100 MB of CSV, 0.6 GB of memory while writing; the paper's scene
/// writes 6 894), 300 figures (≈ 100 MB of report.html; the paper's: 18), 5 000 files, 8 GiB
/// written, 1e10 unknowns × stretches of FE solves (≈ 20 h on 2 cores at [`FE_SECONDS`]).
/// Memory is bounded by what the system has available
/// ([`crate::fem::memory::available_memory`]).
pub const LIMITS: Limits = Limits {
    rows: 500_000,
    figures: 300,
    files: 5_000,
    output_bytes: 8 << 30,
    fe_work: 1e10,
};

/// What `study` will compute and write.
pub fn size_of(study: &Study) -> Size {
    let n = |v: usize| v as u64;
    match study {
        Study::Uniaxial(u) => uniaxial(u),
        Study::Cylinder(c) => cylinder(c),
        // fits.csv's row per case and parameter, and fit_points.csv's.
        Study::Fit(f) => Size {
            rows: n(f.cases.len() * f.free.len().max(1) + super::fit::fit_points_rows(&f.cases)),
            figures: 1,
            tables: 1,
            ..Size::default()
        },
        Study::Stability(s) => Size {
            rows: n(s.stretches.len() * (s.models.len() + usize::from(s.passive))),
            figures: 1,
            ..Size::default()
        },
        Study::Tradeoff(t) => Size {
            // A handful of variants per option group, a figure per group, and their sweeps.
            rows: n(10 * t.options.groups.len()),
            figures: n(t.options.groups.len()),
            ..Size::default()
        },
        Study::ActivationInTime(h) => Size {
            rows: n(h.times.len() * h.models.len()),
            figures: 1,
            tables: 1,
            ..Size::default()
        },
        Study::Shear(s) => Size {
            rows: n(s.shear.len() * s.angles.len() * s.models.len()),
            figures: 1,
            tables: 1,
            ..Size::default()
        },
        Study::Biaxial(b) => Size {
            rows: n(b.pairs.len() * b.models.len()),
            figures: 1,
            tables: 1,
            ..Size::default()
        },
        Study::Tangent(t) => tangent(t),
    }
}

/// Tangents the FE level solves with (exact, symmetric frozen, central differences), and the
/// states of its Taylor tests (the predictor, the converged state).
const FE_TANGENTS: usize = 3;
const FE_TAYLOR_STATES: usize = 2;

/// A tangent study: a row per model, stretch rate, state, direction and step (tangent.csv) and
/// per model, rate and state (tangent_summary.csv), a figure of the remainders; with the FE
/// level, per configuration a row per Taylor state, tangent and step (tangent_fe.csv) and per
/// tangent and Newton iteration (tangent_newton.csv), a figure, and as work two exact solves,
/// Newton with each tangent (five iterations counted as one target stretch) and the Taylor
/// tests' assemblies (about twenty solves' worth).
fn tangent(t: &super::tangent::TangentStudy) -> Size {
    let tests = t.models.len() * t.rates.as_ref().map_or(1, |r| r.0.len()) * t.sources.len();
    let mut size = Size {
        rows: (tests * (1 + t.directions.len() * t.h.len())) as u64,
        figures: 1,
        tables: 2,
        ..Size::default()
    };
    if let Some(fe) = &t.fe {
        let per_element = fe.bases.len() * fe.forms.len();
        let configs = (fe.elements.len() * per_element) as u64;
        let newton_rows = FE_TANGENTS * (fe.max_iterations + 1);
        let taylor_rows = FE_TAYLOR_STATES * FE_TANGENTS * t.h.len();
        let solves = 2.0 + (FE_TANGENTS * fe.max_iterations) as f64 / 5.0 + 20.0;
        let mut work = 0.0f64;
        let mut memory = 0.0f64;
        for &element in &fe.elements {
            let m = MemoryEstimate::structured(
                fe.cells.0,
                fe.cells.1,
                element,
                SolverOptions::default().linear_solver,
            );
            work += m.dofs * solves * per_element as f64;
            memory = memory.max(m.bytes);
        }
        size = size
            + Size {
                rows: configs * (newton_rows + taylor_rows) as u64,
                figures: 1,
                tables: 2,
                sweeps: configs,
                fe_work: work,
                fe_memory: memory,
                ..Size::default()
            };
    }
    size
}

/// A uniaxial study: a row per curve and stretch; a figure of its passive curves, one of its
/// constant-γ curves, and with active models γ and the stresses, the laws and the active curve,
/// the explicit law's two (with the explicit law) and the damages' two (with two damages or
/// more).
fn uniaxial(u: &super::uniaxial::UniaxialStudy) -> Size {
    let curves = usize::from(u.passive) + u.compare.len() + u.constant_gamma.len();
    let active = !u.models.is_empty();
    let mut damages: Vec<f64> = u.models.iter().map(|m| m.damage).collect();
    damages.dedup();
    let explicit = u.models.iter().any(|m| m.law == LawKind::Explicit);
    let figures = u64::from(u.passive || !u.compare.is_empty())
        + u64::from(!u.constant_gamma.is_empty())
        + if active { 3 } else { 0 }
        + if explicit { 2 } else { 0 }
        + if active && damages.len() > 1 { 2 } else { 0 };
    Size {
        rows: ((curves + u.models.len()) * u.stretches.len()) as u64,
        figures,
        ..Size::default()
    }
}

/// A cylinder study: a row per damage and stretch (and per named point), a VTK file per damage
/// and field stretch (and a series per sweep), a sweep per damage.
fn cylinder(c: &super::cylinder::CylinderStudy) -> Size {
    let sweeps = c.models.len() as u64;
    let stretches = c.stretches.len() as u64;
    let memory = MemoryEstimate::structured(
        c.nr,
        c.nz,
        c.element,
        SolverOptions::default().linear_solver,
    );
    let (nodes, cells) = match c.element {
        Element::Q2Q1 => ((2 * c.nr + 1) * (2 * c.nz + 1), c.nr * c.nz),
        Element::Q1P0 => ((c.nr + 1) * (c.nz + 1), c.nr * c.nz),
    };
    let vtk = sweeps * c.vtk.len() as u64;
    Size {
        rows: sweeps * stretches * (1 + c.points.len() as u64),
        figures: 1,
        tables: u64::from(!c.points.is_empty()),
        vtk_files: vtk + if vtk > 0 { sweeps } else { 0 },
        vtk_bytes: vtk * (VTK_NODE_BYTES * nodes as u64 + VTK_CELL_BYTES * cells as u64),
        sweeps,
        fe_work: memory.dofs * (sweeps * stretches) as f64,
        fe_memory: memory.bytes,
    }
}

/// The scene's size: its studies' sizes and the figures they share.
pub fn scene_size(studies: &[Study]) -> Size {
    studies.iter().map(size_of).fold(
        Size {
            figures: SHARED_FIGURES,
            ..Size::default()
        },
        |a, b| a + b,
    )
}

/// Checks the studies' size against [`LIMITS`] and the memory this system has available, with
/// a solve on each of its cores at the same time ([`check_within`]).
pub fn check(studies: &[Study]) -> Result<(), SpecError> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    check_within(studies, crate::fem::memory::available_memory(), cores)
}

/// Checks the studies' size against [`LIMITS`] and the memory available (`available` bytes,
/// `threads` solving at the same time); an error names the estimate, the bound, the study that
/// contributes the most and where to read about the bounds.
pub fn check_within(
    studies: &[Study],
    available: Option<u64>,
    threads: usize,
) -> Result<(), SpecError> {
    match beyond_limits(&scene_size(studies), available, threads) {
        Some(exceeded) => Err(refusal(studies, exceeded)),
        None => Ok(()),
    }
}

/// The refusal of a scene for `what`, at the [[study]] line of the study that contributes the
/// most to it (by `of`).
fn refusal(studies: &[Study], (what, of): Exceeded) -> SpecError {
    let most = studies
        .iter()
        .enumerate()
        .max_by(|a, b| of(&size_of(a.1)).total_cmp(&of(&size_of(b.1))));
    let Some((i, study)) = most else {
        return SpecError::new("study", "", what);
    };
    SpecError::new(
        format!("study[{i}]"),
        format!("{:?}", study.name()),
        format!(
            "{what}; this study contributes the most ({}). The limits keep a typo from \
             running for days or filling a disk: split the scene, or take coarser steps \
             (docs/running.md, \"Limits\")",
            study.describe()
        ),
    )
}

/// A limit exceeded: what the refusal says, and the measure of a study that ranks the studies.
type Exceeded = (String, fn(&Size) -> f64);

/// The first limit of [`LIMITS`] (or the memory `available`) that `total` exceeds: what the
/// refusal says, with the estimate and the bound, and the measure that ranks the studies.
fn beyond_limits(total: &Size, available: Option<u64>, threads: usize) -> Option<Exceeded> {
    if total.rows > LIMITS.rows {
        let what = format!(
            "this scene would write {} rows (≈ {} of CSV); the limit is {} rows",
            grouped(total.rows),
            bytes(total.rows * ROW_BYTES),
            grouped(LIMITS.rows)
        );
        return Some((what, |s| s.rows as f64));
    }
    if total.figures > LIMITS.figures {
        let what = format!(
            "this scene would draw up to {} figures (a report.html of ≈ {}); the limit is {}",
            grouped(total.figures),
            bytes(total.report_bytes()),
            LIMITS.figures
        );
        return Some((what, |s| s.figures as f64));
    }
    if total.files() > LIMITS.files {
        let what = format!(
            "this scene would write {} files ({} of them VTK); the limit is {}",
            grouped(total.files()),
            grouped(total.vtk_files),
            grouped(LIMITS.files)
        );
        return Some((what, |s| s.files() as f64));
    }
    if total.output_bytes() > LIMITS.output_bytes {
        let what = format!(
            "this scene would write ≈ {} ({} of VTK files); the limit is {}",
            bytes(total.output_bytes()),
            bytes(total.vtk_bytes),
            bytes(LIMITS.output_bytes)
        );
        return Some((what, |s| s.output_bytes() as f64));
    }
    if total.fe_work > LIMITS.fe_work {
        let what = format!(
            "this scene's FE sweeps would solve {:.2e} unknowns × stretches (≈ {:.0} h on 2 \
             cores); the limit is {:.0e}",
            total.fe_work,
            total.fe_work * FE_SECONDS / 3600.0,
            LIMITS.fe_work
        );
        return Some((what, |s| s.fe_work));
    }
    let a = available?;
    (total.memory(threads) > a).then(|| {
        let what = format!(
            "this scene would hold ≈ {} in memory ({} rows, the report, {} FE solves at a time \
             of up to {} each); {} are available",
            bytes(total.memory(threads)),
            grouped(total.rows),
            total.sweeps.min(threads as u64),
            bytes(total.fe_memory as u64),
            bytes(a)
        );
        (what, (|s: &Size| s.memory(1) as f64) as fn(&Size) -> f64)
    })
}
