//! Q1/P0: bilinear displacement on the 4 corners ([`NodeLayout::Corners`]), one constant
//! pressure per cell ([`PressureLayout::PerCell`]), 2 × 2 Gauss.
//!
//! N_a(ξ, η) = ℓ_i(ξ) ℓ_j(η) with the linear Lagrange functions ℓ of the ends −1, 1 and (i, j)
//! the corner's ends; M = 1 on the cell.

use super::reference::{lagrange1, ReferenceElement, LATTICE};
use super::{MixedElement, NodeLayout, PressureLayout};

/// Q1/P0: 4 nodes, 1 cell pressure, 2 × 2 Gauss.
pub type Q1P0Reference = ReferenceElement<4, 8, 1, 9, 4>;

impl MixedElement for Q1P0Reference {
    const NAME: &'static str = "Q1/P0";
    const NODE_LAYOUT: NodeLayout = NodeLayout::Corners;
    const PRESSURE_LAYOUT: PressureLayout = PressureLayout::PerCell;
    const CONDENSED_NODE: Option<usize> = None;

    /// Tabulates Q1 shape functions (corners counter-clockwise from (−1, −1)) and the constant
    /// pressure at the 2 × 2 Gauss points.
    fn new() -> Self {
        let g = 1.0 / 3.0f64.sqrt();
        Self::tabulate(
            &[-g, g],
            &[1.0, 1.0],
            |xi, eta| {
                let mut n = [0.0; 4];
                let mut dn = [[0.0; 2]; 4];
                for (a, &(i, j)) in LATTICE[..4].iter().enumerate() {
                    let (si, sj) = (i / 2, j / 2);
                    let (sx, sy) = (
                        if si == 0 { -0.5 } else { 0.5 },
                        if sj == 0 { -0.5 } else { 0.5 },
                    );
                    n[a] = lagrange1(xi, si) * lagrange1(eta, sj);
                    dn[a] = [sx * lagrange1(eta, sj), lagrange1(xi, si) * sy];
                }
                (n, dn)
            },
            |_, _| [1.0],
        )
    }

    /// The cell's pressure at each of its corners.
    fn nodal_pressures(p: &[f64], at_nodes: &mut [f64]) {
        at_nodes.fill(p[0]);
    }
}
