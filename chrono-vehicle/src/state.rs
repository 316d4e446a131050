//! What drivers and output see of a vehicle, and what a driver commands.

use chrono_core::math::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

/// The driver's commands: throttle and brake in `[0, 1]`, steering in `[-1, 1]` (positive
/// turns left, i.e. counter-clockwise seen from above, Z up).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct DriverInputs {
    /// Throttle pedal, 0..1.
    pub throttle: f64,
    /// Brake pedal, 0..1.
    pub brake: f64,
    /// Steering, -1..1 (positive: left turn).
    pub steering: f64,
}

impl DriverInputs {
    /// The same inputs clamped to their ranges (NaN becomes 0).
    pub fn clamped(self) -> Self {
        let c = |x: f64, lo: f64, hi: f64| if x.is_nan() { 0.0 } else { x.clamp(lo, hi) };
        Self {
            throttle: c(self.throttle, 0.0, 1.0),
            brake: c(self.brake, 0.0, 1.0),
            steering: c(self.steering, -1.0, 1.0),
        }
    }
}

/// The chassis state a driver or a recorder reads (world frame, SI, Z up; the vehicle
/// frame is X forward, Y left, Z up).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VehicleState {
    /// Simulation time, s.
    pub time: f64,
    /// Position of the chassis reference point, m.
    pub position: Vector3<f64>,
    /// Orientation of the chassis (vehicle frame to world).
    pub rotation: UnitQuaternion<f64>,
    /// Velocity of the chassis reference point, m/s.
    pub velocity: Vector3<f64>,
    /// Angular velocity of the chassis, world frame, rad/s.
    pub angular_velocity: Vector3<f64>,
}

impl VehicleState {
    /// The forward unit vector (the vehicle's X axis in the world).
    pub fn forward(&self) -> Vector3<f64> {
        self.rotation * Vector3::x()
    }

    /// The speed along the vehicle's forward axis, m/s (negative when reversing).
    pub fn forward_speed(&self) -> f64 {
        self.velocity.dot(&self.forward())
    }

    /// The heading: the angle of the forward axis projected on the ground from world X,
    /// counter-clockwise about Z, rad in (-pi, pi].
    pub fn heading(&self) -> f64 {
        let f = self.forward();
        f.y.atan2(f.x)
    }
}
