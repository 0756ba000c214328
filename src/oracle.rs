//! The reference route: dual numbers over the nine entries of F and γ, with C_e = F_a⁻ᵀ C F_a⁻¹
//! formed by matrix products and inverted by cofactors. Slow (a 10×10 hyper-dual Hessian), but
//! independent of the invariant calculus and of the active-strain map of the fast route, which are
//! tested against it.

use crate::active::map::ActivationMap;
use crate::energy::{Invariants, StrainEnergy};
use crate::{Result, Scalar};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};
use num_dual::{hessian, Dual2SVec64};

type M3<T> = [[T; 3]; 3];

fn mul<T: Scalar>(a: &M3<T>, b: &M3<T>) -> M3<T> {
    let mut c = [[T::zero(); 3]; 3];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, cij) in row.iter_mut().enumerate() {
            *cij = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    c
}

fn transpose<T: Scalar>(a: &M3<T>) -> M3<T> {
    let mut t = *a;
    for (i, row) in t.iter_mut().enumerate() {
        for (j, tij) in row.iter_mut().enumerate() {
            *tij = a[j][i];
        }
    }
    t
}

fn det<T: Scalar>(a: &M3<T>) -> T {
    a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
}

fn inverse<T: Scalar>(a: &M3<T>) -> M3<T> {
    let d = det(a).recip();
    let c = |i: usize, j: usize| {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
        a[i1][j1] * a[i2][j2] - a[i1][j2] * a[i2][j1]
    };
    let mut inv = [[T::zero(); 3]; 3];
    for (i, row) in inv.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = c(j, i) * d;
        }
    }
    inv
}

fn quadratic<T: Scalar>(a: &M3<T>, m: &Vector3<f64>) -> T {
    let mut s = T::zero();
    for i in 0..3 {
        for j in 0..3 {
            s += a[i][j] * (m[i] * m[j]);
        }
    }
    s
}

/// Ŵ(F, γ) = det F_a · W(F_a⁻ᵀ C F_a⁻¹) by matrix products on any scalar, with F_a built entry
/// by entry as a 3×3 matrix: I − γ m⊗m (the chapter's map) or
/// (1 − γ) m⊗m + (1 − γ)^(−½) (I − m⊗m) (the volume-preserving map); det F_a and the inverses
/// by cofactors. For the structural map, W at the invariants of C with the structural invariant
/// C:(L + ωM) = C:L + ω C:M entered through C:M ↦ C:M + (ω/f) C:M.
pub fn active_energy_by_matrices<E: StrainEnergy, T: Scalar>(
    energy: &E,
    map: impl Into<ActivationMap>,
    f: &M3<T>,
    m: &Vector3<f64>,
    gamma: T,
) -> T {
    let map = map.into();
    if let ActivationMap::Structural { fibre_weight } = map {
        let c = mul(&transpose(f), f);
        let c_inv = inverse(&c);
        let c_m = quadratic(&c, m);
        let inv = Invariants {
            tr_c: c[0][0] + c[1][1] + c[2][2],
            c_m: c_m + c_m * gamma / fibre_weight,
            tr_c_inv: c_inv[0][0] + c_inv[1][1] + c_inv[2][2],
            c_inv_m: quadratic(&c_inv, m),
            det_c: det(&c),
        };
        return energy.energy(&inv);
    }
    let mut fa = [[T::zero(); 3]; 3];
    for (i, row) in fa.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            let (mm, delta) = (m[i] * m[j], if i == j { 1.0 } else { 0.0 });
            *x = match map {
                ActivationMap::VolumePreserving => {
                    let c = -gamma + 1.0;
                    c * mm + c.sqrt().recip() * (delta - mm)
                }
                _ => gamma * (-mm) + delta,
            };
        }
    }
    let fa_inv = inverse(&fa);
    let fe = mul(f, &fa_inv);
    let ce = mul(&transpose(&fe), &fe);
    let ce_inv = inverse(&ce);
    let inv = Invariants {
        tr_c: ce[0][0] + ce[1][1] + ce[2][2],
        c_m: quadratic(&ce, m),
        tr_c_inv: ce_inv[0][0] + ce_inv[1][1] + ce_inv[2][2],
        c_inv_m: quadratic(&ce_inv, m),
        det_c: det(&ce),
    };
    det(&fa) * energy.energy(&inv)
}

/// Everything at (F, γ) from one 10-variable Hessian: variables are F's entries row by row, then γ.
#[derive(Debug, Clone, Copy)]
pub struct FullResponse {
    /// Ŵ.
    pub energy: f64,
    /// ∂Ŵ/∂F (row-major).
    pub stress: SVector<f64, 9>,
    /// ∂²Ŵ/∂F².
    pub tangent: SMatrix<f64, 9, 9>,
    /// ∂²Ŵ/∂F∂γ.
    pub dstress_dgamma: SVector<f64, 9>,
    /// ∂Ŵ/∂γ.
    pub denergy_dgamma: f64,
    /// ∂²Ŵ/∂γ².
    pub d2energy_dgamma2: f64,
}

/// The reference response at (F, γ) by dual numbers over F's nine entries and γ, for the
/// chapter's map.
pub fn full_response<E: StrainEnergy>(
    energy: &E,
    f: &Matrix3<f64>,
    m: &Vector3<f64>,
    gamma: f64,
) -> Result<FullResponse> {
    full_response_with(energy, ActivationMap::Chapter, f, m, gamma)
}

/// The reference response at (F, γ) for the active-strain map `map`, by dual numbers over F's
/// nine entries and γ.
pub fn full_response_with<E: StrainEnergy>(
    energy: &E,
    map: impl Into<ActivationMap>,
    f: &Matrix3<f64>,
    m: &Vector3<f64>,
    gamma: f64,
) -> Result<FullResponse> {
    let map = map.into();
    map.check(gamma)?;
    let mut x = SVector::<f64, 10>::zeros();
    for i in 0..3 {
        for j in 0..3 {
            x[3 * i + j] = f[(i, j)];
        }
    }
    x[9] = gamma;
    let (w, g, h) = hessian(
        |v: SVector<Dual2SVec64<10>, 10>| {
            let f = [[v[0], v[1], v[2]], [v[3], v[4], v[5]], [v[6], v[7], v[8]]];
            active_energy_by_matrices(energy, map, &f, m, v[9])
        },
        &x,
    );
    Ok(FullResponse {
        energy: w,
        stress: g.fixed_rows::<9>(0).into(),
        tangent: h.fixed_view::<9, 9>(0, 0).into(),
        dstress_dgamma: h.fixed_view::<9, 1>(0, 9).into(),
        denergy_dgamma: g[9],
        d2energy_dgamma2: h[(9, 9)],
    })
}
