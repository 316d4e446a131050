//! The HMMWV built from the templates. Its parameters are data (`data/hmmwv.json`, the
//! sources named in its `source` field), compiled in so the model works from any directory.

use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::tire::{TMeasyParams, Tire};
use crate::vehicle::VehicleData;

/// The HMMWV description as shipped (`chrono-vehicle/data/hmmwv.json`), rigid tires.
pub const HMMWV_JSON: &str = include_str!("../data/hmmwv.json");

/// Which tire the HMMWV rides on.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TireKind {
    /// Rigid cylinders in the CCP (the data file's tire).
    #[default]
    Rigid,
    /// The TMeasy handling tire with the parameters guessed from the 37x12.5x16.5 size and
    /// its rated load ([`TMeasyParams::hmmwv`]).
    Handling,
}

/// The HMMWV description, parsed and checked (rigid tires).
pub fn hmmwv_data() -> Result<VehicleData> {
    VehicleData::from_json(HMMWV_JSON, "chrono-vehicle/data/hmmwv.json")
}

/// The HMMWV description with the given tire.
pub fn hmmwv_data_with(tire: TireKind) -> Result<VehicleData> {
    let mut d = hmmwv_data()?;
    if tire == TireKind::Handling {
        d.wheel.tire = Tire::TMeasy(TMeasyParams::hmmwv());
        d.validate()?;
    }
    Ok(d)
}
