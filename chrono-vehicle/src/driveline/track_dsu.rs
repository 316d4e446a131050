//! The driveline of a tracked vehicle with a differential steering unit (DSU): a
//! double differential whose two summing gears add the propulsion speed and a steering
//! speed, the steering path driven by a hydrostatic steering motor.
//!
//! ```text
//!  input (transmission output) ==conical r== propulsion shaft (w_p) --+-- summing gear L -- left shaft  ~ left sprocket
//!                                                                     |        | -k
//!  steering motor (w_set, T_max) ~ steering shaft (w_st) -------------+        |
//!                                                                     |        | +k (through a reversing idler)
//!                                                                     +-- summing gear R -- right shaft ~ right sprocket
//! ```
//!
//! Kinematics (two rows of the CCP, each a planetary gear in Willis' form, see
//! [`ShaftSystem::add_planetary`]):
//!
//! ```text
//!  w_L = w_p - k w_st        (row  w_L - w_p + k w_st = 0)
//!  w_R = w_p + k w_st        (row  w_R - w_p - k w_st = 0)
//! ```
//!
//! so that `w_p = (w_L + w_R) / 2` (the propulsion path drives both sprockets through a
//! differential) and `w_R - w_L = 2 k w_st` (the steering path adds equal and opposite
//! speeds to the two sides). `k` is `steering_ratio`, the sprocket speed one unit of
//! steering-shaft speed adds; the summing gears' propulsion factor is folded into the
//! conical ratio `r` (`w_p = r w_input`).
//!
//! Torques: with the row impulses `g_L`, `g_R` (torques `tau_L = g_L / h`, `tau_R = g_R / h`
//! on the sprocket shafts), the propulsion shaft receives `-(tau_L + tau_R)` and the
//! steering shaft `k (tau_L - tau_R)`. In a steady state the steering motor therefore gives
//! `T_st = k (tau_R - tau_L)` (the torque difference of the two sprockets is reacted by the
//! steering path, not by a brake) and the propulsion path `tau_L + tau_R`; the rows do no
//! work (`D'v = 0`), so `T_p w_p + T_st w_st = tau_L w_L + tau_R w_R` plus the shafts'
//! change of kinetic energy (power balance, tested).
//!
//! Steering motor: a [speed motor](ShaftSystem::add_motor) on the steering shaft, `w_st =
//! s w_max` for the steering input `s` in `[-1, 1]` (positive turns left: the right,
//! outer track runs faster), holding it with up to `max_steering_torque` (a hydrostatic
//! pump/motor pair whose displacement follows the steering input, its relief valve the
//! torque limit; the pump's power is not taken from the engine in this model: the motor's
//! power is reported, [`DsuDriveline::steering_power`]). At zero steering the motor holds
//! `w_st = 0`: both sprockets turn together (straight running even with unequal track
//! loads, unlike the open differential of the braked-differential driveline). With the
//! propulsion shaft held (`w_p = 0`) the tracks counter-rotate: a pivot turn about the
//! vehicle's centre.
//!
//! Brakes: the brake pedal acts on the propulsion shaft (a clutch to the hull of limit `2
//! T_b brake`, `T_b` = `brake_max_torque`: while the steering holds, `T_b` on each sprocket
//! as with the sprocket brakes of the braked differential), so braking does not fight the
//! steering: the pivot turn is the brake on, the throttle off and the steering input. The
//! differential lock of [`TrackDrivelineParams`] has no role here (`locked`,
//! `locking_torque_limit` are ignored).
//!
//! Source of the mechanism: J. Y. Wong, *Theory of Ground Vehicles*, 4th ed., Wiley 2008,
//! ch. 7 (steering of tracked vehicles: steering mechanisms, the double-differential steering
//! system, whose two summing planetaries take the propulsion speed and an equal and opposite
//! steering speed); the double differential is the Merritt (Merritt-Brown / Maybach) layout,
//! and a hydrostatic drive of the steering shaft that of hydrostatic-steering cross-drive
//! transmissions. The model (rows, parameters) is our own; the parameter values of
//! `data/m113.json`'s `driveline.dsu` are assumptions (the M113A1 of the data steers with a
//! controlled differential), stated in its provenance.

use chrono_core::BodyHandle;
use chrono_core::math::Vector3;
use serde::{Deserialize, Serialize};

use super::shafts::{LinkId, ShaftId, ShaftSystem};
use super::track_bds::TrackDrivelineParams;
use crate::error::{Result, VehicleError, check_positive};

/// Parameters of the differential steering unit (JSON: `driveline.dsu`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DsuParams {
    /// `k`: sprocket speed added to the right side (and taken from the left) per unit of
    /// steering-shaft speed, `w_R - w_L = 2 k w_st` (finite, > 0).
    pub steering_ratio: f64,
    /// Polar inertia of the steering shaft (with the steering motor's rotor), kg m^2.
    pub steering_shaft_inertia: f64,
    /// Steering-shaft speed at full steering input, rad/s (> 0).
    pub max_steering_speed: f64,
    /// Torque the steering motor can give (its relief valve), N m (> 0).
    pub max_steering_torque: f64,
}

impl DsuParams {
    /// Check every field; errors name `{prefix}.<field>` and the value.
    pub fn validate(&self, prefix: &str) -> Result<()> {
        let f = |name: &str| format!("{prefix}.{name}");
        check_positive(&f("steering_ratio"), self.steering_ratio)?;
        check_positive(&f("steering_shaft_inertia"), self.steering_shaft_inertia)?;
        check_positive(&f("max_steering_speed"), self.max_steering_speed)?;
        check_positive(&f("max_steering_torque"), self.max_steering_torque)?;
        Ok(())
    }

    /// The largest sprocket torque difference the steering motor holds, `tau_R - tau_L =
    /// T_max / k`, N m.
    pub fn max_sprocket_torque_difference(&self) -> f64 {
        self.max_steering_torque / self.steering_ratio
    }
}

/// The DSU track driveline (see the [module docs](self)). Side 0 is the left track, side 1
/// the right.
#[derive(Debug, Clone)]
pub struct DsuDriveline {
    params: TrackDrivelineParams,
    dsu: DsuParams,
    input: ShaftId,
    propulsion: ShaftId,
    steering: ShaftId,
    outputs: [ShaftId; 2],
    summing: [LinkId; 2],
    motor: LinkId,
    brake: LinkId,
    couplings: [LinkId; 2],
    steering_speed: f64,
    brake_torque: f64,
}

impl DsuDriveline {
    /// Build the driveline in `shafts`: `input` is the transmission's output shaft,
    /// `sprockets` the left and right sprocket bodies, `chassis` the reference body of the
    /// sprocket couplings. `params.dsu` must be present; errors name `driveline.<field>` or
    /// `driveline.dsu.<field>`.
    pub fn new(
        params: &TrackDrivelineParams,
        shafts: &mut ShaftSystem,
        input: ShaftId,
        sprockets: [BodyHandle; 2],
        chassis: BodyHandle,
    ) -> Result<Self> {
        params.validate("driveline")?;
        let dsu = params.dsu.clone().ok_or_else(|| {
            VehicleError::invalid(
                "driveline.dsu",
                "none",
                "the differential steering unit needs its parameters",
            )
        })?;
        let p = params;
        let k = dsu.steering_ratio;
        let propulsion = shafts.add_shaft("propulsion shaft", p.differential_box_inertia)?;
        shafts.add_gear(propulsion, input, p.conical_ratio)?;
        let steering = shafts.add_shaft("steering shaft", dsu.steering_shaft_inertia)?;
        let outputs = [
            shafts.add_shaft("left sprocket shaft", p.shaft_inertia)?,
            shafts.add_shaft("right sprocket shaft", p.shaft_inertia)?,
        ];
        // w_L - w_p + k w_st = 0 and w_R - w_p - k w_st = 0.
        let summing = [
            shafts.add_planetary([outputs[0], propulsion, steering], [1.0, -1.0, k])?,
            shafts.add_planetary([outputs[1], propulsion, steering], [1.0, -1.0, -k])?,
        ];
        let motor = shafts.add_motor(steering, 0.0, dsu.max_steering_torque)?;
        let brake = shafts.add_clutch(propulsion, None, 0.0)?;
        let axis = Vector3::from(p.sprocket_axis);
        let couplings = [
            shafts.couple_to_body(outputs[0], sprockets[0], axis, Some(chassis))?,
            shafts.couple_to_body(outputs[1], sprockets[1], axis, Some(chassis))?,
        ];
        Ok(Self {
            params: params.clone(),
            dsu,
            input,
            propulsion,
            steering,
            outputs,
            summing,
            motor,
            brake,
            couplings,
            steering_speed: 0.0,
            brake_torque: 0.0,
        })
    }

    /// The steering motor's commanded speed for a steering input, `s w_max` (rad/s), and
    /// the propulsion brake's limit for a brake pedal, `2 T_b b` (N m). Inputs are clamped
    /// to `[-1, 1]` and `[0, 1]`; NaN is an error naming the input.
    pub fn commands_for(&self, brake: f64, steering: f64) -> Result<(f64, f64)> {
        if brake.is_nan() {
            return Err(VehicleError::invalid("brake", brake, "must not be NaN"));
        }
        if steering.is_nan() {
            return Err(VehicleError::invalid(
                "steering",
                steering,
                "must not be NaN",
            ));
        }
        Ok((
            steering.clamp(-1.0, 1.0) * self.dsu.max_steering_speed,
            2.0 * self.params.brake_max_torque * brake.clamp(0.0, 1.0),
        ))
    }

    /// Once per step before the system steps: the steering motor's speed from the steering
    /// input and the propulsion brake from the brake pedal (see
    /// [`commands_for`](Self::commands_for)).
    pub fn synchronize(
        &mut self,
        brake: f64,
        steering: f64,
        shafts: &mut ShaftSystem,
    ) -> Result<()> {
        let (w, t) = self.commands_for(brake, steering)?;
        shafts.set_motor(self.motor, w, self.dsu.max_steering_torque)?;
        shafts.set_clutch_torque(self.brake, t)?;
        self.steering_speed = w;
        self.brake_torque = t;
        Ok(())
    }

    /// The steering motor's commanded speed in force, rad/s.
    pub fn steering_speed_command(&self) -> f64 {
        self.steering_speed
    }

    /// The propulsion brake's limit in force, N m.
    pub fn brake_torque(&self) -> f64 {
        self.brake_torque
    }

    /// Spin of a side's sprocket relative to the chassis (its output shaft's speed), rad/s.
    pub fn sprocket_speed(&self, side: usize, shafts: &ShaftSystem) -> f64 {
        shafts.speed(self.outputs[side])
    }

    /// Torque the driveline applied to a side's sprocket about its axis in the last step,
    /// N m: minus the coupling row's reaction on the output shaft.
    pub fn sprocket_torque(&self, side: usize, shafts: &ShaftSystem) -> f64 {
        -shafts.reaction(self.couplings[side])
    }

    /// Torque the steering motor applied to the steering shaft in the last step, N m.
    pub fn steering_torque(&self, shafts: &ShaftSystem) -> f64 {
        shafts.reaction(self.motor)
    }

    /// Power the steering motor delivered in the last step, `T_st w_st`, W.
    pub fn steering_power(&self, shafts: &ShaftSystem) -> f64 {
        self.steering_torque(shafts) * shafts.speed(self.steering)
    }

    /// Torque the propulsion brake applied to the propulsion shaft in the last step, N m.
    pub fn propulsion_brake_torque(&self, shafts: &ShaftSystem) -> f64 {
        shafts.reaction(self.brake)
    }

    /// Torque a summing gear applied to its sprocket shaft in the last step (`tau_L`,
    /// `tau_R` of the module docs), N m.
    pub fn summing_torque(&self, side: usize, shafts: &ShaftSystem) -> f64 {
        shafts.reaction(self.summing[side])
    }

    /// The input shaft.
    pub fn input_shaft(&self) -> ShaftId {
        self.input
    }
    /// The propulsion shaft (the double differential's common input, `w_p`).
    pub fn propulsion_shaft(&self) -> ShaftId {
        self.propulsion
    }
    /// The steering shaft (`w_st`).
    pub fn steering_shaft(&self) -> ShaftId {
        self.steering
    }
    /// The output (sprocket) shaft of a side.
    pub fn output_shaft(&self, side: usize) -> ShaftId {
        self.outputs[side]
    }
    /// The parameters.
    pub fn params(&self) -> &TrackDrivelineParams {
        &self.params
    }
    /// The DSU's parameters.
    pub fn dsu(&self) -> &DsuParams {
        &self.dsu
    }
}

#[cfg(test)]
#[path = "track_dsu_tests.rs"]
mod tests;
