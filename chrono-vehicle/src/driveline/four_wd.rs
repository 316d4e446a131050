//! The 4WD driveline of the HMMWV as shafts of a [`ShaftSystem`].
//!
//! ```text
//!  input (transmission output) ==1:1== central box --central differential--+-- front driveshaft
//!                                                                         +-- rear driveshaft
//!  front driveshaft ==conical r_f== front box --front differential--+-- FL axle ~ FL spindle
//!                                                                   +-- FR axle ~ FR spindle
//!  rear driveshaft  ==conical r_r== rear box  --rear differential---+-- RL axle ~ RL spindle
//!                                                                   +-- RR axle ~ RR spindle
//! ```
//!
//! - the differentials are open bevel differentials, `w_box = (w_1 + w_2)/2` (equal torque
//!   split); each has a lock, a clutch between its two outputs with the locking torque
//!   limit when engaged (0 when not), so a locked differential is a limited-slip one
//!   that holds up to the limit;
//! - the conical (ring and pinion) gears are speed ratios `w_box = r w_driveshaft`
//!   (HMMWV 0.2: the axle torque is 5 times the driveshaft's);
//! - each axle shaft is coupled to its spindle's spin about the spindle axis (body frame),
//!   relative to the chassis, which takes the reaction (the axle housing);
//! - each axle has a brake, a clutch to ground (zero speed relative to the chassis) whose
//!   limit is the brake pedal times the axle's maximum brake torque.
//!
//! The reactions of the conical gears and of the central differential are not passed to
//! the chassis (only the axle couplings are): the chassis gets the drive and brake torques
//! about the spindle axes, not the driveshaft's roll torque.
//!
//! Reference: Chrono's `ChShaftsDriveline4WD` / `HMMWV_Driveline4WD` as summarized in our
//! notes (section 7: boxes 0.6 kg m^2, shafts 0.5, conical ratios 0.2, locking limit
//! 100 N m).

use chrono_core::BodyHandle;
use chrono_core::math::Vector3;
use serde::{Deserialize, Serialize};

use super::shafts::{LinkId, ShaftId, ShaftSystem};
use crate::error::{Result, VehicleError, check_non_negative, check_positive};

/// A wheel position; `as usize` is its index in per-wheel arrays.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Wheel {
    /// Front left.
    FrontLeft = 0,
    /// Front right.
    FrontRight = 1,
    /// Rear left.
    RearLeft = 2,
    /// Rear right.
    RearRight = 3,
}

impl Wheel {
    /// The four wheels in index order.
    pub const ALL: [Wheel; 4] = [
        Wheel::FrontLeft,
        Wheel::FrontRight,
        Wheel::RearLeft,
        Wheel::RearRight,
    ];
}

/// Parameters of a [`FourWd`] (JSON-ready; the default is the HMMWV's).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FourWdParams {
    /// Polar inertia of each differential box (central, front, rear), kg m^2 (HMMWV 0.6).
    pub differential_box_inertia: f64,
    /// Polar inertia of the front and rear driveshafts and of each axle shaft, kg m^2
    /// (HMMWV 0.5).
    pub shaft_inertia: f64,
    /// Front conical gear: front box speed over front driveshaft speed (HMMWV 0.2).
    pub front_conical_ratio: f64,
    /// Rear conical gear: rear box speed over rear driveshaft speed (HMMWV 0.2).
    pub rear_conical_ratio: f64,
    /// Torque an engaged differential lock holds, N m (HMMWV 100).
    pub locking_torque_limit: f64,
    /// Central differential locked at start.
    #[serde(default)]
    pub lock_central: bool,
    /// Front differential locked at start.
    #[serde(default)]
    pub lock_front: bool,
    /// Rear differential locked at start.
    #[serde(default)]
    pub lock_rear: bool,
    /// Brake torque of each front wheel at full pedal, N m.
    pub front_brake_max_torque: f64,
    /// Brake torque of each rear wheel at full pedal, N m.
    pub rear_brake_max_torque: f64,
    /// Spin axis of each spindle in the spindle's body frame (normalized; default `+Y`,
    /// forward rolling is a positive spin in the vehicle frame X forward, Y left, Z up).
    pub spindle_axis: [f64; 3],
}

impl Default for FourWdParams {
    /// The HMMWV (Chrono's `HMMWV_Driveline4WD`). The brake torques (4000 N m per wheel) are not in
    /// notes: they are our choice, to be checked against the HMMWV brake data.
    fn default() -> Self {
        Self {
            differential_box_inertia: 0.6,
            shaft_inertia: 0.5,
            front_conical_ratio: 0.2,
            rear_conical_ratio: 0.2,
            locking_torque_limit: 100.0,
            lock_central: false,
            lock_front: false,
            lock_rear: false,
            front_brake_max_torque: 4000.0,
            rear_brake_max_torque: 4000.0,
            spindle_axis: [0.0, 1.0, 0.0],
        }
    }
}

impl FourWdParams {
    /// Check every field; errors name `four_wd.<field>` and the value.
    pub fn validate(&self) -> Result<()> {
        check_positive(
            "four_wd.differential_box_inertia",
            self.differential_box_inertia,
        )?;
        check_positive("four_wd.shaft_inertia", self.shaft_inertia)?;
        for (f, r) in [
            ("four_wd.front_conical_ratio", self.front_conical_ratio),
            ("four_wd.rear_conical_ratio", self.rear_conical_ratio),
        ] {
            if !(r.is_finite() && r != 0.0) {
                return Err(VehicleError::invalid(f, r, "must be finite and nonzero"));
            }
        }
        check_non_negative("four_wd.locking_torque_limit", self.locking_torque_limit)?;
        check_non_negative(
            "four_wd.front_brake_max_torque",
            self.front_brake_max_torque,
        )?;
        check_non_negative("four_wd.rear_brake_max_torque", self.rear_brake_max_torque)?;
        let a = Vector3::from(self.spindle_axis);
        if !(a.iter().all(|x| x.is_finite()) && a.norm() > 1e-12) {
            return Err(VehicleError::invalid(
                "four_wd.spindle_axis",
                format!("{:?}", self.spindle_axis),
                "must be finite and nonzero",
            ));
        }
        Ok(())
    }

    /// Read from JSON and validate.
    pub fn from_json(text: &str) -> Result<Self> {
        let p: Self = serde_json::from_str(text).map_err(|e| VehicleError::Data {
            path: "<four_wd>".into(),
            message: e.to_string(),
        })?;
        p.validate()?;
        Ok(p)
    }
}

/// The HMMWV 4WD driveline (see the [module docs](self)).
#[derive(Debug, Clone)]
pub struct FourWd {
    params: FourWdParams,
    input: ShaftId,
    front_driveshaft: ShaftId,
    rear_driveshaft: ShaftId,
    axles: [ShaftId; 4],
    /// Central, front and rear differential boxes (carriers).
    boxes: [ShaftId; 3],
    differentials: [LinkId; 3],
    locks: [LinkId; 3],
    brakes: [LinkId; 4],
    couplings: [LinkId; 4],
    locked: [bool; 3],
}

impl FourWd {
    /// Build the driveline in `shafts`: `input` is the transmission's output shaft,
    /// `spindles` the four spindle bodies in [`Wheel`] order, `chassis` the reference
    /// body of the axle couplings. Errors name `four_wd.<field>`.
    pub fn new(
        params: &FourWdParams,
        shafts: &mut ShaftSystem,
        input: ShaftId,
        spindles: [BodyHandle; 4],
        chassis: BodyHandle,
    ) -> Result<Self> {
        params.validate()?;
        let p = params;
        let central_box =
            shafts.add_shaft("central differential box", p.differential_box_inertia)?;
        shafts.add_gear(central_box, input, 1.0)?;
        let front_driveshaft = shafts.add_shaft("front driveshaft", p.shaft_inertia)?;
        let rear_driveshaft = shafts.add_shaft("rear driveshaft", p.shaft_inertia)?;
        let front_box = shafts.add_shaft("front differential box", p.differential_box_inertia)?;
        let rear_box = shafts.add_shaft("rear differential box", p.differential_box_inertia)?;
        let names = ["FL axle", "FR axle", "RL axle", "RR axle"];
        let mut axles = [input; 4];
        for (a, name) in axles.iter_mut().zip(names) {
            *a = shafts.add_shaft(name, p.shaft_inertia)?;
        }
        shafts.add_gear(front_box, front_driveshaft, p.front_conical_ratio)?;
        shafts.add_gear(rear_box, rear_driveshaft, p.rear_conical_ratio)?;
        let differentials = [
            shafts.add_differential(central_box, front_driveshaft, rear_driveshaft)?,
            shafts.add_differential(front_box, axles[0], axles[1])?,
            shafts.add_differential(rear_box, axles[2], axles[3])?,
        ];
        let locked = [p.lock_central, p.lock_front, p.lock_rear];
        let limit = |on: bool| if on { p.locking_torque_limit } else { 0.0 };
        let locks = [
            shafts.add_clutch(front_driveshaft, Some(rear_driveshaft), limit(locked[0]))?,
            shafts.add_clutch(axles[0], Some(axles[1]), limit(locked[1]))?,
            shafts.add_clutch(axles[2], Some(axles[3]), limit(locked[2]))?,
        ];
        let mut brakes = [differentials[0]; 4];
        let mut couplings = [differentials[0]; 4];
        let axis = Vector3::from(p.spindle_axis);
        for w in 0..4 {
            brakes[w] = shafts.add_clutch(axles[w], None, 0.0)?;
            couplings[w] = shafts.couple_to_body(axles[w], spindles[w], axis, Some(chassis))?;
        }
        Ok(Self {
            params: params.clone(),
            input,
            front_driveshaft,
            rear_driveshaft,
            axles,
            boxes: [central_box, front_box, rear_box],
            differentials,
            locks,
            brakes,
            couplings,
            locked,
        })
    }

    /// Once per step before the system steps: the brake pedal (clamped to `[0, 1]`, NaN is
    /// an error) sets every wheel's brake to `pedal * max torque` of its axle.
    pub fn synchronize(&mut self, brake: f64, shafts: &mut ShaftSystem) -> Result<()> {
        if brake.is_nan() {
            return Err(VehicleError::invalid("brake", brake, "must not be NaN"));
        }
        let b = brake.clamp(0.0, 1.0);
        let (f, r) = (
            self.params.front_brake_max_torque,
            self.params.rear_brake_max_torque,
        );
        self.set_brake_torques([b * f, b * f, b * r, b * r], shafts)
    }

    /// Set each wheel's brake torque limit directly (N m, finite and >= 0; [`Wheel`]
    /// order), e.g. for braking one side to steer. Holds until the next call or
    /// [`synchronize`](Self::synchronize).
    pub fn set_brake_torques(&mut self, torques: [f64; 4], shafts: &mut ShaftSystem) -> Result<()> {
        for (w, t) in torques.iter().enumerate() {
            if !(t.is_finite() && *t >= 0.0) {
                check_non_negative(&format!("brake torque [{w}]"), *t)?;
            }
        }
        for (link, t) in self.brakes.iter().zip(torques) {
            shafts.set_clutch_torque(*link, t)?;
        }
        Ok(())
    }

    /// Engage or release the locks of the central, front and rear differentials (an
    /// engaged lock holds up to `locking_torque_limit`).
    pub fn set_locks(&mut self, locks: [bool; 3], shafts: &mut ShaftSystem) -> Result<()> {
        for (link, on) in self.locks.iter().zip(locks) {
            let t = if on {
                self.params.locking_torque_limit
            } else {
                0.0
            };
            shafts.set_clutch_torque(*link, t)?;
        }
        self.locked = locks;
        Ok(())
    }

    /// The lock states (central, front, rear).
    pub fn locks(&self) -> [bool; 3] {
        self.locked
    }

    /// Spin of a wheel relative to the chassis (its axle shaft's speed), rad/s.
    pub fn wheel_speed(&self, wheel: Wheel, shafts: &ShaftSystem) -> f64 {
        shafts.speed(self.axles[wheel as usize])
    }

    /// Torque the driveline applied to a wheel's spindle about its spin axis in the last
    /// step (drive minus brake), N m: minus the coupling row's reaction on the axle shaft.
    pub fn wheel_torque(&self, wheel: Wheel, shafts: &ShaftSystem) -> f64 {
        -shafts.reaction(self.couplings[wheel as usize])
    }

    /// Speed of the input (transmission output) shaft, rad/s.
    pub fn driveshaft_speed(&self, shafts: &ShaftSystem) -> f64 {
        shafts.speed(self.input)
    }

    /// The central, front and rear differential boxes (carriers).
    pub fn differential_boxes(&self) -> [ShaftId; 3] {
        self.boxes
    }

    /// The input shaft.
    pub fn input_shaft(&self) -> ShaftId {
        self.input
    }
    /// The front and rear driveshafts.
    pub fn driveshafts(&self) -> [ShaftId; 2] {
        [self.front_driveshaft, self.rear_driveshaft]
    }
    /// The axle shaft of a wheel.
    pub fn axle(&self, wheel: Wheel) -> ShaftId {
        self.axles[wheel as usize]
    }
    /// The differentials' rows (central, front, rear).
    pub fn differentials(&self) -> [LinkId; 3] {
        self.differentials
    }
    /// The lock clutches (central, front, rear).
    pub fn lock_links(&self) -> [LinkId; 3] {
        self.locks
    }
    /// The brake clutch of a wheel.
    pub fn brake(&self, wheel: Wheel) -> LinkId {
        self.brakes[wheel as usize]
    }
    /// The parameters.
    pub fn params(&self) -> &FourWdParams {
        &self.params
    }
}
