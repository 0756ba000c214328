//! VTK XML unstructured-grid (`.vtu`, ASCII) writer for ParaView.

use super::element::Element;
use super::mesh::Mesh;
use std::io::Write;

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
    path: &std::path::Path,
    mesh: &Mesh,
    u: &[[f64; 2]],
    p: &[f64],
    cells: &[[f64; 4]],
) -> std::io::Result<()> {
    refuse_non_finite("u_r", u.iter().map(|v| v[0]), "node")?;
    refuse_non_finite("u_z", u.iter().map(|v| v[1]), "node")?;
    refuse_non_finite("p", p.iter().copied(), "node")?;
    for (k, name) in ["J", "gamma", "fibre_stretch", "P_zz"].iter().enumerate() {
        refuse_non_finite(name, cells.iter().map(|c| c[k]), "cell")?;
    }
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    let (nn, ne) = (mesh.nodes.len(), mesh.n_elements());
    let cell_type = match mesh.element {
        Element::Q2Q1 => VTK_BIQUADRATIC_QUAD,
        Element::Q1P0 => VTK_QUAD,
    };
    writeln!(w, r#"<?xml version="1.0"?>"#)?;
    writeln!(
        w,
        r#"<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">"#
    )?;
    writeln!(w, "<UnstructuredGrid>")?;
    writeln!(w, r#"<Piece NumberOfPoints="{nn}" NumberOfCells="{ne}">"#)?;
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
    writeln!(w, "</Cells>")?;
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
    writeln!(w, "</CellData>")?;
    writeln!(w, "</Piece>")?;
    writeln!(w, "</UnstructuredGrid>")?;
    writeln!(w, "</VTKFile>")?;
    w.flush()
}
