//! Meshes of the half meridian plane [0, R] × [0, L] in (r, z).
//!
//! A [`Mesh`] is stored the way an unstructured mesh would be: node coordinates, 9-node
//! element connectivity (corners counter-clockwise, then edge mid-nodes, then the centre, the
//! VTK_BIQUADRATIC_QUAD order) and boundary node sets by tag. Nothing downstream uses the
//! structured indexing of [`Mesh::structured`].

use super::error::{FemError, FemResult};

/// Boundary parts of the meridian rectangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Boundary {
    /// The symmetry axis r = 0.
    Axis,
    /// The fixed base z = 0.
    Bottom,
    /// The moving base z = L.
    Top,
    /// The lateral surface r = R (traction free).
    Lateral,
}

/// An unstructured 9-node quadrilateral mesh of the meridian plane.
#[derive(Debug, Clone)]
pub struct Mesh {
    /// Node coordinates (r, z).
    pub nodes: Vec<[f64; 2]>,
    /// Element connectivity: 4 corners counter-clockwise, 4 edge mid-nodes (edge 0–1, 1–2, 2–3, 3–0), centre.
    pub elements: Vec<[u32; 9]>,
    /// Boundary node sets: (tag, sorted node indices).
    pub boundaries: Vec<(Boundary, Vec<u32>)>,
    /// Cylinder radius R.
    pub radius: f64,
    /// Cylinder length L.
    pub length: f64,
}

fn positive(name: &'static str, v: f64) -> FemResult<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(FemError::InvalidInput {
            name,
            value: v.to_string(),
            rule: "must be finite and > 0",
        })
    }
}

/// Cell boundaries in z: uniform if `grading == 1`, otherwise geometric, refined symmetrically
/// towards both bases, with (middle cell height) / (base cell height) = `grading`.
fn z_breaks(length: f64, nz: usize, grading: f64) -> Vec<f64> {
    let half = nz.div_ceil(2);
    let q = if half > 1 {
        grading.powf(1.0 / (half - 1) as f64)
    } else {
        1.0
    };
    let heights: Vec<f64> = (0..nz)
        .map(|i| {
            let k = i.min(nz - 1 - i);
            q.powi(k as i32)
        })
        .collect();
    let total: f64 = heights.iter().sum();
    let mut z = Vec::with_capacity(nz + 1);
    let mut acc = 0.0;
    z.push(0.0);
    for h in &heights {
        acc += h;
        z.push(length * acc / total);
    }
    z[nz] = length;
    z
}

impl Mesh {
    /// Structured nr × nz mesh of [0, R] × [0, L] (uniform in r; in z uniform if `grading == 1`,
    /// otherwise geometrically refined towards both bases with middle/base cell-height ratio `grading` ≥ 1).
    pub fn structured(
        radius: f64,
        length: f64,
        nr: usize,
        nz: usize,
        grading: f64,
    ) -> FemResult<Self> {
        positive("radius", radius)?;
        positive("length", length)?;
        if nr == 0 || nz == 0 {
            return Err(FemError::InvalidInput {
                name: "nr, nz",
                value: format!("{nr} × {nz}"),
                rule: "need at least one cell in each direction",
            });
        }
        if !(grading.is_finite() && grading >= 1.0) {
            return Err(FemError::InvalidInput {
                name: "grading",
                value: grading.to_string(),
                rule: "must be finite and ≥ 1",
            });
        }
        let (mr, mz) = (2 * nr + 1, 2 * nz + 1);
        if mr.checked_mul(mz).is_none_or(|n| n > u32::MAX as usize / 4) {
            return Err(FemError::InvalidInput {
                name: "nr, nz",
                value: format!("{nr} × {nz}"),
                rule: "mesh too large for 32-bit indices",
            });
        }
        let zc = z_breaks(length, nz, grading);
        let mut znodes = Vec::with_capacity(mz);
        for j in 0..nz {
            znodes.push(zc[j]);
            znodes.push(0.5 * (zc[j] + zc[j + 1]));
        }
        znodes.push(length);
        let id = |i: usize, j: usize| (j * mr + i) as u32;
        let mut nodes = Vec::with_capacity(mr * mz);
        for &z in &znodes {
            for i in 0..mr {
                let r = if i == mr - 1 {
                    radius
                } else {
                    radius * i as f64 / (mr - 1) as f64
                };
                nodes.push([r, z]);
            }
        }
        let mut elements = Vec::with_capacity(nr * nz);
        for cj in 0..nz {
            for ci in 0..nr {
                let (i, j) = (2 * ci, 2 * cj);
                elements.push([
                    id(i, j),
                    id(i + 2, j),
                    id(i + 2, j + 2),
                    id(i, j + 2),
                    id(i + 1, j),
                    id(i + 2, j + 1),
                    id(i + 1, j + 2),
                    id(i, j + 1),
                    id(i + 1, j + 1),
                ]);
            }
        }
        let axis = (0..mz).map(|j| id(0, j)).collect();
        let lateral = (0..mz).map(|j| id(mr - 1, j)).collect();
        let bottom = (0..mr).map(|i| id(i, 0)).collect();
        let top = (0..mr).map(|i| id(i, mz - 1)).collect();
        Ok(Self {
            nodes,
            elements,
            boundaries: vec![
                (Boundary::Axis, axis),
                (Boundary::Bottom, bottom),
                (Boundary::Top, top),
                (Boundary::Lateral, lateral),
            ],
            radius,
            length,
        })
    }

    /// The node set of a boundary part (empty if the mesh has none).
    pub fn boundary(&self, tag: Boundary) -> &[u32] {
        self.boundaries
            .iter()
            .find(|(t, _)| *t == tag)
            .map(|(_, v)| v.as_slice())
            .unwrap_or(&[])
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.nodes.len()
    }
}
