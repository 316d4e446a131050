//! The powered tracked vehicle: a [`Powertrain`] (engine, torque converter, automatic
//! transmission) and a track driveline ([`SteeredDriveline`]: the braked differential,
//! conical gear, open differential and steering brakes, or the differential steering unit,
//! as the data's `driveline.steering` selects) on one [`ShaftSystem`] item, coupled to the
//! sprockets of a [`TrackedVehicle`].
//!
//! ```text
//!  engine ~ converter ~ gearbox ==conical== differential --+-- left sprocket shaft  ~ left sprocket
//!                                                          +-- right sprocket shaft ~ right sprocket
//! ```
//!
//! Each step, before [`System::step`], the owner calls [`TrackedDrive::synchronize`] with
//! the driver's inputs: throttle (engine torque and shift schedule), brake pedal (both
//! sprocket brakes; the DSU's propulsion brake), steering (positive turns left: by braking
//! the left, inner track, or by the DSU's steering motor).
//!
//! Example (the M113 on flat ground at full throttle):
//!
//! ```no_run
//! use chrono_vehicle::m113::m113_data;
//! use chrono_vehicle::state::DriverInputs;
//! use chrono_vehicle::tracked::TrackedFlatScene;
//! use chrono_vehicle::tracked_drive::TrackedDrive;
//!
//! let data = m113_data()?;
//! let solver = Box::new(chrono_ccp::Schur::new(Default::default()));
//! let mut scene = TrackedFlatScene::new(data.clone(), 0.8, solver)?;
//! let mut drive = TrackedDrive::build(&mut scene.sys, &scene.vehicle, &data)?;
//! let full = DriverInputs { throttle: 1.0, brake: 0.0, steering: 0.0 };
//! for _ in 0..100 {
//!     drive.synchronize(&mut scene.sys, full)?;
//!     scene.sys.step(2e-3)?;
//! }
//! println!("{:.0} rpm", drive.powertrain().engine_speed_rpm());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use chrono_core::item::ItemHandle;
use chrono_core::{Drive, System};

use crate::driveline::{ShaftSystem, SteeredDriveline};
use crate::error::{Result, VehicleError};
use crate::powertrain::Powertrain;
use crate::state::DriverInputs;
use crate::tracked::{TrackedVehicle, TrackedVehicleData};

/// The powertrain and driveline of a [`TrackedVehicle`] (see the [module docs](self)).
#[derive(Debug, Clone)]
pub struct TrackedDrive {
    powertrain: Powertrain,
    driveline: SteeredDriveline,
    shafts: ItemHandle,
    inputs: DriverInputs,
}

impl TrackedDrive {
    /// Build the shafts of `data.powertrain` and `data.driveline` as one item of `sys`,
    /// coupled to `vehicle`'s sprockets relative to its chassis. The sprockets' own joint
    /// drives are released (`Drive::Effort(0)`): the driveline turns them. Errors name
    /// `powertrain.<part>.<field>` or `driveline.<field>`.
    pub fn build(
        sys: &mut System,
        vehicle: &TrackedVehicle,
        data: &TrackedVehicleData,
    ) -> Result<Self> {
        let mut shafts = ShaftSystem::new(format!("{}.driveline", data.name));
        let powertrain = Powertrain::new(&data.powertrain, &mut shafts)?;
        let driveline = SteeredDriveline::new(
            &data.driveline,
            &mut shafts,
            powertrain.output_shaft(),
            [vehicle.sides[0].sprocket, vehicle.sides[1].sprocket],
            vehicle.chassis,
        )?;
        vehicle.set_sprocket_drives(sys, Drive::Effort(0.0))?;
        let shafts = sys.add_item(Box::new(shafts));
        Ok(Self {
            powertrain,
            driveline,
            shafts,
            inputs: DriverInputs::default(),
        })
    }

    /// Apply the driver's inputs for the next step (clamped to their ranges, NaN read as
    /// 0 as for the wheeled vehicle): the engine torque and the gear from the throttle, the
    /// brakes from the brake pedal and the steering brakes or steering motor from the
    /// steering.
    pub fn synchronize(&mut self, sys: &mut System, inputs: DriverInputs) -> Result<()> {
        self.inputs = inputs.clamped();
        let time = sys.time();
        let handle = self.shafts;
        let shafts = sys
            .item_mut::<ShaftSystem>(handle)
            .ok_or_else(|| VehicleError::invalid("tracked.shafts", handle, "no shaft item"))?;
        self.powertrain
            .synchronize(time, self.inputs.throttle, shafts)?;
        self.driveline
            .synchronize(self.inputs.brake, self.inputs.steering, shafts)
    }

    /// Set the vehicle rolling straight ahead at `speed` (m/s) without track slip
    /// ([`TrackedVehicle::set_forward_speed`]) and every shaft at its geared speed: the
    /// sprocket shafts and the differential box (the DSU's propulsion shaft; its steering
    /// shaft stays at rest) at `w_s = speed / r_p` (pitch radius
    /// `r_p`), the transmission's output at `w_s / r_c` (conical ratio `r_c`: `w_box = r_c
    /// w_in`), its input and the crankshaft at that over the current gear's ratio (the
    /// converter locked). A vehicle started at rest would spend its first seconds spinning
    /// the shafts up; a test of a steady drive starts here instead. The gear stays; the next
    /// [`synchronize`](Self::synchronize) shifts if the speed is past its shift point.
    pub fn set_forward_speed(
        &self,
        sys: &mut System,
        vehicle: &TrackedVehicle,
        data: &TrackedVehicleData,
        speed: f64,
    ) -> Result<()> {
        vehicle.set_forward_speed(sys, data, speed)?;
        let w_s = speed / data.track.sprocket.pitch_radius;
        let w_out = w_s / self.driveline.params().conical_ratio;
        let w_in = self
            .powertrain
            .transmission()
            .ratio()
            .map_or(0.0, |r| w_out / r);
        let handle = self.shafts;
        let shafts = sys
            .item_mut::<ShaftSystem>(handle)
            .ok_or_else(|| VehicleError::invalid("tracked.shafts", handle, "no shaft item"))?;
        for side in 0..2 {
            shafts.set_speed(self.driveline.output_shaft(side), w_s)?;
        }
        shafts.set_speed(self.driveline.propulsion_shaft(), w_s)?;
        shafts.set_speed(self.driveline.input_shaft(), w_out)?;
        shafts.set_speed(self.powertrain.input_shaft(), w_in)?;
        shafts.set_speed(self.powertrain.crankshaft(), w_in)?;
        Ok(())
    }

    /// The inputs of the last [`synchronize`](Self::synchronize) (clamped).
    pub fn inputs(&self) -> DriverInputs {
        self.inputs
    }

    /// The powertrain (engine speed and torque, gear, converter state).
    pub fn powertrain(&self) -> &Powertrain {
        &self.powertrain
    }

    /// The driveline.
    pub fn driveline(&self) -> &SteeredDriveline {
        &self.driveline
    }

    /// The shaft item, if it is still in `sys`.
    pub fn shafts<'a>(&self, sys: &'a System) -> Option<&'a ShaftSystem> {
        sys.item::<ShaftSystem>(self.shafts)
    }

    /// Spin of a side's sprocket relative to the chassis (0 left, 1 right), rad/s; NaN if
    /// the shaft item is gone.
    pub fn sprocket_speed(&self, sys: &System, side: usize) -> f64 {
        self.shafts(sys)
            .map_or(f64::NAN, |s| self.driveline.sprocket_speed(side, s))
    }

    /// Torque the driveline applied to a side's sprocket in the last step (drive minus
    /// brake), N m; NaN if the shaft item is gone.
    pub fn sprocket_torque(&self, sys: &System, side: usize) -> f64 {
        self.shafts(sys)
            .map_or(f64::NAN, |s| self.driveline.sprocket_torque(side, s))
    }
}
