//! The HMMWV built from the templates. Its parameters are data (`data/hmmwv.json`, the
//! sources named in its `source` field), compiled in so the model works from any directory.

use crate::error::Result;
use crate::vehicle::VehicleData;

/// The HMMWV description as shipped (`chrono-vehicle/data/hmmwv.json`).
pub const HMMWV_JSON: &str = include_str!("../data/hmmwv.json");

/// The HMMWV description, parsed and checked.
pub fn hmmwv_data() -> Result<VehicleData> {
    VehicleData::from_json(HMMWV_JSON, "chrono-vehicle/data/hmmwv.json")
}
