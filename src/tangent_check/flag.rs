//! Why an observed order leaves its band ([`Flag`]): the first pair of steps (largest h first)
//! where the order of r₀ lies outside [0.5, 2.5] or that of r₁ outside [1.5, 3.5] (expected: 1 and 2;
//! a smooth remainder's higher terms can raise an order towards 3, never this far), with its
//! cause. Below the band the order dropped (a kink or a jump inside the segment, a wrong
//! tangent); above it, the remainder at the pair's larger step is inflated by a kink or a jump
//! the smaller step does not reach. The cause, in this order of precedence:
//!
//! 1. the segment [F, F + hΔF] of that pair's larger step crosses an [`Edge`] of the material
//!    (the fibre stretch |(F + tΔF) m| passes the edge's value for some t ∈ [0, h]);
//! 2. the tangent is an approximation by choice ([`Known::approximate`]);
//! 3. the tangent differs from central differences of the stress by more than
//!    [`WRONG_TANGENT`] (relative): it is not the stress's derivative;
//! 4. both orders lie in their bands on every smaller pair (at least two): the larger steps
//!    reach beyond the scale on which the stress curves (`large-steps`);
//! 5. none of these: unexplained (for r₀, a jump of the stress the material does not know of).

use super::material::{Edge, Known};
use nalgebra::{Matrix3, Vector3};

/// The band of the pair orders of r₀ (expected 1).
pub const BAND_0: (f64, f64) = (0.5, 2.5);
/// The band of the pair orders of r₁ (expected 2).
pub const BAND_1: (f64, f64) = (1.5, 3.5);
/// A central-difference tangent further than this from A (relative, Frobenius) says that A is
/// not the stress's derivative; the differences themselves are ≈ 1e-10 accurate.
pub const WRONG_TANGENT: f64 = 1e-6;

/// Why an order dropped.
#[derive(Debug, Clone, PartialEq)]
pub enum Cause {
    /// The segment crosses a fibre stretch where the material is not smooth.
    Edge(Edge),
    /// The tangent is an approximation by choice (the reason).
    Approximate(String),
    /// The tangent is not the stress's derivative: central differences differ by `fd_error`.
    Tangent {
        /// ‖A_fd − A‖/‖A‖.
        fd_error: f64,
    },
    /// No edge, central differences agree with A, and both orders lie in their bands on every
    /// smaller pair of steps (at least two), from `from` down: the larger steps reach beyond
    /// the scale on which the stress curves (a stiff exponential or volumetric term).
    LargeSteps {
        /// The largest step from which the orders lie in their bands.
        from: f64,
    },
    /// No edge, and central differences agree with A (or could not be taken).
    Unexplained {
        /// ‖A_fd − A‖/‖A‖, if the differences could be taken.
        fd_error: Option<f64>,
    },
}

/// An order that dropped, where, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct Flag {
    /// Which remainder: 0 (r₀) or 1 (r₁).
    pub remainder: u8,
    /// The order observed on the first pair that dropped.
    pub order: f64,
    /// That pair's larger step h.
    pub h: f64,
    /// Why.
    pub cause: Cause,
}

impl Flag {
    /// A short key for tables: the edge's kind, `approximate`, `wrong-tangent` or `unexplained`.
    pub fn kind(&self) -> &'static str {
        match &self.cause {
            Cause::Edge(e) => e.kind,
            Cause::Approximate(_) => "approximate",
            Cause::Tangent { .. } => "wrong-tangent",
            Cause::LargeSteps { .. } => "large-steps",
            Cause::Unexplained { .. } => "unexplained",
        }
    }

    /// The flag in words: which order, from which step, and the cause.
    pub fn reason(&self) -> String {
        let order = format!(
            "r{} order {} from h = {}",
            if self.remainder == 0 { "₀" } else { "₁" },
            crate::text::significant(self.order, 3),
            crate::text::significant(self.h, 3)
        );
        let cause = match &self.cause {
            Cause::Edge(e) => format!("the segment [F, F + hΔF] crosses {}", e.what),
            Cause::Approximate(why) => format!("the tangent is {why}"),
            Cause::Tangent { fd_error } => format!(
                "the tangent is not the stress's derivative: central differences of the stress differ from it by {} (relative)",
                crate::text::significant(*fd_error, 3)
            ),
            Cause::LargeSteps { from } => format!(
                "the orders lie in their bands from h = {} down, and no edge of the model lies on the segment: the larger steps reach beyond the scale on which the stress curves (a stiff exponential or volumetric term); a smaller h.largest tests the tangent",
                crate::text::significant(*from, 3)
            ),
            Cause::Unexplained { fd_error } => format!(
                "no edge of the model lies on the segment and central differences agree with the tangent to {}",
                fd_error.map_or("(not computed)".to_string(), |e| crate::text::significant(e, 3))
            ),
        };
        format!("{order}: {cause}")
    }
}

/// The pair after `k` from which every pair of both orders lies in its band, if there are at
/// least two such pairs and no pair after `k` leaves a band.
fn settles((orders_0, orders_1): (&[Option<f64>], &[Option<f64>]), k: usize) -> Option<usize> {
    let inside = |o: &[Option<f64>], (lo, hi): (f64, f64)| {
        let v: Vec<f64> = o
            .get(k + 1..)
            .unwrap_or(&[])
            .iter()
            .flatten()
            .copied()
            .collect();
        v.len() >= 2 && v.iter().all(|x| *x >= lo && *x <= hi)
    };
    (inside(orders_0, BAND_0) && inside(orders_1, BAND_1)).then_some(k + 1)
}

/// The first pair whose order lies outside `band`: (its index, its order).
fn first_off(orders: &[Option<f64>], (lo, hi): (f64, f64)) -> Option<(usize, f64)> {
    orders
        .iter()
        .enumerate()
        .find_map(|(k, o)| o.filter(|o| *o < lo || *o > hi).map(|o| (k, o)))
}

/// Whether the fibre stretch |(F + tΔF) m| reaches `level` for some t ∈ [0, h]: its square
/// a + 2bt + ct² (a = |Fm|², b = Fm·ΔFm, c = |ΔFm|²) spans [min, max] on the interval, the vertex
/// included where it lies inside.
pub fn crosses(f: &Matrix3<f64>, df: &Matrix3<f64>, m: &Vector3<f64>, h: f64, level: f64) -> bool {
    let (fm, dm) = (f * m, df * m);
    let (a, b, c) = (fm.norm_squared(), fm.dot(&dm), dm.norm_squared());
    let at = |t: f64| a + 2.0 * b * t + c * t * t;
    let mut values = vec![at(0.0), at(h)];
    if c > 0.0 && -b / c > 0.0 && -b / c < h {
        values.push(at(-b / c));
    }
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, u), v| {
            (l.min(*v), u.max(*v))
        });
    // A segment that starts on the level crosses it: |Fm|² and (|Fm|)² may differ in the last bit.
    let target = level * level;
    let touch = 1e-12 * target;
    lo <= target + touch && target - touch <= hi
}

/// The flag of a Taylor test at F along `df` (unit) with steps `h` and pair orders `orders_0`,
/// `orders_1`, or `None` if every order lies in its band (module docs).
pub fn attribute<const N: usize>(
    (f, df): (&Matrix3<f64>, &Matrix3<f64>),
    h: &[f64],
    (orders_0, orders_1): (&[Option<f64>], &[Option<f64>]),
    known: &Known<N>,
    fd_error: Option<f64>,
) -> Option<Flag> {
    // The pair of the largest step where either order leaves its band (r₀ first on a tie).
    let (remainder, (k, order)) = match (first_off(orders_0, BAND_0), first_off(orders_1, BAND_1)) {
        (Some(a), Some(b)) if b.0 < a.0 => (1u8, b),
        (Some(a), _) => (0u8, a),
        (None, Some(b)) => (1u8, b),
        (None, None) => return None,
    };
    let edge = known.fibre.and_then(|m| {
        known
            .edges
            .iter()
            .find(|e| crosses(f, df, &m, h[k], e.fibre_stretch))
    });
    let cause = match (edge, &known.approximate) {
        (Some(e), _) => Cause::Edge(e.clone()),
        (None, Some(why)) if remainder == 1 => Cause::Approximate(why.clone()),
        _ => match fd_error {
            Some(e) if remainder == 1 && e > WRONG_TANGENT => Cause::Tangent { fd_error: e },
            _ => match settles((orders_0, orders_1), k) {
                Some(from) => Cause::LargeSteps { from: h[from] },
                None => Cause::Unexplained { fd_error },
            },
        },
    };
    Some(Flag {
        remainder,
        order,
        h: h[k],
        cause,
    })
}
