//! The engine: a full-throttle torque map and a losses map against crankshaft speed.
//!
//! `T = throttle * T_map(w) + T_loss(w)` (N m) with `w` the crankshaft speed (rad/s) and
//! `throttle` in `[0, 1]`. The maps are piecewise-linear tables ([`Curve`]) given in rpm
//! (as engine data sheets and Chrono's HMMWV files are) and converted to rad/s once. Outside
//! its table a map keeps its end value (constant extrapolation), so a map that ends
//! negative (HMMWV: -400 N m at 2700 rpm) acts as a rev limiter. The torque acts on the
//! crankshaft; its reaction on the engine block is not modelled.
//!
//! Reference: Chrono's `ChEngineShafts` / `HMMWV_EngineShafts` as summarized in our notes
//! (section 7): torque = throttle x map + losses; crankshaft inertia 1.1 kg m^2.

use chrono_core::{Curve, Extrapolation};
use serde::{Deserialize, Serialize};

use crate::error::{Result, check_positive};

/// rad/s per rpm: `2 pi / 60`.
pub const RPM_TO_RAD_S: f64 = std::f64::consts::PI / 30.0;

/// Parameters of an [`Engine`] (JSON: `{"crankshaft_inertia": 1.1, "torque_map_rpm":
/// {"points": [[rpm, N m], ...]}, "losses_map_rpm": {...}}`). The default is the HMMWV.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EngineParams {
    /// Polar inertia of the crankshaft (with flywheel), kg m^2 (HMMWV 1.1).
    pub crankshaft_inertia: f64,
    /// Full-throttle torque, N m, against crankshaft speed in rpm.
    pub torque_map_rpm: Curve,
    /// Losses (friction, pumping; usually <= 0), N m, against crankshaft speed in rpm.
    pub losses_map_rpm: Curve,
}

impl Default for EngineParams {
    /// The HMMWV engine (Project Chrono's `HMMWV_EngineShafts`).
    fn default() -> Self {
        let map = vec![
            [-100.0, 300.0],
            [800.0, 382.0],
            [900.0, 490.0],
            [1000.0, 579.0],
            [1100.0, 650.0],
            [1200.0, 706.0],
            [1300.0, 746.0],
            [1400.0, 774.0],
            [1500.0, 789.0],
            [1600.0, 793.0],
            [1700.0, 788.0],
            [1800.0, 774.0],
            [1900.0, 754.0],
            [2000.0, 728.0],
            [2100.0, 697.0],
            [2200.0, 664.0],
            [2300.0, 628.0],
            [2400.0, 593.0],
            [2500.0, 558.0],
            [2700.0, -400.0],
        ];
        let losses = vec![
            [0.0, 0.0],
            [1000.0, -50.0],
            [2000.0, -70.0],
            [3000.0, -90.0],
        ];
        Self {
            crankshaft_inertia: 1.1,
            torque_map_rpm: Curve::new("engine.torque_map_rpm", map, Extrapolation::Constant)
                .expect("valid table"),
            losses_map_rpm: Curve::new("engine.losses_map_rpm", losses, Extrapolation::Constant)
                .expect("valid table"),
        }
    }
}

impl EngineParams {
    /// Check every field; errors name `{prefix}.field`.
    pub fn validate(&self, prefix: &str) -> Result<()> {
        check_positive(
            &format!("{prefix}.crankshaft_inertia"),
            self.crankshaft_inertia,
        )?;
        self.torque_map_rpm
            .validate(&format!("{prefix}.torque_map_rpm"))?;
        self.losses_map_rpm
            .validate(&format!("{prefix}.losses_map_rpm"))?;
        Ok(())
    }
}

/// An engine: its maps in rad/s.
#[derive(Debug, Clone, PartialEq)]
pub struct Engine {
    map: Curve,
    losses: Curve,
}

impl Engine {
    /// The engine of `params` (validated; errors name `engine.<field>`).
    pub fn new(params: &EngineParams) -> Result<Self> {
        params.validate("engine")?;
        Ok(Self {
            map: params.torque_map_rpm.scaled(RPM_TO_RAD_S, 1.0)?,
            losses: params.losses_map_rpm.scaled(RPM_TO_RAD_S, 1.0)?,
        })
    }

    /// Torque on the crankshaft, N m: `throttle * T_map(w) + T_loss(w)` at crankshaft speed
    /// `speed` (rad/s); `throttle` in `[0, 1]` (the caller clamps it).
    pub fn torque(&self, throttle: f64, speed: f64) -> f64 {
        throttle * self.map.eval(speed) + self.losses.eval(speed)
    }

    /// The full-throttle map against rad/s.
    pub fn torque_map(&self) -> &Curve {
        &self.map
    }

    /// The losses map against rad/s.
    pub fn losses_map(&self) -> &Curve {
        &self.losses
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `throttle * map + losses` at table points and between them, in rad/s.
    #[test]
    fn torque_is_throttle_times_map_plus_losses() {
        let e = Engine::new(&EngineParams::default()).unwrap();
        // 1600 rpm: map 793 (a table point), losses -50 + 0.6 (-70 + 50) = -62.
        let w = 1600.0 * RPM_TO_RAD_S;
        assert!((e.torque(1.0, w) - (793.0 - 62.0)).abs() < 1e-9);
        assert!((e.torque(0.5, w) - (396.5 - 62.0)).abs() < 1e-9);
        assert!((e.torque(0.0, w) + 62.0).abs() < 1e-9);
        // 2600 rpm: halfway between 558 and -400; losses -70 - 0.6 x 20 = -82.
        let w = 2600.0 * RPM_TO_RAD_S;
        assert!((e.torque(1.0, w) - (79.0 - 82.0)).abs() < 1e-9);
        // Beyond the table the ends are kept: a rev limiter.
        let w = 4000.0 * RPM_TO_RAD_S;
        assert!((e.torque(1.0, w) - (-400.0 - 90.0)).abs() < 1e-9);
    }

    #[test]
    fn bad_engine_input_names_the_field() {
        let p = EngineParams {
            crankshaft_inertia: 0.0,
            ..EngineParams::default()
        };
        let e = Engine::new(&p).unwrap_err().to_string();
        assert!(
            e.contains("engine.crankshaft_inertia") && e.contains('0'),
            "{e}"
        );
    }
}
