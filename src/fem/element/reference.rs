//! The reference element: shape functions and Gauss rule tabulated once at the quadrature
//! points ([`ReferenceElement`]; each element's file supplies its functions), and the
//! isoparametric map of a quadrature point to a physical cell ([`PointGeometry`]: position,
//! volume weight and the strain–displacement operator B).

use crate::fem::material::AxiF;
use nalgebra::{SMatrix, SVector};

/// Shape functions and Gauss rule of one element, tabulated at its quadrature points: `NN`
/// nodes, `NU` = 2 `NN` displacement dofs, `NP` pressure dofs, `ND` = `NU` + `NP` dofs, `NQ`
/// points. Stable Rust cannot compute `NU` and `ND` from `NN` and `NP`, so they are spelled out
/// once in each element's file (e.g. [`super::Q2Q1Reference`], [`super::Q1P0Reference`]) and
/// checked at compile time.
#[derive(Debug, Clone, Copy)]
pub struct ReferenceElement<
    const NN: usize,
    const NU: usize,
    const NP: usize,
    const ND: usize,
    const NQ: usize,
> {
    /// N_a(ξ_q) for the displacement nodes.
    pub n: [[f64; NN]; NQ],
    /// ∂N_a/∂(ξ, η) at ξ_q.
    pub dn: [[[f64; 2]; NN]; NQ],
    /// M_c(ξ_q) for the pressure dofs.
    pub m: [SVector<f64, NP>; NQ],
    /// Gauss weights.
    pub w: [f64; NQ],
}

/// (i, j) position of each Q2 node on the 3 × 3 lattice of the reference square (ξ, η) ∈ [−1, 1]².
pub(super) const LATTICE: [(usize, usize); 9] = [
    (0, 0),
    (2, 0),
    (2, 2),
    (0, 2),
    (1, 0),
    (2, 1),
    (1, 2),
    (0, 1),
    (1, 1),
];

/// The 1D linear Lagrange function of the left (`side` 0) or right (`side` 1) end at s.
pub(super) fn lagrange1(s: f64, side: usize) -> f64 {
    if side == 0 {
        0.5 * (1.0 - s)
    } else {
        0.5 * (1.0 + s)
    }
}

/// The mapped geometry of one quadrature point: its position, its volume weight and the
/// nonzero entries of the strain–displacement operator B (δF = B δu). Node a's u_r column of B
/// is (∂N_a/∂r, ∂N_a/∂z, 0, 0, N_a/r) and its u_z column (0, 0, ∂N_a/∂r, ∂N_a/∂z, 0) on
/// [F_rr, F_rz, F_zr, F_zz, F_θθ], so three rows of `NN` numbers hold the 5 × 2`NN` operator.
/// The reference mesh never moves, so the assembly computes it once per mesh
/// ([`ReferenceElement::cell_geometry`]): 8 (3 `NN` + 3) bytes per point, 2 160 per Q2/Q1 cell
/// (9 points), 480 per Q1/P0 cell (4 points).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointGeometry<const NN: usize> {
    /// Radius r at the point (> 0).
    pub r: f64,
    /// Axial coordinate z.
    pub z: f64,
    /// Volume weight dV = 2π r det(∂x/∂ξ) w.
    pub dv: f64,
    /// ∂N_a/∂r.
    pub dn_dr: [f64; NN],
    /// ∂N_a/∂z.
    pub dn_dz: [f64; NN],
    /// N_a / r.
    pub n_over_r: [f64; NN],
}

impl<const NN: usize> PointGeometry<NN> {
    /// F = I + B u on [F_rr, F_rz, F_zr, F_zz, F_θθ] for the element displacements
    /// u = [u_r⁰, u_z⁰, u_r¹, …] (`NU` = 2 `NN`):
    /// F_rr = 1 + Σ ∂N_a/∂r u_r^a, F_rz = Σ ∂N_a/∂z u_r^a, F_zr = Σ ∂N_a/∂r u_z^a,
    /// F_zz = 1 + Σ ∂N_a/∂z u_z^a, F_θθ = 1 + Σ N_a/r u_r^a.
    #[inline(always)]
    pub fn deformation<const NU: usize>(&self, u: &SVector<f64, NU>) -> AxiF {
        let mut f = [0.0; 5];
        for a in 0..NN {
            let (ur, uz) = (u[2 * a], u[2 * a + 1]);
            f[0] += self.dn_dr[a] * ur;
            f[1] += self.dn_dz[a] * ur;
            f[2] += self.dn_dr[a] * uz;
            f[3] += self.dn_dz[a] * uz;
            f[4] += self.n_over_r[a] * ur;
        }
        AxiF::new(f[0] + 1.0, f[1], f[2], f[3] + 1.0, f[4] + 1.0)
    }

    /// Bᵀ s · `scale` for a vector s on the five F entries: node a's pair
    /// (∂N_a/∂r s₀ + ∂N_a/∂z s₁ + N_a/r s₄, ∂N_a/∂r s₂ + ∂N_a/∂z s₃) · `scale`.
    #[inline(always)]
    pub(super) fn transpose_mul<const NU: usize>(&self, s: &AxiF, scale: f64) -> SVector<f64, NU> {
        let mut out = zeroed::<NU, 1>();
        for a in 0..NN {
            let (dr, dz, nr) = (self.dn_dr[a], self.dn_dz[a], self.n_over_r[a]);
            out[2 * a] = (dr * s[0] + dz * s[1] + nr * s[4]) * scale;
            out[2 * a + 1] = (dr * s[2] + dz * s[3]) * scale;
        }
        out
    }
}

/// A zero matrix, zeroed as one block (cheaper than nalgebra's entry-wise `zeros` in hot
/// loops).
pub fn zeroed<const R: usize, const C: usize>() -> SMatrix<f64, R, C> {
    SMatrix::from_array_storage(nalgebra::ArrayStorage([[0.0; R]; C]))
}

impl<const NN: usize, const NU: usize, const NP: usize, const ND: usize, const NQ: usize>
    ReferenceElement<NN, NU, NP, ND, NQ>
{
    const SIZES_ARE_CONSISTENT: () = assert!(NU == 2 * NN && ND == NU + NP);

    /// Nodes per cell (`NN`).
    pub const NODES: usize = NN;
    /// Displacement dofs per cell (`NU` = 2 `NN`).
    pub const DISPLACEMENT_DOFS: usize = NU;
    /// Pressure dofs per cell (`NP`).
    pub const PRESSURES: usize = NP;
    /// Dofs per cell (`ND` = `NU` + `NP`).
    pub const DOFS: usize = ND;
    /// Quadrature points per cell (`NQ`).
    pub const POINTS: usize = NQ;

    /// Tabulates `shape` (N_a and ∂N_a/∂(ξ, η)) and `pressure` (M_c) at the tensor-product
    /// Gauss rule of the 1D `points` and `weights` (point q = k j + i at (ξ_i, η_j)).
    pub(super) fn tabulate(
        points: &[f64],
        weights: &[f64],
        shape: impl Fn(f64, f64) -> ([f64; NN], [[f64; 2]; NN]),
        pressure: impl Fn(f64, f64) -> [f64; NP],
    ) -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::SIZES_ARE_CONSISTENT;
        let k = points.len();
        assert_eq!(k * k, NQ, "Gauss rule size");
        let mut n = [[0.0; NN]; NQ];
        let mut dn = [[[0.0; 2]; NN]; NQ];
        let mut m = [SVector::<f64, NP>::zeros(); NQ];
        let mut w = [0.0; NQ];
        for qj in 0..k {
            for qi in 0..k {
                let q = k * qj + qi;
                let (xi, eta) = (points[qi], points[qj]);
                w[q] = weights[qi] * weights[qj];
                (n[q], dn[q]) = shape(xi, eta);
                m[q] = SVector::<f64, NP>::from(pressure(xi, eta));
            }
        }
        Self { n, dn, m, w }
    }

    /// The positions (r, z) = Σ N_a(ξ_q) x_a of the quadrature points in the cell with nodal
    /// coordinates `x`.
    pub fn positions(&self, x: &[[f64; 2]; NN]) -> [[f64; 2]; NQ] {
        std::array::from_fn(|q| {
            x.iter()
                .zip(&self.n[q])
                .fold([0.0, 0.0], |[r, z], (xa, na)| {
                    [r + na * xa[0], z + na * xa[1]]
                })
        })
    }

    /// Maps the reference point `q` to the cell with nodal coordinates `x`: with the
    /// isoparametric map (r, z) = Σ N_a(ξ, η) x_a and its Jacobian J = ∂(r, z)/∂(ξ, η),
    /// (∂N_a/∂r, ∂N_a/∂z) = J⁻ᵀ (∂N_a/∂ξ, ∂N_a/∂η) and dV = 2π r det J w_q. Returns `None`
    /// when the mapping is not invertible (det J ≤ 0) or the point is not at r > 0.
    pub fn geometry(&self, q: usize, x: &[[f64; 2]; NN]) -> Option<PointGeometry<NN>> {
        let (mut r, mut z) = (0.0, 0.0);
        let (mut r_xi, mut r_eta, mut z_xi, mut z_eta) = (0.0, 0.0, 0.0, 0.0);
        for (a, xa) in x.iter().enumerate() {
            r += self.n[q][a] * xa[0];
            z += self.n[q][a] * xa[1];
            r_xi += self.dn[q][a][0] * xa[0];
            r_eta += self.dn[q][a][1] * xa[0];
            z_xi += self.dn[q][a][0] * xa[1];
            z_eta += self.dn[q][a][1] * xa[1];
        }
        let det = r_xi * z_eta - r_eta * z_xi;
        if !(det > 0.0 && r > 0.0) {
            return None;
        }
        // Inverse Jacobian: ∂ξ/∂r = z_η/det, ∂ξ/∂z = −r_η/det, ∂η/∂r = −z_ξ/det, ∂η/∂z = r_ξ/det.
        let (xi_r, xi_z, eta_r, eta_z) = (z_eta / det, -r_eta / det, -z_xi / det, r_xi / det);
        let mut g = PointGeometry {
            r,
            z,
            dv: 2.0 * std::f64::consts::PI * r * det * self.w[q],
            dn_dr: [0.0; NN],
            dn_dz: [0.0; NN],
            n_over_r: [0.0; NN],
        };
        for a in 0..NN {
            let [dxi, deta] = self.dn[q][a];
            g.dn_dr[a] = dxi * xi_r + deta * eta_r;
            g.dn_dz[a] = dxi * xi_z + deta * eta_z;
            g.n_over_r[a] = self.n[q][a] / r;
        }
        Some(g)
    }

    /// [`Self::geometry`] at every quadrature point of the cell with nodal coordinates `x`
    /// (what the assembly caches per cell); `None` if any point is degenerate.
    pub fn cell_geometry(&self, x: &[[f64; 2]; NN]) -> Option<[PointGeometry<NN>; NQ]> {
        let mut out = [self.geometry(0, x)?; NQ];
        for (q, g) in out.iter_mut().enumerate().skip(1) {
            *g = self.geometry(q, x)?;
        }
        Some(out)
    }
}
