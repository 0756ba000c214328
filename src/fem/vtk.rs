//! VTK XML unstructured-grid (`.vtu`, ASCII) output for ParaView: the fields of a solved
//! state ([`write_state`]), the writer ([`write_vtu`]) and the series of a sweep over its
//! stretches ([`write_series`], a `.pvd` whose time is the stretch λ). The file of a stretch is
//! named once, by [`file_name`].
//!
//! Where each field lives (said in a comment at the top of every file too):
//!
//! - at the nodes (`PointData`): the displacement `u` = (u_r, u_z, 0) and the pressure `p`, the
//!   Lagrange multiplier of J = 1 (Q2/Q1: its Q1 interpolation; Q1/P0: the volume-weighted mean
//!   of the cell pressures around the node);
//! - per cell (`CellData`), the volume-weighted mean over the cell's quadrature points:
//!   `J`, `gamma`, `fibre_stretch`, `P_zz` (nominal, pressure included), the stress tensors
//!   `nominal_stress` P = ∂Ψ/∂F − p J F⁻ᵀ (first Piola–Kirchhoff) and `cauchy_stress`
//!   σ = P Fᵀ / J, and `hydrostatic_pressure` = −tr σ / 3 (which differs from `p` wherever the
//!   deviatoric stress has a trace: p is a multiplier, not a mean stress).
//!
//! The mesh is the meridian section in the (x, y) = (r, z) plane; the tensors are 3 × 3 in that
//! frame with z = θ (9 components, row-major, named `rr`, `rz`, `rtheta`, …): their r–z block,
//! the hoop entry θθ, and zeros for rθ, zθ (no torsion).

use super::assembly::QuadraturePoint;
use super::dofs::DofMap;
use super::element::{jacobian, jacobian_gradient, NodeLayout, PressureLayout};
use super::error::{FemError, FemResult};
use super::material::AxisymmetricMaterial;
use super::mesh::Mesh;
use nalgebra::Matrix3;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The file name of the fields at stretch λ: `lambda_<λ with 4 decimals>.vtu`.
pub fn file_name(stretch: f64) -> String {
    format!("lambda_{stretch:.4}.vtu")
}

/// The series of a sweep's files, for ParaView's time slider (time = λ).
pub const SERIES: &str = "sweep.pvd";

/// Writes the fields of the state `x` into `directory` (created if missing) under
/// [`file_name`]`(stretch)`; returns the path written.
pub fn write_stretch<M: AxisymmetricMaterial + ?Sized>(
    directory: &Path,
    stretch: f64,
    mesh: &Mesh,
    dofs: &DofMap,
    material: &M,
    qps: &[QuadraturePoint],
    x: &[f64],
) -> FemResult<PathBuf> {
    std::fs::create_dir_all(directory).map_err(|source| FemError::Io {
        path: directory.display().to_string(),
        source,
    })?;
    let path = directory.join(file_name(stretch));
    write_state(&path, mesh, dofs, material, qps, x)?;
    Ok(path)
}

/// Writes `SERIES` into `directory`: a ParaView collection of the VTU files `files`
/// ((stretch λ, file name) pairs, written in ascending λ, λ as the time); returns its path.
pub fn write_series(directory: &Path, files: &[(f64, String)]) -> FemResult<PathBuf> {
    let path = directory.join(SERIES);
    let mut sorted: Vec<&(f64, String)> = files.iter().collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut text = String::from(
        "<?xml version=\"1.0\"?>\n<!-- activemuscle: the fields of one FE sweep; the time is \
         the applied stretch λ -->\n<VTKFile type=\"Collection\" version=\"0.1\" \
         byte_order=\"LittleEndian\">\n<Collection>\n",
    );
    for (stretch, file) in sorted {
        text.push_str(&format!(
            "<DataSet timestep=\"{stretch:e}\" group=\"\" part=\"0\" file=\"{file}\"/>\n"
        ));
    }
    text.push_str("</Collection>\n</VTKFile>\n");
    std::fs::write(&path, text).map_err(|source| FemError::Io {
        path: path.display().to_string(),
        source,
    })?;
    Ok(path)
}

/// Writes the state `x` (quadrature points `qps`) as a VTK unstructured grid in the (r, z)
/// plane with the fields of the module's list.
pub fn write_state<M: AxisymmetricMaterial + ?Sized>(
    path: &Path,
    mesh: &Mesh,
    dofs: &DofMap,
    material: &M,
    qps: &[QuadraturePoint],
    x: &[f64],
) -> FemResult<()> {
    let cells = cell_means(mesh.n_elements(), material, qps)?;
    let scalars: Vec<[f64; 4]> = cells.iter().map(|c| c.scalars).collect();
    let nominal: Vec<[f64; 9]> = cells.iter().map(|c| c.nominal).collect();
    let cauchy: Vec<[f64; 9]> = cells.iter().map(|c| c.cauchy).collect();
    let hydrostatic: Vec<f64> = cells.iter().map(|c| c.hydrostatic).collect();
    let damage: Vec<f64> = cells
        .iter()
        .filter_map(|c| c.regional.map(|r| r[0]))
        .collect();
    let activation: Vec<f64> = cells
        .iter()
        .filter_map(|c| c.regional.map(|r| r[1]))
        .collect();
    let mut extra = vec![
        CellField::Tensor("nominal_stress", &nominal),
        CellField::Tensor("cauchy_stress", &cauchy),
        CellField::Scalar("hydrostatic_pressure", &hydrostatic),
    ];
    // A material varying in space: its damage and activation level.
    if damage.len() == cells.len() {
        extra.push(CellField::Scalar("damage", &damage));
        extra.push(CellField::Scalar("activation", &activation));
    }
    let pressure = nodal_pressure(mesh, dofs, &cells, x);
    let u: Vec<[f64; 2]> = dofs
        .node_u
        .iter()
        .map(|d| [x[d[0] as usize], x[d[1] as usize]])
        .collect();
    write_vtu_with(path, mesh, &u, &pressure, &scalars, &extra).map_err(|source| FemError::Io {
        path: path.display().to_string(),
        source,
    })
}

/// The means over one cell's quadrature points (volume-weighted) written per cell.
#[derive(Debug, Clone, Copy, Default)]
struct CellMeans {
    /// J, γ, λ_f, P_zz.
    scalars: [f64; 4],
    /// P and σ in the VTK frame (x, y, z) = (r, z, θ), row-major.
    nominal: [f64; 9],
    cauchy: [f64; 9],
    /// −tr σ / 3.
    hydrostatic: f64,
    /// (damage, activation) of a material varying in space.
    regional: Option<[f64; 2]>,
    /// The cell's volume ∫ dV.
    volume: f64,
}

/// A tensor of the (r, θ, z) entries [rr, rz, zr, zz, θθ] in the VTK frame (x, y, z) = (r, z, θ).
fn in_vtk_frame(e: &[f64; 5]) -> Matrix3<f64> {
    Matrix3::new(e[0], e[1], 0.0, e[2], e[3], 0.0, 0.0, 0.0, e[4])
}

/// Per cell, the volume-weighted means over its quadrature points (see [`CellMeans`]).
fn cell_means<M: AxisymmetricMaterial + ?Sized>(
    n_cells: usize,
    material: &M,
    qps: &[QuadraturePoint],
) -> FemResult<Vec<CellMeans>> {
    let mut cells = vec![CellMeans::default(); n_cells];
    for q in qps {
        let at = [q.r, q.z];
        let (gamma, lf) = material.point_fields_at(&q.f, at)?;
        let j = jacobian(&q.f);
        // P = ∂Ψ/∂F − p ∂J/∂F on the five entries, then σ = P Fᵀ / J.
        let p5 = material.stress_at(&q.f, at)? - jacobian_gradient(&q.f) * q.pressure;
        let nominal = in_vtk_frame(&[p5[0], p5[1], p5[2], p5[3], p5[4]]);
        let f = in_vtk_frame(&[q.f[0], q.f[1], q.f[2], q.f[3], q.f[4]]);
        let cauchy = nominal * f.transpose() / j;
        let c = &mut cells[q.element];
        for (sum, v) in c.scalars.iter_mut().zip([j, gamma, lf, p5[3]]) {
            *sum += v * q.dv;
        }
        // Row-major: nalgebra stores column-major, so index (row, column) explicitly.
        for k in 0..9 {
            c.nominal[k] += nominal[(k / 3, k % 3)] * q.dv;
            c.cauchy[k] += cauchy[(k / 3, k % 3)] * q.dv;
        }
        c.hydrostatic -= cauchy.trace() / 3.0 * q.dv;
        if let Some((d, a)) = material.damage_activation_at(at) {
            let r = c.regional.get_or_insert([0.0; 2]);
            r[0] += d * q.dv;
            r[1] += a * q.dv;
        }
        c.volume += q.dv;
    }
    for c in &mut cells {
        let v = c.volume;
        c.scalars.iter_mut().for_each(|x| *x /= v);
        c.nominal.iter_mut().for_each(|x| *x /= v);
        c.cauchy.iter_mut().for_each(|x| *x /= v);
        c.hydrostatic /= v;
        if let Some(r) = &mut c.regional {
            r.iter_mut().for_each(|x| *x /= v);
        }
    }
    Ok(cells)
}

/// The pressure at every node (see the module's list); `cells` from [`cell_means`].
fn nodal_pressure(mesh: &Mesh, dofs: &DofMap, cells: &[CellMeans], x: &[f64]) -> Vec<f64> {
    let element = mesh.element;
    let nu = 2 * element.nodes();
    let mut pressure = vec![0.0f64; mesh.n_nodes()];
    let mut weight = vec![0.0f64; mesh.n_nodes()];
    let mut cell_p = vec![0.0f64; element.pressures()];
    let mut at_nodes = vec![0.0f64; element.nodes()];
    for (e, conn) in mesh.elements().enumerate() {
        for (p, &g) in cell_p.iter_mut().zip(&dofs.cell_dofs(e)[nu..]) {
            *p = x[g as usize];
        }
        element.nodal_pressures(&cell_p, &mut at_nodes);
        for (&a, &v) in conn.iter().zip(&at_nodes) {
            match element.pressure_layout() {
                // A continuous field: its value at the node.
                PressureLayout::AtCorners => pressure[a as usize] = v,
                // The cell's own pressure, volume-averaged over the cells around each node.
                PressureLayout::PerCell => {
                    pressure[a as usize] += v * cells[e].volume;
                    weight[a as usize] += cells[e].volume;
                }
            }
        }
    }
    for (p, w) in pressure.iter_mut().zip(&weight) {
        if *w > 0.0 {
            *p /= w;
        }
    }
    pressure
}

/// An error (nothing written) if any value of `field` is not finite, naming the field and where.
fn refuse_non_finite(
    field: &str,
    values: impl Iterator<Item = f64>,
    at: &str,
) -> std::io::Result<()> {
    for (i, v) in values.enumerate() {
        if !v.is_finite() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!("refusing to write non-finite {field} ({v}) at {at} {i}"),
            ));
        }
    }
    Ok(())
}

/// VTK cell type of the 9-node biquadratic quadrilateral.
const VTK_BIQUADRATIC_QUAD: u8 = 28;
/// VTK cell type of the 4-node bilinear quadrilateral.
const VTK_QUAD: u8 = 9;

/// A field of the cells beyond J, γ, λ_f and P_zz.
#[derive(Debug, Clone, Copy)]
pub enum CellField<'a> {
    /// A value per cell, e.g. the damage of a material varying in space.
    Scalar(&'a str, &'a [f64]),
    /// A 3 × 3 tensor per cell in the VTK frame (x, y, z) = (r, z, θ), row-major.
    Tensor(&'a str, &'a [[f64; 9]]),
}

impl CellField<'_> {
    fn name(&self) -> &str {
        match self {
            CellField::Scalar(n, _) | CellField::Tensor(n, _) => n,
        }
    }

    /// Every value, cell by cell (a tensor's nine in a row).
    fn values(&self) -> Box<dyn Iterator<Item = f64> + '_> {
        match self {
            CellField::Scalar(_, v) => Box::new(v.iter().copied()),
            CellField::Tensor(_, v) => Box::new(v.iter().flatten().copied()),
        }
    }
}

/// The names of a tensor's components in the VTK frame (x, y, z) = (r, z, θ), row-major.
const TENSOR_COMPONENTS: [&str; 9] = [
    "rr",
    "rz",
    "rtheta",
    "zr",
    "zz",
    "ztheta",
    "thetar",
    "thetaz",
    "thetatheta",
];

/// What the file holds and where, for a reader who opens it as text.
const LEGEND: &str = "<!-- activemuscle: the meridian section of the axisymmetric cylinder in the \
    (x, y) = (r, z) plane. At the nodes: u (u_r, u_z, 0) and p, the pressure (Lagrange multiplier \
    of J = 1). Per cell, the volume-weighted mean over the cell's quadrature points: J, gamma, \
    fibre_stretch, P_zz, nominal_stress (first Piola-Kirchhoff, P = dPsi/dF - p J F^-T), \
    cauchy_stress (sigma = P F^T / J) and hydrostatic_pressure (-tr sigma / 3). Tensors: 9 \
    components, row-major, in the frame (x, y, z) = (r, z, theta). -->";

/// Writes the mesh in the (x, y) = (r, z) plane (9-node cells as VTK_BIQUADRATIC_QUAD, 4-node
/// cells as VTK_QUAD) with point data `u` (as a 3-vector) and `p`, and cell data J, γ, λ_f,
/// P_zz from `cells` (one [J, γ, λ_f, P_zz] per element).
pub fn write_vtu(
    path: &Path,
    mesh: &Mesh,
    u: &[[f64; 2]],
    p: &[f64],
    cells: &[[f64; 4]],
) -> std::io::Result<()> {
    write_vtu_with(path, mesh, u, p, cells, &[])
}

/// [`write_vtu`] with further cell fields `extra` (scalars or tensors, one per cell each).
/// Nothing is written if a value is not finite.
pub fn write_vtu_with(
    path: &Path,
    mesh: &Mesh,
    u: &[[f64; 2]],
    p: &[f64],
    cells: &[[f64; 4]],
    extra: &[CellField],
) -> std::io::Result<()> {
    refuse_non_finite("u_r", u.iter().map(|v| v[0]), "node")?;
    refuse_non_finite("u_z", u.iter().map(|v| v[1]), "node")?;
    refuse_non_finite("p", p.iter().copied(), "node")?;
    for (k, name) in ["J", "gamma", "fibre_stretch", "P_zz"].iter().enumerate() {
        refuse_non_finite(name, cells.iter().map(|c| c[k]), "cell")?;
    }
    for field in extra {
        refuse_non_finite(field.name(), field.values(), "value")?;
    }
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    let (nn, ne) = (mesh.nodes.len(), mesh.n_elements());
    writeln!(w, r#"<?xml version="1.0"?>"#)?;
    writeln!(w, "{LEGEND}")?;
    writeln!(
        w,
        r#"<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">"#
    )?;
    writeln!(w, "<UnstructuredGrid>")?;
    writeln!(w, r#"<Piece NumberOfPoints="{nn}" NumberOfCells="{ne}">"#)?;
    write_geometry(&mut w, mesh)?;
    writeln!(w, r#"<PointData Vectors="u" Scalars="p">"#)?;
    writeln!(
        w,
        r#"<DataArray type="Float64" Name="u" NumberOfComponents="3" format="ascii">"#
    )?;
    for v in u {
        writeln!(w, "{:e} {:e} 0", v[0], v[1])?;
    }
    writeln!(w, "</DataArray>")?;
    write_scalars(&mut w, "p", p.iter().copied())?;
    writeln!(w, "</PointData>")?;
    writeln!(w, "<CellData>")?;
    for (k, name) in ["J", "gamma", "fibre_stretch", "P_zz"].iter().enumerate() {
        write_scalars(&mut w, name, cells.iter().map(|c| c[k]))?;
    }
    for field in extra {
        match field {
            CellField::Scalar(name, values) => write_scalars(&mut w, name, values.iter().copied())?,
            CellField::Tensor(name, values) => write_tensors(&mut w, name, values)?,
        }
    }
    writeln!(w, "</CellData>")?;
    writeln!(w, "</Piece>")?;
    writeln!(w, "</UnstructuredGrid>")?;
    writeln!(w, "</VTKFile>")?;
    w.flush()
}

/// A `<DataArray>` of one value per point or cell.
fn write_scalars(
    w: &mut impl Write,
    name: &str,
    values: impl Iterator<Item = f64>,
) -> std::io::Result<()> {
    writeln!(
        w,
        r#"<DataArray type="Float64" Name="{name}" format="ascii">"#
    )?;
    for v in values {
        writeln!(w, "{v:e}")?;
    }
    writeln!(w, "</DataArray>")
}

/// A `<DataArray>` of a 3 × 3 tensor per cell, its components named ([`TENSOR_COMPONENTS`]).
fn write_tensors(w: &mut impl Write, name: &str, values: &[[f64; 9]]) -> std::io::Result<()> {
    write!(
        w,
        r#"<DataArray type="Float64" Name="{name}" NumberOfComponents="9""#
    )?;
    for (i, c) in TENSOR_COMPONENTS.iter().enumerate() {
        write!(w, r#" ComponentName{i}="{c}""#)?;
    }
    writeln!(w, r#" format="ascii">"#)?;
    for t in values {
        let row: Vec<String> = t.iter().map(|v| format!("{v:e}")).collect();
        writeln!(w, "{}", row.join(" "))?;
    }
    writeln!(w, "</DataArray>")
}

/// The `<Points>` and `<Cells>` sections of `mesh`.
fn write_geometry(w: &mut impl Write, mesh: &Mesh) -> std::io::Result<()> {
    let ne = mesh.n_elements();
    let cell_type = match mesh.element.node_layout() {
        NodeLayout::Biquadratic => VTK_BIQUADRATIC_QUAD,
        NodeLayout::Corners => VTK_QUAD,
    };
    writeln!(
        w,
        r#"<Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">"#
    )?;
    for x in &mesh.nodes {
        writeln!(w, "{:e} {:e} 0", x[0], x[1])?;
    }
    writeln!(w, "</DataArray></Points>")?;
    writeln!(w, "<Cells>")?;
    writeln!(
        w,
        r#"<DataArray type="Int64" Name="connectivity" format="ascii">"#
    )?;
    for e in mesh.elements() {
        let s: Vec<String> = e.iter().map(|a| a.to_string()).collect();
        writeln!(w, "{}", s.join(" "))?;
    }
    writeln!(w, "</DataArray>")?;
    writeln!(
        w,
        r#"<DataArray type="Int64" Name="offsets" format="ascii">"#
    )?;
    for i in 0..ne {
        writeln!(w, "{}", mesh.element.nodes() * (i + 1))?;
    }
    writeln!(w, "</DataArray>")?;
    writeln!(w, r#"<DataArray type="UInt8" Name="types" format="ascii">"#)?;
    for _ in 0..ne {
        writeln!(w, "{cell_type}")?;
    }
    writeln!(w, "</DataArray>")?;
    writeln!(w, "</Cells>")
}
