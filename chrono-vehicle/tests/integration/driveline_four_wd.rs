//! The HMMWV 4WD driveline on four spindle bodies, with a real solver.

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::math::Vector3;
use chrono_core::{BodyHandle, RigidBodyBuilder, System, SystemSettings};
use chrono_vehicle::driveline::{FourWd, FourWdParams, ShaftId, ShaftSystem, Wheel};

const H: f64 = 1e-3;
/// Spin inertia of each spindle body about its Y axis, kg m^2.
const IW: f64 = 1.0;
/// Inertia of the input shaft (standing for the transmission output), kg m^2.
const JIN: f64 = 0.5;

struct Rig {
    sys: System,
    item: chrono_core::item::ItemHandle,
    dl: FourWd,
    input: ShaftId,
    spindles: [BodyHandle; 4],
}

fn rig(params: &FourWdParams) -> Rig {
    let s = SolverSettings {
        tolerance: 1e-12,
        max_iterations: 3000,
        record_history: false,
    };
    let settings = SystemSettings {
        gravity: Vector3::zeros(),
        ..SystemSettings::default()
    };
    let mut sys = System::new(settings, Box::new(Apgd::new(s))).unwrap();
    let chassis = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let mut spindles = [chassis; 4];
    for (w, sp) in spindles.iter_mut().enumerate() {
        let x = if w < 2 { 1.689 } else { -1.689 };
        let y = if w % 2 == 0 { 0.91 } else { -0.91 };
        *sp = sys
            .add_body(
                RigidBodyBuilder::dynamic()
                    .mass(14.705)
                    .inertia_diagonal(Vector3::new(0.5, IW, 0.5))
                    .position(Vector3::new(x, y, 0.0)),
            )
            .unwrap();
    }
    let mut shafts = ShaftSystem::new("driveline");
    let input = shafts.add_shaft("input", JIN).unwrap();
    let dl = FourWd::new(params, &mut shafts, input, spindles, chassis).unwrap();
    let item = sys.add_item(Box::new(shafts));
    Rig {
        sys,
        item,
        dl,
        input,
        spindles,
    }
}

impl Rig {
    fn shafts(&mut self) -> &mut ShaftSystem {
        self.sys.item_mut::<ShaftSystem>(self.item).unwrap()
    }
    fn spin(&self, w: Wheel) -> f64 {
        let b = self.sys.body(self.spindles[w as usize]).unwrap();
        b.angular_velocity().y
    }
}

/// The inertia seen by the input shaft when all wheels turn alike: the input, the central
/// box and both driveshafts at `w`, the two boxes, four axles and four spindles at `r w`.
fn effective_inertia(p: &FourWdParams) -> f64 {
    let r2 = p.front_conical_ratio * p.front_conical_ratio;
    JIN + p.differential_box_inertia
        + 2.0 * p.shaft_inertia
        + r2 * (2.0 * p.differential_box_inertia + 4.0 * p.shaft_inertia + 4.0 * IW)
}

/// A torque on the input spins everything up with the reflected inertia; every wheel turns
/// at `r w_in` (conical 0.2) and gets a quarter of the drive torque times `1/r`, less what
/// the axle shafts and boxes take to accelerate: the spindle's `I_w dw/dt`.
#[test]
fn drive_torque_spins_all_wheels_with_the_reflected_inertia() {
    let p = FourWdParams::default();
    let mut r = rig(&p);
    let t = 100.0;
    let input = r.input;
    r.shafts().set_torque(input, t).unwrap();
    let jeff = effective_inertia(&p);
    for n in 1..=300 {
        r.sys.step(H).unwrap();
        let w_in = r.shafts().speed(input);
        let want = t * n as f64 * H / jeff;
        assert!((w_in - want).abs() < 1e-9, "input {w_in} vs {want}");
        for w in Wheel::ALL {
            let s = r.sys.item::<ShaftSystem>(r.item).unwrap();
            let ws = r.dl.wheel_speed(w, s);
            assert!((ws - 0.2 * w_in).abs() < 1e-9, "{w:?}: {ws}");
            assert!((r.spin(w) - ws).abs() < 1e-9, "{w:?} spindle");
            let tw = r.dl.wheel_torque(w, s);
            let want = IW * 0.2 * t / jeff;
            assert!((tw - want).abs() < 1e-6, "{w:?} torque {tw} vs {want}");
        }
    }
}

/// The front-left wheel held by its brake: the open front differential turns the
/// front-right at twice the front box speed, the rears turn alike, and the central
/// differential keeps the input at the mean of the two driveshafts. With the front lock
/// engaged (limit 100 N m; holding the front-right with the held wheel would take about
/// 260 N m at this input torque, 300 N m) the lock slips and carries
/// exactly its limit, towards the held wheel.
#[test]
fn a_held_wheel_and_the_differential_lock_limit() {
    for locked in [false, true] {
        let p = FourWdParams {
            lock_front: locked,
            ..FourWdParams::default()
        };
        let mut r = rig(&p);
        let input = r.input;
        let [fds, rds] = r.dl.driveshafts();
        let mut dl = r.dl.clone();
        dl.set_brake_torques([1e7, 0.0, 0.0, 0.0], r.shafts())
            .unwrap();
        r.shafts().set_torque(input, 300.0).unwrap();
        for _ in 0..300 {
            r.sys.step(H).unwrap();
            let s = r.sys.item::<ShaftSystem>(r.item).unwrap();
            let ws = Wheel::ALL.map(|w| dl.wheel_speed(w, s));
            let (wf, wr) = (s.speed(fds), s.speed(rds));
            assert!(ws[0].abs() < 1e-9, "held wheel turns: {}", ws[0]);
            assert!((ws[1] - 2.0 * 0.2 * wf).abs() < 1e-9);
            assert!((ws[2] - 0.2 * wr).abs() < 1e-9 && (ws[3] - ws[2]).abs() < 1e-9);
            assert!((s.speed(input) - 0.5 * (wf + wr)).abs() < 1e-9);
            let lock = s.reaction(dl.lock_links()[1]);
            if locked {
                assert!((lock - 100.0).abs() < 1e-9, "lock torque {lock}");
            } else {
                assert_eq!(lock, 0.0);
            }
        }
        assert!(r.sys.item::<ShaftSystem>(r.item).unwrap().speed(fds) > 1.0);
    }
}

/// All wheels rolling, brake pedal at one half: every brake slips at half the maximum
/// torque, so the input decelerates at `4 (T/2) r / J_eff` per second, linearly, and each
/// spindle gets `I_w` times its deceleration.
#[test]
fn brake_pedal_decelerates_the_driveline_linearly() {
    let p = FourWdParams::default();
    let mut r = rig(&p);
    let w0 = 50.0;
    let input = r.input;
    let dl = r.dl.clone();
    // Consistent initial speeds of every shaft and spindle: the boxes and axles at r w0.
    let s = r.shafts();
    let ids: Vec<ShaftId> = s.shaft_ids().collect();
    for id in ids {
        let name = s.shaft_name(id);
        let slow = name.contains("axle")
            || name.starts_with("front differential")
            || name.starts_with("rear differential");
        s.set_speed(id, if slow { 0.2 * w0 } else { w0 }).unwrap();
    }
    for sp in r.spindles {
        r.sys
            .body_mut(sp)
            .unwrap()
            .set_angular_velocity(Vector3::new(0.0, 0.2 * w0, 0.0))
            .unwrap();
    }
    let mut dl = dl;
    let decel = 4.0 * 0.5 * p.front_brake_max_torque * 0.2 / effective_inertia(&p);
    let mut prev = w0;
    for n in 1..=60 {
        dl.synchronize(0.5, r.shafts()).unwrap();
        r.sys.step(H).unwrap();
        let s = r.sys.item::<ShaftSystem>(r.item).unwrap();
        let w = s.speed(input);
        assert!(
            (prev - w - decel * H).abs() < 1e-9,
            "step {n}: {}",
            prev - w
        );
        prev = w;
        for wh in Wheel::ALL {
            let tw = dl.wheel_torque(wh, s);
            assert!((tw + IW * 0.2 * decel).abs() < 1e-6, "{wh:?}: {tw}");
        }
    }
    assert!(prev > 0.0 && prev < w0 - 10.0);
}

#[test]
fn bad_four_wd_input_names_the_field() {
    let p = FourWdParams {
        front_conical_ratio: 0.0,
        ..FourWdParams::default()
    };
    let e = p.validate().unwrap_err().to_string();
    assert!(
        e.contains("four_wd.front_conical_ratio") && e.contains('0'),
        "{e}"
    );
    let p = FourWdParams {
        locking_torque_limit: -100.0,
        ..FourWdParams::default()
    };
    let e = p.validate().unwrap_err().to_string();
    assert!(
        e.contains("four_wd.locking_torque_limit") && e.contains("-100"),
        "{e}"
    );
    let p = FourWdParams {
        spindle_axis: [0.0; 3],
        ..FourWdParams::default()
    };
    assert!(
        p.validate()
            .unwrap_err()
            .to_string()
            .contains("four_wd.spindle_axis")
    );
    let mut json = serde_json::to_value(FourWdParams::default()).unwrap();
    json["shaft_inertia"] = serde_json::json!(-0.5);
    let e = FourWdParams::from_json(&json.to_string())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("four_wd.shaft_inertia") && e.contains("-0.5"),
        "{e}"
    );
    json["shaft_inertia"] = serde_json::json!(0.5);
    json["diff_inertia"] = serde_json::json!(0.5);
    let e = FourWdParams::from_json(&json.to_string())
        .unwrap_err()
        .to_string();
    assert!(e.contains("diff_inertia"), "{e}");
    json.as_object_mut().unwrap().remove("diff_inertia");
    assert_eq!(
        FourWdParams::from_json(&json.to_string()).unwrap(),
        FourWdParams::default()
    );
    let mut shafts = ShaftSystem::new("x");
    let input = shafts.add_shaft("input", 1.0).unwrap();
    let set = chrono_core::Bodies::from_bodies(vec![RigidBodyBuilder::fixed().build().unwrap(); 2]);
    let b = set.handle(0);
    let mut dl = FourWd::new(
        &FourWdParams::default(),
        &mut shafts,
        input,
        [b; 4],
        set.handle(1),
    )
    .unwrap();
    let e = dl
        .synchronize(f64::NAN, &mut shafts)
        .unwrap_err()
        .to_string();
    assert!(e.contains("brake"), "{e}");
}
