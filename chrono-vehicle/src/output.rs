//! A vehicle's time series: one row per recorded step with the chassis motion, the wheel
//! speeds, the driver's inputs and the powertrain's state, written as CSV
//! ([`chrono_core::io::csv`]) for plotting.

use std::path::Path;

use chrono_core::System;
use chrono_core::io::csv::CsvWriter;
use chrono_core::math::Vector3;

use crate::driveline::Wheel;
use crate::error::Result;
use crate::vehicle::WheeledVehicle;

/// The columns of a vehicle log (SI units; accelerations by finite differences of the
/// chassis velocity between recorded rows; wheel speeds are the axle shafts', rad/s).
pub const COLUMNS: [&str; 20] = [
    "t",
    "x",
    "y",
    "z",
    "speed",
    "ax",
    "ay",
    "az",
    "yaw_rate",
    "wheel_fl",
    "wheel_fr",
    "wheel_rl",
    "wheel_rr",
    "throttle",
    "brake",
    "steering",
    "engine_rpm",
    "engine_torque",
    "gear",
    "converter_speed_ratio",
];

/// Writes [`COLUMNS`] for a [`WheeledVehicle`] every call of [`record`](Self::record).
pub struct VehicleLog {
    csv: CsvWriter,
    last: Option<(f64, Vector3<f64>)>,
    row: Vec<f64>,
}

impl VehicleLog {
    /// A log writing to `path` (created or truncated).
    pub fn create(path: impl AsRef<Path>) -> Result<Self> {
        Ok(Self {
            csv: CsvWriter::create(path, &COLUMNS)?,
            last: None,
            row: Vec::with_capacity(COLUMNS.len()),
        })
    }

    /// One row for the vehicle's current state in `sys`. The chassis acceleration is
    /// the change of its velocity since the previous row over the time between them
    /// (zero in the first row).
    pub fn record(&mut self, sys: &System, vehicle: &WheeledVehicle) -> Result<()> {
        let st = vehicle.state(sys)?;
        let acc = match self.last {
            Some((t, v)) if st.time > t => (st.velocity - v) / (st.time - t),
            _ => Vector3::zeros(),
        };
        self.last = Some((st.time, st.velocity));
        let wheels = match vehicle.shafts(sys) {
            Some(s) => [
                Wheel::FrontLeft,
                Wheel::FrontRight,
                Wheel::RearLeft,
                Wheel::RearRight,
            ]
            .map(|w| vehicle.driveline().wheel_speed(w, s)),
            None => [f64::NAN; 4],
        };
        let inputs = vehicle.inputs();
        let pt = vehicle.powertrain();
        self.row.clear();
        self.row.extend_from_slice(&[
            st.time,
            st.position.x,
            st.position.y,
            st.position.z,
            st.forward_speed(),
            acc.x,
            acc.y,
            acc.z,
            st.angular_velocity.z,
        ]);
        self.row.extend_from_slice(&wheels);
        self.row.extend_from_slice(&[
            inputs.throttle,
            inputs.brake,
            inputs.steering,
            pt.engine_speed_rpm(),
            pt.engine_torque(),
            pt.current_gear() as f64,
            pt.converter_state().speed_ratio,
        ]);
        self.csv.write_row(&self.row)?;
        Ok(())
    }

    /// Flush and close the file.
    pub fn finish(self) -> Result<()> {
        self.csv.finish()?;
        Ok(())
    }
}
