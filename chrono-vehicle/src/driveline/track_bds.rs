//! The driveline of a tracked vehicle with steering by differential braking ("BDS":
//! bevel gear, differential, steering brakes) as shafts of a [`ShaftSystem`].
//!
//! ```text
//!  input (transmission output) ==conical r== differential box --differential--+-- left shaft  ~ left sprocket
//!                                                                             +-- right shaft ~ right sprocket
//! ```
//!
//! - the conical (bevel) gear is a speed ratio `w_box = r w_input` (the M113: 0.5);
//! - the differential is an open bevel differential, `w_box = (w_l + w_r) / 2` (equal torque
//!   split), with a lock (a clutch between the two outputs holding up to
//!   `locking_torque_limit` when engaged);
//! - each output shaft is coupled to its sprocket's spin about the sprocket axis (body
//!   frame) relative to the chassis, which takes the reaction (the final drive housing);
//! - each output shaft has a brake, a clutch to ground (zero speed relative to the chassis)
//!   whose limit is set per step: the brake pedal brakes both sides, the steering input
//!   brakes the inner side ([`TrackDriveline::synchronize`]). With the open differential,
//!   slowing one side speeds up the other (`w_l + w_r = 2 w_box`): the vehicle turns about
//!   the braked side, the classic "braked differential" skid steering (Wong, *Theory of
//!   Ground Vehicles*, 4th ed., ch. 7, steering of tracked vehicles).
//!
//! As in [`super::FourWd`], the reactions of the conical gear and of the differential box
//! are not passed to the chassis; the sprocket couplings pass drive and brake torques.
//!
//! Reference values: Project Chrono's `M113_DrivelineBDS` (conical ratio 0.5, box inertia
//! 0.6 kg m^2, driveshaft inertia 0.5 kg m^2, locking limit 100 N m) and
//! `M113_BrakeSimple` (10 000 N m per side), read for their numbers.

use chrono_core::BodyHandle;
use chrono_core::math::Vector3;
use serde::{Deserialize, Serialize};

use super::shafts::{LinkId, ShaftId, ShaftSystem};
use super::track_dsu::DsuParams;
use crate::error::{Result, VehicleError, check_non_negative, check_positive};

/// Parameters of a [`TrackDriveline`] (JSON-ready; the M113's are in `data/m113.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackDrivelineParams {
    /// Polar inertia of the differential box, kg m^2.
    pub differential_box_inertia: f64,
    /// Polar inertia of each output (sprocket) shaft, kg m^2.
    pub shaft_inertia: f64,
    /// Conical gear: differential box speed over input speed (finite, nonzero).
    pub conical_ratio: f64,
    /// Torque an engaged differential lock holds, N m.
    pub locking_torque_limit: f64,
    /// Differential locked at start.
    #[serde(default)]
    pub locked: bool,
    /// Brake torque of each sprocket at full pedal or full steering, N m.
    pub brake_max_torque: f64,
    /// Spin axis of each sprocket in its body frame (normalized; `+Y`: forward driving is
    /// a positive spin in the vehicle frame X forward, Y left, Z up).
    pub sprocket_axis: [f64; 3],
    /// The steering mechanism built: `braked_differential` (this module's, the default) or
    /// `dsu` (the differential steering unit of [`super::track_dsu`], which needs `dsu`).
    #[serde(default)]
    pub steering: TrackSteering,
    /// The differential steering unit's parameters (used when `steering` is `dsu`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dsu: Option<DsuParams>,
}

/// The steering mechanism of a track driveline (JSON `driveline.steering`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TrackSteering {
    /// Open differential and a steering brake per side ([`TrackDriveline`]).
    #[default]
    BrakedDifferential,
    /// Double differential with a steering motor ([`super::DsuDriveline`]).
    Dsu,
}

impl std::str::FromStr for TrackSteering {
    type Err = VehicleError;
    /// `braked_differential` or `dsu`; anything else is an error naming `driveline.steering`.
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "braked_differential" => Ok(Self::BrakedDifferential),
            "dsu" => Ok(Self::Dsu),
            other => Err(VehicleError::invalid(
                "driveline.steering",
                format!("\"{other}\""),
                "must be \"braked_differential\" or \"dsu\"",
            )),
        }
    }
}

impl TrackDrivelineParams {
    /// Check every field; errors name `{prefix}.<field>` and the value.
    pub fn validate(&self, prefix: &str) -> Result<()> {
        let f = |name: &str| format!("{prefix}.{name}");
        check_positive(
            &f("differential_box_inertia"),
            self.differential_box_inertia,
        )?;
        check_positive(&f("shaft_inertia"), self.shaft_inertia)?;
        if !(self.conical_ratio.is_finite() && self.conical_ratio != 0.0) {
            return Err(VehicleError::invalid(
                f("conical_ratio"),
                self.conical_ratio,
                "must be finite and nonzero",
            ));
        }
        check_non_negative(&f("locking_torque_limit"), self.locking_torque_limit)?;
        check_non_negative(&f("brake_max_torque"), self.brake_max_torque)?;
        let a = Vector3::from(self.sprocket_axis);
        if !(a.iter().all(|x| x.is_finite()) && a.norm() > 1e-12) {
            return Err(VehicleError::invalid(
                f("sprocket_axis"),
                format!("{:?}", self.sprocket_axis),
                "must be finite and nonzero",
            ));
        }
        if let Some(d) = &self.dsu {
            d.validate(&f("dsu"))?;
        } else if self.steering == TrackSteering::Dsu {
            return Err(VehicleError::invalid(
                f("dsu"),
                "none",
                "`steering` = \"dsu\" needs the differential steering unit's parameters",
            ));
        }
        Ok(())
    }
}

/// The braked-differential track driveline (see the [module docs](self)). Side 0 is the
/// left track, side 1 the right.
#[derive(Debug, Clone)]
pub struct TrackDriveline {
    params: TrackDrivelineParams,
    input: ShaftId,
    differential_box: ShaftId,
    outputs: [ShaftId; 2],
    differential: LinkId,
    lock: LinkId,
    brakes: [LinkId; 2],
    couplings: [LinkId; 2],
    brake_torques: [f64; 2],
}

impl TrackDriveline {
    /// Build the driveline in `shafts`: `input` is the transmission's output shaft,
    /// `sprockets` the left and right sprocket bodies, `chassis` the reference body of the
    /// sprocket couplings. Errors name `driveline.<field>`.
    pub fn new(
        params: &TrackDrivelineParams,
        shafts: &mut ShaftSystem,
        input: ShaftId,
        sprockets: [BodyHandle; 2],
        chassis: BodyHandle,
    ) -> Result<Self> {
        params.validate("driveline")?;
        let p = params;
        let differential_box = shafts.add_shaft("differential box", p.differential_box_inertia)?;
        shafts.add_gear(differential_box, input, p.conical_ratio)?;
        let outputs = [
            shafts.add_shaft("left sprocket shaft", p.shaft_inertia)?,
            shafts.add_shaft("right sprocket shaft", p.shaft_inertia)?,
        ];
        let differential = shafts.add_differential(differential_box, outputs[0], outputs[1])?;
        let limit = if p.locked {
            p.locking_torque_limit
        } else {
            0.0
        };
        let lock = shafts.add_clutch(outputs[0], Some(outputs[1]), limit)?;
        let axis = Vector3::from(p.sprocket_axis);
        let brakes = [
            shafts.add_clutch(outputs[0], None, 0.0)?,
            shafts.add_clutch(outputs[1], None, 0.0)?,
        ];
        let couplings = [
            shafts.couple_to_body(outputs[0], sprockets[0], axis, Some(chassis))?,
            shafts.couple_to_body(outputs[1], sprockets[1], axis, Some(chassis))?,
        ];
        Ok(Self {
            params: params.clone(),
            input,
            differential_box,
            outputs,
            differential,
            lock,
            brakes,
            couplings,
            brake_torques: [0.0; 2],
        })
    }

    /// The brake torque limits of both sides from the driver's inputs, N m:
    /// `T_side = T_max max(brake, s_side)` with `s_left = max(steering, 0)` and `s_right =
    /// max(-steering, 0)` (`steering` > 0 turns left: the left, inner track is braked).
    /// Inputs are clamped to `[0, 1]` and `[-1, 1]`; NaN is an error naming the input.
    pub fn brake_torques_for(&self, brake: f64, steering: f64) -> Result<[f64; 2]> {
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
        let b = brake.clamp(0.0, 1.0);
        let s = steering.clamp(-1.0, 1.0);
        let t = self.params.brake_max_torque;
        Ok([t * b.max(s.max(0.0)), t * b.max((-s).max(0.0))])
    }

    /// Once per step before the system steps: set both brakes from the brake pedal and the
    /// steering input (see [`brake_torques_for`](Self::brake_torques_for)).
    pub fn synchronize(
        &mut self,
        brake: f64,
        steering: f64,
        shafts: &mut ShaftSystem,
    ) -> Result<()> {
        let t = self.brake_torques_for(brake, steering)?;
        self.set_brake_torques(t, shafts)
    }

    /// Set each side's brake torque limit directly (N m, finite and >= 0; left, right).
    /// Holds until the next call or [`synchronize`](Self::synchronize).
    pub fn set_brake_torques(&mut self, torques: [f64; 2], shafts: &mut ShaftSystem) -> Result<()> {
        for (k, t) in torques.iter().enumerate() {
            check_non_negative(&format!("brake torque [{k}]"), *t)?;
        }
        for (link, t) in self.brakes.iter().zip(torques) {
            shafts.set_clutch_torque(*link, t)?;
        }
        self.brake_torques = torques;
        Ok(())
    }

    /// Engage or release the differential lock (an engaged lock holds up to
    /// `locking_torque_limit`).
    pub fn set_locked(&mut self, on: bool, shafts: &mut ShaftSystem) -> Result<()> {
        let t = if on {
            self.params.locking_torque_limit
        } else {
            0.0
        };
        shafts.set_clutch_torque(self.lock, t)
    }

    /// The brake torque limits in force (left, right), N m.
    pub fn brake_torques(&self) -> [f64; 2] {
        self.brake_torques
    }

    /// Spin of a side's sprocket relative to the chassis (its output shaft's speed), rad/s.
    pub fn sprocket_speed(&self, side: usize, shafts: &ShaftSystem) -> f64 {
        shafts.speed(self.outputs[side])
    }

    /// Torque the driveline applied to a side's sprocket about its axis in the last step
    /// (drive minus brake), N m: minus the coupling row's reaction on the output shaft.
    pub fn sprocket_torque(&self, side: usize, shafts: &ShaftSystem) -> f64 {
        -shafts.reaction(self.couplings[side])
    }

    /// The input shaft.
    pub fn input_shaft(&self) -> ShaftId {
        self.input
    }
    /// The differential box (carrier).
    pub fn differential_box(&self) -> ShaftId {
        self.differential_box
    }
    /// The output (sprocket) shaft of a side.
    pub fn output_shaft(&self, side: usize) -> ShaftId {
        self.outputs[side]
    }
    /// The differential's row.
    pub fn differential(&self) -> LinkId {
        self.differential
    }
    /// The parameters.
    pub fn params(&self) -> &TrackDrivelineParams {
        &self.params
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use chrono_ccp::Schur;
    use chrono_core::{JointBuilder, JointKind, RigidBodyBuilder, System, SystemSettings};

    fn params() -> TrackDrivelineParams {
        TrackDrivelineParams {
            differential_box_inertia: 0.6,
            shaft_inertia: 0.5,
            conical_ratio: 0.5,
            locking_torque_limit: 100.0,
            locked: false,
            brake_max_torque: 1.0e4,
            sprocket_axis: [0.0, 1.0, 0.0],
            steering: TrackSteering::BrakedDifferential,
            dsu: None,
        }
    }

    /// A fixed chassis with two sprocket wheels on revolute joints about Y, driven through
    /// the driveline from a torque on the input shaft.
    fn rig(brake: f64, steering: f64, input_torque: f64, steps: usize) -> ([f64; 2], f64) {
        let mut sys = System::new(
            SystemSettings::default(),
            Box::new(Schur::new(Default::default())),
        )
        .unwrap();
        let chassis = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
        let mut sprockets = [chassis; 2];
        for (k, s) in sprockets.iter_mut().enumerate() {
            let y = if k == 0 { 1.0 } else { -1.0 };
            *s = sys
                .add_body(
                    RigidBodyBuilder::dynamic()
                        .mass(10.0)
                        .inertia_diagonal(Vector3::new(1.0, 2.0, 1.0))
                        .position(Vector3::new(0.0, y, 0.0)),
                )
                .unwrap();
            sys.add_joint(JointBuilder::at_axis(
                JointKind::Revolute,
                chassis,
                *s,
                Vector3::new(0.0, y, 0.0),
                Vector3::y(),
            ))
            .unwrap();
        }
        let mut shafts = ShaftSystem::new("test");
        let input = shafts.add_shaft("input", 0.5).unwrap();
        let mut d = TrackDriveline::new(&params(), &mut shafts, input, sprockets, chassis).unwrap();
        shafts.set_torque(input, input_torque).unwrap();
        d.synchronize(brake, steering, &mut shafts).unwrap();
        let item = sys.add_item(Box::new(shafts));
        for _ in 0..steps {
            sys.step(1e-3).unwrap();
        }
        let s = sys.item::<ShaftSystem>(item).unwrap();
        (
            [d.sprocket_speed(0, s), d.sprocket_speed(1, s)],
            s.speed(d.input_shaft()),
        )
    }

    #[test]
    fn an_open_differential_splits_speed_and_torque_equally() {
        let ([l, r], w_in) = rig(0.0, 0.0, 100.0, 200);
        assert!(l > 0.0 && (l - r).abs() < 1e-9 * l, "{l} {r}");
        // The box turns at the mean of the outputs and at r times the input.
        assert!(
            (0.5 * (l + r) - 0.5 * w_in).abs() < 1e-6 * w_in,
            "{l} {r} {w_in}"
        );
        // Energy: the input torque's work goes into the inertias (1 ms steps, 0.2 s):
        // I_eff w_in = T t with I_eff = 0.5 + 0.6 r^2 + 2 (0.5 + 2) r^2.
        let i_eff = 0.5 + 0.25 * (0.6 + 2.0 * 2.5);
        let expected = 100.0 * 0.2 / i_eff;
        assert!((w_in / expected - 1.0).abs() < 1e-3, "{w_in} {expected}");
    }

    #[test]
    fn steering_brakes_the_inner_side_and_speeds_up_the_outer() {
        // Full steering to the left holds the left sprocket (the brake's 1e4 N m exceeds the
        // drive torque): the right one turns at twice the box speed, `w_r = 2 r w_in = w_in`,
        // and the input torque accelerates I_eff = 0.5 + 0.6 r^2 + (0.5 + 2) (2 r)^2.
        let expected = 100.0 * 0.2 / (0.5 + 0.25 * 0.6 + 2.5);
        let ([l, r], w_in) = rig(0.0, 1.0, 100.0, 200);
        assert!(l.abs() < 1e-9 * r, "left {l}");
        assert!(
            (r / expected - 1.0).abs() < 1e-3 && (r - w_in).abs() < 1e-6 * r,
            "{r} {w_in} {expected}"
        );
        let ([l2, r2], _) = rig(0.0, -1.0, 100.0, 200);
        assert!(
            r2.abs() < 1e-9 * l2 && (l2 / expected - 1.0).abs() < 1e-3,
            "{l2} {r2}"
        );
    }

    #[test]
    fn bad_inputs_are_errors_naming_the_field() {
        let mut p = params();
        p.conical_ratio = 0.0;
        let e = p.validate("driveline").unwrap_err().to_string();
        assert!(e.contains("driveline.conical_ratio"), "{e}");
        let mut p = params();
        p.brake_max_torque = -1.0;
        let e = p.validate("driveline").unwrap_err().to_string();
        assert!(e.contains("driveline.brake_max_torque"), "{e}");
        let mut shafts = ShaftSystem::new("t");
        let input = shafts.add_shaft("input", 0.5).unwrap();
        let mut sys = System::new(
            SystemSettings::default(),
            Box::new(Schur::new(Default::default())),
        )
        .unwrap();
        let c = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
        let s = sys.add_body(RigidBodyBuilder::dynamic().mass(1.0)).unwrap();
        let d = TrackDriveline::new(&params(), &mut shafts, input, [s, s], c).unwrap();
        let e = d.brake_torques_for(0.0, f64::NAN).unwrap_err().to_string();
        assert!(e.contains("steering"), "{e}");
        assert_eq!(d.brake_torques_for(0.5, 0.8).unwrap(), [8000.0, 5000.0]);
    }
}
