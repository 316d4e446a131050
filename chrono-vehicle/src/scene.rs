//! Setting a vehicle down in a scene and reading what a test course needs from it.
//!
//! - [`start_height`]: the chassis reference height that puts the tires a clearance above
//!   the ground;
//! - [`FlatScene`]: a system with flat rigid ground and a wheeled vehicle resting just
//!   above it (the scene of the HMMWV validation cases and the examples);
//! - [`steer_angles`], [`max_front_steer`]: the wheels' steer angles, and the steering
//!   linkage's full-lock angle a path follower needs;
//! - [`mean_wheel_surface_speed`], [`mean_sinkage`]: wheel quantities of the
//!   off-road courses ([`TractionControl`](crate::driver::TractionControl), sinkage on a
//!   granular bed);
//! - [`lock_differentials`], [`front_reach`]: a vehicle prepared for loose ground and the
//!   room it needs ahead of its reference point.

use std::sync::Arc;

use chrono_ccp::CcpSolver;
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::{ContactMaterial, System, SystemSettings};

use crate::error::{Result, VehicleError};
use crate::state::DriverInputs;
use crate::terrain::{FlatTerrain, Terrain};
use crate::vehicle::{VehicleData, WheeledVehicle};

/// The height of the chassis reference point (m) that puts the lowest point of the tires
/// `clearance` m above a ground at height `ground` (m): the wheel centres sit at the
/// spindle points' height (the first axle's `spindle[2]`) below the reference, and the
/// tires reach one tire radius below them.
pub fn start_height(data: &VehicleData, ground: f64, clearance: f64) -> f64 {
    let spindle_z = data.axles[0].suspension.points.spindle[2];
    ground + data.wheel.tire.radius() - spindle_z + clearance
}

/// A system with flat rigid ground at `z = 0` (friction `mu`) and a vehicle resting with
/// its tires 5 mm above it, unrotated, its reference point above the origin.
pub struct FlatScene {
    /// The system (default settings: gravity [`GRAVITY`](chrono_core::math::GRAVITY)).
    pub sys: System,
    /// The vehicle.
    pub vehicle: WheeledVehicle,
    /// Its description.
    pub data: VehicleData,
}

/// Gap between the tires and the ground at the start of a [`FlatScene`], m.
pub const START_CLEARANCE: f64 = 0.005;

impl FlatScene {
    /// Build the scene for `data` with tire–ground friction `mu` and the CCP `solver` (the
    /// suspension joints and driveline shafts are rows of its problem; `chrono_ccp::Schur`
    /// solves them directly).
    pub fn new(data: VehicleData, mu: f64, solver: Box<dyn CcpSolver>) -> Result<Self> {
        let mut sys = System::new(SystemSettings::default(), solver)?;
        let terrain = Arc::new(FlatTerrain::new(0.0, mu)?);
        terrain.add_to_system(&mut sys, ContactMaterial::with_friction(mu))?;
        let z0 = start_height(&data, 0.0, START_CLEARANCE);
        let vehicle = WheeledVehicle::build(
            &mut sys,
            &data,
            &Isometry3::translation(0.0, 0.0, z0),
            terrain,
        )?;
        Ok(Self { sys, vehicle, data })
    }

    /// Steer angle of each wheel ([`steer_angles`]).
    pub fn steer_angles(&self) -> Result<Vec<f64>> {
        steer_angles(&self.sys, &self.vehicle)
    }

    /// Forward speed of the chassis, m/s.
    pub fn forward_speed(&self) -> Result<f64> {
        Ok(self.vehicle.state(&self.sys)?.forward_speed())
    }

    /// One step of `h` s with the driver's `inputs`.
    pub fn step(&mut self, inputs: DriverInputs, h: f64) -> Result<()> {
        self.vehicle.synchronize(&mut self.sys, inputs)?;
        self.sys.step(h)?;
        Ok(())
    }
}

/// Steer angle of each wheel about the chassis' Z axis, rad (positive: turned left), from
/// the spindles' spin axes in the chassis frame, in the order of
/// [`WheeledVehicle::wheels`].
pub fn steer_angles(sys: &System, vehicle: &WheeledVehicle) -> Result<Vec<f64>> {
    let chassis = sys.body(vehicle.chassis())?.rotation();
    vehicle
        .wheels()
        .iter()
        .map(|w| {
            let axis = chassis.inverse() * (sys.body(w.spindle)?.rotation() * Vector3::y());
            Ok((-axis.x).atan2(axis.y))
        })
        .collect()
}

/// The mean front-wheel steer angle at full left input (rad), measured on a separate
/// [`FlatScene`] of `data` at rest (braked; 40 ms to settle, then 20 ms at full lock, steps
/// of 1 ms): the steering linkage's ratio, which a path follower needs to turn a wanted
/// wheel angle into a steering input.
pub fn max_front_steer(data: VehicleData, mu: f64, solver: Box<dyn CcpSolver>) -> Result<f64> {
    let mut s = FlatScene::new(data, mu, solver)?;
    let h = 1e-3;
    for k in 0..60 {
        let steering = if k < 40 { 0.0 } else { 1.0 };
        s.step(
            DriverInputs {
                steering,
                brake: 1.0,
                ..Default::default()
            },
            h,
        )?;
    }
    let a = s.steer_angles()?;
    if a.len() < 2 {
        return Err(VehicleError::invalid(
            "axles",
            a.len() / 2,
            "a steered front axle with two wheels is needed",
        ));
    }
    Ok(0.5 * (a[0] + a[1]))
}

/// The mean surface speed of the wheels `omega_y R` (m/s) about the (level) axle axis,
/// tire radius `radius` (m): the speed a wheel would roll at without slip.
pub fn mean_wheel_surface_speed(
    sys: &System,
    vehicle: &WheeledVehicle,
    radius: f64,
) -> Result<f64> {
    let mut wr = 0.0;
    for w in vehicle.wheels() {
        wr += sys.body(w.spindle)?.angular_velocity().y * radius;
    }
    Ok(wr / vehicle.wheels().len() as f64)
}

/// The mean sinkage of the wheels into a bed whose surface is at height `surface` (m):
/// the surface minus the lowest point of each tire (spindle height minus `radius`; an
/// ANCF tire's lowest tread point, [`WheeledVehicle::tire_bottom`]), averaged over the
/// wheels, m.
pub fn mean_sinkage(
    sys: &System,
    vehicle: &WheeledVehicle,
    surface: f64,
    radius: f64,
) -> Result<f64> {
    let sink = (0..vehicle.wheels().len())
        .map(|i| vehicle.tire_bottom(sys, i, radius).map(|z| surface - z))
        .collect::<Result<Vec<f64>>>()?;
    Ok(sink.iter().sum::<f64>() / sink.len() as f64)
}

/// Engage the central, front and rear differential locks of `data`, each holding up to
/// `torque` N m (`> 0`): loose ground needs them, since an open differential sends the
/// torque to the wheel with the least grip.
pub fn lock_differentials(data: &mut VehicleData, torque: f64) -> Result<()> {
    crate::error::check_positive("driveline.locking_torque_limit", torque)?;
    data.driveline.locking_torque_limit = torque;
    data.driveline.lock_central = true;
    data.driveline.lock_front = true;
    data.driveline.lock_rear = true;
    Ok(())
}

/// How far ahead of the vehicle's reference point the front tires reach, plus `margin`
/// (m): the largest axle `x` plus the tire radius.
pub fn front_reach(data: &VehicleData, margin: f64) -> f64 {
    data.axles
        .iter()
        .map(|a| a.location[0])
        .fold(f64::NEG_INFINITY, f64::max)
        + data.wheel.tire.radius()
        + margin
}
