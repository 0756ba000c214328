//! The mixed u–p quadrilaterals a user trades speed for accuracy with ([`Element`]): shape
//! functions and Gauss rule tabulated once ([`ReferenceElement`]), the map to a physical cell,
//! and the element residual and tangent of the weak form.
//!
//! Local dof order: [u_r⁰, u_z⁰, …, u_r^{n−1}, u_z^{n−1}, p⁰, …]: the displacement on the cell's
//! n nodes, then the pressure dofs (the 4 corner values for Q2/Q1, the one cell value for Q1/P0).

pub use super::kinematics::{jacobian, jacobian_gradient, jacobian_hessian};
use super::material::{AxiF, AxisymmetricMaterial};
use crate::volumetric::Volumetric;
use nalgebra::{SMatrix, SVector};
use std::ops::AddAssign;

/// The mixed element: a user's choice between accuracy per dof and cost per dof.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Element {
    /// Taylor–Hood Q2/Q1: biquadratic displacement on 9 nodes, continuous bilinear pressure on
    /// the 4 corners, 3 × 3 Gauss. Inf–sup stable; J = 1 holds weakly,
    /// ∫ q (J − 1) dV = 0 for every continuous bilinear q. Second-order displacement.
    #[default]
    Q2Q1,
    /// Q1/P0: bilinear displacement on the 4 corners, one constant pressure per cell, 2 × 2
    /// Gauss: the axisymmetric hybrid element of commercial codes (e.g. Abaqus CAX4H).
    /// Incompressibility holds in the mean per cell, ∫_e (J − 1) dV = 0. A third of the dofs
    /// and 4–8 × less assembly time than Q2/Q1 on the same cells (`examples/fem_scaling.rs`),
    /// but first-order displacement and not inf–sup stable (the pressure may oscillate from
    /// cell to cell near constrained boundaries).
    Q1P0,
}

impl Element {
    /// Both elements, Q2/Q1 first.
    pub const ALL: [Element; 2] = [Element::Q2Q1, Element::Q1P0];

    /// Nodes per cell.
    pub const fn nodes(self) -> usize {
        match self {
            Element::Q2Q1 => 9,
            Element::Q1P0 => 4,
        }
    }

    /// Quadrature points per cell.
    pub const fn quadrature_points(self) -> usize {
        match self {
            Element::Q2Q1 => 9,
            Element::Q1P0 => 4,
        }
    }

    /// Pressure dofs per cell (shared with neighbours for Q2/Q1, the cell's own for Q1/P0).
    pub const fn pressures(self) -> usize {
        match self {
            Element::Q2Q1 => 4,
            Element::Q1P0 => 1,
        }
    }

    /// Short name, "Q2/Q1" or "Q1/P0".
    pub const fn name(self) -> &'static str {
        match self {
            Element::Q2Q1 => "Q2/Q1",
            Element::Q1P0 => "Q1/P0",
        }
    }
}

impl std::str::FromStr for Element {
    type Err = String;

    /// "Q2Q1" or "Q2/Q1", "Q1P0" or "Q1/P0" (any case).
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_uppercase().replace('/', "").as_str() {
            "Q2Q1" => Ok(Element::Q2Q1),
            "Q1P0" => Ok(Element::Q1P0),
            _ => Err(format!("unknown element {s:?} (expected Q2/Q1 or Q1/P0)")),
        }
    }
}

impl std::fmt::Display for Element {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Element vector (`ND` dofs).
pub type ElementVector<const ND: usize> = SVector<f64, ND>;
/// Element matrix (column-major, as nalgebra stores it).
pub type ElementMatrix<const ND: usize> = SMatrix<f64, ND, ND>;

/// Shape functions and Gauss rule of one element, tabulated at its quadrature points: `NN`
/// nodes, `NU` = 2 `NN` displacement dofs, `NP` pressure dofs, `ND` = `NU` + `NP` dofs, `NQ`
/// points. Stable Rust cannot compute `NU` and `ND` from `NN` and `NP`, so they are spelled out
/// once in [`Q2Q1Reference`] and [`Q1P0Reference`] and checked at compile time.
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

/// Taylor–Hood Q2/Q1: 9 nodes, 4 corner pressures, 3 × 3 Gauss.
pub type Q2Q1Reference = ReferenceElement<9, 18, 4, 22, 9>;
/// Q1/P0: 4 nodes, 1 cell pressure, 2 × 2 Gauss.
pub type Q1P0Reference = ReferenceElement<4, 8, 1, 9, 4>;

/// (i, j) position of each Q2 node on the 3 × 3 lattice of the reference square (ξ, η) ∈ [−1, 1]².
const LATTICE: [(usize, usize); 9] = [
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

fn lagrange2(x: f64) -> ([f64; 3], [f64; 3]) {
    (
        [0.5 * x * (x - 1.0), 1.0 - x * x, 0.5 * x * (x + 1.0)],
        [x - 0.5, -2.0 * x, x + 0.5],
    )
}

/// The 1D linear Lagrange function of the left (`side` 0) or right (`side` 1) end at s.
fn lagrange1(s: f64, side: usize) -> f64 {
    if side == 0 {
        0.5 * (1.0 - s)
    } else {
        0.5 * (1.0 + s)
    }
}

impl Q2Q1Reference {
    /// Tabulates Q2 and Q1 shape functions at the 3 × 3 Gauss points.
    pub fn new() -> Self {
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
}

impl Default for Q2Q1Reference {
    fn default() -> Self {
        Self::new()
    }
}

impl Q1P0Reference {
    /// Tabulates Q1 shape functions (corners counter-clockwise from (−1, −1)) and the constant
    /// pressure at the 2 × 2 Gauss points.
    pub fn new() -> Self {
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
}

impl Default for Q1P0Reference {
    fn default() -> Self {
        Self::new()
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
    #[inline]
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
    #[inline]
    fn transpose_mul<const NU: usize>(&self, s: &AxiF, scale: f64) -> SVector<f64, NU> {
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

/// K[0..NU, 0..NU] += Bᵀ D B (`K` of any size R ≥ NU = 2 `NN`), using the structure of B
/// ([`PointGeometry`]): the 2 × 2 block of nodes (a, b) costs 10 products once D's columns are
/// combined for b. With `lower`, only the blocks a ≥ b (for a symmetric D; see
/// [`mirror_node_blocks`]).
fn add_btdb<const NN: usize, const R: usize>(
    k: &mut SMatrix<f64, R, R>,
    g: &PointGeometry<NN>,
    d: &SMatrix<f64, 5, 5>,
    lower: bool,
) {
    for nb in 0..NN {
        let (rb, zb) = (2 * nb, 2 * nb + 1);
        let (dr, dz, nr) = (g.dn_dr[nb], g.dn_dz[nb], g.n_over_r[nb]);
        let cr: [f64; 5] =
            std::array::from_fn(|i| d[(i, 0)] * dr + d[(i, 1)] * dz + d[(i, 4)] * nr);
        let cz: [f64; 5] = std::array::from_fn(|i| d[(i, 2)] * dr + d[(i, 3)] * dz);
        for na in if lower { nb } else { 0 }..NN {
            let (ra, za) = (2 * na, 2 * na + 1);
            let (ar, az, an) = (g.dn_dr[na], g.dn_dz[na], g.n_over_r[na]);
            k[(ra, rb)] += ar * cr[0] + az * cr[1] + an * cr[4];
            k[(za, rb)] += ar * cr[2] + az * cr[3];
            k[(ra, zb)] += ar * cz[0] + az * cz[1] + an * cz[4];
            k[(za, zb)] += ar * cz[2] + az * cz[3];
        }
    }
}

/// Completes a matrix of 2 × 2 node blocks of which [`add_btdb`] filled the blocks a ≥ b:
/// block (b, a) = block (a, b)ᵀ.
fn mirror_node_blocks<const NU: usize>(k: &mut SMatrix<f64, NU, NU>) {
    for nb in 0..NU / 2 {
        for na in nb + 1..NU / 2 {
            for i in 0..2 {
                for j in 0..2 {
                    k[(2 * nb + i, 2 * na + j)] = k[(2 * na + j, 2 * nb + i)];
                }
            }
        }
    }
}

/// What one element evaluation returns besides its vectors: the stress scale max |P_ij|, |p ∂J/∂F_ij| \[kPa\].
#[derive(Debug, Clone, Copy, Default)]
pub struct ElementScale {
    /// Largest stress magnitude met at the element's quadrature points.
    pub stress: f64,
}

impl<const NN: usize, const NU: usize, const NP: usize, const ND: usize, const NQ: usize>
    ReferenceElement<NN, NU, NP, ND, NQ>
{
    const SIZES_ARE_CONSISTENT: () = assert!(NU == 2 * NN && ND == NU + NP);

    /// Tabulates `shape` (N_a and ∂N_a/∂(ξ, η)) and `pressure` (M_c) at the tensor-product
    /// Gauss rule of the 1D `points` and `weights` (point q = k j + i at (ξ_i, η_j)).
    fn tabulate(
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

    /// Residual and (optionally) tangent of one element.
    ///
    /// Weak form (Π(u, p) = ∫ [Ψ(F) − p (J − 1)] dV, dV = 2π r dr dz, q and δu test functions):
    ///
    /// R_u(δu) = ∫ (P(F) − p ∂J/∂F) : δF dV,      δF = B δu,
    /// R_p(q)  = −∫ q (J − 1) dV,
    ///
    /// and its linearisation (A = ∂P/∂F, possibly non-symmetric; H = ∂²J/∂F∂F):
    ///
    /// K_uu = ∫ Bᵀ (A − p H) B dV,   K_up = −∫ Bᵀ ∂J/∂F M dV,   K_pu = −∫ M (∂J/∂F)ᵀ B dV,   K_pp = 0.
    ///
    /// For Q1/P0 the only M is 1 on the cell, so R_p = −∫_e (J − 1) dV: incompressibility in
    /// the mean per cell. `geometry` is the cell's mapped geometry ([`Self::cell_geometry`]).
    ///
    /// Nearly incompressible (`volumetric` = U(J), strictly convex): the perturbed Lagrangian
    /// with the Legendre transform Φ(p) = sup_J [−p (J − 1) − U(J)] of U,
    ///
    /// Π(u, p) = ∫ [Ψ(F) − p (J − 1) − Φ(p)] dV,
    ///
    /// whose stationarity in p, J = J̃(p) := (U′)⁻¹(−p), gives back ∫ [Ψ + U(J)] dV. The
    /// displacement equations are those of the exact constraint; the pressure equation and block
    /// become ([`crate::volumetric::Volumetric::dilatation`]: Φ′ = 1 − J̃, Φ″ = 1/U″(J̃))
    ///
    /// R_p(q) = −∫ q [J − J̃(p)] dV,   K_pp = −∫ M Mᵀ / U″(J̃(p)) dV,
    ///
    /// for U = (κ/2)(J − 1)²: R_p = −∫ q [(J − 1) + p/κ] dV, K_pp = −∫ M Mᵀ/κ dV, and κ = ∞ is the
    /// exact constraint. U is evaluated at the interpolated pressure, never at the pointwise J of
    /// the displacement (which the mixed element keeps close to J̃ only weakly): a stiff,
    /// non-quadratic U (4C's J^(−2κ)) then stays as well conditioned as the quadratic one.
    #[allow(clippy::too_many_arguments)]
    pub fn residual_tangent<M: AxisymmetricMaterial + ?Sized>(
        &self,
        geometry: &[PointGeometry<NN>; NQ],
        u: &SVector<f64, NU>,
        p: &SVector<f64, NP>,
        material: &M,
        volumetric: Option<&Volumetric>,
        residual: &mut ElementVector<ND>,
        tangent: Option<&mut ElementMatrix<ND>>,
    ) -> crate::Result<ElementScale> {
        // (J − J̃(p), 1/U″(J̃)) at J and the pressure p: (J − 1, 0) for the exact constraint.
        let constraint = |j: f64, p: f64| -> crate::Result<(f64, f64)> {
            match volumetric {
                None => Ok((j - 1.0, 0.0)),
                Some(v) => {
                    let (jt, compliance) = v.dilatation(p)?;
                    Ok((j - jt, compliance))
                }
            }
        };
        residual.as_mut_slice().fill(0.0);
        let mut scale = ElementScale::default();
        match tangent {
            None => {
                for (g, m) in geometry.iter().zip(&self.m) {
                    let f = g.deformation(u);
                    let pq = m.dot(p);
                    let pk = material.stress_at(&f, [g.r, g.z])?;
                    let dj = jacobian_gradient(&f);
                    let s = pk - dj * pq;
                    scale.stress = scale.stress.max(pk.amax()).max(s.amax());
                    let ru = g.transpose_mul::<NU>(&s, g.dv);
                    residual.fixed_rows_mut::<NU>(0).add_assign(&ru);
                    let rp = m * (-constraint(jacobian(&f), pq)?.0 * g.dv);
                    residual.fixed_rows_mut::<NP>(NU).add_assign(&rp);
                }
            }
            Some(k) => {
                // Contiguous zeroing (nalgebra's `fill` walks the matrix entry by entry).
                k.as_mut_slice().fill(0.0);
                let mut kuu_lower = zeroed::<NU, NU>();
                for (g, m) in geometry.iter().zip(&self.m) {
                    let f = g.deformation(u);
                    let pq = m.dot(p);
                    let (pk, a) = material.stress_tangent_at(&f, [g.r, g.z])?;
                    let dj = jacobian_gradient(&f);
                    let s = pk - dj * pq;
                    scale.stress = scale.stress.max(pk.amax()).max(s.amax());
                    let ru = g.transpose_mul::<NU>(&s, g.dv);
                    residual.fixed_rows_mut::<NU>(0).add_assign(&ru);
                    let (c, compliance) = constraint(jacobian(&f), pq)?;
                    let rp = m * (-c * g.dv);
                    residual.fixed_rows_mut::<NP>(NU).add_assign(&rp);
                    if volumetric.is_some() {
                        k.fixed_view_mut::<NP, NP>(NU, NU)
                            .add_assign(&(m * m.transpose() * (-compliance * g.dv)));
                    }
                    // K_uu += Bᵀ D B with D = (A − p H) dV; for a symmetric D (a hyperelastic
                    // material) only the node blocks below the diagonal, mirrored at the end.
                    let d = (a - jacobian_hessian(&f) * pq) * g.dv;
                    if (1..5).all(|i| (0..i).all(|j| d[(i, j)] == d[(j, i)])) {
                        add_btdb(&mut kuu_lower, g, &d, true);
                    } else {
                        add_btdb(k, g, &d, false);
                    }
                    // K_up = −Bᵀ ∂J/∂F Mᵀ dV, K_pu = −M (∂J/∂F)ᵀ B dV.
                    let bdj = g.transpose_mul::<NU>(&dj, -g.dv);
                    let kup = bdj * m.transpose();
                    k.fixed_view_mut::<NU, NP>(0, NU).add_assign(&kup);
                }
                // K_pu = K_upᵀ, copied once rather than accumulated point by point.
                for i in 0..NP {
                    for j in 0..NU {
                        k[(NU + i, j)] = k[(j, NU + i)];
                    }
                }
                mirror_node_blocks(&mut kuu_lower);
                k.fixed_view_mut::<NU, NU>(0, 0).add_assign(&kuu_lower);
            }
        }
        Ok(scale)
    }
}
