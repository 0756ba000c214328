//! The Taylor–Hood Q2/Q1 axisymmetric element: shape functions, 3 × 3 Gauss quadrature,
//! kinematics at a quadrature point and the element residual and tangent.
//!
//! Local dof order: [u_r⁰, u_z⁰, …, u_r⁸, u_z⁸, p⁰, …, p³] (biquadratic displacement on the 9
//! nodes, bilinear continuous pressure on the 4 corners).

use super::material::{AxiF, AxisymmetricMaterial};
use nalgebra::{SMatrix, SVector};

/// Displacement dofs per element (9 nodes × 2).
pub const N_U: usize = 18;
/// Pressure dofs per element (4 corners).
pub const N_P: usize = 4;
/// All dofs per element.
pub const N_DOF: usize = N_U + N_P;
/// Quadrature points per element (3 × 3 Gauss).
pub const N_QP: usize = 9;

/// Element vector.
pub type ElementVector = SVector<f64, N_DOF>;
/// Element matrix (column-major, as nalgebra stores it).
pub type ElementMatrix = SMatrix<f64, N_DOF, N_DOF>;
/// Strain–displacement operator: δF (5 entries) = B δu.
pub type BMatrix = SMatrix<f64, 5, N_U>;

/// (i, j) position of each node on the 3 × 3 lattice of the reference square (ξ, η) ∈ [−1, 1]².
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

/// Shape functions and their reference gradients tabulated at the quadrature points.
#[derive(Debug, Clone)]
pub struct ReferenceElement {
    /// N_a(ξ_q) for the 9 displacement nodes.
    pub n: [[f64; 9]; N_QP],
    /// ∂N_a/∂(ξ, η) at ξ_q.
    pub dn: [[[f64; 2]; 9]; N_QP],
    /// M_c(ξ_q) for the 4 pressure nodes.
    pub m: [[f64; N_P]; N_QP],
    /// Gauss weights.
    pub w: [f64; N_QP],
}

impl Default for ReferenceElement {
    fn default() -> Self {
        Self::new()
    }
}

impl ReferenceElement {
    /// Tabulates Q2 and Q1 shape functions at the 3 × 3 Gauss points.
    pub fn new() -> Self {
        let g = (0.6f64).sqrt();
        let pts = [-g, 0.0, g];
        let wts = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
        let mut n = [[0.0; 9]; N_QP];
        let mut dn = [[[0.0; 2]; 9]; N_QP];
        let mut m = [[0.0; N_P]; N_QP];
        let mut w = [0.0; N_QP];
        for qj in 0..3 {
            for qi in 0..3 {
                let q = 3 * qj + qi;
                let (xi, eta) = (pts[qi], pts[qj]);
                w[q] = wts[qi] * wts[qj];
                let (lx, dlx) = lagrange2(xi);
                let (ly, dly) = lagrange2(eta);
                for (a, &(i, j)) in LATTICE.iter().enumerate() {
                    n[q][a] = lx[i] * ly[j];
                    dn[q][a] = [dlx[i] * ly[j], lx[i] * dly[j]];
                }
                let l1 = |s: f64, side: usize| {
                    if side == 0 {
                        0.5 * (1.0 - s)
                    } else {
                        0.5 * (1.0 + s)
                    }
                };
                for (c, &(i, j)) in LATTICE[..4].iter().enumerate() {
                    m[q][c] = l1(xi, i / 2) * l1(eta, j / 2);
                }
            }
        }
        Self { n, dn, m, w }
    }
}

/// Geometry of one quadrature point in physical space.
#[derive(Debug, Clone, Copy)]
pub struct QuadratureGeometry {
    /// Radius r at the point (> 0).
    pub r: f64,
    /// Axial coordinate z.
    pub z: f64,
    /// Volume weight dV = 2π r det(∂x/∂ξ) w.
    pub dv: f64,
    /// B operator (δF = B δu).
    pub b: BMatrix,
}

/// Maps the reference point `q` to the element with nodal coordinates `x`. Returns `None`
/// when the mapping is not invertible or the point is not at r > 0.
pub fn geometry(re: &ReferenceElement, q: usize, x: &[[f64; 2]; 9]) -> Option<QuadratureGeometry> {
    let (mut r, mut z) = (0.0, 0.0);
    let (mut r_xi, mut r_eta, mut z_xi, mut z_eta) = (0.0, 0.0, 0.0, 0.0);
    for (a, xa) in x.iter().enumerate() {
        r += re.n[q][a] * xa[0];
        z += re.n[q][a] * xa[1];
        r_xi += re.dn[q][a][0] * xa[0];
        r_eta += re.dn[q][a][1] * xa[0];
        z_xi += re.dn[q][a][0] * xa[1];
        z_eta += re.dn[q][a][1] * xa[1];
    }
    let det = r_xi * z_eta - r_eta * z_xi;
    if !(det > 0.0 && r > 0.0) {
        return None;
    }
    // Inverse Jacobian: ∂ξ/∂r = z_η/det, ∂ξ/∂z = −r_η/det, ∂η/∂r = −z_ξ/det, ∂η/∂z = r_ξ/det.
    let (xi_r, xi_z, eta_r, eta_z) = (z_eta / det, -r_eta / det, -z_xi / det, r_xi / det);
    let mut b = BMatrix::zeros();
    for a in 0..9 {
        let [dxi, deta] = re.dn[q][a];
        let dr = dxi * xi_r + deta * eta_r;
        let dz = dxi * xi_z + deta * eta_z;
        // u_r column: δF_rr = ∂δu_r/∂r, δF_rz = ∂δu_r/∂z, δF_θθ = δu_r / r.
        b[(0, 2 * a)] = dr;
        b[(1, 2 * a)] = dz;
        b[(4, 2 * a)] = re.n[q][a] / r;
        // u_z column: δF_zr = ∂δu_z/∂r, δF_zz = ∂δu_z/∂z.
        b[(2, 2 * a + 1)] = dr;
        b[(3, 2 * a + 1)] = dz;
    }
    Some(QuadratureGeometry {
        r,
        z,
        dv: 2.0 * std::f64::consts::PI * r * det * re.w[q],
        b,
    })
}

/// F = I + B u on the five entries [F_rr, F_rz, F_zr, F_zz, F_θθ].
#[inline]
pub fn deformation(b: &BMatrix, u: &SVector<f64, N_U>) -> AxiF {
    let mut f = b * u;
    f[0] += 1.0;
    f[3] += 1.0;
    f[4] += 1.0;
    f
}

/// J = F_θθ (F_rr F_zz − F_rz F_zr).
#[inline]
pub fn jacobian(f: &AxiF) -> f64 {
    f[4] * (f[0] * f[3] - f[1] * f[2])
}

/// ∂J/∂F on the five entries.
#[inline]
pub fn jacobian_gradient(f: &AxiF) -> AxiF {
    AxiF::new(
        f[4] * f[3],
        -f[4] * f[2],
        -f[4] * f[1],
        f[4] * f[0],
        f[0] * f[3] - f[1] * f[2],
    )
}

/// ∂²J/∂F∂F on the five entries (symmetric).
#[inline]
pub fn jacobian_hessian(f: &AxiF) -> SMatrix<f64, 5, 5> {
    let mut h = SMatrix::<f64, 5, 5>::zeros();
    let mut set = |i: usize, j: usize, v: f64| {
        h[(i, j)] = v;
        h[(j, i)] = v;
    };
    set(0, 3, f[4]);
    set(0, 4, f[3]);
    set(1, 2, -f[4]);
    set(1, 4, -f[2]);
    set(2, 4, -f[1]);
    set(3, 4, f[0]);
    h
}

/// What one element evaluation returns besides its vectors: the stress scale max |P_ij|, |p ∂J/∂F_ij| \[kPa\].
#[derive(Debug, Clone, Copy, Default)]
pub struct ElementScale {
    /// Largest stress magnitude met at the element's quadrature points.
    pub stress: f64,
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
/// `x` holds the element's nodal coordinates (validated by the caller: see [`geometry`]).
pub fn element_residual_tangent<M: AxisymmetricMaterial + ?Sized>(
    re: &ReferenceElement,
    x: &[[f64; 2]; 9],
    u: &SVector<f64, N_U>,
    p: &SVector<f64, N_P>,
    material: &M,
    residual: &mut ElementVector,
    tangent: Option<&mut ElementMatrix>,
) -> crate::Result<ElementScale> {
    residual.fill(0.0);
    let mut scale = ElementScale::default();
    match tangent {
        None => {
            for q in 0..N_QP {
                let g = &geometry_checked(re, q, x)?;
                let f = deformation(&g.b, u);
                let m = SVector::<f64, N_P>::from_row_slice(&re.m[q]);
                let pq = m.dot(p);
                let pk = material.stress(&f)?;
                let dj = jacobian_gradient(&f);
                let s = pk - dj * pq;
                scale.stress = scale.stress.max(pk.amax()).max(s.amax());
                let ru = g.b.tr_mul(&s) * g.dv;
                residual.fixed_rows_mut::<N_U>(0).add_assign(&ru);
                let rp = m * (-(jacobian(&f) - 1.0) * g.dv);
                residual.fixed_rows_mut::<N_P>(N_U).add_assign(&rp);
            }
        }
        Some(k) => {
            k.fill(0.0);
            for q in 0..N_QP {
                let g = &geometry_checked(re, q, x)?;
                let f = deformation(&g.b, u);
                let m = SVector::<f64, N_P>::from_row_slice(&re.m[q]);
                let pq = m.dot(p);
                let (pk, a) = material.stress_tangent(&f)?;
                let dj = jacobian_gradient(&f);
                let s = pk - dj * pq;
                scale.stress = scale.stress.max(pk.amax()).max(s.amax());
                let ru = g.b.tr_mul(&s) * g.dv;
                residual.fixed_rows_mut::<N_U>(0).add_assign(&ru);
                let rp = m * (-(jacobian(&f) - 1.0) * g.dv);
                residual.fixed_rows_mut::<N_P>(N_U).add_assign(&rp);
                // K_uu += Bᵀ D B with D = (A − p H) dV.
                let d = (a - jacobian_hessian(&f) * pq) * g.dv;
                // B is sparse: a u_r column is (∂N/∂r, ∂N/∂z, 0, 0, N/r), a u_z column
                // (0, 0, ∂N/∂r, ∂N/∂z, 0); only those entries are multiplied.
                let db = d * g.b;
                for j in 0..N_U {
                    let c = db.column(j);
                    for a in 0..9 {
                        let (ra, za) = (2 * a, 2 * a + 1);
                        k[(ra, j)] +=
                            g.b[(0, ra)] * c[0] + g.b[(1, ra)] * c[1] + g.b[(4, ra)] * c[4];
                        k[(za, j)] += g.b[(2, za)] * c[2] + g.b[(3, za)] * c[3];
                    }
                }
                // K_up = −Bᵀ ∂J/∂F Mᵀ dV, K_pu = −M (∂J/∂F)ᵀ B dV.
                let bdj = g.b.tr_mul(&dj) * (-g.dv);
                let kup = bdj * m.transpose();
                k.fixed_view_mut::<N_U, N_P>(0, N_U).add_assign(&kup);
                k.fixed_view_mut::<N_P, N_U>(N_U, 0)
                    .add_assign(&kup.transpose());
            }
        }
    }
    Ok(scale)
}

use std::ops::AddAssign;

/// [`geometry`] for a mesh already validated; a degenerate point becomes an error, not a panic.
fn geometry_checked(
    re: &ReferenceElement,
    q: usize,
    x: &[[f64; 2]; 9],
) -> crate::Result<QuadratureGeometry> {
    geometry(re, q, x).ok_or_else(|| crate::Error::NonFinite {
        quantity: "element geometry",
        value: f64::NAN,
        context: format!("degenerate element mapping at quadrature point {q}, nodes {x:?}"),
    })
}
