//! Rigid marker carriers: wall markers that move with a rigid motion set from outside
//! (a body of a multibody system, through chrono-fsi), and the force and impulse the fluid
//! puts on them.
//!
//! A carrier's markers keep their body-frame offsets `r0` (in
//! [`ParticleData::anchor`](crate::ParticleData)); at time `s` a marker is at
//! `x = c(s) + R(s) r0` with the [`RigidMotion`] of the carrier:
//!
//! ```text
//! c(s) = c0 + (s - t0) v,     R(s) = exp((s - t0) [w]) R0          (constant-velocity screw)
//! v_m  = v + w x r,           a_m  = a + alpha x r + w x (w x r),  r = R(s) r0
//! ```
//!
//! `v_m` is the marker velocity of the continuity equation and of the no-slip
//! extrapolation (Adami, Hu and Adams 2012, `v_w = 2 v_m - v~_f`: carrier markers have no
//! wall normal), `a_m` enters the pressure extrapolation `p_w = ... + (b - a_m) . ...`
//! (`b` the fluid's body acceleration).
//!
//! The force on a carrier is the sum over its markers `w` of the reactions of the fluid
//! pair terms, `F = - sum_w sum_f m_f a_fw` with `a_fw` the pressure and viscous
//! acceleration of fluid particle `f` due to marker `w` (the term the fluid's force pass
//! adds), and the torque `T = sum_w r_w x F_w` about `c(s)`. Summed in slot order
//! (deterministic). The impulse over a kick-drift-kick step of size `dt` is
//! `dt (F^n + F^(n+1)) / 2`: the very kicks the fluid gets, so fluid plus carrier
//! momentum is conserved to round-off.
//!
//! # Point carriers (deformable bodies)
//!
//! A *point carrier* ([`SphBuilder::add_point_markers`](crate::SphBuilder::add_point_markers))
//! has no rigid motion: each marker `w` moves with its own constant velocity over the
//! interval set from outside ([`SphSystem::set_point_motion`](crate::SphSystem::set_point_motion)),
//!
//! ```text
//! x_w(s) = x_w(t0) + (s - t0) v_w,    a_w = 0 (pressure extrapolation)
//! ```
//!
//! e.g. the markers of a finite-element mesh whose nodes move with their velocity over a
//! multibody step (chrono-fsi interpolates them with the shape functions). The fluid's
//! force and impulse are kept per marker (same sums as for rigid carriers), so the caller
//! can distribute them to its own coordinates.

use nalgebra::{UnitQuaternion, Vector3};

use crate::error::{Result, SphError};

/// Marker carrier index of a particle that belongs to no carrier.
pub const NO_CARRIER: u32 = u32::MAX;

/// Bit of a [`ParticleData::carrier`](crate::ParticleData) code that marks a point
/// carrier's marker (the low bits are the point carrier's index);
/// [`NO_CARRIER`] has it set too and is tested first.
pub const POINT_CARRIER: u32 = 1 << 31;

/// The rigid motion of a carrier over an interval (see the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidMotion {
    /// Reference time, s.
    pub t0: f64,
    /// Centre (the body's centre of mass) at `t0`, m.
    pub position: Vector3<f64>,
    /// Orientation at `t0` (body to world).
    pub rotation: UnitQuaternion<f64>,
    /// Velocity of the centre, m/s.
    pub velocity: Vector3<f64>,
    /// Angular velocity (world), rad/s.
    pub angular_velocity: Vector3<f64>,
    /// Acceleration of the centre (for the pressure extrapolation only), m/s^2.
    pub acceleration: Vector3<f64>,
    /// Angular acceleration (world; pressure extrapolation only), rad/s^2.
    pub angular_acceleration: Vector3<f64>,
}

impl RigidMotion {
    /// At rest at `position` with `rotation`, from `t0 = 0`.
    pub fn at_rest(position: Vector3<f64>, rotation: UnitQuaternion<f64>) -> Self {
        Self {
            t0: 0.0,
            position,
            rotation,
            velocity: Vector3::zeros(),
            angular_velocity: Vector3::zeros(),
            acceleration: Vector3::zeros(),
            angular_acceleration: Vector3::zeros(),
        }
    }

    /// Checks that every field is finite; `field` names the carrier in the error.
    pub fn validate(&self, field: &str) -> Result<()> {
        let ok = self.t0.is_finite()
            && self.position.iter().all(|x| x.is_finite())
            && self.rotation.coords.iter().all(|x| x.is_finite())
            && self.velocity.iter().all(|x| x.is_finite())
            && self.angular_velocity.iter().all(|x| x.is_finite())
            && self.acceleration.iter().all(|x| x.is_finite())
            && self.angular_acceleration.iter().all(|x| x.is_finite());
        if ok {
            Ok(())
        } else {
            Err(SphError::invalid(
                field,
                format!("{self:?}"),
                "every field must be finite",
            ))
        }
    }

    /// Centre and orientation at time `s`.
    pub fn pose_at(&self, s: f64) -> (Vector3<f64>, UnitQuaternion<f64>) {
        let dt = s - self.t0;
        let c = self.position + dt * self.velocity;
        let r = UnitQuaternion::from_scaled_axis(dt * self.angular_velocity) * self.rotation;
        (c, r)
    }
}

/// A carrier: its motion and the fluid's load on it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Carrier {
    pub motion: RigidMotion,
    /// Centre and orientation at the current time.
    pub centre: Vector3<f64>,
    pub rotation: UnitQuaternion<f64>,
    /// Force (N) and torque about the centre (N m) of the last force evaluation.
    pub load: [Vector3<f64>; 2],
    /// Impulse (N s) and angular impulse (N m s) accumulated since the last take.
    pub impulse: [Vector3<f64>; 2],
}

impl Carrier {
    pub fn new(motion: RigidMotion) -> Self {
        let (centre, rotation) = motion.pose_at(motion.t0);
        Self {
            motion,
            centre,
            rotation,
            load: [Vector3::zeros(); 2],
            impulse: [Vector3::zeros(); 2],
        }
    }
}

/// A point carrier: markers with per-marker positions at `t0` and velocities, and the
/// fluid's per-marker force and impulse (see the [module docs](self)). The markers have
/// consecutive particle ids from `first_id` (creation order).
#[derive(Debug, Clone)]
pub(crate) struct PointCarrier {
    pub first_id: u32,
    pub t0: f64,
    /// Positions at `t0`, m.
    pub x0: Vec<[f64; 3]>,
    /// Velocities, m/s.
    pub v: Vec<[f64; 3]>,
    /// Force of the last force evaluation, N.
    pub force: Vec<[f64; 3]>,
    /// Impulse accumulated since the last take, N s.
    pub impulse: Vec<[f64; 3]>,
}

impl PointCarrier {
    pub fn new(first_id: u32, x0: Vec<[f64; 3]>) -> Self {
        let n = x0.len();
        Self {
            first_id,
            t0: 0.0,
            x0,
            v: vec![[0.0; 3]; n],
            force: vec![[0.0; 3]; n],
            impulse: vec![[0.0; 3]; n],
        }
    }
}
