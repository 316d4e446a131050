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
//! A turbine faster than the pump (`w_t / w_p > 1`, reverse flow: engine braking) or
//! turning the other way (`< 0`) is clamped to the ends of the curves: the converter keeps
//! its lock-up (`s = 1`) or stall (`s = 0`) behaviour there; [`ConverterTorques::reverse_flow`]
//! flags the first case. A converter model for reverse flow is left for later.
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
    /// The HMMWV converter (our notes, section 7).
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
    /// Speed ratio `s` used in the curves (clamped to `[0, 1]`).
    pub speed_ratio: f64,
    /// Torque absorbed by the pump, N m (the crankshaft receives `-pump_torque`).
    pub pump_torque: f64,
    /// Torque delivered to the turbine (transmission input shaft), N m.
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
            reverse_flow: raw > 1.0,
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
        // Turbine overrunning the pump: clamped to lock-up (K = 35, R = 1), flagged.
        let t = c.torques(100.0, 120.0);
        assert!(t.reverse_flow && t.speed_ratio == 1.0);
        assert!((t.pump_torque - (100.0f64 / 35.0).powi(2)).abs() < 1e-12);
        // No pump speed, no torque.
        assert_eq!(c.torques(0.0, 50.0).pump_torque, 0.0);
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
