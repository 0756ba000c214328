//! Where an activation law holds: the fibre stretches and effective damages it was fitted on. A
//! law that solves its equation (implicit, energy) holds wherever it has a root; a fitted
//! approximation (the chapter's explicit law, eq. (14)) holds only on its [`Domain`], and a
//! result outside it must say so ([`OutsideDomain`]).

use crate::active::drive::Drive;
use crate::text::significant;
use std::fmt;

/// The closed ranges of fibre stretch λ_f and effective damage
/// d_eff = 1 − (1 − d)·a·f_v on which a law holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Domain {
    /// [λ_lo, λ_hi] of the fibre stretch [-].
    pub stretch: [f64; 2],
    /// [lo, hi] of the effective damage [-] (d_eff = 1, no activation, is exact for every law:
    /// γ = 0).
    pub effective_damage: [f64; 2],
    /// Where the domain comes from and what the law does outside it, for messages.
    pub why: &'static str,
}

/// How far (relative) a fibre stretch may lie beyond an end of [`Domain::stretch`] and still
/// count as inside: an FE solution holds λ_f = 0.7 of a cylinder stretched to 0.7 with sliding
/// bases only to its Newton tolerance (1e-10 by default).
pub const STRETCH_TOLERANCE: f64 = 1e-9;

/// Why a law is evaluated outside its [`Domain`]: the value that left it (the stretch is checked
/// after the damage).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OutsideDomain {
    /// The effective damage d_eff [-] is outside `Domain::effective_damage`.
    EffectiveDamage(f64),
    /// The fibre stretch λ_f [-] is outside `Domain::stretch`.
    Stretch(f64),
}

impl Domain {
    /// Whether the effective damage `d_eff` lies in the domain, or is 1 (no activation, γ = 0
    /// exactly).
    pub fn holds_at_damage(&self, d_eff: f64) -> bool {
        let [lo, hi] = self.effective_damage;
        d_eff == 1.0 || (lo..=hi).contains(&d_eff)
    }

    /// Where fibre stretch `lambda` under `drive` leaves the domain, if it does: d_eff at λ
    /// ([`Drive::effective_damage_at`], with the force–velocity factor) first, then λ, whose
    /// ends are widened by [`STRETCH_TOLERANCE`].
    pub fn outside(&self, lambda: f64, drive: &Drive) -> Option<OutsideDomain> {
        let d_eff = drive.effective_damage_at(lambda);
        let [lo, hi] = self.stretch;
        let (lo, hi) = (
            lo * (1.0 - STRETCH_TOLERANCE),
            hi * (1.0 + STRETCH_TOLERANCE),
        );
        if !self.holds_at_damage(d_eff) {
            Some(OutsideDomain::EffectiveDamage(d_eff))
        } else if !(lo..=hi).contains(&lambda) {
            Some(OutsideDomain::Stretch(lambda))
        } else {
            None
        }
    }

    /// `0.7 ≤ λ_f ≤ 1.5 and 0 ≤ d_eff ≤ 0.5`.
    pub fn describe(&self) -> String {
        let [l0, l1] = self.stretch;
        let [d0, d1] = self.effective_damage;
        format!("{l0} ≤ λ_f ≤ {l1} and {d0} ≤ d_eff ≤ {d1}")
    }
}

impl fmt::Display for OutsideDomain {
    /// `λ_f = 1.6` or `d_eff = 0.999`.
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            OutsideDomain::EffectiveDamage(d) => write!(f, "d_eff = {}", significant(*d, 6)),
            OutsideDomain::Stretch(l) => write!(f, "λ_f = {}", significant(*l, 6)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const D: Domain = Domain {
        stretch: [0.7, 1.5],
        effective_damage: [0.0, 0.5],
        why: "",
    };

    #[test]
    fn the_ends_belong_to_the_domain_and_no_activation_is_exact() {
        let drive = |d: f64, a: f64| Drive::new(d, a).unwrap();
        assert_eq!(D.outside(0.7, &drive(0.5, 1.0)), None);
        assert_eq!(D.outside(1.5, &drive(0.0, 0.5)), None);
        assert_eq!(D.outside(0.7 - 1e-12, &drive(0.0, 1.0)), None);
        assert!(D.outside(0.7 - 1e-6, &drive(0.0, 1.0)).is_some());
        assert_eq!(D.outside(1.0, &drive(1.0, 1.0)), None);
        assert_eq!(D.outside(1.0, &drive(0.0, 0.0)), None);
        assert_eq!(
            D.outside(1.0, &drive(0.0, 1e-6)),
            Some(OutsideDomain::EffectiveDamage(1.0 - 1e-6))
        );
        assert_eq!(
            D.outside(1.6, &drive(0.0, 1.0)),
            Some(OutsideDomain::Stretch(1.6))
        );
        // a > 1 asks for more than the fitted target: d_eff < 0.
        assert!(matches!(
            D.outside(1.0, &drive(0.0, 1.5)),
            Some(OutsideDomain::EffectiveDamage(d)) if d < 0.0
        ));
    }
}
