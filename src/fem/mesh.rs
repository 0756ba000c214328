//! Meshes of the half meridian plane [0, R] × [0, L] in (r, z).
//!
//! A [`Mesh`] is stored the way an unstructured mesh would be: node coordinates, the
//! [`Element`] its cells are made for, flat connectivity and boundary node sets by tag. A
//! Q2/Q1 cell has 9 nodes (corners counter-clockwise, then edge mid-nodes, then the centre, the
//! VTK_BIQUADRATIC_QUAD order), a Q1/P0 cell its 4 corners (VTK_QUAD order). Nothing downstream
//! uses the structured indexing of [`Mesh::structured`]; [`Mesh::with_element`] turns the cells of
//! one element into those of the other on the same geometry.

use super::element::{Element, NodeLayout, PressureLayout, ReferenceElement, References, Visit};
use super::error::{FemError, FemResult};
use super::linear_solver::LinearSolver;
use super::memory::{self, Counts, MemoryEstimate};
use std::collections::HashMap;

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

/// An unstructured quadrilateral mesh of the meridian plane.
#[derive(Debug, Clone)]
pub struct Mesh {
    /// Node coordinates (r, z).
    pub nodes: Vec<[f64; 2]>,
    /// The element the cells are made for; it fixes the nodes per cell ([`Element::nodes`]).
    pub element: Element,
    /// Cell connectivity, [`Element::nodes`] entries per cell: 4 corners counter-clockwise, then
    /// (9-node cells only) 4 edge mid-nodes (edge 0–1, 1–2, 2–3, 3–0) and the centre.
    pub connectivity: Vec<u32>,
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
            value: crate::text::shortest(v),
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

/// The nodes of the Q2 lattice: `mr` per row, uniform in r on [0, R]; rows at the cell
/// boundaries `zc` and their midpoints.
fn lattice(radius: f64, zc: &[f64], mr: usize) -> Vec<[f64; 2]> {
    let nz = zc.len() - 1;
    let mut znodes = Vec::with_capacity(2 * nz + 1);
    for j in 0..nz {
        znodes.push(zc[j]);
        znodes.push(0.5 * (zc[j] + zc[j + 1]));
    }
    znodes.push(zc[nz]);
    let mut nodes = Vec::with_capacity(mr * znodes.len());
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
    nodes
}

impl Mesh {
    /// Structured nr × nz mesh of [0, R] × [0, L] with 9-node (Q2/Q1) cells (uniform in r; in z
    /// uniform if `grading == 1`, otherwise geometrically refined towards both bases with
    /// middle/base cell-height ratio `grading` ≥ 1). For Q1/P0 cells on the same cells, see
    /// [`Mesh::with_element`]. A mesh on which even the cheapest solve (Q1/P0 on its cells) would
    /// exceed the default memory limit ([`memory::default_limit`]) is refused with
    /// [`FemError::MemoryLimit`] from its counts, before anything is allocated.
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
                value: crate::text::shortest(grading),
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
        let estimate_with =
            |e| MemoryEstimate::structured(nr, nz, e, LinearSolver::SymmetricPartGmres);
        let cheapest = Element::ALL.into_iter().fold(Element::default(), |a, b| {
            if estimate_with(b).bytes < estimate_with(a).bytes {
                b
            } else {
                a
            }
        });
        let mut estimate = estimate_with(cheapest);
        estimate.mesh = format!("{nr} × {nz} cells with the cheapest element, {cheapest}");
        estimate.check(memory::default_limit())?;
        let nodes = lattice(radius, &z_breaks(length, nz, grading), mr);
        let id = |i: usize, j: usize| (j * mr + i) as u32;
        let mut connectivity = Vec::with_capacity(9 * nr * nz);
        for cj in 0..nz {
            for ci in 0..nr {
                let (i, j) = (2 * ci, 2 * cj);
                connectivity.extend_from_slice(&[
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
            element: Element::Q2Q1,
            connectivity,
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

    /// The same cells for `element`: a 9-node mesh keeps only its corners (renumbered in their
    /// order) for a 4-node element such as Q1/P0; a 4-node mesh gains straight-edge mid-nodes and
    /// centres for a 9-node one such as Q2/Q1 (numbered after the corners). Boundary sets follow
    /// (a new mid-node lies on a part when both ends of its edge do). The same nodes if the
    /// element's [`NodeLayout`] is the mesh's.
    pub fn with_element(self, element: Element) -> Self {
        match (self.element.node_layout(), element.node_layout()) {
            (NodeLayout::Biquadratic, NodeLayout::Corners) => self.corners(element),
            (NodeLayout::Corners, NodeLayout::Biquadratic) => self.biquadratic(element),
            _ => Self { element, ..self },
        }
    }

    /// The corners of the cells, as the cells of `element`.
    fn corners(self, element: Element) -> Self {
        let mut new_id = vec![u32::MAX; self.nodes.len()];
        for e in self.elements() {
            for &a in &e[..4] {
                new_id[a as usize] = 0;
            }
        }
        // Number the corners in their old order (keeps a structured numbering structured).
        let mut next = 0u32;
        let mut nodes = Vec::new();
        for (a, id) in new_id.iter_mut().enumerate() {
            if *id != u32::MAX {
                *id = next;
                next += 1;
                nodes.push(self.nodes[a]);
            }
        }
        let mut connectivity = Vec::with_capacity(4 * self.n_elements());
        for e in self.elements() {
            connectivity.extend(e[..4].iter().map(|&a| new_id[a as usize]));
        }
        let boundaries = self
            .boundaries
            .iter()
            .map(|(tag, set)| {
                let kept = set
                    .iter()
                    .map(|&a| new_id[a as usize])
                    .filter(|&a| a != u32::MAX)
                    .collect();
                (*tag, kept)
            })
            .collect();
        Self {
            nodes,
            element,
            connectivity,
            boundaries,
            radius: self.radius,
            length: self.length,
        }
    }

    /// The cells with mid-nodes on their (straight) edges and centres, as the cells of `element`.
    fn biquadratic(self, element: Element) -> Self {
        let mut nodes = self.nodes.clone();
        let mut edge_node: HashMap<(u32, u32), u32> = HashMap::new();
        let mut connectivity = Vec::with_capacity(9 * self.n_elements());
        let mut new_boundaries = self.boundaries.clone();
        let on = |set: &[u32], a: u32| set.binary_search(&a).is_ok();
        for e in self.elements() {
            let c = [e[0], e[1], e[2], e[3]];
            let mut cell = [0u32; 9];
            cell[..4].copy_from_slice(&c);
            for k in 0..4 {
                let (a, b) = (c[k], c[(k + 1) % 4]);
                let key = (a.min(b), a.max(b));
                cell[4 + k] = *edge_node.entry(key).or_insert_with(|| {
                    let id = nodes.len() as u32;
                    let (xa, xb) = (nodes[a as usize], nodes[b as usize]);
                    nodes.push([0.5 * (xa[0] + xb[0]), 0.5 * (xa[1] + xb[1])]);
                    for ((_, old), (_, new)) in
                        self.boundaries.iter().zip(new_boundaries.iter_mut())
                    {
                        if on(old, a) && on(old, b) {
                            new.push(id);
                        }
                    }
                    id
                });
            }
            let centre = c.iter().fold([0.0, 0.0], |s, &a| {
                let x = nodes[a as usize];
                [s[0] + 0.25 * x[0], s[1] + 0.25 * x[1]]
            });
            cell[8] = nodes.len() as u32;
            nodes.push(centre);
            connectivity.extend_from_slice(&cell);
        }
        for (_, set) in new_boundaries.iter_mut() {
            set.sort_unstable();
        }
        Self {
            nodes,
            element,
            connectivity,
            boundaries: new_boundaries,
            radius: self.radius,
            length: self.length,
        }
    }

    /// The memory a solve on this mesh (with its element's cells) needs, estimated from its
    /// counts ([`MemoryEstimate`]) before anything large is allocated.
    pub fn memory_estimate(&self, linear: LinearSolver) -> MemoryEstimate {
        let element = self.element;
        let cells = self.n_elements();
        let pressures = match element.pressure_layout() {
            PressureLayout::AtCorners => {
                let mut corner = vec![false; self.n_nodes()];
                for e in self.elements() {
                    for &a in &e[..4] {
                        corner[a as usize] = true;
                    }
                }
                corner.iter().filter(|&&c| c).count()
            }
            PressureLayout::PerCell => element.pressures() * cells,
        };
        let counts = Counts {
            nodes: self.n_nodes() as f64,
            cells: cells as f64,
            pressures: pressures as f64,
            element,
        };
        MemoryEstimate::of_counts(counts, &format!("{cells} {element} cells"), linear)
    }

    /// The cells, each as its [`Element::nodes`] node indices.
    pub fn elements(&self) -> std::slice::ChunksExact<'_, u32> {
        self.connectivity.chunks_exact(self.element.nodes())
    }

    /// The reference positions (r, z) of every quadrature point, cell by cell: where the
    /// assembly evaluates the material (a region that holds none of them has no effect). Cells
    /// with a node index out of range are left out (the assembly refuses them).
    pub fn quadrature_positions(&self) -> Vec<[f64; 2]> {
        self.element.reference().visit(QuadraturePositions(self))
    }

    /// Number of cells.
    pub fn n_elements(&self) -> usize {
        self.connectivity.len() / self.element.nodes()
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

/// The reference positions of every quadrature point of a mesh ([`Mesh::quadrature_positions`]).
struct QuadraturePositions<'a>(&'a Mesh);

impl Visit<References> for QuadraturePositions<'_> {
    type Output = Vec<[f64; 2]>;

    fn visit<
        const NN: usize,
        const NU: usize,
        const NP: usize,
        const ND: usize,
        const NQ: usize,
    >(
        self,
        re: &ReferenceElement<NN, NU, NP, ND, NQ>,
    ) -> Vec<[f64; 2]> {
        let mesh = self.0;
        mesh.elements()
            .filter_map(|conn| {
                let mut x = [[0.0; 2]; NN];
                for (xa, &node) in x.iter_mut().zip(conn) {
                    *xa = *mesh.nodes.get(node as usize)?;
                }
                Some(re.positions(&x))
            })
            .flatten()
            .collect()
    }
}
