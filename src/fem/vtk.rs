//! VTK XML unstructured-grid (`.vtu`, ASCII) output for ParaView: the fields of a solved
//! state ([`write_state`]) and the writer ([`write_vtu`]). The file of a stretch is named once,
//! by [`file_name`].

use super::assembly::QuadraturePoint;
use super::dofs::DofMap;
use super::element::{jacobian, jacobian_gradient, NodeLayout, PressureLayout};
use super::error::{FemError, FemResult};
use super::material::AxisymmetricMaterial;
use super::mesh::Mesh;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The file name of the fields at stretch λ: `lambda_<λ with 4 decimals>.vtu`.
pub fn file_name(stretch: f64) -> String {
    format!("lambda_{stretch:.4}.vtu")
}

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

/// Writes the state `x` (quadrature points `qps`) as a VTK unstructured grid in the (r, z)
/// plane: point data u (u_r, u_z, 0) and p (Q2/Q1: Q1-interpolated to all nodes; Q1/P0:
/// volume-weighted mean of the cell pressures around each node); cell data J, γ, λ_f, P_zz
/// (nominal, pressure included) as volume-weighted averages over the cell's quadrature points.
pub fn write_state<M: AxisymmetricMaterial + ?Sized>(
    path: &Path,
    mesh: &Mesh,
    dofs: &DofMap,
    material: &M,
    qps: &[QuadraturePoint],
    x: &[f64],
) -> FemResult<()> {
    let cell = cell_sums(mesh.n_elements(), material, qps)?;
    // A material varying in space: its damage and activation level, cell averages.
    let mut regional = vec![[0.0f64; 3]; mesh.n_elements()];
    let mut varying = false;
    for q in qps {
        if let Some((d, a)) = material.damage_activation_at([q.r, q.z]) {
            varying = true;
            let c = &mut regional[q.element];
            c[0] += d * q.dv;
            c[1] += a * q.dv;
            c[2] += q.dv;
        }
    }
    let damage: Vec<f64> = regional.iter().map(|c| c[0] / c[2]).collect();
    let activation: Vec<f64> = regional.iter().map(|c| c[1] / c[2]).collect();
    let extra: &[(&str, &[f64])] = if varying {
        &[("damage", &damage), ("activation", &activation)]
    } else {
        &[]
    };
    let pressure = nodal_pressure(mesh, dofs, &cell, x);
    let u: Vec<[f64; 2]> = dofs
        .node_u
        .iter()
        .map(|d| [x[d[0] as usize], x[d[1] as usize]])
        .collect();
    let cells: Vec<[f64; 4]> = cell
        .iter()
        .map(|c| [c[0] / c[4], c[1] / c[4], c[2] / c[4], c[3] / c[4]])
        .collect();
    write_vtu_with(path, mesh, &u, &pressure, &cells, extra).map_err(|source| FemError::Io {
        path: path.display().to_string(),
        source,
    })
}

/// Per cell: ∫ J, ∫ γ, ∫ λ_f, ∫ P_zz and the volume ∫ dV over its quadrature points.
fn cell_sums<M: AxisymmetricMaterial + ?Sized>(
    n_cells: usize,
    material: &M,
    qps: &[QuadraturePoint],
) -> FemResult<Vec<[f64; 5]>> {
    let mut cell = vec![[0.0f64; 5]; n_cells];
    for q in qps {
        let (gamma, lf) = material.point_fields_at(&q.f, [q.r, q.z])?;
        let pk = material.stress_at(&q.f, [q.r, q.z])?;
        let pzz = pk[3] - q.pressure * jacobian_gradient(&q.f)[3];
        let c = &mut cell[q.element];
        c[0] += jacobian(&q.f) * q.dv;
        c[1] += gamma * q.dv;
        c[2] += lf * q.dv;
        c[3] += pzz * q.dv;
        c[4] += q.dv;
    }
    Ok(cell)
}

/// The pressure at every node (see [`write_state`]); `cell` from [`cell_sums`].
fn nodal_pressure(mesh: &Mesh, dofs: &DofMap, cell: &[[f64; 5]], x: &[f64]) -> Vec<f64> {
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
                    pressure[a as usize] += v * cell[e][4];
                    weight[a as usize] += cell[e][4];
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

/// [`write_vtu`] with further named cell fields `extra` (one value per cell each), e.g. the
/// damage and activation level of a material varying in space.
pub fn write_vtu_with(
    path: &Path,
    mesh: &Mesh,
    u: &[[f64; 2]],
    p: &[f64],
    cells: &[[f64; 4]],
    extra: &[(&str, &[f64])],
) -> std::io::Result<()> {
    refuse_non_finite("u_r", u.iter().map(|v| v[0]), "node")?;
    refuse_non_finite("u_z", u.iter().map(|v| v[1]), "node")?;
    refuse_non_finite("p", p.iter().copied(), "node")?;
    for (k, name) in ["J", "gamma", "fibre_stretch", "P_zz"].iter().enumerate() {
        refuse_non_finite(name, cells.iter().map(|c| c[k]), "cell")?;
    }
    for (name, values) in extra {
        refuse_non_finite(name, values.iter().copied(), "cell")?;
    }
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    let (nn, ne) = (mesh.nodes.len(), mesh.n_elements());
    writeln!(w, r#"<?xml version="1.0"?>"#)?;
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
    writeln!(w, r#"<DataArray type="Float64" Name="p" format="ascii">"#)?;
    for v in p {
        writeln!(w, "{v:e}")?;
    }
    writeln!(w, "</DataArray>")?;
    writeln!(w, "</PointData>")?;
    writeln!(w, "<CellData>")?;
    for (k, name) in ["J", "gamma", "fibre_stretch", "P_zz"].iter().enumerate() {
        writeln!(
            w,
            r#"<DataArray type="Float64" Name="{name}" format="ascii">"#
        )?;
        for c in cells {
            writeln!(w, "{:e}", c[k])?;
        }
        writeln!(w, "</DataArray>")?;
    }
    for (name, values) in extra {
        writeln!(
            w,
            r#"<DataArray type="Float64" Name="{name}" format="ascii">"#
        )?;
        for v in *values {
            writeln!(w, "{v:e}")?;
        }
        writeln!(w, "</DataArray>")?;
    }
    writeln!(w, "</CellData>")?;
    writeln!(w, "</Piece>")?;
    writeln!(w, "</UnstructuredGrid>")?;
    writeln!(w, "</VTKFile>")?;
    w.flush()
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
