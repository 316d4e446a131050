//! The torque converter: a hydrodynamic coupling between the crankshaft (pump, impeller)
//! and the transmission input shaft (turbine), given by two curves of the speed ratio.
//!
//! With `w_p` the pump (crankshaft) speed and `w_t` the turbine speed (rad/s):
//!
//! ```text
//! s   = clamp(w_t / w_p, 0, 1)          speed ratio (0 when w_p = 0)
//! T_p = sign(w_p) (w_p / K(s))^2        torque absorbed by the pump, N m
//! T_t = R(s) T_p                        torque delivered to the turbine, N m
//! ```
//!
//! `K(s)` is the capacity factor (rad/s per sqrt(N m), > 0) and `R(s)` the torque ratio
//! (torque multiplication, 2.0 at stall for the HMMWV). The crankshaft receives `-T_p`,
//! the turbine `+T_t`; the difference `(R - 1) T_p` is taken by the converter's stator
//! (the housing, not modelled). The torques are explicit: evaluated from the speeds at the
//! start of each step, as applied shaft torques.
//!
//! Reverse flow (the turbine overruns the pump, `w_t > w_p >= 0`: coasting, engine braking):
//! the roles swap, the turbine drives the pump as a fluid coupling (the stator freewheels,
//! torque ratio 1) with the capacity curve read at the inverse ratio:
//!
//! ```text
//! s_r = w_p / w_t,   T = (w_t / K(s_r))^2,   turbine receives -T,   crankshaft receives +T
//! ```
//!
//! so torque always flows from the faster member to the slower one. (Clamping `s` to 1
//! instead, as a forward converter at lock-up, keeps pushing the turbine forward however
//! fast it overruns the engine: a vehicle at full throttle then accelerates past its
//! governed speed, which the M998 acceleration run showed.) The torque is continuous
//! through `s = 1` only if `T(1) -> 0`, i.e. `K(1)` much larger than `w / sqrt(T)`:
//! true of a real converter (a coupling transmits no torque without slip), not of Chrono's
//! HMMWV curve (`K(1) = 35`, a lock-up), which then jumps by `2 (w / K(1))^2` at `s = 1`.
//! A turbine turning the other way (`w_t / w_p < 0`) is clamped to stall (`s = 0`).
//!
//! Reference: Chrono's `ChShaftsTorqueConverter` as described in our notes (section 7,
//! `HMMWV_AutomaticTransmissionShafts`: K 15 ... 35, R 2.0 ... 1.0).

use chrono_core::{Curve, Extrapolation};
use serde::{Deserialize, Serialize};

use crate::error::{Result, VehicleError};

/// Parameters of a [`TorqueConverter`]; the default is the HMMWV's.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TorqueConverterParams {
    /// Capacity factor `K(s)`, rad/s per sqrt(N m) (every value > 0), against speed ratio.
    pub capacity_factor: Curve,
    /// Torque ratio `R(s)` (every value > 0), against speed ratio.
    pub torque_ratio: Curve,
}

impl Default for TorqueConverterParams {
    /// The HMMWV converter (Project Chrono's `HMMWV_AutomaticTransmissionShafts`).
    fn default() -> Self {
        let k = vec![
            [0.0, 15.0],
            [0.25, 15.0],
            [0.5, 15.0],
            [0.75, 16.0],
            [0.9, 18.0],
            [1.0, 35.0],
        ];
        let r = vec![
            [0.0, 2.0],
            [0.25, 1.8],
            [0.5, 1.5],
            [0.75, 1.15],
            [1.0, 1.0],
        ];
        Self {
            capacity_factor: Curve::new(
                "torque_converter.capacity_factor",
                k,
                Extrapolation::Constant,
            )
            .expect("valid table"),
            torque_ratio: Curve::new("torque_converter.torque_ratio", r, Extrapolation::Constant)
                .expect("valid table"),
        }
    }
}

impl TorqueConverterParams {
    /// Check both curves (finite, increasing abscissae, values > 0); errors name
    /// `{prefix}.field.points[i]`.
    pub fn validate(&self, prefix: &str) -> Result<()> {
        for (name, c) in [
            ("capacity_factor", &self.capacity_factor),
            ("torque_ratio", &self.torque_ratio),
        ] {
            let field = format!("{prefix}.{name}");
            c.validate(&field)?;
            if let Some(i) = c.points().iter().position(|p| p[1] <= 0.0) {
                let p = c.points()[i];
                return Err(VehicleError::invalid(
                    format!("{field}.points[{i}]"),
                    format!("[{}, {}]", p[0], p[1]),
                    "values must be > 0",
                ));
            }
        }
        Ok(())
    }
}

/// The converter's state for a pair of speeds.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ConverterTorques {
    /// Speed ratio `w_t / w_p` (0 when the pump stands, 0 when they turn opposite ways;
    /// above 1 in reverse flow).
    pub speed_ratio: f64,
    /// Torque absorbed by the pump, N m (the crankshaft receives `-pump_torque`; negative
    /// in reverse flow: the crankshaft is driven).
    pub pump_torque: f64,
    /// Torque delivered to the turbine (transmission input shaft), N m (negative in
    /// reverse flow: the turbine is braked).
    pub turbine_torque: f64,
    /// True when the turbine overran the pump (`w_t / w_p > 1`).
    pub reverse_flow: bool,
}

/// A torque converter (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq)]
pub struct TorqueConverter {
    k: Curve,
    r: Curve,
}

impl TorqueConverter {
    /// The converter of `params` (validated; errors name `torque_converter.<field>`).
    pub fn new(params: &TorqueConverterParams) -> Result<Self> {
        params.validate("torque_converter")?;
        Ok(Self {
            k: params.capacity_factor.clone(),
            r: params.torque_ratio.clone(),
        })
    }

    /// Pump and turbine torques at pump speed `w_pump` and turbine speed `w_turbine`
    /// (rad/s).
    pub fn torques(&self, w_pump: f64, w_turbine: f64) -> ConverterTorques {
        if w_pump >= 0.0 && w_turbine > w_pump {
            // Reverse flow: a coupling driven by the turbine.
            let s_r = w_pump / w_turbine;
            let x = w_turbine / self.k.eval(s_r);
            let t = x * x;
            return ConverterTorques {
                speed_ratio: if w_pump > 0.0 {
                    w_turbine / w_pump
                } else {
                    0.0
                },
                pump_torque: -t,
                turbine_torque: -t,
                reverse_flow: true,
            };
        }
        let raw = if w_pump != 0.0 {
            w_turbine / w_pump
        } else {
            0.0
        };
        let s = raw.clamp(0.0, 1.0);
        let x = w_pump / self.k.eval(s);
        let pump = x * x.abs();
        ConverterTorques {
            speed_ratio: s,
            pump_torque: pump,
            turbine_torque: self.r.eval(s) * pump,
            reverse_flow: false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pump_and_turbine_torques_follow_the_curves() {
        let c = TorqueConverter::new(&TorqueConverterParams::default()).unwrap();
        // Speed ratio 0.9: K = 18, R = 1.15 + (0.15 / 0.25) (1.0 - 1.15) = 1.06.
        let t = c.torques(200.0, 180.0);
        assert!((t.speed_ratio - 0.9).abs() < 1e-15);
        let tp = (200.0f64 / 18.0).powi(2);
        assert!((t.pump_torque - tp).abs() < 1e-9 * tp);
        assert!((t.turbine_torque - 1.06 * tp).abs() < 1e-9 * tp);
        assert!(!t.reverse_flow);
        // A pump turning backwards absorbs a negative torque (signed square).
        let t = c.torques(-150.0, 0.0);
        assert!((t.pump_torque + 100.0).abs() < 1e-9 && (t.turbine_torque + 200.0).abs() < 1e-9);
        // Turbine overrunning the pump: reverse flow, a coupling driven by the turbine at
        // s_r = 100/120: K = 16 + (0.0833 / 0.15) (18 - 16), torque ratio 1.
        let t = c.torques(100.0, 120.0);
        assert!(t.reverse_flow && (t.speed_ratio - 1.2).abs() < 1e-12);
        let k = 16.0 + (100.0 / 120.0 - 0.75) / 0.15 * 2.0;
        let tr = (120.0f64 / k).powi(2);
        assert!((t.turbine_torque + tr).abs() < 1e-9 * tr, "{t:?}");
        assert!((t.pump_torque + tr).abs() < 1e-9 * tr);
        // A stopped pump is driven by a turning turbine (s_r = 0, K = 15).
        let t = c.torques(0.0, 60.0);
        assert!(t.reverse_flow && (t.turbine_torque + 16.0).abs() < 1e-9);
        // Nothing turns, no torque.
        assert_eq!(c.torques(0.0, 0.0).pump_torque, 0.0);
    }

    /// Torque flows from the faster member to the slower one, and with a capacity that
    /// grows without bound at s = 1 (a coupling without lock-up) the turbine torque is
    /// continuous through s = 1, so an overrunning turbine is braked, not pushed.
    #[test]
    fn reverse_flow_brakes_the_turbine_and_is_continuous_without_lock_up() {
        let p = TorqueConverterParams {
            capacity_factor: Curve::new(
                "k",
                vec![[0.0, 12.0], [0.9, 14.0], [0.98, 30.0], [1.0, 1e6]],
                Extrapolation::Constant,
            )
            .unwrap(),
            torque_ratio: Curve::new(
                "r",
                vec![[0.0, 2.2], [0.85, 1.0], [1.0, 1.0]],
                Extrapolation::Constant,
            )
            .unwrap(),
        };
        let c = TorqueConverter::new(&p).unwrap();
        let w = 380.0;
        let below = c.torques(w, w * (1.0 - 1e-9)).turbine_torque;
        let above = c.torques(w, w * (1.0 + 1e-9)).turbine_torque;
        assert!(below >= 0.0 && above <= 0.0);
        assert!((below - above).abs() < 1e-6, "{below} {above}");
        // Well into reverse flow the turbine is braked as a coupling at the inverse ratio.
        let t = c.torques(w, w / 0.9);
        assert!((t.turbine_torque + (w / 0.9 / 14.0f64).powi(2)).abs() < 1e-9);
        // Forward near s = 1: small positive torque.
        let f = c.torques(w, 0.97 * w);
        assert!(f.turbine_torque > 0.0 && !f.reverse_flow);
    }

    #[test]
    fn non_positive_curve_values_are_rejected_by_point() {
        let p = TorqueConverterParams {
            torque_ratio: Curve::new("r", vec![[0.0, 2.0], [1.0, -1.0]], Extrapolation::Constant)
                .unwrap(),
            ..TorqueConverterParams::default()
        };
        let e = TorqueConverter::new(&p).unwrap_err().to_string();
        assert!(
            e.contains("torque_converter.torque_ratio.points[1]") && e.contains("-1"),
            "{e}"
        );
    }
}
