//! The report's statement of how far J = det F is from 1 in the cylinder's solutions, and where.
//!
//! The mixed elements enforce J = 1 weakly: with Q2/Q1 (Taylor–Hood) J − 1 is orthogonal to
//! the continuous bilinear pressures, ∫ q (J − 1) dV = 0 for every such q, not 0 at every
//! point; with Q1/P0 the mean of J over each cell is 1. Clamped bases, which cannot widen,
//! concentrate J − 1 where a base meets the lateral surface; sliding bases deform homogeneously
//! and keep J = 1 to round-off. A nearly incompressible material's J − 1 is its own volume
//! change, not a discretisation error.

use super::{CylinderResult, Sweep, VolumeError};
use crate::studies::outputs::Of;
use crate::text::{escape_html as escape, significant};
use std::fmt::Write;

/// `(r, z)` in words: next to a base, at the lateral surface or on the axis, and the numbers.
fn place(at: [f64; 2], [radius, length]: [f64; 2]) -> String {
    let (r, z) = (at[0] / radius, at[1] / length);
    let axial = if z < 0.2 {
        "next to the base z = 0"
    } else if z > 0.8 {
        "next to the base z = L"
    } else {
        "away from the bases"
    };
    let radial = if r > 0.9 {
        ", at the lateral surface"
    } else if r < 0.1 {
        ", on the axis"
    } else {
        ""
    };
    format!(
        "{axial}{radial} (r/R = {}, z/L = {})",
        significant(r, 3),
        significant(z, 3)
    )
}

/// The largest of `of` over a sweep's stretches: the value, the stretch and the place.
fn worst(sweep: &Sweep, of: fn(&VolumeError) -> (f64, [f64; 2])) -> Option<(f64, f64, [f64; 2])> {
    sweep
        .points
        .iter()
        .zip(&sweep.volume)
        .map(|(p, v)| (of(v).0, p.lambda, of(v).1))
        .max_by(|a, b| a.0.total_cmp(&b.0))
}

/// |J − 1| in words: `2.8 %`, or `6.8e-15` below 0.01 %.
pub fn deviation(e: f64) -> String {
    if e >= 1e-4 {
        format!("{} %", significant(100.0 * e, 3))
    } else {
        format!("{e:.1e}")
    }
}

/// One cell of the table: `2.8 % at λ = 0.7, next to the base z = 0, at the lateral surface (…)`.
fn cell(w: Option<(f64, f64, [f64; 2])>, dimensions: [f64; 2]) -> String {
    w.map_or("–".into(), |(e, lambda, at)| {
        format!(
            "{} at λ = {}, {}",
            deviation(e),
            lambda,
            place(at, dimensions)
        )
    })
}

/// The section: per sweep, the largest |J − 1| at a quadrature point and of a cell's mean J (as
/// the VTK files show it), with the stretch and the place.
pub fn volume_note(h: &mut String, studies: &[Of<CylinderResult>]) {
    let mut rows = String::new();
    for s in studies {
        let c = s.result;
        for sweep in c.sweeps.iter().filter(|w| !w.points.is_empty()) {
            let _ = writeln!(
                rows,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                escape(s.name),
                escape(&sweep.label),
                cell(worst(sweep, |v| v.at_points), c.dimensions),
                cell(worst(sweep, |v| v.of_cells), c.dimensions),
            );
        }
    }
    if rows.is_empty() {
        return;
    }
    let nearly = studies.iter().any(|s| s.result.nearly_incompressible);
    let _ = writeln!(
        h,
        "<h2>How far J = det F is from 1</h2>\n<p>The mixed elements enforce J = 1 weakly: with \
         Q2/Q1 (Taylor–Hood) J − 1 is orthogonal to the continuous bilinear pressures on the \
         mesh, not 0 at every point; with Q1/P0 a cell's mean J is 1. Clamped bases, which cannot \
         widen, concentrate J − 1 where a base meets the lateral surface; sliding bases deform \
         homogeneously and keep J = 1 to round-off. The VTK files' <code>J</code> is a cell's \
         volume-weighted mean (last column); r and z are reference coordinates.{}</p>\n<table>\
         <tr><th>study</th><th>model</th><th>max |J − 1| at a quadrature point</th>\
         <th>max |J − 1| of a cell's mean J</th></tr>\n{rows}</table>",
        if nearly {
            " With a volumetric energy ([incompressibility]) J − 1 is also the material's own \
             volume change, not only a discretisation error."
        } else {
            ""
        }
    );
}
