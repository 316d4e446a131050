//! The HMMWV built from the templates. Its parameters are data (`data/hmmwv.json`, the
//! sources named in its `source` field), compiled in so the model works from any directory.
//!
//! Two powertrains ([`PowertrainKind`]): Chrono's HMMWV values (the data file's, the
//! default) and the M998's published drivetrain (`data/hmmwv_m998_powertrain.json`: the
//! 6.2 L diesel, 150 hp at 3600 rpm and 250 lb-ft; the THM400 three-speed 2.48/1.48/1.00;
//! differential 2.73 and geared hubs 1.92; chassis drag), which the acceleration case
//! compares with the published top speed.

use serde::{Deserialize, Serialize};

use crate::aero::AeroDragData;
use crate::error::Result;
use crate::powertrain::PowertrainParams;
use crate::tire::{AncfTireData, TMeasyParams, Tire};
use crate::vehicle::VehicleData;

/// The HMMWV description as shipped (`chrono-vehicle/data/hmmwv.json`), rigid tires.
pub const HMMWV_JSON: &str = include_str!("../data/hmmwv.json");

/// The M998 drivetrain overlay (`chrono-vehicle/data/hmmwv_m998_powertrain.json`).
pub const HMMWV_M998_POWERTRAIN_JSON: &str = include_str!("../data/hmmwv_m998_powertrain.json");

/// Which powertrain and final drive the HMMWV gets.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PowertrainKind {
    /// Chrono's HMMWV engine map, converter and gears (the data file's).
    #[default]
    Chrono,
    /// The M998's published engine ratings, THM400 ratios and final drive, with chassis
    /// drag (`data/hmmwv_m998_powertrain.json`; its `source` names what is published and
    /// what is assumed).
    M998,
}

/// A powertrain overlay: replaces the powertrain, the conical (differential plus hub)
/// ratio of both axles and the chassis drag of a vehicle description.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct PowertrainOverlay {
    #[allow(dead_code)]
    name: String,
    source: Vec<String>,
    powertrain: PowertrainParams,
    conical_ratio: f64,
    aero: Option<AeroDragData>,
}

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
    /// The ANCF shell tire: a pressurized deformable carcass of the HMMWV tire's size
    /// ([`AncfTireData::hmmwv`]).
    Ancf,
}

/// The HMMWV description, parsed and checked (rigid tires).
pub fn hmmwv_data() -> Result<VehicleData> {
    VehicleData::from_json(HMMWV_JSON, "chrono-vehicle/data/hmmwv.json")
}

/// The HMMWV description with the given tire.
pub fn hmmwv_data_with(tire: TireKind) -> Result<VehicleData> {
    hmmwv_data_variant(tire, PowertrainKind::Chrono)
}

/// The HMMWV description with the given tire and powertrain.
pub fn hmmwv_data_variant(tire: TireKind, powertrain: PowertrainKind) -> Result<VehicleData> {
    let mut d = hmmwv_data()?;
    match tire {
        TireKind::Rigid => {}
        TireKind::Handling => d.wheel.tire = Tire::TMeasy(TMeasyParams::hmmwv()),
        TireKind::Ancf => d.wheel.tire = Tire::Ancf(AncfTireData::hmmwv()),
    }
    if powertrain == PowertrainKind::M998 {
        d = with_powertrain_overlay(
            d,
            HMMWV_M998_POWERTRAIN_JSON,
            "chrono-vehicle/data/hmmwv_m998_powertrain.json",
        )?;
    }
    d.validate()?;
    Ok(d)
}

/// `data` with the powertrain overlay `text` (JSON, read from `path`, named in errors)
/// applied: its powertrain, its conical (differential plus hub) ratio on both axles and its
/// chassis drag replace the data's, and its sources are added. The result is validated;
/// an error names the field (its path in the overlay for a parse error).
pub fn with_powertrain_overlay(
    mut data: VehicleData,
    text: &str,
    path: &str,
) -> Result<VehicleData> {
    let o: PowertrainOverlay = crate::json_path::parse(text, path)?;
    data.powertrain = o.powertrain;
    data.driveline.front_conical_ratio = o.conical_ratio;
    data.driveline.rear_conical_ratio = o.conical_ratio;
    data.chassis.aero = o.aero;
    data.source.extend(o.source);
    data.validate()?;
    Ok(data)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::powertrain::engine::{Engine, RPM_TO_RAD_S};

    /// The M998 overlay reproduces the ratings it cites: 150 hp at 3600 rpm and a
    /// 250 lb-ft peak (net of the losses map), and the final drive 1/(2.73 x 1.92).
    #[test]
    fn m998_powertrain_matches_its_published_ratings() {
        let d = hmmwv_data_variant(TireKind::Handling, PowertrainKind::M998).unwrap();
        let e = Engine::new(&d.powertrain.engine).unwrap();
        let w = 3600.0 * RPM_TO_RAD_S;
        let hp = e.torque(1.0, w) * w / 745.7;
        assert!((hp / 150.0 - 1.0).abs() < 0.01, "{hp} hp at 3600 rpm");
        let peak = (700..3600)
            .step_by(50)
            .map(|r| e.torque(1.0, r as f64 * RPM_TO_RAD_S))
            .fold(0.0, f64::max);
        let lbft = peak / 1.355_818;
        assert!((lbft / 250.0 - 1.0).abs() < 0.01, "{lbft} lb-ft peak");
        let overall = 1.0 / (d.driveline.front_conical_ratio * 2.73 * 1.92);
        assert!((overall - 1.0).abs() < 1e-5);
        let first = 1.0 / d.powertrain.transmission.forward_ratios[0];
        assert!((first - 2.48).abs() < 1e-4);
        assert!(d.chassis.aero.is_some());
        assert!(d.source.iter().any(|s| s.contains("THM400")));
        // The default keeps Chrono's values and no drag.
        let c = hmmwv_data_with(TireKind::Rigid).unwrap();
        assert!(c.chassis.aero.is_none());
        assert_eq!(c.driveline.front_conical_ratio, 0.2);
    }
}
