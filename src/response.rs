//! The single place that seeds dual numbers. Callers say what they need ([`Order`]) and pay for
//! nothing else: the energy alone is an `f64` evaluation, the stress a 5-component gradient, the
//! tangent a 5×5 Hessian — always over the five invariants of C_e, never over the entries of F.
//!
//! Chain (with Ie = A(γ) j the active-strain map of [`crate::active::strain`], φ = det F_a its
//! factor — 1 − γ for the chapter's map, 1 for the volume-preserving one — g and H the gradient
//! and Hessian of the user's W at Ie):
//!
//! - Ŵ = φ W, Ŵ_j = φ Aᵀ g, Ŵ_jj = φ Aᵀ H A,
//! - Ŵ_γ = φ′ W + φ g·Ie_γ, Ŵ_jγ = φ′ Aᵀ g + φ A_γᵀ g + φ Aᵀ H Ie_γ,
//! - Ŵ_γγ = φ″ W + 2 φ′ g·Ie_γ + φ (Ie_γᵀ H Ie_γ + g·Ie_γγ),
//!
//! then P = Dᵀ Ŵ_j, ∂P/∂F = Σ Ŵ_j ∂²j/∂F² + Dᵀ Ŵ_jj D, dP/dγ = Dᵀ Ŵ_jγ (D = ∂j/∂F, see
//! [`crate::invariants`]). The congruence is formed in F space, Dᵀ Ŵ_jj D = φ D_eᵀ H D_e with
//! D_e = A D the gradients of the elastic invariants (A has seven non-zero entries), over the
//! rows of H that are not identically zero: an energy that is linear in tr C_e⁻¹ and C_e⁻¹:M
//! (the chapter's) and ignores det C_e has a 2×2 block of H, not 5×5. Which rows are zero is
//! read off H at each point, so any energy gets the right answer; the shortcut only saves work.

use crate::active::map::{ActivationMap, StrainMap};
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

/// Second derivatives of Ŵ(j, γ).
#[derive(Debug, Clone, Copy)]
pub struct SecondDerivatives {
    /// H = ∂²W/∂Ie∂Ie, the Hessian of the user's energy at the elastic invariants Ie = A j
    /// (Ŵ_jj = φ Aᵀ H A; rows and columns of invariants the energy ignores are zero).
    pub energy_hessian: SMatrix<f64, 5, 5>,
    /// ∂²Ŵ/∂j∂γ.
    pub d_jgamma: SVector<f64, 5>,
    /// ∂²Ŵ/∂γ².
    pub d_gammagamma: f64,
}

/// Derivatives of Ŵ(j, γ) = φ(γ) W(A(γ) j) with respect to the invariants j of C and γ.
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
    /// The active-strain map A(γ).
    map: StrainMap,
    /// γ.
    gamma: f64,
}

impl InvariantDerivatives {
    /// Ŵ_jj = φ Aᵀ H A, the Hessian of Ŵ in the invariants of C (present for [`Order::Tangent`]).
    pub fn d_jj(&self) -> Option<SMatrix<f64, 5, 5>> {
        self.second
            .as_ref()
            .map(|s| self.map.congruence(&s.energy_hessian) * self.map.det)
    }
}

fn invariants_of<T: Copy>(v: &SVector<T, 5>) -> Invariants<T> {
    Invariants::from_array([v[0], v[1], v[2], v[3], v[4]])
}

/// The first non-finite entry of `x`, if any. The test over all entries is one sum on four
/// independent lanes (a NaN or an infinity makes it non-finite; SSE2 has no 64-bit integer
/// compare, so a bit test per entry is not vectorised); the search runs only when the sum is not
/// finite (and finds nothing if it merely overflowed).
#[inline(always)]
pub(crate) fn first_non_finite(x: &[f64]) -> Option<f64> {
    let mut lanes = [0.0; 4];
    let chunks = x.chunks_exact(4);
    let rest = chunks.remainder();
    for chunk in chunks {
        for k in 0..4 {
            lanes[k] += chunk[k];
        }
    }
    for (k, v) in rest.iter().enumerate() {
        lanes[k] += v;
    }
    if ((lanes[0] + lanes[1]) + (lanes[2] + lanes[3])).is_finite() {
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

/// Derivatives of the active-strain energy in invariant space, to the order asked, for the
/// chapter's map (see [`invariant_derivatives_with`]).
#[inline(always)]
pub fn invariant_derivatives<E: StrainEnergy>(
    energy: &E,
    j: &SVector<f64, 5>,
    gamma: f64,
    order: Order,
) -> Result<InvariantDerivatives> {
    invariant_derivatives_with(energy, ActivationMap::Chapter, j, gamma, order)
}

/// Derivatives of the activated energy in invariant space for the activation map `map`, to the
/// order asked. Rejects a non-finite value (an exp overflow of the energy, or of the map's
/// s² = (1 − γ)⁻² factors).
#[inline(always)]
pub fn invariant_derivatives_with<E: StrainEnergy>(
    energy: &E,
    map: impl Into<ActivationMap>,
    j: &SVector<f64, 5>,
    gamma: f64,
    order: Order,
) -> Result<InvariantDerivatives> {
    let d = unchecked_derivatives(energy, map.into(), j, gamma, order)?;
    let fail = |quantity, bad| Err(non_finite(quantity, bad, j, gamma));
    if let Some(bad) = first_non_finite(d.d_j.as_slice()).or(first_non_finite(&[d.d_gamma])) {
        return fail("energy gradient", bad);
    }
    if let Some(s) = &d.second {
        if let Some(bad) = first_non_finite(s.energy_hessian.as_slice())
            .or(first_non_finite(s.d_jgamma.as_slice()))
            .or(first_non_finite(&[s.d_gammagamma]))
        {
            return fail("energy Hessian", bad);
        }
    }
    Ok(d)
}

/// [`invariant_derivatives`] with only the energy checked: for the routes that check what they
/// return (a non-finite derivative shows in their stress or tangent).
#[inline(always)]
pub(crate) fn unchecked_derivatives<E: StrainEnergy>(
    energy: &E,
    map: ActivationMap,
    j: &SVector<f64, 5>,
    gamma: f64,
    order: Order,
) -> Result<InvariantDerivatives> {
    map.check(gamma)?;
    let map = StrainMap::new(map, gamma);
    let (c, c1, c2) = (map.det, map.det_rate, map.det_rate2);
    let (w, g, h) = energy_derivatives(energy, &map.apply(j), order);
    if !w.is_finite() {
        return Err(non_finite("strain energy", w, j, gamma));
    }
    let mut out = InvariantDerivatives {
        energy: c * w,
        d_j: SVector::zeros(),
        d_gamma: 0.0,
        second: None,
        map,
        gamma,
    };
    let Some(g) = g else { return Ok(out) };
    let ie_gamma = map.rate(j);
    let a_t_g = map.transpose_apply(&g);
    out.d_j = a_t_g * c;
    out.d_gamma = c1 * w + c * g.dot(&ie_gamma);
    if let Some(h) = h {
        let h_ie_gamma = h * ie_gamma;
        out.second = Some(SecondDerivatives {
            energy_hessian: h,
            d_jgamma: a_t_g * c1
                + (map.rate_transpose_apply(&g) + map.transpose_apply(&h_ie_gamma)) * c,
            d_gammagamma: c2 * w
                + 2.0 * c1 * g.dot(&ie_gamma)
                + c * (ie_gamma.dot(&h_ie_gamma) + g.dot(&map.rate2(j))),
        });
    }
    Ok(out)
}

/// Rejects a non-finite entry in what a route returns: the stress, ∂Ŵ/∂γ and, with second
/// derivatives, the tangent, dP/dγ and ∂²Ŵ/∂γ² (a summed test per part, see
/// [`first_non_finite`]; the entry is named only when it fails).
#[inline(always)]
pub(crate) fn check_returned<const N: usize>(
    d: &InvariantDerivatives,
    f: &FSpace<N>,
    tangent: Option<&SMatrix<f64, N, N>>,
    invariants: &[f64; 5],
) -> Result<()> {
    let gamma = d.gamma;
    let j = SVector::from(*invariants);
    let scalars = [d.d_gamma, d.second.map_or(0.0, |s| s.d_gammagamma)];
    let parts: [(&'static str, &[f64]); 4] = [
        ("stress", f.stress.as_slice()),
        ("stress tangent", tangent.map_or(&[][..], |t| t.as_slice())),
        (
            "dP/dgamma",
            f.dstress_dgamma.as_ref().map_or(&[][..], |v| v.as_slice()),
        ),
        ("derivatives in gamma", &scalars),
    ];
    if parts.iter().all(|(_, x)| first_non_finite(x).is_none()) {
        return Ok(());
    }
    for (quantity, x) in parts {
        if let Some(bad) = x.iter().copied().find(|v| !v.is_finite()) {
            return Err(non_finite(quantity, bad, &j, gamma));
        }
    }
    Ok(())
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

/// Ŵ(F, γ) and, to the order asked, its derivatives in F and γ (γ held fixed: no law), for the
/// chapter's map (a [`crate::Muscle`] with a constant law answers for either map).
#[inline(always)]
pub fn active_response<E: StrainEnergy, const N: usize>(
    energy: &E,
    kinematics: &Kinematics,
    gamma: f64,
    order: Order,
    entries: &Entries<N>,
) -> Result<Response<N>> {
    let j = SVector::from(kinematics.invariants);
    let d = unchecked_derivatives(energy, ActivationMap::Chapter, &j, gamma, order)?;
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
    out.tangent = d.second.map(|_| SMatrix::zeros());
    let f = in_f_space(kinematics, entries, &d, (0.0, 0.0), out.tangent.as_mut());
    check_returned(&d, &f, out.tangent.as_ref(), &kinematics.invariants)?;
    out.denergy_dgamma = Some(d.d_gamma);
    out.stress = Some(f.stress);
    out.dstress_dgamma = f.dstress_dgamma;
    out.d2energy_dgamma2 = d.second.map(|s| s.d_gammagamma);
    Ok(out)
}

/// Stress and dP/dγ over the entries of F (see [`in_f_space`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct FSpace<const N: usize> {
    /// P = Dᵀ (Ŵ_j + a e₂).
    pub stress: SVector<f64, N>,
    /// dP/dγ = Dᵀ Ŵ_jγ (with second derivatives).
    pub dstress_dgamma: Option<SVector<f64, N>>,
    /// D₂ = ∂(C:M)/∂F, the gradient of the fibre invariant j₂ = λ_f².
    pub fibre_gradient: SVector<f64, N>,
}

/// The invariant-space derivatives `d` taken to the entries of F (module docs), with extra
/// weights on the fibre invariant j₂ = C:M: `a` is added to ∂Ŵ/∂j₂ and `b` to ∂²Ŵ/∂j₂² (both 0
/// with γ held; the consistent coupling's terms otherwise, see [`crate::active::coupling`]).
/// With second derivatives, `tangent` receives Σ_j (Ŵ_j + a e₂)_j ∂²j/∂F² + φ D_eᵀ H D_e +
/// b D₂ D₂ᵀ, written in place (every entry overwritten). Nothing is checked here: the caller
/// checks what it returns ([`check_returned`]).
#[inline(always)]
pub(crate) fn in_f_space<const N: usize>(
    kinematics: &Kinematics,
    entries: &Entries<N>,
    d: &InvariantDerivatives,
    (a, b): (f64, f64),
    tangent: Option<&mut SMatrix<f64, N, N>>,
) -> FSpace<N> {
    let grad = kinematics.gradients(entries);
    let mut w = d.d_j;
    w[1] += a;
    let fibre_gradient: SVector<f64, N> = grad.row(1).transpose();
    let mut out = FSpace {
        stress: grad.tr_mul(&w),
        dstress_dgamma: None,
        fibre_gradient,
    };
    if let (Some(s), Some(t)) = (&d.second, tangent) {
        kinematics.curvature_into(&w, entries, t);
        let h = &s.energy_hessian;
        // The rows of H in use (H is symmetric: its rows are its columns); any non-zero entry,
        // NaN included, counts.
        let nonzero = |r: usize, n: usize| (0..n).fold(false, |any, k| any | (h[(r, k)] != 0.0));
        if nonzero(4, 5) {
            add_congruence::<5, N>(t, &d.map, &grad, h);
        } else if nonzero(2, 4) | nonzero(3, 4) {
            add_congruence::<4, N>(t, &d.map, &grad, h);
        } else {
            add_congruence::<2, N>(t, &d.map, &grad, h);
        }
        if b != 0.0 {
            for x in 0..N {
                for y in 0..N {
                    t[(x, y)] += b * fibre_gradient[x] * fibre_gradient[y];
                }
            }
        }
        out.dstress_dgamma = Some(grad.tr_mul(&s.d_jgamma));
    }
    out
}

/// T += φ Eᵀ H E for a symmetric H whose rows and columns beyond the first `R` are zero, E = A D
/// the gradients of the elastic invariants (rows; only the first `R` are formed): G = φ H E
/// over those rows once, then the upper triangle (Eᵀ G)_ab = Σ_j E_ja G_jb, mirrored. All loop
/// bounds are constants (unrolled; the test on b folds away).
#[inline(always)]
fn add_congruence<const R: usize, const N: usize>(
    t: &mut SMatrix<f64, N, N>,
    map: &StrainMap,
    d: &SMatrix<f64, 5, N>,
    h: &SMatrix<f64, 5, 5>,
) {
    let e: [[f64; N]; R] = std::array::from_fn(|r| std::array::from_fn(|k| map.row(r, d, k)));
    let mut g = [[0.0; N]; R];
    for j in 0..R {
        for b in 0..N {
            let mut v = 0.0;
            for l in 0..R {
                v += h[(j, l)] * e[l][b];
            }
            g[j][b] = map.det * v;
        }
    }
    for a in 0..N {
        for b in 0..N {
            if b >= a {
                let mut v = 0.0;
                for j in 0..R {
                    v += e[j][a] * g[j][b];
                }
                t[(a, b)] += v;
                if b != a {
                    t[(b, a)] += v;
                }
            }
        }
    }
}
