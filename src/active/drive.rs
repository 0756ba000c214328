//! What the activation laws reproduce: the target active stress along the fibres,
//!
//! T(λ) = (1 − d) · a · f_v(λ̇) · P_act(λ)  \[kPa\],
//!
//! with the damage d ∈ [0, 1] (loss of activation, the chapter's section 4), the activation
//! level a ≥ 0 (the recruited fraction of the optimal active stress; 1 is the chapter's
//! tetanised muscle; 4C's twitch trains, with P_opt = N_a, give a ≫ 1), the force–velocity factor
//! f_v of the fibre stretch rate λ̇ ([`ForceVelocity`]; 1 when the study is quasi-static) and the
//! active curve P_act ([`crate::active::curve`]). A [`Drive`] holds d, a and the rate state;
//! [`Drive::target`] is the one place that multiplies them, and [`Drive::work`] the one place
//! that scales ∫P_act for the energy law and the active-stress approach.

use crate::active::curve::ActiveCurve;
use crate::{Error, Result, Scalar};

/// The force–velocity factor of Böl & Reese (2008), as 4C's
/// `Mat::Utils::Muscle::evaluate_force_velocity_dependency_boel`, of the fibre stretch rate λ̇
/// \[1/s\] with r = λ̇/λ̇_min (λ̇_min < 0, the fastest shortening):
///
/// - lengthening, λ̇ > 0: f_v = (1 + d_e) − d_e (1 + r)/(1 − k_e k_c r);
/// - shortening or at rest, λ̇ ≤ 0: f_v = max(0, (1 − d_c) + d_c (1 − r)/(1 + k_c r)).
///
/// The parameters and their ranges (checked when a scene is read, [`Self::validated`]):
///
/// - λ̇_min (`min_rate`) < 0 \[1/s\]: the fastest shortening the curve describes, where the
///   fibre's force has fallen to f_v = 1 − d_c (Hill's maximal shortening velocity);
/// - d_c (`dc`) ∈ [0, 1]: how far the force falls from rest to λ̇_min (d_c = 1: to nothing);
///   1 − d_c is a fraction of the isometric force, so d_c > 1 would make it push;
/// - k_c (`kc`) ≥ 0: the curvature of the shortening branch (Hill's hyperbola; 0: a straight
///   line);
/// - d_e (`de`) ≥ 0: the force gained in lengthening: f_v rises from 1 towards
///   1 + d_e (1 + 1/(k_e k_c)) for fast lengthening (without bound when k_e k_c = 0);
/// - k_e (`ke`) ≥ 0: the curvature of the lengthening branch, with k_c.
///
/// With these ranges f_v(0) = 1 on both branches, f_v ≥ 1 when lengthening (the denominator
/// 1 − k_e k_c r ≥ 1), and f_v falls monotonically from 1 at rest to 1 − d_c ≥ 0 at λ̇_min.
/// Beyond the curve's range, shortening faster than |λ̇_min|, the formula goes on falling
/// towards 1 − d_c − d_c/k_c and turns negative (with d_c = 1, at once): there f_v is clamped at
/// 0 (a fibre shortening faster than it can contract carries no active force; the active
/// stress never pushes), and such a step is flagged by the study that computes it
/// ([`Self::within_range`]). The slopes at 0 are −d_e (1 + k_e k_c)/λ̇_min and
/// −d_c (1 + k_c)/λ̇_min, so the slope jumps at λ̇ = 0 unless they agree (as in 4C). d_e = d_c = 0
/// switches the dependence off. In a scene:
/// `force_velocity = { min_rate = -17.0, ke = 5.0, kc = 5.0, de = 0.5, dc = 1.0 }`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForceVelocity {
    /// λ̇_min \[1/s\] < 0: the fastest shortening rate (f_v = 1 − d_c there).
    pub min_rate: f64,
    /// k_e [-] ≥ 0: curvature of the lengthening branch.
    pub ke: f64,
    /// k_c [-] ≥ 0: curvature of the shortening branch.
    pub kc: f64,
    /// d_e [-] ≥ 0: amplitude of the lengthening branch.
    pub de: f64,
    /// d_c [-] ∈ [0, 1]: amplitude of the shortening branch (f_v = 1 − d_c at λ̇_min).
    pub dc: f64,
}

impl ForceVelocity {
    /// Validates λ̇_min < 0, k_e, k_c, d_e ≥ 0 and d_c ∈ [0, 1], all finite.
    pub fn new(min_rate: f64, ke: f64, kc: f64, de: f64, dc: f64) -> Result<Self> {
        let fv = Self {
            min_rate,
            ke,
            kc,
            de,
            dc,
        };
        fv.validated()
    }

    /// This factor, checked as [`new`](Self::new) checks it.
    pub fn validated(self) -> Result<Self> {
        let bad = |name, value, rule| Err(Error::InvalidParameter { name, value, rule });
        if !(self.min_rate.is_finite() && self.min_rate < 0.0) {
            return bad(
                "force_velocity.min_rate",
                self.min_rate,
                "must be finite and < 0 (the fastest shortening rate, 1/s)",
            );
        }
        for (name, v) in [
            ("force_velocity.ke", self.ke),
            ("force_velocity.kc", self.kc),
            ("force_velocity.de", self.de),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return bad(name, v, "must be finite and >= 0");
            }
        }
        if !(0.0..=1.0).contains(&self.dc) {
            return bad(
                "force_velocity.dc",
                self.dc,
                "must lie in [0, 1]: f_v = 1 - dc at the fastest shortening (min_rate) is a \
                 fraction of the isometric force, and dc > 1 would make the active stress push",
            );
        }
        Ok(self)
    }

    /// f_v(λ̇) [-] for any scalar (the branch, and the clamp at 0, chosen on the real part; a
    /// clamped factor is 0 with zero derivatives).
    pub fn factor<T: Scalar>(&self, rate: T) -> T {
        let r = rate / self.min_rate;
        if rate.re() > 0.0 {
            -(r + 1.0) * self.de / (-r * (self.ke * self.kc) + 1.0) + (1.0 + self.de)
        } else {
            let f = (-r + 1.0) * self.dc / (r * self.kc + 1.0) + (1.0 - self.dc);
            if f.re() < 0.0 {
                T::zero()
            } else {
                f
            }
        }
    }

    /// Whether the curve describes the rate `rate` \[1/s\]: no faster shortening than
    /// |λ̇_min|. Beyond it f_v is extrapolated (and clamped at 0 where it turns negative).
    pub fn within_range(&self, rate: f64) -> bool {
        rate >= self.min_rate
    }
}

/// The fibre stretch rate of one time step, by backward Euler: λ̇ = (λ − λ_prev)/Δt.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StretchRate {
    /// The force–velocity factor.
    pub law: ForceVelocity,
    /// λ_prev [-]: the fibre stretch at the end of the previous step.
    pub previous: f64,
    /// Δt \[s\] > 0.
    pub dt: f64,
}

impl StretchRate {
    /// λ̇(λ) \[1/s\] for any scalar: its derivative in λ is 1/Δt.
    pub fn rate<T: Scalar>(&self, lambda: T) -> T {
        (lambda - self.previous) / self.dt
    }
}

/// Rejects d ∉ [0, 1].
pub fn check_damage(damage: f64) -> Result<f64> {
    if (0.0..=1.0).contains(&damage) {
        Ok(damage)
    } else {
        Err(Error::InvalidParameter {
            name: "damage",
            value: damage,
            rule: "must lie in [0, 1]",
        })
    }
}

/// What scales the active curve at a point: damage d, activation level a and, in a time
/// study with force–velocity, the rate state. `Drive::from(d)` is the chapter's tetanised
/// muscle at damage d, quasi-static (a = 1, f_v = 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drive {
    damage: f64,
    level: f64,
    velocity: Option<StretchRate>,
}

impl From<f64> for Drive {
    /// Damage d, a = 1, quasi-static (checked where it is used: [`Drive::check`]).
    fn from(damage: f64) -> Self {
        Self {
            damage,
            level: 1.0,
            velocity: None,
        }
    }
}

impl Drive {
    /// Damage d ∈ [0, 1] and activation level a ≥ 0 (finite), quasi-static.
    pub fn new(damage: f64, level: f64) -> Result<Self> {
        let drive = Self {
            damage,
            level,
            velocity: None,
        };
        drive.check()?;
        Ok(drive)
    }

    /// The same drive with the stretch-rate state of a time step (force–velocity).
    pub fn with_rate(self, rate: StretchRate) -> Result<Self> {
        rate.law.validated()?;
        if !(rate.dt.is_finite() && rate.dt > 0.0 && rate.previous.is_finite()) {
            return Err(Error::InvalidParameter {
                name: "time step",
                value: rate.dt,
                rule: "the rate needs a finite previous stretch and a finite time step > 0 s",
            });
        }
        Ok(Self {
            velocity: Some(rate),
            ..self
        })
    }

    /// The same drive, quasi-static (f_v = 1).
    pub fn without_rate(self) -> Self {
        Self {
            velocity: None,
            ..self
        }
    }

    /// Rejects d ∉ [0, 1] and a < 0 or non-finite.
    pub fn check(&self) -> Result<()> {
        check_damage(self.damage)?;
        if !(self.level.is_finite() && self.level >= 0.0) {
            return Err(Error::InvalidParameter {
                name: "activation level",
                value: self.level,
                rule: "must be finite and >= 0",
            });
        }
        Ok(())
    }

    /// Damage d [-].
    pub fn damage(&self) -> f64 {
        self.damage
    }
    /// Activation level a [-].
    pub fn level(&self) -> f64 {
        self.level
    }
    /// The stretch-rate state, if the drive has one.
    pub fn rate(&self) -> Option<&StretchRate> {
        self.velocity.as_ref()
    }

    /// d_eff = d + (1 − d)(1 − a): the damage a law at a = 1 would need for the same scale
    /// s = 1 − d_eff = (1 − d)·a. Written so that a = 1 gives d_eff = d exactly (the chapter's
    /// runs are bit-for-bit those of a damage alone) and a = 0 gives d_eff = 1 exactly. Negative
    /// for a > 1.
    pub fn effective_damage(&self) -> f64 {
        self.damage + (1.0 - self.damage) * (1.0 - self.level)
    }

    /// d_eff at fibre stretch λ with the force–velocity factor: 1 − (1 − d)·a·f_v(λ̇(λ)) [-],
    /// the damage a quasi-static law at a = 1 would need for the same target there; without a
    /// stretch rate [`effective_damage`](Self::effective_damage) exactly.
    pub fn effective_damage_at(&self, lambda: f64) -> f64 {
        match &self.velocity {
            None => self.effective_damage(),
            Some(_) => 1.0 - self.scale() * self.velocity_factor(lambda),
        }
    }

    /// s = (1 − d)·a = 1 − d_eff [-]: the quasi-static scale of the active curve.
    pub fn scale(&self) -> f64 {
        1.0 - self.effective_damage()
    }

    /// Whether the target is 0 at every stretch (s = 0: d = 1 or a = 0), where every law gives
    /// γ = 0 without a solve.
    pub fn is_off(&self) -> bool {
        self.scale() <= 0.0
    }

    /// The damage of a quasi-static drive, by which a tabulated law finds its table: d_eff
    /// (`None` with a stretch rate, whose target no table holds).
    pub fn table_damage(&self) -> Option<f64> {
        self.velocity.is_none().then(|| self.effective_damage())
    }

    /// f_v(λ̇(λ)) [-] (1 without a rate), generic: its λ-derivatives include dλ̇/dλ = 1/Δt.
    pub fn velocity_factor<T: Scalar>(&self, lambda: T) -> T {
        match &self.velocity {
            None => T::one(),
            Some(v) => v.law.factor(v.rate(lambda)),
        }
    }

    /// The target T(λ) = (1 − d)·a·f_v(λ̇(λ))·P_act(λ) \[kPa\], generic so that dual numbers
    /// give its derivatives.
    pub fn target<T: Scalar>(&self, curve: &ActiveCurve, lambda: T) -> T {
        let active = curve.value(lambda) * self.scale();
        match &self.velocity {
            None => active,
            Some(_) => active * self.velocity_factor(lambda),
        }
    }

    /// The active work (1 − d)·a·f_v(λ̇(λ))·∫_{λ_min}^{λ} P_act \[kPa\], generic: ∫P_act is
    /// lifted from its value and its derivatives P_act, P_act′, P_act″ at λ's real part (exact to
    /// third order) (no quadrature
    /// in dual arithmetic). With a stretch rate, f_v at the current rate is a factor of the
    /// work, as 4C's MAT_Muscle_Giantesio writes its energy condition; its λ-derivatives are
    /// taken exactly (4C holds λ̇ fixed in them).
    pub fn work<T: Scalar>(&self, curve: &ActiveCurve, lambda: T) -> T {
        let l = lambda.re();
        let (p, p_l, p_ll) = num_dual::second_derivative(|s| curve.value(s), l);
        let h = lambda - l;
        let integral = ((h * (p_ll / 6.0) + 0.5 * p_l) * h + p) * h + curve.integral(l);
        let work = integral * self.scale();
        match &self.velocity {
            None => work,
            Some(_) => work * self.velocity_factor(lambda),
        }
    }
}
