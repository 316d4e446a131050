//! A track driveline of either steering mechanism, chosen by the data's
//! `driveline.steering` ([`TrackSteering`]): the braked differential ([`TrackDriveline`])
//! or the differential steering unit ([`DsuDriveline`]). Both take the same driver inputs
//! (brake pedal, steering in `[-1, 1]`, positive turning left) and drive the same sprocket
//! couplings.

use chrono_core::BodyHandle;

use super::shafts::{ShaftId, ShaftSystem};
use super::track_bds::{TrackDriveline, TrackDrivelineParams, TrackSteering};
use super::track_dsu::DsuDriveline;
use crate::error::Result;

/// The track driveline built from [`TrackDrivelineParams`] (see the [module docs](self)).
#[derive(Debug, Clone)]
pub enum SteeredDriveline {
    /// Open differential and steering brakes.
    Braked(TrackDriveline),
    /// Double differential and a steering motor.
    Dsu(DsuDriveline),
}

impl SteeredDriveline {
    /// Build the driveline `params.steering` selects (arguments as
    /// [`TrackDriveline::new`]); errors name `driveline.<field>`.
    pub fn new(
        params: &TrackDrivelineParams,
        shafts: &mut ShaftSystem,
        input: ShaftId,
        sprockets: [BodyHandle; 2],
        chassis: BodyHandle,
    ) -> Result<Self> {
        Ok(match params.steering {
            TrackSteering::BrakedDifferential => Self::Braked(TrackDriveline::new(
                params, shafts, input, sprockets, chassis,
            )?),
            TrackSteering::Dsu => Self::Dsu(DsuDriveline::new(
                params, shafts, input, sprockets, chassis,
            )?),
        })
    }

    /// Once per step before the system steps: the brake pedal (`[0, 1]`) and the steering
    /// input (`[-1, 1]`) into brakes or the steering motor.
    pub fn synchronize(
        &mut self,
        brake: f64,
        steering: f64,
        shafts: &mut ShaftSystem,
    ) -> Result<()> {
        match self {
            Self::Braked(d) => d.synchronize(brake, steering, shafts),
            Self::Dsu(d) => d.synchronize(brake, steering, shafts),
        }
    }

    /// Spin of a side's sprocket relative to the chassis, rad/s.
    pub fn sprocket_speed(&self, side: usize, shafts: &ShaftSystem) -> f64 {
        match self {
            Self::Braked(d) => d.sprocket_speed(side, shafts),
            Self::Dsu(d) => d.sprocket_speed(side, shafts),
        }
    }

    /// Torque the driveline applied to a side's sprocket in the last step, N m.
    pub fn sprocket_torque(&self, side: usize, shafts: &ShaftSystem) -> f64 {
        match self {
            Self::Braked(d) => d.sprocket_torque(side, shafts),
            Self::Dsu(d) => d.sprocket_torque(side, shafts),
        }
    }

    /// The input shaft (the transmission's output).
    pub fn input_shaft(&self) -> ShaftId {
        match self {
            Self::Braked(d) => d.input_shaft(),
            Self::Dsu(d) => d.input_shaft(),
        }
    }

    /// The shaft turning at the mean of the sprocket speeds: the differential box, or the
    /// DSU's propulsion shaft.
    pub fn propulsion_shaft(&self) -> ShaftId {
        match self {
            Self::Braked(d) => d.differential_box(),
            Self::Dsu(d) => d.propulsion_shaft(),
        }
    }

    /// The output (sprocket) shaft of a side.
    pub fn output_shaft(&self, side: usize) -> ShaftId {
        match self {
            Self::Braked(d) => d.output_shaft(side),
            Self::Dsu(d) => d.output_shaft(side),
        }
    }

    /// The parameters.
    pub fn params(&self) -> &TrackDrivelineParams {
        match self {
            Self::Braked(d) => d.params(),
            Self::Dsu(d) => d.params(),
        }
    }

    /// The DSU, if this is one.
    pub fn as_dsu(&self) -> Option<&DsuDriveline> {
        match self {
            Self::Dsu(d) => Some(d),
            Self::Braked(_) => None,
        }
    }

    /// The braked differential, if this is one.
    pub fn as_braked(&self) -> Option<&TrackDriveline> {
        match self {
            Self::Braked(d) => Some(d),
            Self::Dsu(_) => None,
        }
    }
}
