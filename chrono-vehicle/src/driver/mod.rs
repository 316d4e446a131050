//! Drivers: what turns the vehicle's state into throttle, brake and steering.
//!
//! - [`OpenLoopDriver`]: time series (tables) of the three inputs;
//! - [`SpeedController`]: a PID on the forward speed, positive output to the throttle,
//!   negative to the brake, with anti-windup;
//! - [`PathFollowerDriver`]: a [`PurePursuit`] steering controller on a [`Path`] plus a
//!   [`SpeedController`]; [`Path`] has builders for the ISO 3888-1 double lane change and
//!   for a circle, and the courses of the lane-change and turn tests;
//! - [`TractionControl`]: the throttle cut by wheel slip.
//!
//! Drivers read the time from [`VehicleState::time`] (the controllers integrate and
//! differentiate over the time between calls), so `synchronize` is called once per driver
//! update, at any rate.

mod follower;
mod path;
mod speed;
mod traction;

pub use follower::{PathFollowerDriver, PathFollowerParams, PurePursuit};
pub use path::{IsoDoubleLaneChange, Path, PathPoint};
pub use speed::{PidGains, SpeedController};
pub use traction::TractionControl;

use chrono_core::Curve;
use serde::{Deserialize, Serialize};

use crate::error::{Result, VehicleError};
use crate::state::{DriverInputs, VehicleState};

/// A driver: from the vehicle state to the inputs of this update.
pub trait Driver: Send {
    /// The inputs at `state.time` (clamped to their ranges by the implementations).
    fn synchronize(&mut self, state: &VehicleState) -> DriverInputs;
}

/// Inputs given as functions of time: piecewise-linear [`Curve`]s of throttle (0..1),
/// brake (0..1) and steering (-1..1) against time (s). Values are clamped to their ranges.
///
/// In serde form: `{"throttle": {"points": [[0, 0], [1, 0.5]]}, "brake": ..., "steering": ...}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OpenLoopDriver {
    /// Throttle against time.
    pub throttle: Curve,
    /// Brake against time.
    pub brake: Curve,
    /// Steering against time.
    pub steering: Curve,
}

impl OpenLoopDriver {
    /// A driver from the three time series; errors name the curve and point.
    pub fn new(throttle: Curve, brake: Curve, steering: Curve) -> Result<Self> {
        let d = Self {
            throttle,
            brake,
            steering,
        };
        d.validate()?;
        Ok(d)
    }

    /// Check the curves (after deserializing).
    pub fn validate(&self) -> Result<()> {
        let map = |e: chrono_core::ChronoError| match e {
            chrono_core::ChronoError::InvalidParameter {
                field,
                value,
                reason,
            } => VehicleError::InvalidParameter {
                field,
                value,
                reason,
            },
            e => VehicleError::Core(e),
        };
        self.throttle
            .validate("open_loop_driver.throttle")
            .map_err(map)?;
        self.brake.validate("open_loop_driver.brake").map_err(map)?;
        self.steering
            .validate("open_loop_driver.steering")
            .map_err(map)?;
        Ok(())
    }

    /// The inputs at time `t`, s.
    pub fn inputs_at(&self, t: f64) -> DriverInputs {
        DriverInputs {
            throttle: self.throttle.eval(t),
            brake: self.brake.eval(t),
            steering: self.steering.eval(t),
        }
        .clamped()
    }
}

impl Driver for OpenLoopDriver {
    fn synchronize(&mut self, state: &VehicleState) -> DriverInputs {
        self.inputs_at(state.time)
    }
}
