//! The speed controller (PID on the forward speed).

use serde::{Deserialize, Serialize};

use crate::error::{Result, check_finite, check_non_negative};

/// PID gains (serde: `{"kp": 0.4, "ki": 0.0, "kd": 0.0}`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PidGains {
    /// Proportional gain (output per unit error).
    pub kp: f64,
    /// Integral gain (output per unit error and second).
    pub ki: f64,
    /// Derivative gain (output per unit error rate, s).
    pub kd: f64,
}

impl PidGains {
    /// The HMMWV speed controller gains of Chrono's data (`SpeedController.json`,
    /// reference notes sec. 7): `kp = 0.4`, `ki = 0`, `kd = 0` (per m/s).
    pub fn hmmwv_speed() -> Self {
        Self {
            kp: 0.4,
            ki: 0.0,
            kd: 0.0,
        }
    }

    /// Check the gains (finite, >= 0); errors name `{field}.kp` etc.
    pub fn validate(&self, field: &str) -> Result<()> {
        check_non_negative(&format!("{field}.kp"), self.kp)?;
        check_non_negative(&format!("{field}.ki"), self.ki)?;
        check_non_negative(&format!("{field}.kd"), self.kd)?;
        Ok(())
    }
}

/// A PID controller of the forward speed.
///
/// With the error `e = v_target - v` (m/s), at each call at time `t` with
/// `dt = t - t_prev`:
///
/// ```text
/// I' = I + dt (e + e_prev)/2          (trapezoid)
/// D  = (e - e_prev)/dt                (backward difference; 0 on the first call)
/// u  = clamp(kp e + ki I' + kd D, -1, 1)
/// ```
///
/// Anti-windup by conditional integration: the new integral `I'` is kept only if the
/// unclamped output is inside `[-1, 1]` or the error drives it back inside; otherwise the
/// integral is frozen. `u > 0` is the throttle, `u < 0` the brake
/// ([`SpeedController::pedals`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedController {
    gains: PidGains,
    target: f64,
    integral: f64,
    last_error: f64,
    last_time: Option<f64>,
    output: f64,
}

impl SpeedController {
    /// A controller with `gains` and target speed `target` (m/s).
    pub fn new(gains: PidGains, target: f64) -> Result<Self> {
        gains.validate("speed_controller")?;
        check_finite("speed_controller.target", target)?;
        Ok(Self {
            gains,
            target,
            integral: 0.0,
            last_error: 0.0,
            last_time: None,
            output: 0.0,
        })
    }

    /// Set the target speed, m/s (the integral is kept).
    pub fn set_target(&mut self, target: f64) {
        self.target = target;
    }

    /// The target speed, m/s.
    pub fn target(&self) -> f64 {
        self.target
    }

    /// The last output in `[-1, 1]`.
    pub fn output(&self) -> f64 {
        self.output
    }

    /// The integral of the error, m.
    pub fn integral(&self) -> f64 {
        self.integral
    }

    /// Forget the history (integral, last error and time).
    pub fn reset(&mut self) {
        self.integral = 0.0;
        self.last_error = 0.0;
        self.last_time = None;
        self.output = 0.0;
    }

    /// Update at time `time` (s) with the measured forward speed `speed` (m/s); returns
    /// the output `u` in `[-1, 1]`.
    pub fn advance(&mut self, time: f64, speed: f64) -> f64 {
        let e = self.target - speed;
        let dt = self.last_time.map_or(0.0, |t0| (time - t0).max(0.0));
        let g = self.gains;
        let (candidate, de) = if dt > 0.0 {
            (
                self.integral + 0.5 * dt * (e + self.last_error),
                (e - self.last_error) / dt,
            )
        } else {
            (self.integral, 0.0)
        };
        let raw = g.kp * e + g.ki * candidate + g.kd * de;
        let saturated_further = (raw > 1.0 && e > 0.0) || (raw < -1.0 && e < 0.0);
        if !saturated_further {
            self.integral = candidate;
        }
        let u = g.kp * e + g.ki * self.integral + g.kd * de;
        self.output = if u.is_nan() { 0.0 } else { u.clamp(-1.0, 1.0) };
        self.last_error = e;
        self.last_time = Some(time);
        self.output
    }

    /// `(throttle, brake)` of an output `u`: `(max(u, 0), max(-u, 0))`.
    pub fn pedals(u: f64) -> (f64, f64) {
        (u.max(0.0), (-u).max(0.0))
    }
}
