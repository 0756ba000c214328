//! The Taylor test of a material at a state ([`taylor_test`]): what is checked once per state
//! ([`state_report`]: central differences, symmetry, approximate tangents, ellipticity) and per
//! direction ([`remainders`]: r₀(h), r₁(h), their orders and the flag). The equations are in
//! the [module docs](super).

use super::differences::central_differences;
use super::flag::{attribute, Flag};
use super::material::{Known, TangentMaterial};
use crate::stability::Ellipticity;
use crate::{Error, Result};
use nalgebra::{Matrix3, SMatrix, SVector};

/// Remainders below this many ε times the size of the stress's terms, ‖P‖ + ‖A‖ ‖F‖, are
/// rounding, not truncation (module docs).
pub const FLOOR_EPSILONS: f64 = 1e3;

/// The most steps a test takes (halvings from just below 1 reach 2⁻⁶⁰ within this).
pub const MAX_STEPS: usize = 60;

/// What is checked once at a state.
#[derive(Debug, Clone, PartialEq)]
pub struct StateReport {
    /// ‖P‖ \[kPa\].
    pub stress_norm: f64,
    /// ‖A‖ \[kPa\].
    pub tangent_norm: f64,
    /// ‖A_fd − A‖/‖A‖ of the central-difference tangent (`None`: a stress near F could not be
    /// evaluated, see `fd_failure`).
    pub fd_error: Option<f64>,
    /// Why the differences could not be taken.
    pub fd_failure: Option<String>,
    /// ‖A − Aᵀ‖/‖A‖.
    pub asymmetry: f64,
    /// The same of A_fd: equal to `asymmetry` where the stress is not a gradient, ≈ 0 where
    /// only the tangent is not symmetric.
    pub fd_asymmetry: Option<f64>,
    /// The material's reason for an asymmetric tangent, where it has one.
    pub asymmetry_reason: Option<String>,
    /// ‖Ã − A‖/‖A‖ of each approximate tangent Ã, by name.
    pub approximations: Vec<(String, f64)>,
    /// Strong ellipticity, where the material can tell.
    pub ellipticity: Option<Ellipticity>,
    /// What else the material says of the state.
    pub notes: Vec<String>,
}

/// The remainders along one direction and what their orders say.
#[derive(Debug, Clone, PartialEq)]
pub struct Remainders {
    /// The steps h, descending.
    pub h: Vec<f64>,
    /// r₀(h) (`None`: the stress could not be evaluated at F + hΔF).
    pub r0: Vec<Option<f64>>,
    /// r₁(h).
    pub r1: Vec<Option<f64>>,
    /// Order of r₀ on each pair (h_k, h_{k+1}) (`None`: a remainder below the floor or missing).
    pub orders_0: Vec<Option<f64>>,
    /// Order of r₁ on each pair.
    pub orders_1: Vec<Option<f64>>,
    /// The median of the pair orders of r₀.
    pub order_0: Option<f64>,
    /// The median of the pair orders of r₁.
    pub order_1: Option<f64>,
    /// The least pair order of r₁.
    pub least_order_1: Option<f64>,
    /// The rounding floor η (module docs).
    pub floor: f64,
    /// The largest step at which the stress could not be evaluated, and why.
    pub unevaluable: Option<(f64, String)>,
    /// The first drop of an order and its cause.
    pub flag: Option<Flag>,
}

/// A Taylor test at one state along one direction.
#[derive(Debug, Clone, PartialEq)]
pub struct TaylorReport {
    /// What is checked at the state.
    pub state: StateReport,
    /// The remainders along the direction.
    pub remainders: Remainders,
}

/// h = 2⁻ᵏ for every k with `smallest` ≤ 2⁻ᵏ ≤ `largest`, descending. Both must lie in (0, 1)
/// with `largest` > `smallest`, and give at least three steps (two pairs) and at most
/// [`MAX_STEPS`].
pub fn halvings(largest: f64, smallest: f64) -> Result<Vec<f64>> {
    for (name, v) in [("h.largest", largest), ("h.smallest", smallest)] {
        if !(v > 0.0 && v < 1.0) {
            return Err(Error::InvalidParameter {
                name,
                value: v,
                rule: "a step must lie in (0, 1)",
            });
        }
    }
    let first = (-largest.log2()).ceil() as i32;
    let last = (-smallest.log2()).floor() as i32;
    let count = (last - first + 1).max(0) as usize;
    if count < 3 {
        return Err(Error::InvalidParameter {
            name: "h.smallest",
            value: smallest,
            rule: "the range must hold at least three powers of two 2^-k (two pairs of steps for an order)",
        });
    }
    if count > MAX_STEPS {
        return Err(Error::InvalidParameter {
            name: "h.smallest",
            value: smallest,
            rule: "the range holds more than 60 powers of two: below 2^-60 every remainder is rounding",
        });
    }
    Ok((first..=last).map(|k| 2f64.powi(-k)).collect())
}

/// F's entries in `entries`' order.
fn entries_of<const N: usize, M: TangentMaterial<N> + ?Sized>(
    material: &M,
    f: &Matrix3<f64>,
) -> SVector<f64, N> {
    let entries = material.entries();
    SVector::from_fn(|a, _| {
        let (i, j) = entries.index[a];
        f[(i, j)]
    })
}

/// ‖x‖/‖y‖, or ‖x‖ where y vanishes.
fn relative(x: f64, y: f64) -> f64 {
    if y > 0.0 {
        x / y
    } else {
        x
    }
}

/// What is checked once at F, where the material has stress `p`, tangent `a` and says `known`.
pub fn state_report<const N: usize, M: TangentMaterial<N> + ?Sized>(
    material: &M,
    f: &Matrix3<f64>,
    (p, a): (&SVector<f64, N>, &SMatrix<f64, N, N>),
    known: &Known<N>,
) -> StateReport {
    let norm = a.norm();
    let asymmetry = |t: &SMatrix<f64, N, N>| relative((t - t.transpose()).norm(), t.norm());
    let fd = central_differences(material, f);
    StateReport {
        stress_norm: p.norm(),
        tangent_norm: norm,
        fd_error: fd.as_ref().ok().map(|d| relative((d - a).norm(), norm)),
        fd_failure: fd.as_ref().err().map(ToString::to_string),
        asymmetry: asymmetry(a),
        fd_asymmetry: fd.as_ref().ok().map(asymmetry),
        asymmetry_reason: known.asymmetry.clone(),
        approximations: known
            .approximations
            .iter()
            .map(|x| (x.name.clone(), relative((x.tangent - a).norm(), norm)))
            .collect(),
        ellipticity: known.ellipticity,
        notes: known.notes.clone(),
    }
}

/// ΔF over the material's entries, scaled to unit norm; an entry outside them, a non-finite
/// entry or ΔF = 0 is refused.
fn unit_direction<const N: usize, M: TangentMaterial<N> + ?Sized>(
    material: &M,
    df: &Matrix3<f64>,
) -> Result<(Matrix3<f64>, SVector<f64, N>)> {
    let entries = material.entries();
    let mut inside = Matrix3::zeros();
    for &(i, j) in &entries.index {
        inside[(i, j)] = df[(i, j)];
    }
    let bad = |value: f64, rule| Error::InvalidParameter {
        name: "dF",
        value,
        rule,
    };
    if let Some(v) = df.iter().find(|v| !v.is_finite()) {
        return Err(bad(*v, "every entry of the direction must be finite"));
    }
    if let Some(v) = (df - inside).iter().find(|v| **v != 0.0) {
        return Err(bad(
            *v,
            "the direction has an entry the material does not vary (an axisymmetric material varies F_rr, F_rz, F_zr, F_zz, F_θθ only)",
        ));
    }
    let norm = inside.norm();
    if norm == 0.0 {
        return Err(bad(0.0, "the direction must not be zero"));
    }
    let unit = inside / norm;
    Ok((unit, entries_of(material, &unit)))
}

/// The median of the values.
pub(crate) fn median(mut v: Vec<f64>) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    Some(if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    })
}

/// The order of each pair of consecutive steps whose remainders both lie above `floor`.
pub fn pair_orders(h: &[f64], r: &[Option<f64>], floor: f64) -> Vec<Option<f64>> {
    (0..h.len().saturating_sub(1))
        .map(|k| match (r[k], r[k + 1]) {
            (Some(a), Some(b)) if a > floor && b > floor => {
                Some((a / b).ln() / (h[k] / h[k + 1]).ln())
            }
            _ => None,
        })
        .collect()
}

impl Remainders {
    /// The remainders `r0`, `r1` over the steps `h` (descending) with their pair orders above
    /// `floor`, the orders' medians and the least pair order of r₁; nothing unevaluable noted,
    /// no flag.
    pub(crate) fn of(h: Vec<f64>, r0: Vec<Option<f64>>, r1: Vec<Option<f64>>, floor: f64) -> Self {
        let (orders_0, orders_1) = (pair_orders(&h, &r0, floor), pair_orders(&h, &r1, floor));
        let valid = |o: &[Option<f64>]| o.iter().flatten().copied().collect::<Vec<_>>();
        let (order_0, order_1) = (median(valid(&orders_0)), median(valid(&orders_1)));
        let least_order_1 = valid(&orders_1).into_iter().reduce(f64::min);
        Self {
            h,
            r0,
            r1,
            orders_0,
            orders_1,
            order_0,
            order_1,
            least_order_1,
            floor,
            unevaluable: None,
            flag: None,
        }
    }
}

/// The remainders at F (stress `p`, tangent `a`, what the material says `known`, the
/// central-difference error `fd_error` of its [`StateReport`]) along `df` (scaled to unit norm)
/// for the steps `h` (each in (0, 1); sorted descending here).
pub fn remainders<const N: usize, M: TangentMaterial<N> + ?Sized>(
    material: &M,
    f: &Matrix3<f64>,
    (p, a): (&SVector<f64, N>, &SMatrix<f64, N, N>),
    (known, fd_error): (&Known<N>, Option<f64>),
    df: &Matrix3<f64>,
    h: &[f64],
) -> Result<Remainders> {
    let mut h = h.to_vec();
    if let Some(bad) = h.iter().find(|h| !(**h > 0.0 && **h < 1.0)) {
        return Err(Error::InvalidParameter {
            name: "h",
            value: *bad,
            rule: "every step must lie in (0, 1)",
        });
    }
    h.sort_by(|x, y| y.total_cmp(x));
    h.dedup();
    let (unit, dv) = unit_direction(material, df)?;
    let slope = a * dv;
    let (mut r0, mut r1) = (Vec::with_capacity(h.len()), Vec::with_capacity(h.len()));
    let mut unevaluable = None;
    for &step in &h {
        match material.stress_of(&(f + unit * step)) {
            Ok(ph) => {
                let change = ph - p;
                r0.push(Some(change.norm()));
                r1.push(Some((change - slope * step).norm()));
            }
            Err(e) => {
                unevaluable.get_or_insert((step, e.to_string()));
                r0.push(None);
                r1.push(None);
            }
        }
    }
    let floor =
        FLOOR_EPSILONS * f64::EPSILON * (p.norm() + a.norm() * entries_of(material, f).norm());
    let mut r = Remainders::of(h, r0, r1, floor);
    r.flag = attribute(
        (f, &unit),
        &r.h,
        (&r.orders_0, &r.orders_1),
        known,
        fd_error,
    );
    r.unevaluable = unevaluable;
    Ok(r)
}

/// Refuses an F with a non-finite entry or det F ≤ 0.
pub fn check_state(f: &Matrix3<f64>) -> Result<()> {
    if let Some(v) = f.iter().find(|v| !v.is_finite()) {
        return Err(Error::NonFinite {
            quantity: "entry of F",
            value: *v,
            context: format!("in F = {:?}", f.transpose()),
        });
    }
    let det = f.determinant();
    if det > 0.0 {
        Ok(())
    } else {
        Err(Error::NonPositiveJacobian {
            det,
            f: f.transpose().into(),
        })
    }
}

/// The Taylor test of `material` at F along ΔF = `df` (scaled to unit norm over the material's
/// entries) for the steps `h` (each in (0, 1), e.g. [`halvings`]): the remainders and their
/// orders, the flag where an order leaves its band, and what is checked at the state. Errors: F not
/// finite or det F ≤ 0, ΔF zero, non-finite or outside the material's entries, a step outside
/// (0, 1), and the material's own error at F (a stress that cannot be evaluated at F + hΔF is a
/// missing remainder instead, [`Remainders::unevaluable`]).
pub fn taylor_test<const N: usize, M: TangentMaterial<N> + ?Sized>(
    material: &M,
    f: &Matrix3<f64>,
    df: &Matrix3<f64>,
    h: &[f64],
) -> Result<TaylorReport> {
    check_state(f)?;
    let (p, a) = material.stress_and_tangent(f)?;
    let known = material.known(f, &a)?;
    let state = state_report(material, f, (&p, &a), &known);
    let remainders = remainders(material, f, (&p, &a), (&known, state.fd_error), df, h)?;
    Ok(TaylorReport { state, remainders })
}
