//! Activation in time: the activation level a(t) ∈ [0, 1], the fraction of the optimal active
//! stress recruited at time t, which scales the active curve like the damage does (the laws see
//! (1 − d)·a·P_act, see [`crate::active::Drive::effective_damage`]).
//!
//! - A [`Schedule`] a_s(t): (t \[s\], value) points, piecewise constant (the value of the last point
//!   at or before t) or piecewise linear; before the first point and after the last the end
//!   values hold.
//! - Optionally [`MotorUnits`]: the twitch superposition of Ehret, Böl & Itskov (2011) as 4C
//!   computes it (`Mat::Utils::Muscle::evaluate_time_dependent_active_stress_ehret`,
//!   `src/mat/4C_mat_muscle_utils.cpp`; used by `MAT_Muscle_Giantesio` and
//!   `MAT_Muscle_Weickenmeier`). Per motor-unit type i a fraction ρ_i, a twitch force F_i [-], a
//!   twitch contraction time T_i \[s\] and an interstimulus interval I_i \[s\]; each schedule
//!   interval [t_k, t_{k+1}) starts a train of stimuli t_kj = t_k + j I_i (t_kj < min(t, t_{k+1});
//!   the last interval is open), each weighted by the schedule there, and
//!
//!   a(t) = Σ_i ρ_i G_i Σ_{k,j} a_s(t_kj) F_i (t − t_kj)/T_i exp(1 − (t − t_kj)/T_i),
//!   G_i = (1 − exp(−2 (T_i/I_i)³)) / (T_i/I_i)  (the gain function).
//!
//!   This is 4C's P_opt(t)/N_a (4C multiplies by N_a, "ACTMUNUM", in stress units; here the
//!   chapter's P_opt plays that role). For a piecewise constant schedule it is 4C's formula term
//!   for term; for a linear one each stimulus takes the schedule's value at its time. A fused
//!   tetanus (I_i ≪ T_i) tends to e F_i G_i T_i/I_i → e F_i, so F_i ≈ 1/e makes a ≈ 1 at full
//!   stimulation; a must stay in [0, 1] (checked where it is evaluated).

use crate::{Error, Result};

/// How a [`Schedule`] fills the time between its points (in a scene:
/// `interpolation = "constant" | "linear"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Interpolation {
    /// The value of the last point at or before t (4C's ACTTIMES/ACTVALUES intervals).
    #[default]
    Constant,
    /// Linear between points (4C's activation maps).
    Linear,
}

impl Interpolation {
    /// `constant` or `linear`.
    pub fn name(self) -> &'static str {
        match self {
            Interpolation::Constant => "constant",
            Interpolation::Linear => "linear",
        }
    }
}

/// A schedule a_s(t) ∈ [0, 1] from (t \[s\], value) points with strictly increasing times.
#[derive(Debug, Clone, PartialEq)]
pub struct Schedule {
    points: Vec<(f64, f64)>,
    interpolation: Interpolation,
}

/// Why a list of (t, value) points is not a schedule: the index of the offending point and the
/// rule (the scene names the key and line).
#[derive(Debug, Clone, PartialEq)]
pub struct ScheduleError {
    /// Index of the offending point (0 for an empty list).
    pub index: usize,
    /// The offending number.
    pub value: f64,
    /// The rule it breaks.
    pub rule: &'static str,
}

impl Schedule {
    /// Points (t \[s\], value): at least one, finite times strictly increasing, every value
    /// accepted by `admissible`, whose rule `rule` the error states.
    pub fn checked(
        points: Vec<(f64, f64)>,
        interpolation: Interpolation,
        admissible: fn(f64) -> bool,
        rule: &'static str,
    ) -> std::result::Result<Self, ScheduleError> {
        if points.is_empty() {
            return Err(ScheduleError {
                index: 0,
                value: f64::NAN,
                rule: "a schedule needs at least one (t, value) point",
            });
        }
        for (i, &(t, v)) in points.iter().enumerate() {
            if !t.is_finite() {
                return Err(ScheduleError {
                    index: i,
                    value: t,
                    rule: "times must be finite",
                });
            }
            if i > 0 && t <= points[i - 1].0 {
                return Err(ScheduleError {
                    index: i,
                    value: t,
                    rule: "times must increase strictly from point to point",
                });
            }
            if !admissible(v) {
                return Err(ScheduleError {
                    index: i,
                    value: v,
                    rule,
                });
            }
        }
        Ok(Self {
            points,
            interpolation,
        })
    }

    /// An activation schedule: values in [0, 1].
    pub fn new(
        points: Vec<(f64, f64)>,
        interpolation: Interpolation,
    ) -> std::result::Result<Self, ScheduleError> {
        Self::checked(
            points,
            interpolation,
            |v| (0.0..=1.0).contains(&v),
            "values must lie in [0, 1]",
        )
    }

    /// The constant schedule a_s ≡ `value`.
    pub fn constant(value: f64) -> Result<Self> {
        Self::new(vec![(0.0, value)], Interpolation::Constant).map_err(|e| {
            Error::InvalidParameter {
                name: "schedule value",
                value: e.value,
                rule: e.rule,
            }
        })
    }

    /// The (t, value) points.
    pub fn points(&self) -> &[(f64, f64)] {
        &self.points
    }

    /// How values between points are filled.
    pub fn interpolation(&self) -> Interpolation {
        self.interpolation
    }

    /// a_s(t): the end values outside [t_0, t_last]; between points constant (the value of the
    /// last point at or before t) or linear.
    pub fn value(&self, t: f64) -> f64 {
        let k = self.points.partition_point(|p| p.0 <= t);
        if k == 0 {
            return self.points[0].1;
        }
        let (t0, v0) = self.points[k - 1];
        match (self.interpolation, self.points.get(k)) {
            (Interpolation::Linear, Some(&(t1, v1))) => v0 + (v1 - v0) * (t - t0) / (t1 - t0),
            _ => v0,
        }
    }
}

/// One motor-unit type of the twitch superposition.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotorUnit {
    /// Fraction ρ of this type among the active motor units [-] (4C: FRACACTMU).
    pub fraction: f64,
    /// Twitch force F [-] (4C: FTWITCH).
    pub twitch_force: f64,
    /// Twitch contraction time T \[s\]: the twitch peaks T after its stimulus (4C: TTWITCH).
    pub contraction_time: f64,
    /// Interstimulus interval I \[s\] (4C: INTERSTIM).
    pub interstimulus: f64,
}

impl MotorUnit {
    /// Checks ρ ∈ [0, 1], F ≥ 0, T > 0, I > 0 (all finite); the error names the parameter.
    pub fn new(
        fraction: f64,
        twitch_force: f64,
        contraction_time: f64,
        interstimulus: f64,
    ) -> Result<Self> {
        let bad = |name, value, rule| Err(Error::InvalidParameter { name, value, rule });
        if !(0.0..=1.0).contains(&fraction) {
            return bad("fraction", fraction, "must lie in [0, 1]");
        }
        if !(twitch_force.is_finite() && twitch_force >= 0.0) {
            return bad("twitch_force", twitch_force, "must be finite and ≥ 0");
        }
        if !(contraction_time.is_finite() && contraction_time > 0.0) {
            return bad(
                "contraction_time",
                contraction_time,
                "must be finite and > 0",
            );
        }
        if !(interstimulus.is_finite() && interstimulus > 0.0) {
            return bad("interstimulus", interstimulus, "must be finite and > 0");
        }
        Ok(Self {
            fraction,
            twitch_force,
            contraction_time,
            interstimulus,
        })
    }

    /// The gain G = (1 − exp(−2 (T/I)³)) / (T/I) [-].
    pub fn gain(&self) -> f64 {
        let x = self.contraction_time / self.interstimulus;
        -(-2.0 * x * x * x).exp_m1() / x
    }

    /// One twitch s \[s\] after its stimulus: F (s/T) exp(1 − s/T) for s ≥ 0, else 0 [-].
    pub fn twitch(&self, s: f64) -> f64 {
        if s <= 0.0 {
            return 0.0;
        }
        let x = s / self.contraction_time;
        self.twitch_force * x * (1.0 - x).exp()
    }
}

/// The motor-unit types of a muscle, fractions summing to 1.
#[derive(Debug, Clone, PartialEq)]
pub struct MotorUnits {
    units: Vec<MotorUnit>,
}

/// How far the fractions may sum from 1 (rounding of decimal inputs such as 0.1 + 0.2 + 0.7).
pub const FRACTION_TOLERANCE: f64 = 1e-12;

impl MotorUnits {
    /// At least one type; the fractions must sum to 1 within [`FRACTION_TOLERANCE`] (4C checks
    /// the same, exactly, for more than one type).
    pub fn new(units: Vec<MotorUnit>) -> Result<Self> {
        if units.is_empty() {
            return Err(Error::InvalidParameter {
                name: "motor_units",
                value: 0.0,
                rule: "give at least one motor-unit type",
            });
        }
        let sum: f64 = units.iter().map(|u| u.fraction).sum();
        if (sum - 1.0).abs() > FRACTION_TOLERANCE {
            return Err(Error::InvalidParameter {
                name: "fraction",
                value: sum,
                rule: "the fractions of the motor-unit types must sum to 1",
            });
        }
        Ok(Self { units })
    }

    /// The types.
    pub fn units(&self) -> &[MotorUnit] {
        &self.units
    }
}

/// The activation level in time: a schedule, optionally driving a twitch superposition.
#[derive(Debug, Clone, PartialEq)]
pub struct ActivationInTime {
    schedule: Schedule,
    motor_units: Option<MotorUnits>,
}

impl ActivationInTime {
    /// a(t) = a_s(t) (no motor units) or the twitch superposition driven by a_s.
    pub fn new(schedule: Schedule, motor_units: Option<MotorUnits>) -> Self {
        Self {
            schedule,
            motor_units,
        }
    }

    /// The schedule a_s.
    pub fn schedule(&self) -> &Schedule {
        &self.schedule
    }

    /// The motor units, if a(t) is a twitch superposition.
    pub fn motor_units(&self) -> Option<&MotorUnits> {
        self.motor_units.as_ref()
    }

    /// Stimuli fired before `t` (what one evaluation of [`level`](Self::level) sums), per
    /// motor-unit type, rounded up: Σ_i Σ_k ⌈(min(t, t_{k+1}) − t_k)/I_i⌉.
    pub fn stimuli_before(&self, t: f64) -> f64 {
        let Some(mu) = &self.motor_units else {
            return 0.0;
        };
        let p = self.schedule.points();
        let mut n = 0.0;
        for u in mu.units() {
            for (k, &(tk, _)) in p.iter().enumerate() {
                let end = p.get(k + 1).map_or(t, |q| q.0.min(t));
                if end > tk {
                    n += ((end - tk) / u.interstimulus).ceil();
                }
            }
        }
        n
    }

    /// a(t) [-] (see the module's doc for the formula). Not clamped: the caller checks a ≤ 1.
    pub fn level(&self, t: f64) -> f64 {
        let Some(mu) = &self.motor_units else {
            return self.schedule.value(t);
        };
        let p = self.schedule.points();
        let mut a = 0.0;
        for u in mu.units() {
            let mut sum = 0.0;
            for (k, &(tk, _)) in p.iter().enumerate() {
                let end = p.get(k + 1).map_or(t, |q| q.0.min(t));
                let mut j = 0.0;
                loop {
                    // t_kj = t_k + j I, not accumulated, so that late stimuli do not drift.
                    let stimulus = tk + j * u.interstimulus;
                    if stimulus >= end {
                        break;
                    }
                    sum += self.schedule.value(stimulus) * u.twitch(t - stimulus);
                    j += 1.0;
                }
            }
            a += u.fraction * u.gain() * sum;
        }
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(t: f64, i: f64) -> MotorUnit {
        MotorUnit::new(1.0, 1.0, t, i).unwrap()
    }

    #[test]
    fn constant_schedule_holds_the_last_value_and_linear_interpolates() {
        let pts = vec![(0.0, 0.0), (1.0, 1.0), (3.0, 0.5)];
        let c = Schedule::new(pts.clone(), Interpolation::Constant).unwrap();
        let l = Schedule::new(pts, Interpolation::Linear).unwrap();
        assert_eq!(c.value(-1.0), 0.0);
        assert_eq!(c.value(0.999), 0.0);
        assert_eq!(c.value(1.0), 1.0);
        assert_eq!(c.value(2.5), 1.0);
        assert_eq!(c.value(7.0), 0.5);
        assert_eq!(l.value(0.25), 0.25);
        assert_eq!(l.value(2.0), 0.75);
        assert_eq!(l.value(9.0), 0.5);
    }

    #[test]
    fn bad_schedules_name_the_point() {
        let e = Schedule::new(vec![(0.0, 0.1), (0.0, 0.2)], Interpolation::Linear).unwrap_err();
        assert_eq!(e.index, 1);
        let e = Schedule::new(vec![(0.0, 0.1), (1.0, -0.2)], Interpolation::Linear).unwrap_err();
        assert_eq!((e.index, e.value), (1, -0.2));
        assert!(Schedule::new(vec![], Interpolation::Linear).is_err());
    }

    #[test]
    fn gain_is_the_closed_form() {
        let u = unit(0.1, 0.05);
        let x: f64 = 2.0;
        assert!((u.gain() - (1.0 - (-2.0 * x.powi(3)).exp()) / x).abs() < 1e-16);
    }

    #[test]
    fn fractions_must_sum_to_one() {
        let a = MotorUnit::new(0.3, 1.0, 0.1, 0.01).unwrap();
        let b = MotorUnit::new(0.6, 1.0, 0.1, 0.01).unwrap();
        assert!(MotorUnits::new(vec![a, b]).is_err());
        let c = MotorUnit::new(0.1, 1.0, 0.1, 0.01).unwrap();
        assert!(MotorUnits::new(vec![a, b, c]).is_ok());
    }
}
