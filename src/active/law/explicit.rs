use super::{ActivationLaw, Domain, LawValue, OutsideDomain};
use crate::active::curve::ActiveCurve;
use crate::active::drive::Drive;
use crate::active::strain::check_activation;
use crate::energy::{positive, GiantesioMusesti, ScalarWith};
use crate::{Error, Result, Scalar};
use num_dual::{first_derivative, second_derivative};

/// The chapter's closed-form activation law (eq. D:gamma), a first fixed-point step for the
/// exponent of eq. D:eqgammaesplicita with fitted a, b:
///
/// γ(λ) = a [ r(g(λ_min), λ_min) λ_min − r(g(λ), λ) λ ] for λ > λ_min, 0 otherwise,
/// r(g, λ) = sqrt( (1 − 2w0/3) / (g/α + w0/(3λ)) ),
/// g(λ) = ln α + α(1 − w0/λ) − ½ ln((1 − 2w0/3)/q) + ln{ b (2/μ)[(1 − d) P_act + P_pas]
///        + sqrt((1 − 2w0/3)/q) [ (1 − 2w0/3)²/q − λ w0/3 ] },  q = 1/α + w0/(3λ),
///
/// with P_pas of eq. D:Ppas and the chapter's energy parameters (μ, α, w0), and the target
/// T = (1 − d)·a·f_v·P_act ([`Drive::target`]) in place of the printed (1 − d) P_act. Defaults
/// a = 1.0133, b = 0.2050.
///
/// Where the target is 0 at every stretch (d = 1, a = 0) the law gives γ = 0, as every law does:
/// the formula itself would give the approximation's own offset there (at d = 1, γ(0.8) ≈ 0.18 and
/// at λ = 1.2 a stress 56 % above the passive one). Just above λ_min, where the chapter's P_act
/// underflows to 0 but the drive is on, the formula is kept: it tends to 0 there continuously.
///
/// Fast: one formula, derivatives by dual numbers. As printed, γ stays positive up to λ ≈ 1.73
/// (the chapter says 1.6); beyond its zero crossing this implementation returns γ = 0 ("one can
/// even neglect the activation for large stretches"), so the law has a kink there.
///
/// **Its domain** ([`ExplicitLaw::DOMAIN`]) is what it was fitted on and what the chapter uses
/// it for: 0.7 ≤ λ_f ≤ 1.5 (the chapter fits a, b at d = 0 on "0.7 < λ < 1.5"; the fit redone
/// in `scenes/paper.toml` includes both ends) and 0 ≤ d_eff ≤ 0.5 (the chapter scales P_act by
/// (1 − d) for d ≤ 0.5), with d_eff = 1 − (1 − d)·a·f_v: activation levels, regions and the
/// force–velocity factor enter as damage does. There (frozen, d = 0 and 0.5, measured on a
/// grid of 0.005) it follows the implicit γ within 0.021 (0.004 on [0.8, 1.5]) and its stress
/// within 3.1 kPa up to λ = 1.3 and 13.4 kPa (2.3 %) at λ = 1.5. Outside it the formula is evaluated all the same, but it is no
/// approximation of the implicit law: as the target vanishes (d_eff → 1) it keeps γ ≈ 0.19,
/// so a block at a = 1e-6 contracts freely to λ = 0.736 (the implicit law: 0.9999) and at
/// d = 0.999999 P(1) = 0.25 kPa where the target is 6.3e-5 kPa; exactly at d_eff = 1 it gives
/// γ = 0, a jump. Hence ([`ExplicitLaw::outside`]) the scenes refuse what is bound to leave the
/// domain (a damage in (0.5, 1), an activation schedule or a region with d_eff in (0.5, 1) or
/// below 0) and flag every computed point that leaves it on the way (a stretch outside
/// [0.7, 1.5], a force–velocity factor that moves d_eff out): the `in_domain` column, an
/// OUTSIDE line in the summary and the report (`docs/explicit_law.md`). Where it gives γ = 0
/// exactly as every law does (λ_f ≤ λ_min, d_eff = 1) it holds everywhere.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExplicitLaw {
    a: f64,
    b: f64,
    passive: GiantesioMusesti,
    curve: ActiveCurve,
    /// r(g(λ_min), λ_min) λ_min with this b, γ's constant first term (over a), computed once:
    /// it was 2 logarithms and an exponential at every evaluation.
    start: f64,
}

impl ExplicitLaw {
    /// Where eq. (14) holds: 0.7 ≤ λ_f ≤ 1.5 and 0 ≤ d_eff ≤ 0.5 (see the type's doc).
    pub const DOMAIN: Domain = Domain {
        stretch: [0.7, 1.5],
        effective_damage: [0.0, 0.5],
        why: "eq. (14) is fitted at d = 0 on 0.7 < λ < 1.5 and the chapter uses it up to \
              d = 0.5; outside, it keeps γ ≈ 0.19 as the target vanishes: at d = 0.999999, \
              P(1) = 0.25 kPa where the target is 6.3e-5 kPa",
    };

    /// Where γ at `lambda` under `drive` leaves [`Self::DOMAIN`], if it does; `None` where the
    /// law gives γ = 0 exactly (λ ≤ λ_min, no activation), whatever λ and d_eff.
    pub fn outside(&self, lambda: f64, drive: impl Into<Drive>) -> Option<OutsideDomain> {
        let drive = drive.into();
        if lambda <= self.curve.lambda_min() || drive.is_off() {
            return None;
        }
        Self::DOMAIN.outside(lambda, &drive)
    }

    /// a [-] > 0, b [-] > 0, the chapter's energy parameters and the active curve.
    pub fn new(a: f64, b: f64, passive: GiantesioMusesti, curve: ActiveCurve) -> Result<Self> {
        let mut law = Self {
            a: positive("a", a)?,
            b: positive("b", b)?,
            passive,
            curve,
            start: f64::NAN,
        };
        law.start = law.start(law.b);
        Ok(law)
    }

    /// The chapter's a = 1.0133, b = 0.2050 with its energy and active curve.
    pub fn paper() -> Self {
        Self::new(
            1.0133,
            0.2050,
            GiantesioMusesti::paper(),
            ActiveCurve::paper(),
        )
        .expect("the chapter's a and b are positive")
    }

    /// Fitting parameters (a, b).
    pub fn coefficients(&self) -> (f64, f64) {
        (self.a, self.b)
    }

    /// The active curve the law reproduces.
    pub fn curve(&self) -> &ActiveCurve {
        &self.curve
    }

    /// P_pas(λ) of eq. D:Ppas \[kPa\].
    fn passive_stress<T: Scalar>(&self, l: T) -> T {
        let (mu, al, w0) = (self.passive.mu(), self.passive.alpha(), self.passive.w0());
        let f = 1.0 - 2.0 * w0 / 3.0;
        let inv = l.recip();
        let expo = ((l * l * f + inv * (2.0 * w0 / 3.0) - 1.0) * al).exp();
        ((l * f - inv * inv * (w0 / 3.0)) * expo - inv * inv * inv * f + w0 / 3.0) * (mu / 2.0)
    }

    /// g(λ) of eq. D:gamma, with b as `f64` or a dual number.
    fn g<P: Scalar, T: ScalarWith<P>>(&self, l: T, active: T, b: P) -> T {
        let (mu, al, w0) = (self.passive.mu(), self.passive.alpha(), self.passive.w0());
        let f = 1.0 - 2.0 * w0 / 3.0;
        let q = l.recip() * (w0 / 3.0) + 1.0 / al;
        let ratio = q.recip() * f;
        let bracket = (active + self.passive_stress(l)) * (b * 2.0 / mu)
            + ratio.sqrt() * (q.recip() * (f * f) - l * (w0 / 3.0));
        (-l.recip() * w0 + 1.0) * al + al.ln() - ratio.ln() * 0.5 + bracket.ln()
    }

    /// r(g, λ) λ.
    fn scaled_root<T: Scalar>(&self, g: T, l: T) -> T {
        let (al, w0) = (self.passive.alpha(), self.passive.w0());
        let f = 1.0 - 2.0 * w0 / 3.0;
        ((g / al + l.recip() * (w0 / 3.0)).recip() * f).sqrt() * l
    }

    /// r(g(λ_min), λ_min) λ_min for the coefficient b: γ = a (start − r(g(λ), λ) λ).
    fn start<P: Scalar>(&self, b: P) -> P {
        let lmin = P::from(self.curve.lambda_min());
        self.scaled_root(self.g(lmin, P::zero(), b), lmin)
    }

    /// γ(λ) on any scalar, clamped at 0 beyond its zero crossing. Errors if the formula leaves
    /// its domain (a logarithm or square root of a non-positive number) or γ ≥ 1.
    pub fn gamma<T: Scalar>(&self, lambda: T, drive: impl Into<Drive>) -> Result<T> {
        self.gamma_from(self.a, self.b, || self.start, lambda, drive)
    }

    /// γ(λ) of eq. D:gamma, written once, with (a, b) as `f64` ([`gamma`](Self::gamma)) or dual
    /// numbers (derivatives in a and b, for fitting); the energy and the curve are this law's.
    /// The values of a and b are not checked here.
    pub fn gamma_with<P: Scalar, T: ScalarWith<P>>(
        &self,
        a: P,
        b: P,
        lambda: T,
        drive: impl Into<Drive>,
    ) -> Result<T> {
        self.gamma_from(a, b, || self.start(b), lambda, drive)
    }

    /// γ(λ) with (a, b) and the constant term `start` (evaluated only where γ may be nonzero).
    fn gamma_from<P: Scalar, T: ScalarWith<P>>(
        &self,
        a: P,
        b: P,
        start: impl FnOnce() -> P,
        lambda: T,
        drive: impl Into<Drive>,
    ) -> Result<T> {
        let drive = drive.into();
        drive.check()?;
        let damage = drive.damage();
        let lmin = self.curve.lambda_min();
        if lambda <= lmin {
            return Ok(T::zero());
        }
        if drive.is_off() {
            return Ok(T::zero());
        }
        let active = drive.target(&self.curve, lambda);
        let gamma = (-self.scaled_root(self.g(lambda, active, b), lambda) + start()) * a;
        if !gamma.re().is_finite() {
            return Err(Error::NonFinite {
                quantity: "explicit activation gamma",
                value: gamma.re(),
                context: format!(
                    "at lambda = {}, d = {}: eq. (14) left its domain (a logarithm or square root of a non-positive number)",
                    crate::text::shortest(lambda.re()),
                    crate::text::shortest(damage)
                ),
            });
        }
        if gamma.re() < 0.0 {
            return Ok(T::zero());
        }
        check_activation(gamma.re())?;
        Ok(gamma)
    }
}

impl ActivationLaw for ExplicitLaw {
    fn evaluate(&self, lambda: f64, drive: impl Into<Drive>) -> Result<LawValue> {
        let drive = drive.into();
        let (gamma, slope, curvature) = second_derivative(|l| self.gamma(l, drive), lambda)?;
        Ok(LawValue {
            gamma,
            slope,
            curvature,
        })
    }

    fn activation(&self, lambda: f64, drive: impl Into<Drive>) -> Result<f64> {
        self.gamma(lambda, drive)
    }

    fn gamma_and_slope(&self, lambda: f64, drive: impl Into<Drive>) -> Result<(f64, f64)> {
        let drive = drive.into();
        first_derivative(|l| self.gamma(l, drive), lambda)
    }

    fn gamma<T: Scalar>(&self, lambda: T, drive: impl Into<Drive>) -> Result<T> {
        ExplicitLaw::gamma(self, lambda, drive)
    }

    fn outside(&self, lambda: f64, drive: impl Into<Drive>) -> Option<OutsideDomain> {
        ExplicitLaw::outside(self, lambda, drive)
    }
}
