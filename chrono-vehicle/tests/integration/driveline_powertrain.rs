//! The powertrain (engine map, torque converter, automatic gearbox) on shafts in the CCP.

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::System;
use chrono_core::SystemSettings;
use chrono_core::math::Vector3;
use chrono_vehicle::driveline::ShaftSystem;
use chrono_vehicle::powertrain::{Powertrain, PowertrainParams, RPM_TO_RAD_S, ShiftSpeed};

const H: f64 = 1e-3;

fn system() -> System {
    let s = SolverSettings {
        tolerance: 1e-12,
        max_iterations: 2000,
        record_history: false,
    };
    let settings = SystemSettings {
        gravity: Vector3::zeros(),
        ..SystemSettings::default()
    };
    System::new(settings, Box::new(Apgd::new(s))).unwrap()
}

/// Linear interpolation in a table (written here, independently of `Curve`), clamped.
fn interp(table: &[[f64; 2]], x: f64) -> f64 {
    if x <= table[0][0] {
        return table[0][1];
    }
    for w in table.windows(2) {
        if x <= w[1][0] {
            let t = (x - w[0][0]) / (w[1][0] - w[0][0]);
            return w[0][1] + t * (w[1][1] - w[0][1]);
        }
    }
    table[table.len() - 1][1]
}

/// Step the system `n` times, synchronizing the powertrain before each step; `each` sees
/// the powertrain and the shafts after every step.
fn run(
    sys: &mut System,
    item: chrono_core::item::ItemHandle,
    pt: &mut Powertrain,
    n: usize,
    throttle: f64,
    mut each: impl FnMut(&Powertrain, &ShaftSystem, f64),
) {
    for _ in 0..n {
        let time = sys.time();
        pt.synchronize(time, throttle, sys.item_mut::<ShaftSystem>(item).unwrap())
            .unwrap();
        sys.step(H).unwrap();
        each(pt, sys.item::<ShaftSystem>(item).unwrap(), time);
    }
}

/// Output held by a brake, full throttle: the engine settles at the stall speed where the
/// engine torque equals the pump torque, `T_map(w) + T_loss(w) = (w / K(0))^2` (solved
/// here by bisection on the HMMWV tables), the converter multiplies that torque by the
/// torque ratio at speed ratio 0 (2.0), and the brake holds `2 T_p / r_1` on the output
/// shaft (the gear row multiplies by `1 / r_1 = 5`).
#[test]
fn stall_multiplies_torque_by_the_stall_torque_ratio() {
    let mut params = PowertrainParams::default();
    // Shift on the input shaft, which is held: stay in first gear at stall.
    params.transmission.shift_speed = ShiftSpeed::InputShaft;
    let mut shafts = ShaftSystem::new("powertrain");
    let mut pt = Powertrain::new(&params, &mut shafts).unwrap();
    let brake = shafts.add_clutch(pt.output_shaft(), None, 1e7).unwrap();
    let mut sys = system();
    let i = sys.add_item(Box::new(shafts));
    run(&mut sys, i, &mut pt, 1500, 1.0, |_, _, _| {});

    let map: Vec<[f64; 2]> = params.engine.torque_map_rpm.points().to_vec();
    let loss: Vec<[f64; 2]> = params.engine.losses_map_rpm.points().to_vec();
    let k0 = 15.0; // HMMWV capacity factor at speed ratio 0
    let excess = |rpm: f64| {
        let w = rpm * std::f64::consts::PI / 30.0;
        interp(&map, rpm) + interp(&loss, rpm) - (w / k0).powi(2)
    };
    let (mut lo, mut hi) = (1000.0, 2700.0);
    assert!(excess(lo) > 0.0 && excess(hi) < 0.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if excess(mid) > 0.0 {
            lo = mid
        } else {
            hi = mid
        }
    }
    let stall_rpm = 0.5 * (lo + hi);
    let s = sys.item::<ShaftSystem>(i).unwrap();
    let rpm = s.speed(pt.crankshaft()) / RPM_TO_RAD_S;
    assert!(
        (rpm - stall_rpm).abs() < 1e-6,
        "stall {rpm} rpm vs {stall_rpm}"
    );
    assert!((pt.engine_speed_rpm() - stall_rpm).abs() < 1e-6);
    assert_eq!(pt.current_gear(), 1);
    let c = pt.converter_state();
    assert_eq!(c.speed_ratio, 0.0);
    assert!(s.speed(pt.input_shaft()).abs() < 1e-9);
    let tp = (stall_rpm * RPM_TO_RAD_S / k0).powi(2);
    assert!(
        (c.pump_torque - tp).abs() < 1e-6 * tp,
        "{} vs {tp}",
        c.pump_torque
    );
    assert!(
        (pt.engine_torque() - tp).abs() < 1e-6 * tp,
        "engine = pump at stall"
    );
    assert!((c.turbine_torque - 2.0 * c.pump_torque).abs() < 1e-12 * tp);
    // Through the CCP: gearbox output torque and brake reaction.
    let out = 2.0 * tp / 0.2;
    assert!(
        (pt.output_torque(s) - out).abs() < 1e-6 * out,
        "{}",
        pt.output_torque(s)
    );
    assert!(
        (s.reaction(brake) + out).abs() < 1e-6 * out,
        "{}",
        s.reaction(brake)
    );
    assert!((pt.converter_slip() - 1.0).abs() < 1e-15);
}

/// A flywheel on the output, full throttle from rest: the gearbox upshifts 1 -> 2 -> 3,
/// each time at the first synchronize whose engine speed exceeds the upshift speed
/// (2500 rpm) once the shift latency (1 s) has passed; the output speed is continuous
/// through a shift and the input shaft follows the new ratio. Then throttle off and a
/// brake on the flywheel: downshifts at engine speeds below 1200 rpm.
#[test]
fn upshifts_and_downshifts_at_the_set_engine_speeds() {
    let mut params = PowertrainParams::default();
    params.transmission.output_shaft_inertia = 40.0;
    let up = params.transmission.upshift_rpm;
    let down = params.transmission.downshift_rpm;
    let latency = params.transmission.shift_latency;
    let mut shafts = ShaftSystem::new("powertrain");
    let mut pt = Powertrain::new(&params, &mut shafts).unwrap();
    let brake = shafts.add_clutch(pt.output_shaft(), None, 0.0).unwrap();
    let mut sys = system();
    let i = sys.add_item(Box::new(shafts));

    let shifts = std::cell::RefCell::new(Vec::<(f64, i32, i32)>::new()); // (time, from, to)
    let mut gear = pt.current_gear();
    let mut prev_rpm = 0.0;
    let mut check = |pt: &Powertrain, s: &ShaftSystem, time: f64| {
        let g = pt.current_gear();
        let rpm = pt.engine_speed_rpm();
        if g != gear {
            let since = shifts.borrow().last().map_or(f64::INFINITY, |x| time - x.0);
            assert!(
                since >= latency,
                "shift {gear}->{g} only {since} s after the last"
            );
            if g > gear {
                assert!(rpm > up, "upshift at {rpm} rpm");
                // The shift came at the first chance: the previous step was below the
                // upshift speed or still within the latency.
                assert!(prev_rpm <= up || since - H < latency, "late upshift");
            } else {
                assert!(rpm < down, "downshift at {rpm} rpm");
                assert!(prev_rpm >= down || since - H < latency, "late downshift");
            }
            shifts.borrow_mut().push((time, gear, g));
            gear = g;
        }
        prev_rpm = rpm;
        // The gear row holds in every step (the ratio of the gear engaged for it).
        let r = params.transmission.forward_ratios[g as usize - 1];
        let (wi, wo) = (s.speed(pt.input_shaft()), s.speed(pt.output_shaft()));
        assert!((wo - r * wi).abs() < 1e-9, "gear row {wo} vs {r} x {wi}");
    };
    run(&mut sys, i, &mut pt, 6000, 1.0, &mut check);
    let ups: Vec<_> = shifts.borrow().iter().map(|x| (x.1, x.2)).collect();
    assert_eq!(ups, vec![(1, 2), (2, 3)], "{shifts:?}");
    assert_eq!(pt.current_gear(), 3);

    sys.item_mut::<ShaftSystem>(i)
        .unwrap()
        .set_clutch_torque(brake, 600.0)
        .unwrap();
    run(&mut sys, i, &mut pt, 6000, 0.0, &mut check);
    let shifts = shifts.into_inner();
    let downs: Vec<_> = shifts[2..].iter().map(|x| (x.1, x.2)).collect();
    assert_eq!(downs, vec![(3, 2), (2, 1)], "{shifts:?}");
}

#[test]
fn bad_powertrain_input_names_the_field() {
    let mut p = PowertrainParams::default();
    p.engine.crankshaft_inertia = -1.1;
    let e = p.validate().unwrap_err().to_string();
    assert!(
        e.contains("powertrain.engine.crankshaft_inertia") && e.contains("-1.1"),
        "{e}"
    );
    let mut p = PowertrainParams::default();
    p.transmission.forward_ratios = vec![0.2, 0.1];
    let e = p.validate().unwrap_err().to_string();
    assert!(
        e.contains("powertrain.transmission.forward_ratios[1]") && e.contains("0.1"),
        "{e}"
    );
    let mut p = PowertrainParams::default();
    p.transmission.downshift_rpm = 3000.0;
    let e = p.validate().unwrap_err().to_string();
    assert!(e.contains("downshift_rpm") && e.contains("3000"), "{e}");
    let mut json = serde_json::to_value(PowertrainParams::default()).unwrap();
    json["torque_converter"]["capacity_factor"]["points"][2] = serde_json::json!([0.5, 0.0]);
    let e = PowertrainParams::from_json(&json.to_string())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("powertrain.torque_converter.capacity_factor.points[2]"),
        "{e}"
    );
    json["engine"]["turbo"] = serde_json::json!(true);
    let e = PowertrainParams::from_json(&json.to_string())
        .unwrap_err()
        .to_string();
    assert!(e.contains("turbo"), "{e}");
    // The default round-trips through JSON.
    let text = serde_json::to_string(&PowertrainParams::default()).unwrap();
    assert_eq!(
        PowertrainParams::from_json(&text).unwrap(),
        PowertrainParams::default()
    );
    let mut shafts = ShaftSystem::new("p");
    let mut pt = Powertrain::new(&PowertrainParams::default(), &mut shafts).unwrap();
    let e = pt
        .synchronize(0.0, f64::NAN, &mut shafts)
        .unwrap_err()
        .to_string();
    assert!(e.contains("throttle"), "{e}");
}
