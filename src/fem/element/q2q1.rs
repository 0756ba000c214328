//! Taylor–Hood Q2/Q1: biquadratic displacement on the 9 nodes of the lattice
//! ([`NodeLayout::Biquadratic`]), continuous bilinear pressure on the 4 corners
//! ([`PressureLayout::AtCorners`]), 3 × 3 Gauss; the centre node is condensed out of the global system
//! ([`crate::fem::condensation`]).
//!
//! N_a(ξ, η) = ℓ_i(ξ) ℓ_j(η) with the quadratic Lagrange functions ℓ on {−1, 0, 1} and (i, j) the
//! node's place on the lattice; M_c(ξ, η) the bilinear functions of the corners.

use super::reference::{lagrange1, ReferenceElement, LATTICE};
use super::{MixedElement, NodeLayout, PressureLayout};

/// Taylor–Hood Q2/Q1: 9 nodes, 4 corner pressures, 3 × 3 Gauss.
pub type Q2Q1Reference = ReferenceElement<9, 18, 4, 22, 9>;

/// The 1D quadratic Lagrange functions of the nodes −1, 0, 1 at x, and their derivatives.
fn lagrange2(x: f64) -> ([f64; 3], [f64; 3]) {
    (
        [0.5 * x * (x - 1.0), 1.0 - x * x, 0.5 * x * (x + 1.0)],
        [x - 0.5, -2.0 * x, x + 0.5],
    )
}

impl MixedElement for Q2Q1Reference {
    const NAME: &'static str = "Q2/Q1";
    const NODE_LAYOUT: NodeLayout = NodeLayout::Biquadratic;
    const PRESSURE_LAYOUT: PressureLayout = PressureLayout::AtCorners;
    /// The centre: it couples to its own cell only.
    const CONDENSED_NODE: Option<usize> = Some(8);

    /// Tabulates Q2 and Q1 shape functions at the 3 × 3 Gauss points.
    fn new() -> Self {
        let g = (0.6f64).sqrt();
        Self::tabulate(
            &[-g, 0.0, g],
            &[5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0],
            |xi, eta| {
                let (lx, dlx) = lagrange2(xi);
                let (ly, dly) = lagrange2(eta);
                let mut n = [0.0; 9];
                let mut dn = [[0.0; 2]; 9];
                for (a, &(i, j)) in LATTICE.iter().enumerate() {
                    n[a] = lx[i] * ly[j];
                    dn[a] = [dlx[i] * ly[j], lx[i] * dly[j]];
                }
                (n, dn)
            },
            |xi, eta| {
                let mut m = [0.0; 4];
                for (c, &(i, j)) in LATTICE[..4].iter().enumerate() {
                    m[c] = lagrange1(xi, i / 2) * lagrange1(eta, j / 2);
                }
                m
            },
        )
    }

    /// Q1 interpolation of the corner pressures at the reference positions of the 9 nodes.
    fn nodal_pressures(pc: &[f64], at_nodes: &mut [f64]) {
        at_nodes.copy_from_slice(&[
            pc[0],
            pc[1],
            pc[2],
            pc[3],
            0.5 * (pc[0] + pc[1]),
            0.5 * (pc[1] + pc[2]),
            0.5 * (pc[2] + pc[3]),
            0.5 * (pc[3] + pc[0]),
            0.25 * (pc[0] + pc[1] + pc[2] + pc[3]),
        ]);
    }
}
