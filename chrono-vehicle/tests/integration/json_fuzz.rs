//! Fuzzed vehicle descriptions: generated mutations of the HMMWV description
//! (`data/hmmwv.json`) and of its M998 powertrain overlay (`data/hmmwv_m998_powertrain.json`)
//! never make loading or building panic, and every rejected description is an error that
//! names the mutated field (its key, or the path of the object or array it sits in).

use std::sync::Arc;

use chrono_ccp::{Schur, SolverSettings};
use chrono_core::math::Isometry3;
use chrono_core::testing::json_mutation::{
    MUTATIONS, Mutation, Seg, error_names_path, key_names, mutate, paths,
};
use chrono_core::{ContactMaterial, System, SystemSettings};
use chrono_vehicle::hmmwv::{HMMWV_JSON, HMMWV_M998_POWERTRAIN_JSON, hmmwv_data};
use chrono_vehicle::terrain::{FlatTerrain, Terrain};
use chrono_vehicle::{VehicleData, VehicleError, WheeledVehicle};
use proptest::prelude::*;
use serde_json::Value;

/// Build the vehicle on flat ground; an error must name a field.
fn build(data: &VehicleData) -> Result<(), VehicleError> {
    let solver = Schur::new(SolverSettings {
        tolerance: 1e-8,
        max_iterations: 50,
        record_history: false,
    });
    let mut sys = System::new(SystemSettings::default(), Box::new(solver))?;
    let terrain = Arc::new(FlatTerrain::new(0.0, 0.9)?);
    terrain.add_to_system(&mut sys, ContactMaterial::with_friction(0.9))?;
    WheeledVehicle::build(
        &mut sys,
        data,
        &Isometry3::translation(0.0, 0.0, 0.5),
        terrain,
    )?;
    Ok(())
}

/// Loading's error names the mutated member: its key or the key of an enclosing object.
fn check_load_error(e: &VehicleError, path: &[Seg], m: Mutation) -> Result<(), TestCaseError> {
    let msg = e.to_string();
    let innermost = key_names(path).pop().unwrap_or_default();
    prop_assert!(
        error_names_path(&msg, path, m),
        "{m:?} at {path:?}: the error does not name `{innermost}`: {msg}"
    );
    Ok(())
}

/// A build error (after the data passed validation) must name some field.
fn check_build_error(e: &VehicleError, path: &[Seg], m: Mutation) -> Result<(), TestCaseError> {
    let msg = e.to_string();
    prop_assert!(
        matches!(
            e,
            VehicleError::InvalidParameter { .. } | VehicleError::Core(_)
        ) && msg.contains('`'),
        "{m:?} at {path:?}: the build error names no field: {msg}"
    );
    Ok(())
}

fn fuzz_case(
    text: &str,
    index: usize,
    mutation: usize,
    load: impl Fn(&str) -> Result<VehicleData, VehicleError>,
) -> Result<(), TestCaseError> {
    let mut root: Value = serde_json::from_str(text).unwrap();
    let all = paths(&root);
    let path = &all[index % all.len()];
    let m = MUTATIONS[mutation % MUTATIONS.len()];
    if !mutate(&mut root, path, m) {
        return Ok(());
    }
    let text = serde_json::to_string_pretty(&root).unwrap();
    match load(&text) {
        Err(e) => check_load_error(&e, path, m),
        Ok(data) => match build(&data) {
            Ok(()) => Ok(()),
            Err(e) => check_build_error(&e, path, m),
        },
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 160, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn mutated_hmmwv_description_never_panics(index in 0usize..10_000, mutation in 0usize..10) {
        fuzz_case(HMMWV_JSON, index, mutation, |t| VehicleData::from_json(t, "hmmwv.json"))?;
    }

    #[test]
    fn mutated_m998_overlay_never_panics(index in 0usize..10_000, mutation in 0usize..10) {
        fuzz_case(HMMWV_M998_POWERTRAIN_JSON, index, mutation, |t| {
            chrono_vehicle::hmmwv::with_powertrain_overlay(hmmwv_data()?, t, "overlay.json")
        })?;
    }
}
