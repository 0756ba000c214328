//! Degrees of freedom and Dirichlet conditions.
//!
//! Global numbering: free displacement dofs `[0, n_free_u)`, free pressure dofs
//! `[n_free_u, n_free)` (one per corner node for Q2/Q1, one per cell for Q1/P0, following the
//! [`PressureLayout`] of the mesh's [`Element`]), prescribed dofs `[n_free, n_total)`. Prescribed dofs never enter the
//! linear system (they are eliminated, not penalised); their values are x_c = (λ − 1) d_c, with
//! d_c = L for u_z on z = L and 0 otherwise.

use super::element::{Element, PressureLayout};
use super::mesh::{Boundary, Mesh};

/// Which displacement components the bases hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bases {
    /// u_r free on both bases: the exact solution is homogeneous uniaxial stretch.
    Sliding,
    /// u_r = 0 on both bases.
    Clamped,
}

/// The dof numbering of a mesh with its boundary conditions.
#[derive(Debug, Clone)]
pub struct DofMap {
    /// Global dof of (u_r, u_z) at each node.
    pub node_u: Vec<[u32; 2]>,
    /// Global pressure dof at each node (`u32::MAX` at nodes without one; all of them for Q1/P0).
    pub node_p: Vec<u32>,
    /// Global pressure dofs of each cell, [`Element::pressures`] per cell
    /// ([`PressureLayout::PerCell`], e.g. Q1/P0; empty for Q2/Q1).
    pub element_p: Vec<u32>,
    /// The element the numbering is for.
    pub element: Element,
    /// Global dofs of every cell in local order, [`Self::dofs_per_element`] per cell.
    pub element_dofs: Vec<u32>,
    /// Number of free displacement dofs.
    pub n_free_u: usize,
    /// Number of free dofs (displacement and pressure).
    pub n_free: usize,
    /// Number of dofs.
    pub n_total: usize,
    /// dx/dλ on the prescribed dofs (index `k` ↔ global dof `n_free + k`).
    pub prescribed_rate: Vec<f64>,
    /// Global dofs of u_z on the moving base z = L (for the reaction).
    pub top_axial: Vec<u32>,
}

/// Which displacement components of every node are held, and their rate d x_c/dλ (L for u_z on
/// z = L).
fn constraints(mesh: &Mesh, bases: Bases) -> (Vec<[bool; 2]>, Vec<[f64; 2]>) {
    let nn = mesh.n_nodes();
    let mut fixed = vec![[false; 2]; nn];
    let mut rate = vec![[0.0f64; 2]; nn];
    for &a in mesh.boundary(Boundary::Axis) {
        fixed[a as usize][0] = true;
    }
    for &a in mesh.boundary(Boundary::Bottom) {
        fixed[a as usize][1] = true;
        if bases == Bases::Clamped {
            fixed[a as usize][0] = true;
        }
    }
    for &a in mesh.boundary(Boundary::Top) {
        fixed[a as usize][1] = true;
        rate[a as usize][1] = mesh.length;
        if bases == Bases::Clamped {
            fixed[a as usize][0] = true;
        }
    }
    (fixed, rate)
}

impl DofMap {
    /// Dofs per cell: 2 per node, then the cell's pressure dofs.
    pub fn dofs_per_element(&self) -> usize {
        2 * self.element.nodes() + self.element.pressures()
    }

    /// The global dofs of cell `e` in local order.
    pub fn cell_dofs(&self, e: usize) -> &[u32] {
        let n = self.dofs_per_element();
        &self.element_dofs[n * e..n * (e + 1)]
    }

    /// Numbers the dofs of `mesh` (for its [`Mesh::element`]) with the conditions of `bases`.
    pub fn new(mesh: &Mesh, bases: Bases) -> Self {
        let nn = mesh.n_nodes();
        let (fixed, rate) = constraints(mesh, bases);
        let element = mesh.element;
        let per_cell = element.pressure_layout() == PressureLayout::PerCell;
        let mut has_p = vec![false; nn];
        if !per_cell {
            for e in mesh.elements() {
                for &c in &e[..4] {
                    has_p[c as usize] = true;
                }
            }
        }
        let mut node_u = vec![[u32::MAX; 2]; nn];
        let mut node_p = vec![u32::MAX; nn];
        let mut next = 0u32;
        for a in 0..nn {
            for c in 0..2 {
                if !fixed[a][c] {
                    node_u[a][c] = next;
                    next += 1;
                }
            }
        }
        let n_free_u = next as usize;
        for a in 0..nn {
            if has_p[a] {
                node_p[a] = next;
                next += 1;
            }
        }
        let mut element_p = Vec::new();
        if per_cell {
            let n = (mesh.n_elements() * element.pressures()) as u32;
            element_p = (0..n).map(|k| next + k).collect();
            next += n;
        }
        let n_free = next as usize;
        let mut prescribed_rate = Vec::new();
        let mut top_axial = Vec::new();
        for a in 0..nn {
            for c in 0..2 {
                if fixed[a][c] {
                    node_u[a][c] = next;
                    next += 1;
                    prescribed_rate.push(rate[a][c]);
                    if c == 1 && rate[a][c] != 0.0 {
                        top_axial.push(node_u[a][c]);
                    }
                }
            }
        }
        let mut element_dofs =
            Vec::with_capacity(mesh.n_elements() * (2 * element.nodes() + element.pressures()));
        for (e, cell) in mesh.elements().enumerate() {
            for &node in cell {
                element_dofs.extend_from_slice(&node_u[node as usize]);
            }
            if per_cell {
                let np = element.pressures();
                element_dofs.extend_from_slice(&element_p[np * e..np * (e + 1)]);
            } else {
                element_dofs.extend(cell[..4].iter().map(|&c| node_p[c as usize]));
            }
        }
        Self {
            node_u,
            node_p,
            element_p,
            element,
            element_dofs,
            n_free_u,
            n_free,
            n_total: next as usize,
            prescribed_rate,
            top_axial,
        }
    }

    /// Sets the prescribed dofs of `x` for the stretch λ.
    pub fn apply_stretch(&self, x: &mut [f64], stretch: f64) {
        for (xc, d) in x[self.n_free..].iter_mut().zip(&self.prescribed_rate) {
            *xc = (stretch - 1.0) * d;
        }
    }
}
