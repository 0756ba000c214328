//! The single place that seeds dual numbers. Callers say what they need ([`Order`]) and pay for
//! nothing else: the energy alone is an `f64` evaluation, the stress a 5-component gradient, the
//! tangent a 5×5 Hessian — always over the five invariants of C_e, never over the entries of F.
//!
//! Chain (with Ie = A(γ) j the active-strain map of [`crate::active::strain`], c = 1 − γ, g and
//! H the gradient and Hessian of the user's W at Ie):
//!
//! - Ŵ = c W, Ŵ_j = c Aᵀ g, Ŵ_jj = c Aᵀ H A,
//! - Ŵ_γ = −W + c g·Ie_γ, Ŵ_jγ = −Aᵀ g + c A_γᵀ g + c Aᵀ H Ie_γ,
//! - Ŵ_γγ = −2 g·Ie_γ + c (Ie_γᵀ H Ie_γ + g·Ie_γγ),
//!
//! then P = Dᵀ Ŵ_j, ∂P/∂F = Dᵀ Ŵ_jj D + Σ Ŵ_j ∂²j/∂F², dP/dγ = Dᵀ Ŵ_jγ
//! (D = ∂j/∂F, see [`crate::invariants`]).

use crate::active::strain::{check_activation, StrainMap};
use crate::energy::{Invariants, StrainEnergy};
use crate::invariants::{Entries, Kinematics};
use crate::{Error, Result};
use nalgebra::{SMatrix, SVector};
use num_dual::{gradient, hessian, Dual2SVec64, DualSVec64};

/// What a caller needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Order {
    /// Ŵ only.
    Energy,
    /// Ŵ, P and ∂Ŵ/∂γ.
    Stress,
    /// Ŵ, P, ∂Ŵ/∂γ, ∂P/∂F, dP/dγ and ∂²Ŵ/∂γ².
    Tangent,
}

/// Second derivatives of Ŵ(j, γ) in invariant space.
#[derive(Debug, Clone, Copy)]
pub struct SecondDerivatives {
    /// ∂²Ŵ/∂j∂j.
    pub d_jj: SMatrix<f64, 5, 5>,
    /// ∂²Ŵ/∂j∂γ.
    pub d_jgamma: SVector<f64, 5>,
    /// ∂²Ŵ/∂γ².
    pub d_gammagamma: f64,
}

/// Derivatives of Ŵ(j, γ) = (1 − γ) W(A(γ) j) with respect to the invariants j of C and γ.
#[derive(Debug, Clone, Copy)]
pub struct InvariantDerivatives {
    /// Ŵ \[kPa\].
    pub energy: f64,
    /// ∂Ŵ/∂j (zero for [`Order::Energy`]).
    pub d_j: SVector<f64, 5>,
    /// ∂Ŵ/∂γ (zero for [`Order::Energy`]).
    pub d_gamma: f64,
    /// Present for [`Order::Tangent`].
    pub second: Option<SecondDerivatives>,
}

fn invariants_of<T: Copy>(v: &SVector<T, 5>) -> Invariants<T> {
    Invariants::from_array([v[0], v[1], v[2], v[3], v[4]])
}

/// The first non-finite entry of `x`, if any. The test over all entries is one branch-free pass
/// (the compiler vectorises it); the search runs only when it fails.
#[inline(always)]
fn first_non_finite(x: &[f64]) -> Option<f64> {
    if x.iter().fold(true, |ok, v| ok & v.is_finite()) {
        None
    } else {
        x.iter().copied().find(|v| !v.is_finite())
    }
}

fn non_finite(quantity: &'static str, value: f64, j: &SVector<f64, 5>, gamma: f64) -> Error {
    Error::NonFinite {
        quantity,
        value,
        context: format!(
            "at invariants [tr C, C:M, tr C^-1, C^-1:M, det C] = [{:.6e}, {:.6e}, {:.6e}, {:.6e}, {:.6e}], gamma = {gamma} (exp overflow?)",
            j[0], j[1], j[2], j[3], j[4]
        ),
    }
}

/// W, its gradient and its Hessian at the elastic invariants `ie`, to the order asked; over four
/// invariants (det C held) when the energy does not use det C.
#[inline(always)]
fn energy_derivatives<E: StrainEnergy>(
    energy: &E,
    ie: &SVector<f64, 5>,
    order: Order,
) -> (f64, Option<SVector<f64, 5>>, Option<SMatrix<f64, 5, 5>>) {
    match order {
        Order::Energy => (energy.energy(&invariants_of(ie)), None, None),
        Order::Stress => {
            let (w, g) = energy_gradient(energy, ie);
            (w, Some(g), None)
        }
        Order::Tangent => {
            let (w, g, h) = energy_hessian(energy, ie);
            (w, Some(g), Some(h))
        }
    }
}

/// W and its gradient, over four invariants when the energy does not use det C.
#[inline(always)]
fn energy_gradient<E: StrainEnergy>(energy: &E, ie: &SVector<f64, 5>) -> (f64, SVector<f64, 5>) {
    if energy.uses_det_c() {
        return gradient(
            |v: SVector<DualSVec64<5>, 5>| energy.energy(&invariants_of(&v)),
            ie,
        );
    }
    let det_c = ie[4];
    let (w, g) = gradient(
        |v: SVector<DualSVec64<4>, 4>| {
            let det_c = DualSVec64::from_re(det_c);
            energy.energy(&Invariants::from_array([v[0], v[1], v[2], v[3], det_c]))
        },
        &ie.fixed_rows::<4>(0).into_owned(),
    );
    (w, SVector::from([g[0], g[1], g[2], g[3], 0.0]))
}

/// W, its gradient and its Hessian, over four invariants when the energy does not use det C.
#[inline(always)]
fn energy_hessian<E: StrainEnergy>(
    energy: &E,
    ie: &SVector<f64, 5>,
) -> (f64, SVector<f64, 5>, SMatrix<f64, 5, 5>) {
    if energy.uses_det_c() {
        return hessian(
            |v: SVector<Dual2SVec64<5>, 5>| energy.energy(&invariants_of(&v)),
            ie,
        );
    }
    let det_c = ie[4];
    let (w, g, h) = hessian(
        |v: SVector<Dual2SVec64<4>, 4>| {
            let det_c = Dual2SVec64::from_re(det_c);
            energy.energy(&Invariants::from_array([v[0], v[1], v[2], v[3], det_c]))
        },
        &ie.fixed_rows::<4>(0).into_owned(),
    );
    let h = SMatrix::<f64, 5, 5>::from_fn(|r, c| if r < 4 && c < 4 { h[(r, c)] } else { 0.0 });
    (w, SVector::from([g[0], g[1], g[2], g[3], 0.0]), h)
}

/// Derivatives of the active-strain energy in invariant space, to the order asked.
#[inline(always)]
pub fn invariant_derivatives<E: StrainEnergy>(
    energy: &E,
    j: &SVector<f64, 5>,
    gamma: f64,
    order: Order,
) -> Result<InvariantDerivatives> {
    check_activation(gamma)?;
    let map = StrainMap::new(gamma);
    let c = map.c;
    let (w, g, h) = energy_derivatives(energy, &map.apply(j), order);
    if !w.is_finite() {
        return Err(non_finite("strain energy", w, j, gamma));
    }
    let mut out = InvariantDerivatives {
        energy: c * w,
        d_j: SVector::zeros(),
        d_gamma: 0.0,
        second: None,
    };
    let Some(g) = g else { return Ok(out) };
    // Finiteness is checked on the chained derivatives: a non-finite g or H shows there, and so
    // does a finite one that the map's s² = (1 − γ)⁻² factors overflow.
    let ie_gamma = map.rate(j);
    let a_t_g = map.transpose_apply(&g);
    out.d_j = a_t_g * c;
    out.d_gamma = -w + c * g.dot(&ie_gamma);
    if let Some(bad) = first_non_finite(out.d_j.as_slice()).or(first_non_finite(&[out.d_gamma])) {
        return Err(non_finite("energy gradient", bad, j, gamma));
    }
    if let Some(h) = h {
        let h_ie_gamma = h * ie_gamma;
        let second = SecondDerivatives {
            d_jj: map.congruence(&h) * c,
            d_jgamma: -a_t_g
                + (map.rate_transpose_apply(&g) + map.transpose_apply(&h_ie_gamma)) * c,
            d_gammagamma: -2.0 * g.dot(&ie_gamma)
                + c * (ie_gamma.dot(&h_ie_gamma) + g.dot(&map.rate2(j))),
        };
        if let Some(bad) = first_non_finite(second.d_jj.as_slice())
            .or(first_non_finite(second.d_jgamma.as_slice()))
            .or(first_non_finite(&[second.d_gammagamma]))
        {
            return Err(non_finite("energy Hessian", bad, j, gamma));
        }
        out.second = Some(second);
    }
    Ok(out)
}

/// Response of the active-strain energy at a given γ, over the entries of F in `entries`.
#[derive(Debug, Clone, Copy)]
pub struct Response<const N: usize> {
    /// Ŵ(F, γ) \[kPa\].
    pub energy: f64,
    /// ∂Ŵ/∂γ \[kPa\] (from [`Order::Stress`]).
    pub denergy_dgamma: Option<f64>,
    /// P = ∂Ŵ/∂F \[kPa\], without the pressure term (from [`Order::Stress`]).
    pub stress: Option<SVector<f64, N>>,
    /// ∂P/∂F \[kPa\] (from [`Order::Tangent`]).
    pub tangent: Option<SMatrix<f64, N, N>>,
    /// dP/dγ = ∂²Ŵ/∂F∂γ \[kPa\] (from [`Order::Tangent`]).
    pub dstress_dgamma: Option<SVector<f64, N>>,
    /// ∂²Ŵ/∂γ² \[kPa\] (from [`Order::Tangent`]).
    pub d2energy_dgamma2: Option<f64>,
}

/// Ŵ(F, γ) and, to the order asked, its derivatives in F and γ (γ held fixed: no law).
#[inline(always)]
pub fn active_response<E: StrainEnergy, const N: usize>(
    energy: &E,
    kinematics: &Kinematics,
    gamma: f64,
    order: Order,
    entries: &Entries<N>,
) -> Result<Response<N>> {
    let j = SVector::from(kinematics.invariants);
    let d = invariant_derivatives(energy, &j, gamma, order)?;
    let mut out = Response {
        energy: d.energy,
        denergy_dgamma: None,
        stress: None,
        tangent: None,
        dstress_dgamma: None,
        d2energy_dgamma2: None,
    };
    if order == Order::Energy {
        return Ok(out);
    }
    let grad = kinematics.gradients(entries);
    out.denergy_dgamma = Some(d.d_gamma);
    out.stress = Some(grad.tr_mul(&d.d_j));
    if let Some(s) = d.second {
        let mut t = kinematics.curvature(&d.d_j, entries);
        if energy.uses_det_c() {
            add_congruence::<5, N>(&mut t, &grad, &s.d_jj);
        } else {
            add_congruence::<4, N>(&mut t, &grad, &s.d_jj);
        }
        out.tangent = Some(t);
        out.dstress_dgamma = Some(grad.tr_mul(&s.d_jgamma));
        out.d2energy_dgamma2 = Some(s.d_gammagamma);
    }
    Ok(out)
}

/// T += Dᵀ K D for a symmetric K (∂²Ŵ/∂j∂j at γ held) whose rows and columns beyond the first
/// `R` invariants are zero (R = 4 for an energy without det C): E = K D over those rows once,
/// then the upper triangle (Dᵀ E)_ab = Σ_j D_ja E_jb, mirrored.
#[inline(always)]
fn add_congruence<const R: usize, const N: usize>(
    t: &mut SMatrix<f64, N, N>,
    d: &SMatrix<f64, 5, N>,
    k: &SMatrix<f64, 5, 5>,
) {
    let e: [[f64; N]; R] = std::array::from_fn(|j| {
        std::array::from_fn(|b| (0..R).map(|l| k[(j, l)] * d[(l, b)]).sum())
    });
    for a in 0..N {
        for b in a..N {
            let v: f64 = (0..R).map(|j| d[(j, a)] * e[j][b]).sum();
            t[(a, b)] += v;
            if b != a {
                t[(b, a)] += v;
            }
        }
    }
}
