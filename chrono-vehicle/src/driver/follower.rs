//! The path follower: pure-pursuit steering plus the speed controller.

use nalgebra::Vector2;
use serde::{Deserialize, Serialize};

use super::Driver;
use super::path::Path;
use super::speed::{PidGains, SpeedController};
use crate::error::{Result, check_finite, check_positive};
use crate::state::{DriverInputs, VehicleState};

/// The pure-pursuit steering controller (R. C. Coulter, "Implementation of the Pure
/// Pursuit Path Tracking Algorithm", CMU-RI-TR-92-01, 1992).
///
/// With the rear-axle point `r` (the vehicle reference point moved by
/// `rear_axle_offset` along the vehicle's X axis), the closest path point `s_0` to `r`,
/// and the goal point `g = path(s_0 + lookahead)`, expressed in the vehicle frame as
/// `(l_x, l_y)` (X forward, Y left):
///
/// ```text
/// kappa = 2 l_y / (l_x^2 + l_y^2)          (the arc through r tangent to the heading and g)
/// delta = atan(wheelbase kappa)            (kinematic bicycle)
/// steering input = clamp(delta / max_steer_angle, -1, 1)
/// ```
///
/// On a circle of radius `R` the steady state of a kinematic vehicle is exactly the
/// circle (the arc through `r` and a goal point on the circle is the circle itself).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PurePursuit {
    /// Look-ahead distance along the path, m.
    pub lookahead: f64,
    /// Wheelbase, m.
    pub wheelbase: f64,
    /// Road-wheel angle at full steering input, rad.
    pub max_steer_angle: f64,
    /// X of the rear axle in the vehicle (chassis reference) frame, m (e.g. -1.689 for
    /// the HMMWV, whose reference is between the axles).
    pub rear_axle_offset: f64,
}

impl PurePursuit {
    /// Check the fields; errors name them.
    pub fn validate(&self) -> Result<()> {
        check_positive("pure_pursuit.lookahead", self.lookahead)?;
        check_positive("pure_pursuit.wheelbase", self.wheelbase)?;
        check_positive("pure_pursuit.max_steer_angle", self.max_steer_angle)?;
        check_finite("pure_pursuit.rear_axle_offset", self.rear_axle_offset)?;
        Ok(())
    }

    /// The steering input in `[-1, 1]` and the goal point for the vehicle `state` on
    /// `path`.
    pub fn steer(&self, path: &Path, state: &VehicleState) -> (f64, Vector2<f64>) {
        let fwd = state.forward();
        let h = Vector2::new(fwd.x, fwd.y);
        let h = if h.norm() > 1e-12 {
            h.normalize()
        } else {
            Vector2::x()
        };
        let r = Vector2::new(state.position.x, state.position.y) + self.rear_axle_offset * h;
        let c = path.closest(r);
        let (goal, _) = path.point_at(c.s + self.lookahead);
        let d = goal - r;
        let (lx, ly) = (h.dot(&d), h.x * d.y - h.y * d.x);
        let l2 = lx * lx + ly * ly;
        if l2 <= 1e-12 {
            return (0.0, goal);
        }
        let delta = (self.wheelbase * 2.0 * ly / l2).atan();
        ((delta / self.max_steer_angle).clamp(-1.0, 1.0), goal)
    }
}

/// Parameters of a [`PathFollowerDriver`] (serde).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PathFollowerParams {
    /// The steering controller.
    pub steering: PurePursuit,
    /// Speed PID gains.
    pub speed: PidGains,
    /// Target speed, m/s.
    pub target_speed: f64,
}

impl PathFollowerParams {
    /// HMMWV values: look-ahead 5 m and speed gains (0.4, 0, 0) from Chrono's HMMWV
    /// controller data, wheelbase 3.378 m, rear axle 1.689 m behind the reference, maximum
    /// steering angle 30 degrees (reference notes sec. 7).
    pub fn hmmwv(target_speed: f64) -> Self {
        Self {
            steering: PurePursuit {
                lookahead: 5.0,
                wheelbase: 3.378,
                max_steer_angle: 30f64.to_radians(),
                rear_axle_offset: -1.689,
            },
            speed: PidGains::hmmwv_speed(),
            target_speed,
        }
    }
}

/// Follows a [`Path`] at a target speed: [`PurePursuit`] steering and a
/// [`SpeedController`] on the pedals.
#[derive(Debug, Clone, PartialEq)]
pub struct PathFollowerDriver {
    path: Path,
    steering: PurePursuit,
    speed: SpeedController,
    goal: Vector2<f64>,
}

impl PathFollowerDriver {
    /// A driver following `path` with `params`; errors name the field.
    pub fn new(path: Path, params: PathFollowerParams) -> Result<Self> {
        params.steering.validate()?;
        let speed = SpeedController::new(params.speed, params.target_speed)?;
        Ok(Self {
            path,
            steering: params.steering,
            speed,
            goal: Vector2::zeros(),
        })
    }

    /// The path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The speed controller (to change the target speed).
    pub fn speed_controller_mut(&mut self) -> &mut SpeedController {
        &mut self.speed
    }

    /// The goal point of the last update.
    pub fn goal(&self) -> Vector2<f64> {
        self.goal
    }
}

impl Driver for PathFollowerDriver {
    fn synchronize(&mut self, state: &VehicleState) -> DriverInputs {
        let (steering, goal) = self.steering.steer(&self.path, state);
        self.goal = goal;
        let u = self.speed.advance(state.time, state.forward_speed());
        let (throttle, brake) = SpeedController::pedals(u);
        DriverInputs {
            throttle,
            brake,
            steering,
        }
        .clamped()
    }
}
