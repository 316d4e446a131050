//! The HMMWV assembles from its data, settles on flat rigid ground with its weight on the
//! tires, and steers with the Pitman arm.

use chrono_ccp::{Schur, SolverSettings};
use chrono_core::math::GRAVITY_MAGNITUDE;
use chrono_core::math::{Isometry3, Vector3};
use std::sync::Arc;

use chrono_core::{ContactMaterial, System, SystemSettings};
use chrono_vehicle::hmmwv::{TireKind, hmmwv_data, hmmwv_data_with};
use chrono_vehicle::terrain::{FlatTerrain, Terrain};
use chrono_vehicle::{DriverInputs, VehicleData, WheeledVehicle};

const H: f64 = 1e-3;

fn on_flat_ground(data: &VehicleData) -> (System, WheeledVehicle) {
    on_flat_ground_with(data, usize::MAX)
}

/// With `max_dense_rows = 0` the Schur solver applies the Schur complement matrix-free
/// (its mode for granular terrain).
fn on_flat_ground_with(data: &VehicleData, max_dense_rows: usize) -> (System, WheeledVehicle) {
    let s = SolverSettings {
        tolerance: 1e-8,
        max_iterations: 500,
        record_history: false,
    };
    let solver = Schur::new(s).with_max_dense_rows(max_dense_rows);
    let mut sys = System::new(SystemSettings::default(), Box::new(solver)).unwrap();
    let terrain = Arc::new(FlatTerrain::new(0.0, 0.9).unwrap());
    terrain
        .add_to_system(&mut sys, ContactMaterial::with_friction(0.9))
        .unwrap();
    let pose = Isometry3::translation(0.0, 0.0, 0.467 + 0.0263 + 0.005);
    let v = WheeledVehicle::build(&mut sys, data, &pose, terrain).unwrap();
    (sys, v)
}

#[test]
fn hmmwv_settles_with_its_weight_on_the_tires() {
    for kind in [TireKind::Rigid, TireKind::Handling] {
        settles_with(kind);
    }
}

#[test]
fn hmmwv_settles_with_the_implicit_schur_mode() {
    settles_with_solver(TireKind::Rigid, 0);
}

fn settles_with(kind: TireKind) {
    settles_with_solver(kind, usize::MAX);
}

fn settles_with_solver(kind: TireKind, max_dense_rows: usize) {
    let data = hmmwv_data_with(kind).unwrap();
    let (mut sys, mut v) = on_flat_ground_with(&data, max_dense_rows);
    for _ in 0..4000 {
        v.synchronize(&mut sys, DriverInputs::default()).unwrap();
        sys.step(H).unwrap();
    }
    let st = v.state(&sys).unwrap();
    // Without brakes the wheels roll freely: only the vertical motion must have settled.
    assert!(
        st.velocity.z.abs() < 1e-3,
        "{kind:?}: still moving: {}",
        st.velocity
    );
    assert!(sys.max_joint_violation() < 1e-6);
    let forces = v.tire_forces(&sys, H);
    let total: f64 = forces.iter().map(|f| f.z).sum();
    let weight = data.total_mass() * GRAVITY_MAGNITUDE;
    assert!(
        (total - weight).abs() < 5e-3 * weight,
        "{kind:?}: tire loads {total} N vs weight {weight} N"
    );
    // Left and right carry the same load (the vehicle is symmetric).
    for axle in 0..2 {
        let (l, r) = (forces[2 * axle].z, forces[2 * axle + 1].z);
        assert!((l - r).abs() < 1e-2 * l, "{kind:?} axle {axle}: {l} vs {r}");
    }
}

#[test]
fn positive_steering_turns_the_front_wheels_left() {
    let data = hmmwv_data().unwrap();
    let (mut sys, mut v) = on_flat_ground(&data);
    let inputs = DriverInputs {
        steering: 0.5,
        ..DriverInputs::default()
    };
    // Settle first, then steer: the position-driven gear moves the linkage in one step.
    for _ in 0..300 {
        v.synchronize(&mut sys, DriverInputs::default()).unwrap();
        sys.step(H).unwrap();
    }
    // Steer angle of each wheel about the chassis Z (the spin axis, spindle Y, turned
    // counter-clockwise gets a negative X component in the chassis frame).
    let (chassis_h, wheels) = (v.chassis(), v.wheels().to_vec());
    let steer_angles = |sys: &System| -> Vec<f64> {
        let chassis = sys.body(chassis_h).unwrap().rotation();
        wheels
            .iter()
            .map(|w| {
                let axis =
                    chassis.inverse() * (sys.body(w.spindle).unwrap().rotation() * Vector3::y());
                (-axis.x).atan2(axis.y)
            })
            .collect()
    };
    let before = steer_angles(&sys);
    for _ in 0..20 {
        v.synchronize(&mut sys, inputs).unwrap();
        sys.step(H).unwrap();
    }
    let after = steer_angles(&sys);
    for side in 0..2 {
        let d = after[side] - before[side];
        assert!(d > 0.05, "front side {side}: steer change {d} rad");
    }
    // The rear wheels do not steer: their toe changes only with the suspension travel
    // (bump steer) as the body reacts to the front tires' scrub.
    for side in 2..4 {
        let d = after[side] - before[side];
        let front = after[side - 2] - before[side - 2];
        assert!(
            d.abs() < 0.1 * front,
            "rear side {side}: steer change {d} rad"
        );
    }
}

#[test]
fn bad_vehicle_data_names_the_field() {
    let mut data = hmmwv_data().unwrap();
    data.axles[1].suspension.lower_arm.mass = -1.0;
    let e = data.validate().unwrap_err().to_string();
    assert!(e.contains("axles[1].suspension.lower_arm.mass"), "{e}");
    let e = VehicleData::from_json("{\"name\": 3}", "x.json")
        .unwrap_err()
        .to_string();
    assert!(e.contains("x.json"), "{e}");
}

#[test]
fn the_vehicle_log_writes_one_row_per_record() {
    let data = hmmwv_data().unwrap();
    let (mut sys, mut v) = on_flat_ground(&data);
    let path = std::env::temp_dir().join(format!("hmmwv_log_{}.csv", std::process::id()));
    let mut log = chrono_vehicle::output::VehicleLog::create(&path).unwrap();
    let brake = DriverInputs {
        brake: 0.5,
        ..DriverInputs::default()
    };
    for _ in 0..5 {
        v.synchronize(&mut sys, brake).unwrap();
        sys.step(H).unwrap();
        log.record(&sys, &v).unwrap();
    }
    log.finish().unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::remove_file(&path).ok();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 6, "{text}");
    assert_eq!(
        lines[0].split(',').count(),
        chrono_vehicle::output::COLUMNS.len()
    );
    let last: Vec<f64> = lines[5].split(',').map(|x| x.parse().unwrap()).collect();
    assert!((last[0] - 5.0 * H).abs() < 1e-12);
    assert_eq!(last[14], 0.5, "brake column");
}

/// Started at 2 m/s (first gear) with the shafts turning at the speeds the gears impose,
/// the vehicle coasts on: after 50 ms its speed is within 1 % of 2 m/s and the wheels still roll
/// without slip. (With the shafts at rest the first step would spin up their inertia
/// through the gear ratios, about 1 000 kg reflected to the wheels, and cut the speed by a
/// third.)
#[test]
fn set_forward_speed_starts_the_vehicle_rolling() {
    let data = hmmwv_data_with(TireKind::Rigid).unwrap();
    let (mut sys, mut v) = on_flat_ground(&data);
    v.set_forward_speed(&mut sys, 2.0).unwrap();
    for _ in 0..50 {
        v.synchronize(&mut sys, DriverInputs::default()).unwrap();
        sys.step(H).unwrap();
    }
    let speed = v.state(&sys).unwrap().forward_speed();
    assert!((speed - 2.0).abs() < 0.02, "speed {speed}");
    for w in v.wheels() {
        let rolling = sys.body(w.spindle).unwrap().angular_velocity().y * 0.467;
        assert!(
            (rolling - speed).abs() < 0.02 * speed,
            "wheel {rolling} vs {speed}"
        );
    }
    let shafts = v.shafts(&sys).unwrap();
    let engine = shafts.speed(v.powertrain().crankshaft());
    assert!(engine > 50.0, "engine speed {engine} rad/s");
    assert!(v.set_forward_speed(&mut sys, f64::NAN).is_err());
}
