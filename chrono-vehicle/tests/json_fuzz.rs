//! Fuzzed vehicle descriptions: generated mutations of the HMMWV description
//! (`data/hmmwv.json`) and of its M998 powertrain overlay (`data/hmmwv_m998_powertrain.json`)
//! never make loading or building panic, and every rejected description is an error that
//! names the mutated field (its key, or the path of the object or array it sits in).

use std::sync::Arc;

use chrono_ccp::{Schur, SolverSettings};
use chrono_core::math::Isometry3;
use chrono_core::{ContactMaterial, System, SystemSettings};
use chrono_vehicle::hmmwv::{HMMWV_JSON, HMMWV_M998_POWERTRAIN_JSON, hmmwv_data};
use chrono_vehicle::terrain::{FlatTerrain, Terrain};
use chrono_vehicle::{VehicleData, VehicleError, WheeledVehicle};
use proptest::prelude::*;
use serde_json::Value;

/// One step of a path into a JSON value.
#[derive(Debug, Clone)]
enum Seg {
    Key(String),
    Index(usize),
}

/// A change to the value at a path.
#[derive(Debug, Clone, Copy)]
enum Mutation {
    /// Remove the member (or array element).
    Delete,
    /// A number made negative (`-|x| - 1`).
    Negative,
    /// A number set to zero.
    Zero,
    /// A number set to `1e308` (JSON has no NaN: the largest finite values stand in).
    Huge,
    /// A number set to `-1e308`.
    NegHuge,
    /// The value replaced by a string.
    Text,
    /// An array cut to half its length.
    Truncate,
    /// A string replaced by a name no enum has.
    UnknownName,
    /// The value wrapped in an object.
    NestObject,
    /// The value wrapped in an array.
    NestArray,
}

const MUTATIONS: [Mutation; 10] = [
    Mutation::Delete,
    Mutation::Negative,
    Mutation::Zero,
    Mutation::Huge,
    Mutation::NegHuge,
    Mutation::Text,
    Mutation::Truncate,
    Mutation::UnknownName,
    Mutation::NestObject,
    Mutation::NestArray,
];

/// Every path of `v` (the root excluded).
fn paths(v: &Value, prefix: &mut Vec<Seg>, out: &mut Vec<Vec<Seg>>) {
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                prefix.push(Seg::Key(k.clone()));
                out.push(prefix.clone());
                paths(x, prefix, out);
                prefix.pop();
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                prefix.push(Seg::Index(i));
                out.push(prefix.clone());
                paths(x, prefix, out);
                prefix.pop();
            }
        }
        _ => {}
    }
}

fn get_mut<'a>(v: &'a mut Value, path: &[Seg]) -> &'a mut Value {
    path.iter().fold(v, |v, s| match s {
        Seg::Key(k) => &mut v[k.as_str()],
        Seg::Index(i) => &mut v[*i],
    })
}

/// Apply `m` at `path`; false if it does not apply to the value there.
fn mutate(root: &mut Value, path: &[Seg], m: Mutation) -> bool {
    let (last, parent) = path.split_last().expect("a non-root path");
    if let Mutation::Delete = m {
        match (get_mut(root, parent), last) {
            (Value::Object(o), Seg::Key(k)) => {
                o.remove(k);
            }
            (Value::Array(a), Seg::Index(i)) => {
                a.remove(*i);
            }
            _ => return false,
        }
        return true;
    }
    let v = get_mut(root, path);
    let new = match (m, &*v) {
        (Mutation::Negative, Value::Number(n)) => (-n.as_f64().unwrap().abs() - 1.0).into(),
        (Mutation::Zero, Value::Number(_)) => 0.0.into(),
        (Mutation::Huge, Value::Number(_)) => 1e308.into(),
        (Mutation::NegHuge, Value::Number(_)) => (-1e308).into(),
        (Mutation::Text, _) => Value::String("fuzz".into()),
        (Mutation::Truncate, Value::Array(a)) => Value::Array(a[..a.len() / 2].to_vec()),
        (Mutation::UnknownName, Value::String(_)) => Value::String("no_such_kind".into()),
        (Mutation::NestObject, x) => serde_json::json!({ "value": x }),
        (Mutation::NestArray, x) => Value::Array(vec![x.clone()]),
        _ => return false,
    };
    *v = new;
    true
}

/// The names an error about the mutation may use: the object keys along the path (the
/// member itself, or for an array element or a removed member, an enclosing key).
fn key_names(path: &[Seg]) -> Vec<String> {
    path.iter()
        .filter_map(|s| match s {
            Seg::Key(k) => Some(k.clone()),
            Seg::Index(_) => None,
        })
        .collect()
}

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
    let keys = key_names(path);
    // The innermost key is the field; a deleted or wrapped member is reported by its
    // enclosing object, a bad array element by its array.
    let innermost = keys.last().cloned().unwrap_or_default();
    let named = msg.contains(&innermost)
        || matches!(m, Mutation::Delete | Mutation::Truncate)
            && keys.iter().any(|k| msg.contains(k.as_str()));
    prop_assert!(
        named,
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
    let mut all = Vec::new();
    paths(&root, &mut Vec::new(), &mut all);
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
