//! Cylinder studies (`kind = "cylinder"`): the axisymmetric FE cylinder of the chapter's
//! numerical validation ([`crate::fem`]), one load sweep per damage value (in parallel), each
//! next to the homogeneous (0D) curve of the same model.

mod output;
mod volume;

use super::domain::{lines, Tally, Words};
use super::rules::{cell_count, grading, positive};
use super::spec::StretchSpec;
use super::spec::{required_stretches, Defaults, ModelKeys};
use super::{slug, Failure, Outcome, RunContext, StudyKind, StudyResult};
use crate::active::drive::Drive;
use crate::active::OutsideDomain;
use crate::app_error::{AppError, SpecError};
use crate::energy::Energy;
use crate::fem::material::axial_stretch;
use crate::fem::solver::MIN_TOLERANCE;
use crate::fem::QuadraturePoint;
use crate::fem::{
    AxisymmetricMaterial, AxisymmetricSolver, Bases, Element, FemError, Mesh,
    Progress as FemProgress, Region, Regions, SolverOptions, Stepping, VtkOutput,
};
use crate::models::{CouplingKind, LawKind, ModelChoice, Models};
use crate::stability::diagnose_axisymmetric;
use crate::text::shortest;
use crate::uniaxial::Direction;
use crate::Muscle;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Scene names of [`Bases`] (serde's remote definition: the FE solver's own type).
#[derive(Serialize, Deserialize)]
#[serde(remote = "Bases", rename_all = "kebab-case")]
enum BasesDef {
    /// u_r free on the bases (homogeneous solution).
    Sliding,
    /// u_r = 0 on the bases.
    Clamped,
}

/// Scene names of [`Element`] (serde's remote definition: the FE solver's own type).
#[derive(Serialize, Deserialize)]
#[serde(remote = "Element")]
enum ElementDef {
    /// Taylor–Hood: biquadratic displacement, continuous bilinear pressure.
    #[serde(rename = "Q2/Q1")]
    Q2Q1,
    /// Bilinear displacement, one pressure per cell.
    #[serde(rename = "Q1/P0")]
    Q1P0,
}

fn clamped() -> Bases {
    Bases::Clamped
}

/// `[[study]] kind = "cylinder"` as written; `None` is a key left to its default.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CylinderSpec {
    /// Label (default: `cylinder <bases> <law> <coupling>`).
    pub name: Option<String>,
    /// Target stretches (required).
    pub stretch: Option<StretchSpec>,
    /// Damage values, one FE sweep each (default: `activation.damage`).
    pub damage: Option<Vec<f64>>,
    /// Radius R (default 1).
    pub radius: Option<f64>,
    /// Length L (default 4).
    pub length: Option<f64>,
    /// Cells in r (default 6).
    pub nr: Option<i64>,
    /// Cells in z (default 24).
    pub nz: Option<i64>,
    /// Middle/base cell-height ratio ≥ 1 (default 1: uniform).
    pub grading: Option<f64>,
    /// `clamped` (default) or `sliding`.
    #[serde(default = "clamped", with = "BasesDef")]
    pub bases: Bases,
    /// `"Q2/Q1"` (default) or `"Q1/P0"`.
    #[serde(default, with = "ElementDef")]
    pub element: Element,
    /// Activation law (default `activation.law`).
    pub law: Option<LawKind>,
    /// Coupling (default `activation.coupling`).
    pub coupling: Option<CouplingKind>,
    /// Stretches at which VTK fields are written (must be among the stretches; default none).
    pub vtk: Option<Vec<f64>>,
    /// Newton tolerance (default 1e-10).
    pub tolerance: Option<f64>,
    /// Named boundary points `name = [r, z]` (reference coordinates, the mesh's length unit,
    /// e.g. mm) whose nodal displacements are reported (`[study.points]`; default none). Each
    /// must be a node of the mesh on the boundary of the meridian section (axis, lateral
    /// surface or a base).
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "crate::fixed_length::exact"
    )]
    pub points: Option<BTreeMap<String, [f64; 2]>>,
    /// Regions of the meridian section with their own damage and/or activation level
    /// (`[[study.regions]]`; default none: the model's damage and a = 1 everywhere). A later
    /// region overrides an earlier one where they overlap.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub regions: Option<Vec<RegionSpec>>,
}

/// `[[study.regions]]` of a cylinder study as written: the rectangle r ∈ [r0, r1] (in units of
/// R), z ∈ [z0, z1] (in units of L) of the reference meridian section, and its damage d and/or
/// activation level a, each in [0, 1]. Inside, the law sees d_eff = d + (1 − d)(1 − a) (d the
/// sweep's damage where `damage` is not given, a = 1 where `activation` is not given).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionSpec {
    /// [r0, r1] in units of R (default [0, 1]).
    #[serde(default, deserialize_with = "crate::fixed_length::exact")]
    pub r: Option<[f64; 2]>,
    /// [z0, z1] in units of L (default [0, 1]).
    #[serde(default, deserialize_with = "crate::fixed_length::exact")]
    pub z: Option<[f64; 2]>,
    /// Damage d inside [-] (default: the sweep's damage).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damage: Option<f64>,
    /// Activation level a inside [-] (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub activation: Option<f64>,
}

/// A validated region of a cylinder study (see [`RegionSpec`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StudyRegion {
    /// [r0, r1] in units of R.
    pub r: [f64; 2],
    /// [z0, z1] in units of L.
    pub z: [f64; 2],
    /// Damage inside (`None`: the sweep's).
    pub damage: Option<f64>,
    /// Activation level inside.
    pub activation: f64,
}

impl StudyRegion {
    /// `r/R ∈ [0.8, 1], z/L ∈ [0, 1], d = 0.5, a = 1` (`d = the sweep's` without its own damage).
    pub fn describe(&self) -> String {
        format!(
            "r/R ∈ [{}, {}], z/L ∈ [{}, {}], d = {}, a = {}",
            self.r[0],
            self.r[1],
            self.z[0],
            self.z[1],
            self.damage
                .map_or("the sweep's".to_string(), |d| d.to_string()),
            self.activation
        )
    }
}

/// Validates the regions: ranges finite, ordered and inside [0, 1], values in [0, 1], at least
/// one of damage and activation; errors name `regions[i].key`.
fn regions(specs: &[RegionSpec]) -> Result<Vec<StudyRegion>, SpecError> {
    let unit = |x: f64| (0.0..=1.0).contains(&x);
    let mut out = Vec::with_capacity(specs.len());
    for (i, g) in specs.iter().enumerate() {
        let key = |k: &str| format!("regions[{i}].{k}");
        let r = g.r.unwrap_or([0.0, 1.0]);
        let z = g.z.unwrap_or([0.0, 1.0]);
        for (k, v, unit_of) in [("r", r, "R"), ("z", z, "L")] {
            if !(unit(v[0]) && unit(v[1]) && v[0] < v[1]) {
                return Err(SpecError::new(
                    key(k),
                    format!("[{}, {}]", shortest(v[0]), shortest(v[1])),
                    format!(
                        "must be [{k}0, {k}1] with 0 ≤ {k}0 < {k}1 ≤ 1 (in units of {unit_of})"
                    ),
                ));
            }
        }
        for (k, v) in [("damage", g.damage), ("activation", g.activation)] {
            if let Some(v) = v.filter(|v| !unit(*v)) {
                return Err(SpecError::new(key(k), v, "must lie in [0, 1]"));
            }
        }
        if g.damage.is_none() && g.activation.is_none() {
            return Err(SpecError::new(
                format!("regions[{i}]"),
                format!(
                    "r = [{}, {}], z = [{}, {}]",
                    shortest(r[0]),
                    shortest(r[1]),
                    shortest(z[0]),
                    shortest(z[1])
                ),
                "a region needs damage and/or activation",
            ));
        }
        out.push(StudyRegion {
            r,
            z,
            damage: g.damage,
            activation: g.activation.unwrap_or(1.0),
        });
    }
    Ok(out)
}

/// Refuses a region that takes a model whose law has a domain ([`LawKind::domain`]: the
/// explicit law's) outside it: d_eff = d + (1 − d)(1 − a) ∉ [0, 0.5] and ≠ 1 inside the region
/// for one of the sweeps' damages (`models`), as a weakly recruited core does.
fn regions_in_domain(regions: &[StudyRegion], models: &[ModelChoice]) -> Result<(), SpecError> {
    for m in models {
        let Some(domain) = m.activation_law().and_then(|(law, _)| law.domain()) else {
            continue;
        };
        for (i, g) in regions.iter().enumerate() {
            let d = g.damage.unwrap_or(m.damage);
            let d_eff = d + (1.0 - d) * (1.0 - g.activation);
            if domain.holds_at_damage(d_eff) {
                continue;
            }
            let key = if g.activation < 1.0 {
                "activation"
            } else {
                "damage"
            };
            return Err(SpecError::new(
                format!("regions[{i}].{key}"),
                if g.activation < 1.0 { g.activation } else { d },
                format!(
                    "inside it (d = {d}, a = {}) the {} law would see d_eff = d + (1 − d)(1 − a) = {}, and it holds for {} ({}): keep (1 − d)·a in [{}, 1] or at 0, or use the implicit or the energy law",
                    g.activation,
                    m.law.name(),
                    crate::text::significant(d_eff, 6),
                    domain.describe(),
                    domain.why,
                    1.0 - domain.effective_damage[1],
                ),
            ));
        }
    }
    Ok(())
}

/// Refuses a region that governs no quadrature point of `mesh` (none lies inside it, or later
/// regions cover all that do): its damage and activation would have no effect on the solve.
fn regions_take_effect(
    regions: &[StudyRegion],
    mesh: &Mesh,
    mesh_name: &str,
) -> Result<(), SpecError> {
    let (radius, length) = (mesh.radius, mesh.length);
    let inside = |g: &StudyRegion, [r, z]: [f64; 2]| {
        g.r[0] * radius <= r && r <= g.r[1] * radius && g.z[0] * length <= z && z <= g.z[1] * length
    };
    let positions = mesh.quadrature_positions();
    let mut governs = vec![false; regions.len()];
    for &at in &positions {
        if let Some(i) = regions.iter().rposition(|g| inside(g, at)) {
            governs[i] = true;
        }
    }
    match governs.iter().position(|&g| !g) {
        None => Ok(()),
        Some(i) => {
            let g = &regions[i];
            let holds_any = positions.iter().any(|&at| inside(g, at));
            Err(SpecError::new(
                format!("regions[{i}]"),
                format!(
                    "r = [{}, {}], z = [{}, {}]",
                    shortest(g.r[0]),
                    shortest(g.r[1]),
                    shortest(g.z[0]),
                    shortest(g.z[1])
                ),
                if holds_any {
                    format!("later regions cover every quadrature point of the {mesh_name} mesh inside it (the last region holding a point governs it), so it has no effect: remove it or reorder")
                } else {
                    format!("holds no quadrature point of the {mesh_name} mesh, so it would have no effect: widen it or refine the mesh")
                },
            ))
        }
    }
}

/// A named boundary node of a cylinder study.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedPoint {
    /// Name as given in the scene.
    pub name: String,
    /// Reference coordinates (r, z).
    pub at: [f64; 2],
    /// Node index in the solver's mesh (the cells of the study's element).
    pub node: usize,
}

/// The nodes of `mesh` named by `points`, each a boundary node (within 1e-9 max(R, L));
/// otherwise an error naming the nearest boundary node and its distance.
fn named_points(
    points: &BTreeMap<String, [f64; 2]>,
    mesh: &Mesh,
    cells: &str,
) -> Result<Vec<NamedPoint>, SpecError> {
    let (radius, length) = (mesh.radius, mesh.length);
    let tol = 1e-9 * radius.max(length);
    let on_boundary = |x: &[f64; 2]| {
        x[0].abs() <= tol
            || (x[0] - radius).abs() <= tol
            || x[1].abs() <= tol
            || (x[1] - length).abs() <= tol
    };
    let mut out = Vec::with_capacity(points.len());
    for (name, at) in points {
        let key = format!("points.{name}");
        let shown = format!("[{}, {}]", shortest(at[0]), shortest(at[1]));
        if !(at[0].is_finite() && at[1].is_finite()) {
            return Err(SpecError::new(key, shown, "coordinates must be finite"));
        }
        let nearest = mesh
            .nodes
            .iter()
            .enumerate()
            .filter(|(_, x)| on_boundary(x))
            .map(|(k, x)| (k, (x[0] - at[0]).hypot(x[1] - at[1])))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match nearest {
            Some((node, d)) if d <= tol => out.push(NamedPoint {
                name: name.clone(),
                at: *at,
                node,
            }),
            Some((node, d)) => {
                let x = mesh.nodes[node];
                return Err(SpecError::new(
                    key,
                    shown,
                    format!(
                        "a named point must be a mesh node on the boundary (r = 0, r = R, z = 0 or z = L) of the {cells} mesh: the nearest is node {node} at [{}, {}], {d:.3e} away",
                        shortest(x[0]),
                        shortest(x[1])
                    ),
                ));
            }
            None => return Err(SpecError::new(key, shown, "the mesh has no boundary node")),
        }
    }
    Ok(out)
}

/// Keys a cylinder study does not take, and what to write instead.
pub const HINTS: &[(&str, &str)] = &[
    ("laws", "a cylinder study takes one law: law = \"...\""),
    (
        "couplings",
        "a cylinder study takes one coupling: coupling = \"...\"",
    ),
];

/// A validated cylinder study.
#[derive(Debug, Clone, PartialEq)]
pub struct CylinderStudy {
    /// Label.
    pub name: String,
    /// Radius R.
    pub radius: f64,
    /// Length L.
    pub length: f64,
    /// Cells in r.
    pub nr: usize,
    /// Cells in z.
    pub nz: usize,
    /// Middle/base cell-height ratio.
    pub grading: f64,
    /// Base conditions.
    pub bases: Bases,
    /// Finite element.
    pub element: Element,
    /// Target stretches, ascending.
    pub stretches: Vec<f64>,
    /// The scene's approach.
    pub approach: crate::active::Approach,
    /// The models, one per damage value (the scene's approach, the study's law and coupling):
    /// one FE sweep each.
    pub models: Vec<ModelChoice>,
    /// Stretches with VTK output.
    pub vtk: Vec<f64>,
    /// Newton tolerance.
    pub tolerance: f64,
    /// Named boundary points whose displacements are reported.
    pub points: Vec<NamedPoint>,
    /// Regions with their own damage and/or activation (empty: uniform).
    pub regions: Vec<StudyRegion>,
}

/// `clamped` or `sliding`.
pub fn bases_name(b: Bases) -> &'static str {
    match b {
        Bases::Clamped => "clamped",
        Bases::Sliding => "sliding",
    }
}

/// Validates `spec` against the scene's defaults; returns the study and the spec with every
/// default written out.
pub fn resolve(
    spec: &CylinderSpec,
    d: &Defaults,
) -> Result<(CylinderStudy, CylinderSpec), SpecError> {
    let stretches = required_stretches(&spec.stretch)?;
    let set = ModelKeys::one(&spec.law, &spec.coupling, &spec.damage).of_scene(d)?;
    let radius = positive("radius", spec.radius.unwrap_or(1.0))?;
    let length = positive("length", spec.length.unwrap_or(4.0))?;
    let nr = cell_count("nr", spec.nr.unwrap_or(6))?;
    let nz = cell_count("nz", spec.nz.unwrap_or(24))?;
    let grading = grading("grading", spec.grading.unwrap_or(1.0))?;
    let tolerance = tolerance(spec.tolerance.unwrap_or(1e-10))?;
    let (law, coupling) = set.single();
    let vtk = vtk_stretches(spec.vtk.as_deref().unwrap_or_default(), &stretches)?;
    let regions = regions(spec.regions.as_deref().unwrap_or_default())?;
    regions_in_domain(&regions, &set.choices)?;
    let name = spec.name.clone().unwrap_or_else(|| {
        let model = match (law, coupling) {
            (Some(law), Some(coupling)) => format!("{} {}", law.name(), coupling.name()),
            _ => d.approach.name().to_string(),
        };
        format!("cylinder {} {model}", bases_name(spec.bases))
    });
    let resolved = CylinderSpec {
        name: Some(name.clone()),
        stretch: spec.stretch.clone(),
        damage: Some(set.damage.clone()),
        radius: Some(radius),
        length: Some(length),
        nr: Some(nr as i64),
        nz: Some(nz as i64),
        grading: Some(grading),
        bases: spec.bases,
        element: spec.element,
        law,
        coupling,
        vtk: Some(vtk.clone()),
        tolerance: Some(tolerance),
        points: spec.points.clone(),
        regions: spec.regions.as_ref().map(|_| written_regions(&regions)),
    };
    let points = mesh_checks(spec, (radius, length, grading), (nr, nz), &regions)?;
    Ok((
        CylinderStudy {
            name,
            radius,
            length,
            nr,
            nz,
            grading,
            bases: spec.bases,
            element: spec.element,
            stretches,
            approach: d.approach,
            models: set.choices,
            vtk,
            tolerance,
            points,
            regions,
        },
        resolved,
    ))
}

/// The Newton tolerance: finite, > 0 and at least 4 ε.
fn tolerance(tolerance: f64) -> Result<f64, SpecError> {
    let tolerance = positive("tolerance", tolerance)?;
    if tolerance < MIN_TOLERANCE {
        return Err(SpecError::new(
            "tolerance",
            format!("{tolerance:e}"),
            format!(
                "must be at least 4 ε = {MIN_TOLERANCE:.1e}: a scaled residual of f64 numbers does not go below its round-off"
            ),
        ));
    }
    Ok(tolerance)
}

/// The stretches with VTK output, each one of the computed `stretches`.
fn vtk_stretches(vtk: &[f64], stretches: &[f64]) -> Result<Vec<f64>, SpecError> {
    for (j, v) in vtk.iter().enumerate() {
        if !stretches.iter().any(|l| (l - v).abs() < 1e-12) {
            return Err(SpecError::new(
                format!("vtk[{j}]"),
                v,
                "VTK output is written only at computed stretches: add it to stretch",
            ));
        }
    }
    Ok(vtk.to_vec())
}

/// The regions as the resolved scene writes them.
fn written_regions(regions: &[StudyRegion]) -> Vec<RegionSpec> {
    regions
        .iter()
        .map(|g| RegionSpec {
            r: Some(g.r),
            z: Some(g.z),
            damage: g.damage,
            activation: Some(g.activation),
        })
        .collect()
}

/// What the mesh must allow, checked before anything runs (`check` says it too): the solve's
/// memory from the counts; where named points or regions need the mesh, that the regions take
/// effect on it; the named points, located on it.
fn mesh_checks(
    spec: &CylinderSpec,
    (radius, length, grading): (f64, f64, f64),
    (nr, nz): (usize, usize),
    regions: &[StudyRegion],
) -> Result<Vec<NamedPoint>, SpecError> {
    crate::fem::MemoryEstimate::structured(
        nr,
        nz,
        spec.element,
        crate::fem::SolverOptions::default().linear_solver,
    )
    .check(crate::fem::memory::default_limit())
    .map_err(|e| SpecError::new("nr", nr, e.to_string()))?;
    let wanted = spec.points.as_ref().is_some_and(|p| !p.is_empty()) || !regions.is_empty();
    let mesh = wanted
        .then(|| {
            Mesh::structured(radius, length, nr, nz, grading)
                .map(|m| m.with_element(spec.element))
                .map_err(|e| SpecError::new("nr", nr, e.to_string()))
        })
        .transpose()?;
    let mesh_name = format!("{nr} × {nz} {}", spec.element);
    if let Some(mesh) = &mesh {
        regions_take_effect(regions, mesh, &mesh_name)?;
    }
    Ok(match (&spec.points, &mesh) {
        (Some(p), Some(mesh)) if !p.is_empty() => named_points(p, mesh, &mesh_name)?,
        _ => Vec::new(),
    })
}

/// One converged stretch of a sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SweepPoint {
    /// Stretch λ [-].
    pub lambda: f64,
    /// γ at the quadrature point nearest the centre of the cylinder [-].
    pub gamma_centre: f64,
    /// Fibre stretch λ_f at the same point [-] (the law's argument there: γ = 0 where
    /// λ_f ≤ λ_min for the implicit and explicit laws).
    pub fibre_stretch_centre: f64,
    /// Nominal axial stress: axial reaction / (π R²) \[kPa\].
    pub stress: f64,
    /// Newton iterations to reach this stretch from the previous one.
    pub newton_iterations: usize,
    /// The homogeneous (0D) stress of the same model at λ \[kPa\], if it could be computed.
    pub stress_0d: Option<f64>,
    /// The homogeneous passive stress P_pas(λ) \[kPa\], if it could be computed.
    pub passive_0d: Option<f64>,
    /// The target active stress (1 − d) P_act(λ) \[kPa\].
    pub active_0d: f64,
    /// The lowest and the highest fibre stretch over the quadrature points at which the law
    /// there is outside its domain, if any is (the explicit law's: [`crate::active::Domain`]).
    pub outside: [Option<OutsideDomain>; 2],
}

/// The sweep of one model.
#[derive(Debug, Clone, PartialEq)]
pub struct Sweep {
    /// The model.
    pub model: ModelChoice,
    /// The model in words (energy, law, coupling, d).
    pub label: String,
    /// Free dofs.
    pub dofs: usize,
    /// Converged stretches in sweep order.
    pub points: Vec<SweepPoint>,
    /// VTK files written, relative to the run's VTK directory.
    pub vtk_files: Vec<PathBuf>,
    /// Per converged stretch (aligned with `points`), the displacement (u_r, u_z) of each named
    /// point of the study ([`CylinderResult::points`]), in the mesh's length unit.
    pub displacements: Vec<Vec<[f64; 2]>>,
    /// Per converged stretch (aligned with `points`), how far J is from 1.
    pub volume: Vec<VolumeError>,
}

/// How far J = det F is from 1 in a solved state (Taylor–Hood enforces J = 1 weakly: J − 1 is
/// orthogonal to the pressure's bilinear functions on each cell, not 0 at every point).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VolumeError {
    /// max |J − 1| over the quadrature points, and the reference (r, z) of that point.
    pub at_points: (f64, [f64; 2]),
    /// max |J̄ − 1| over the cells (J̄ a cell's volume-weighted mean of J, as the VTK files show
    /// it), and the reference (r, z) of that cell's centroid.
    pub of_cells: (f64, [f64; 2]),
}

impl Sweep {
    /// max |P_FE − P_0D| \[kPa\], the stretch where it occurs and P_0D there; `None` when no
    /// stretch has a 0D value (e.g. a sweep that reached no stretch).
    pub fn worst_against_0d(&self) -> Option<(f64, f64, f64)> {
        self.points
            .iter()
            .filter_map(|p| {
                p.stress_0d
                    .map(|zero| ((p.stress - zero).abs(), p.lambda, zero))
            })
            .max_by(|a, b| a.0.total_cmp(&b.0))
    }
}

/// The sweeps of a cylinder study.
#[derive(Debug, Clone, PartialEq)]
pub struct CylinderResult {
    /// The energy's name.
    pub energy: String,
    /// The activation approach of every sweep.
    pub approach: crate::active::Approach,
    /// Base conditions.
    pub bases: Bases,
    /// Finite element.
    pub element: Element,
    /// One sweep per damage value, in the study's order.
    pub sweeps: Vec<Sweep>,
    /// The named boundary points, name and reference (r, z).
    pub points: Vec<(String, [f64; 2])>,
    /// The regions with their own damage or activation (empty: a uniform body). With regions
    /// the 0D curve of a sweep is the uniform model's at the sweep's d, a reference only.
    pub regions: Vec<StudyRegion>,
    /// Radius R and length L of the cylinder (the mesh's length unit).
    pub dimensions: [f64; 2],
    /// Whether the material is nearly incompressible (a volumetric energy): then J − 1 is its
    /// own volume change too.
    pub nearly_incompressible: bool,
}

impl CylinderResult {
    /// The regions in words, `; `-separated (`None` for a uniform body).
    pub fn regions_in_words(&self) -> Option<String> {
        (!self.regions.is_empty()).then(|| {
            self.regions
                .iter()
                .map(StudyRegion::describe)
                .collect::<Vec<_>>()
                .join("; ")
        })
    }
}

/// The lowest and the highest fibre stretch among the quadrature points `qps` at which the law
/// of the muscle there (`muscle_at` their reference (r, z)) leaves its domain.
fn outside_domain<'m>(
    qps: &[QuadraturePoint],
    muscle_at: impl Fn([f64; 2]) -> &'m Muscle<Energy>,
) -> [Option<OutsideDomain>; 2] {
    let value = |o: &OutsideDomain| match *o {
        OutsideDomain::Stretch(v) | OutsideDomain::EffectiveDamage(v) => v,
    };
    let outside: Vec<OutsideDomain> = qps
        .iter()
        .filter_map(|q| muscle_at([q.r, q.z]).outside_domain(axial_stretch(&q.f)))
        .collect();
    [
        outside
            .iter()
            .copied()
            .min_by(|a, b| value(a).total_cmp(&value(b))),
        outside
            .iter()
            .copied()
            .max_by(|a, b| value(a).total_cmp(&value(b))),
    ]
}

/// How a cylinder study's line names its points.
const WORDS: Words = Words {
    points: "stretches with quadrature points",
    x: "λ",
    unit: "",
    target: "",
    file: super::table::CURVES_FILE,
};

/// Where the quadrature points of `sweep` left its law's domain (`None`: a law that holds
/// everywhere).
fn sweep_tally(sweep: &Sweep) -> Option<Tally> {
    let mut tally = Tally::of(&sweep.model)?;
    for p in &sweep.points {
        tally.add(p.lambda, p.outside.into_iter().flatten(), None);
    }
    Some(tally)
}

/// How far a sweep is from its 0D curve, in words: what the two are (a body with `bases`, with
/// regions or not, against homogeneous tension), the largest |P_FE − P_0D| in kPa and where, the
/// same number the report's table "FE vs homogeneous (0D) tension" gives over all stretches;
/// "no stretch converged" when there is nothing to compare.
fn against_0d(sweep: &Sweep, bases: Bases, regions: bool) -> String {
    let what = match (regions, bases) {
        (true, _) => {
            "the body with its regions against the uniform model's homogeneous tension (0D)"
        }
        (false, Bases::Clamped) => {
            "the clamped body against homogeneous tension (0D), the end effect"
        }
        (false, Bases::Sliding) => "sliding bases against homogeneous tension (0D), a verification",
    };
    match sweep.worst_against_0d() {
        None => "no stretch converged: nothing to compare with the 0D curve".into(),
        Some((difference, lambda, zero)) => format!(
            "{what}: largest |P_FE − P_0D| = {} kPa at λ = {lambda} ({} % of |P_0D| there)",
            crate::text::significant(difference, 4),
            crate::text::significant(100.0 * difference / zero.abs().max(1e-300), 4)
        ),
    }
}

/// The VTK files a sweep wrote, relative to `vtk_dir`, and its `.pvd` series (time = λ),
/// written beside them into `vtk_dir/sub` when there are any.
fn vtk_files(
    results: &[crate::fem::StretchResult],
    vtk_dir: Option<&Path>,
    sub: &Path,
) -> Result<Vec<PathBuf>, AppError> {
    let written: Vec<(f64, String)> = results
        .iter()
        .filter_map(|r| {
            let name = r.vtk_file.as_ref()?.file_name()?;
            Some((r.stretch, name.to_string_lossy().into_owned()))
        })
        .collect();
    let mut files: Vec<PathBuf> = written.iter().map(|(_, f)| sub.join(f)).collect();
    if let (Some(dir), false) = (vtk_dir, written.is_empty()) {
        crate::fem::vtk::write_series(&dir.join(sub), &written)?;
        files.push(sub.join(crate::fem::vtk::SERIES));
    }
    Ok(files)
}

/// A sweep that stopped, in words: how far it got and why.
fn describe_failure(f: &FemError) -> String {
    match f {
        FemError::TargetNotReached {
            target,
            reached,
            attempted,
            cause,
            ..
        } => format!(
            "stopped before target lambda = {}: converged up to lambda = {}; \
             the step to {attempted:.5} failed even at the smallest load step ({cause})",
            crate::text::significant(*target, 10),
            crate::text::significant(*reached, 10)
        ),
        other => other.to_string(),
    }
}

impl CylinderStudy {
    /// One line for `check`.
    pub fn describe(&self) -> String {
        format!(
            "{}: {} × {} cells, {} stretches, {} FE sweep(s)",
            self.name,
            self.nr,
            self.nz,
            self.stretches.len(),
            self.models.len()
        )
    }

    /// Runs one FE sweep per damage value (in parallel). A sweep that stops early (the material
    /// or the solver gives up) is a failure with a diagnosis of the failed state; a model or
    /// mesh that cannot be built is an error.
    pub fn run(&self, models: &Models, ctx: &RunContext) -> Result<Outcome, AppError> {
        let bases = bases_name(self.bases);
        let choices = &self.models;
        for m in choices {
            ctx.progress.log(&format!(
                "{}: {} bases, {}, R = {}, L = {}, {} × {} {} cells (grading {})",
                self.name,
                bases,
                models.label(m),
                self.radius,
                self.length,
                self.nr,
                self.nz,
                self.element,
                self.grading
            ));
        }
        ctx.progress
            .start(&self.name, choices.len() * self.stretches.len());
        let sweeps: Vec<Result<(Sweep, Vec<Failure>), AppError>> = choices
            .par_iter()
            .map(|m| self.sweep(models, m, ctx))
            .collect();
        ctx.progress.finish();
        let mut result = CylinderResult {
            energy: crate::StrainEnergy::name(&models.energy).to_string(),
            approach: self.approach,
            bases: self.bases,
            element: self.element,
            sweeps: Vec::with_capacity(sweeps.len()),
            points: self.points.iter().map(|p| (p.name.clone(), p.at)).collect(),
            regions: self.regions.clone(),
            dimensions: [self.radius, self.length],
            nearly_incompressible: models.volumetric.is_some(),
        };
        let (mut failures, mut tallies) = (Vec::new(), Vec::new());
        let mut details = self.geometry_details();
        for (s, m) in sweeps.into_iter().zip(choices) {
            // A sweep that cannot start (model, mesh, memory) costs only its own model.
            let (sweep, stops) = match s {
                Ok(s) => s,
                Err(e) => {
                    details.push(format!(
                        "d = {}: not run (see \"Where a model stopped\")",
                        m.damage
                    ));
                    failures.push(Failure {
                        model: models.label(m),
                        message: e.to_string(),
                    });
                    continue;
                }
            };
            details.push(self.sweep_detail(&sweep, !stops.is_empty()));
            failures.extend(stops);
            tallies.extend(sweep_tally(&sweep).map(|t| (sweep.label.clone(), t)));
            result.sweeps.push(sweep);
        }
        let points = result.sweeps.iter().map(|s| s.points.len()).sum();
        Ok(Outcome {
            name: self.name.clone(),
            kind: StudyKind::Cylinder,
            models: choices.len(),
            points,
            requested: choices.len() * self.stretches.len(),
            elapsed: Default::default(),
            details,
            failures,
            left_domain: lines(tallies, &WORDS),
            result: StudyResult::Cylinder(result),
        })
    }

    /// A sweep's line of the study's details: its stretches, unknowns and the distance from the
    /// 0D curve; whether it `stopped` early.
    fn sweep_detail(&self, sweep: &Sweep, stopped: bool) -> String {
        format!(
            "d = {}: {}/{} stretches, {} dofs, {}{}",
            sweep.model.damage,
            sweep.points.len(),
            self.stretches.len(),
            sweep.dofs,
            against_0d(sweep, self.bases, !self.regions.is_empty()),
            if stopped {
                " (stopped: see \"Where a model stopped\")"
            } else {
                ""
            }
        )
    }

    /// The study's facts before its sweeps': geometry, mesh, bases, stretches, regions.
    fn geometry_details(&self) -> Vec<String> {
        let mut details = vec![format!(
            "R = {}, L = {}, {} × {} {} cells (grading {}), {} bases, {} stretches",
            self.radius,
            self.length,
            self.nr,
            self.nz,
            self.element,
            self.grading,
            bases_name(self.bases),
            self.stretches.len()
        )];
        if !self.regions.is_empty() {
            details.push(format!(
                "{} region(s) with their own damage/activation (a later one wins where they overlap): P_0D is the uniform model's, for reference only",
                self.regions.len()
            ));
            for (i, g) in self.regions.iter().enumerate() {
                details.push(format!("region {}: {}", i + 1, g.describe()));
            }
        }
        details
    }

    /// The material of model `m` varying by [`Self::regions`] (`None` without regions): in each
    /// region the muscle at its damage (default `m.damage`) and activation level
    /// ([`Models::muscle_at`]), scaled to the cylinder's R and L.
    fn regional(
        &self,
        models: &Models,
        m: &ModelChoice,
    ) -> Result<Option<Regions<Muscle<Energy>>>, AppError> {
        if self.regions.is_empty() {
            return Ok(None);
        }
        let base = models.muscle(*m)?;
        let mut out = Vec::with_capacity(self.regions.len());
        for g in &self.regions {
            let damage = g.damage.unwrap_or(m.damage);
            let model = ModelChoice { damage, ..*m };
            out.push(Region {
                r: g.r.map(|x| x * self.radius),
                z: g.z.map(|x| x * self.length),
                material: models.muscle_at(model, g.activation)?,
                fields: (damage, g.activation),
            });
        }
        Ok(Some(Regions::new(base, (m.damage, 1.0), out)))
    }

    /// A progress line for each stretch the sweep of model `label` solved.
    fn solved(&self, ctx: &RunContext, label: &str, p: FemProgress<'_>) {
        if let FemProgress::Stretch(r) = p {
            ctx.progress.point(&format!(
                "{}: {label}: lambda = {} solved, P = {:.4} kPa",
                self.name, r.stretch, r.nominal_stress
            ));
        }
    }

    /// The nodal displacements (u_r, u_z) of the named points at each stretch `sweep` solved.
    fn displacements(
        &self,
        solver: &AxisymmetricSolver<'_, impl AxisymmetricMaterial + ?Sized>,
        sweep: &crate::fem::solver::Sweep,
    ) -> Vec<Vec<[f64; 2]>> {
        let node_u = &solver.dofs().node_u;
        sweep
            .results
            .iter()
            .map(|r| {
                self.points
                    .iter()
                    .map(|p| node_u[p.node].map(|g| r.state.x[g as usize]))
                    .collect()
            })
            .collect()
    }

    /// The sweep of model `m`, with the failures of the directions that stopped.
    fn sweep(
        &self,
        models: &Models,
        m: &ModelChoice,
        ctx: &RunContext,
    ) -> Result<(Sweep, Vec<Failure>), AppError> {
        let muscle = models.muscle(*m)?;
        let mesh = Mesh::structured(self.radius, self.length, self.nr, self.nz, self.grading)?;
        // The damage written short: 1e-300 is not 302 characters of a directory name.
        let sub = PathBuf::from(format!(
            "{}_d{}",
            slug(&self.name),
            crate::text::shortest(m.damage)
        ));
        // The uniform cylinder solves the muscle itself; regions wrap one muscle per region.
        let regional = self.regional(models, m)?;
        let material: &dyn AxisymmetricMaterial = match &regional {
            Some(r) => r,
            None => &muscle,
        };
        let options = self.solver_options(models, ctx, &sub);
        let mut solver = AxisymmetricSolver::new(mesh, self.bases, material, options)?;
        let dofs = solver.n_free_dofs();
        let label = models.label(m);
        let sweep = solver.sweep_with(&self.stretches, &mut |p| self.solved(ctx, &label, p))?;
        let passive = models.passive();
        let displacements = self.displacements(&solver, &sweep);
        // Where the law (of the region) at each quadrature point leaves its domain.
        let bounded = m.activation_law().and_then(|(l, _)| l.domain()).is_some();
        let outside = |r: &crate::fem::StretchResult| match (bounded, &regional) {
            (false, _) => [None; 2],
            (true, None) => outside_domain(&solver.quadrature_points(&r.state), |_| &muscle),
            (true, Some(g)) => outside_domain(&solver.quadrature_points(&r.state), |at| g.at(at).0),
        };
        let points = sweep
            .results
            .iter()
            .map(|r| sweep_point(models, m, (&muscle, &passive), r, outside(r)))
            .collect();
        let failures = sweep_failures(&sweep, ctx, &muscle, &label);
        Ok((
            Sweep {
                model: *m,
                label,
                dofs,
                points,
                vtk_files: vtk_files(&sweep.results, ctx.vtk_dir, &sub)?,
                displacements,
                volume: sweep
                    .results
                    .iter()
                    .map(|r| VolumeError {
                        at_points: (r.max_volume_error, r.max_volume_error_at),
                        of_cells: r.max_cell_volume_error,
                    })
                    .collect(),
            },
            failures,
        ))
    }

    /// The solver's options: the study's tolerance and element, the scene's volumetric energy,
    /// the VTK files at the study's `vtk` stretches into `vtk_dir/sub`, the run's stop.
    fn solver_options(&self, models: &Models, ctx: &RunContext, sub: &Path) -> SolverOptions {
        let vtk = match (ctx.vtk_dir, self.vtk.is_empty()) {
            (Some(dir), false) => Some(VtkOutput {
                directory: dir.join(sub),
                stretches: self.vtk.clone(),
            }),
            _ => None,
        };
        SolverOptions {
            stepping: Stepping {
                tolerance: self.tolerance,
                ..Stepping::default()
            },
            element: self.element,
            vtk,
            cancel: ctx.stop.map(|s| s.flag().clone()),
            volumetric: models.volumetric,
            ..SolverOptions::default()
        }
    }
}

/// The point of a sweep at the solved stretch `r` of model `m`, with the homogeneous (0D)
/// stresses of its muscle and passive counterpart there, and where its law left its domain
/// (`outside`: [`outside_domain`]).
fn sweep_point(
    models: &Models,
    m: &ModelChoice,
    (muscle, passive): (&Muscle<Energy>, &Muscle<Energy>),
    r: &crate::fem::StretchResult,
    outside: [Option<OutsideDomain>; 2],
) -> SweepPoint {
    let stress = |muscle| {
        models
            .uniaxial(muscle, Direction::Along, r.stretch)
            .ok()
            .map(|p| p.stress)
    };
    SweepPoint {
        lambda: r.stretch,
        gamma_centre: r.gamma_centre,
        fibre_stretch_centre: r.fibre_stretch_centre,
        stress: r.nominal_stress,
        newton_iterations: r.steps.iter().map(|st| st.iterations.len()).sum(),
        stress_0d: stress(muscle),
        passive_0d: stress(passive),
        active_0d: Drive::from(m.damage).target(&models.curve, r.stretch),
        outside,
    }
}

/// The failures of the directions of `sweep` that stopped, each with a material diagnosis of
/// its last rejected trial, or the run's stop reason.
fn sweep_failures(
    sweep: &crate::fem::Sweep,
    ctx: &RunContext,
    muscle: &Muscle<Energy>,
    label: &str,
) -> Vec<Failure> {
    sweep
        .failures
        .iter()
        .zip(&sweep.failed_trials)
        .map(|(f, trial)| {
            let mut message = describe_failure(f);
            if let (FemError::Cancelled { .. }, Some(reason)) =
                (f, ctx.stop.and_then(|s| s.reason()))
            {
                message = format!("{reason}: {message}; the stretches solved before are kept");
            }
            if let Some(points) = trial {
                let f: Vec<_> = points.iter().map(|q| q.f).collect();
                let diagnosis = diagnose_axisymmetric(muscle, &f, 100);
                message.push_str(&format!("; material diagnosis: {diagnosis}"));
            }
            Failure {
                model: label.to_string(),
                message,
            }
        })
        .collect()
}
