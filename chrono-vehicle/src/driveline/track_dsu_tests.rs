//! Tests of the differential steering unit on a rig: a fixed hull with two sprocket wheels
//! on revolute joints about Y, driven through the DSU from a torque on the input shaft.

use super::*;
use crate::driveline::TrackSteering;
use chrono_ccp::Schur;
use chrono_core::{JointBuilder, JointKind, RigidBodyBuilder, System, SystemSettings};

const H: f64 = 1e-3;

fn params() -> TrackDrivelineParams {
    TrackDrivelineParams {
        differential_box_inertia: 0.6,
        shaft_inertia: 0.5,
        conical_ratio: 0.5,
        locking_torque_limit: 100.0,
        locked: false,
        brake_max_torque: 1.0e4,
        sprocket_axis: [0.0, 1.0, 0.0],
        steering: TrackSteering::Dsu,
        dsu: Some(DsuParams {
            steering_ratio: 0.5,
            steering_shaft_inertia: 0.3,
            max_steering_speed: 8.0,
            max_steering_torque: 1.0e4,
        }),
    }
}

/// The rig's state after some steps.
struct Rig {
    sys: System,
    item: chrono_core::item::ItemHandle,
    d: DsuDriveline,
    sprockets: [BodyHandle; 2],
    input: ShaftId,
    /// Spin inertia of each sprocket wheel about Y, kg m^2.
    wheel_inertia: [f64; 2],
}

impl Rig {
    fn new(p: &TrackDrivelineParams, wheel_inertia: [f64; 2]) -> Self {
        // The box rows (steering motor, brake) are solved iteratively: a tight tolerance so
        // that the kinematic checks can be tight.
        let settings = chrono_core::descriptor::SolverSettings {
            tolerance: 1e-13,
            max_iterations: 5000,
            record_history: false,
        };
        let mut sys =
            System::new(SystemSettings::default(), Box::new(Schur::new(settings))).unwrap();
        let chassis = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
        let mut sprockets = [chassis; 2];
        for (k, s) in sprockets.iter_mut().enumerate() {
            let y = if k == 0 { 1.0 } else { -1.0 };
            *s = sys
                .add_body(
                    RigidBodyBuilder::dynamic()
                        .mass(10.0)
                        .inertia_diagonal(Vector3::new(1.0, wheel_inertia[k], 1.0))
                        .position(Vector3::new(0.0, y, 0.0)),
                )
                .unwrap();
            sys.add_joint(JointBuilder::at_axis(
                JointKind::Revolute,
                chassis,
                *s,
                Vector3::new(0.0, y, 0.0),
                Vector3::y(),
            ))
            .unwrap();
        }
        let mut shafts = ShaftSystem::new("test");
        let input = shafts.add_shaft("input", 0.5).unwrap();
        let d = DsuDriveline::new(p, &mut shafts, input, sprockets, chassis).unwrap();
        let item = sys.add_item(Box::new(shafts));
        Self {
            sys,
            item,
            d,
            sprockets,
            input,
            wheel_inertia,
        }
    }

    fn shafts(&self) -> &ShaftSystem {
        self.sys.item::<ShaftSystem>(self.item).unwrap()
    }

    /// One step with the input torque and the driver's brake and steering.
    fn step(&mut self, input_torque: f64, brake: f64, steering: f64) {
        let s = self.sys.item_mut::<ShaftSystem>(self.item).unwrap();
        s.set_torque(self.input, input_torque).unwrap();
        self.d.synchronize(brake, steering, s).unwrap();
        self.sys.step(H).unwrap();
    }

    /// Every speed of the rig with its inertia: the shafts, then the sprocket wheels' spins.
    fn speeds(&self) -> Vec<(f64, f64)> {
        let s = self.shafts();
        let mut v: Vec<(f64, f64)> = s.shaft_ids().map(|i| (s.inertia(i), s.speed(i))).collect();
        for k in 0..2 {
            let w = self
                .sys
                .body(self.sprockets[k])
                .unwrap()
                .angular_velocity()
                .y;
            v.push((self.wheel_inertia[k], w));
        }
        v
    }

    /// `(w_p, w_st, w_L, w_R)`.
    fn state(&self) -> (f64, f64, f64, f64) {
        let s = self.shafts();
        (
            s.speed(self.d.propulsion_shaft()),
            s.speed(self.d.steering_shaft()),
            self.d.sprocket_speed(0, s),
            self.d.sprocket_speed(1, s),
        )
    }
}

/// `w_L = w_p - k w_st`, `w_R = w_p + k w_st`, `w_p = r w_in`, the steering shaft at the
/// commanded `s w_max`, and each sprocket wheel at its shaft's speed; under steering of
/// either sign and while the input accelerates the whole.
#[test]
fn the_sprockets_turn_at_propulsion_plus_minus_k_times_steering() {
    for steer in [0.5, -0.25, 1.0] {
        let mut r = Rig::new(&params(), [2.0, 2.0]);
        for _ in 0..300 {
            r.step(100.0, 0.0, steer);
        }
        let (wp, wst, wl, wr) = r.state();
        let k = 0.5;
        let w_in = r.shafts().speed(r.input);
        assert!(wp > 1.0, "propulsion {wp}");
        assert!(
            (wst - steer * 8.0).abs() < 1e-9,
            "steering {wst} for {steer}"
        );
        assert!((wl - (wp - k * wst)).abs() < 1e-9, "{wl} {wp} {wst}");
        assert!((wr - (wp + k * wst)).abs() < 1e-9, "{wr} {wp} {wst}");
        assert!((wr - wl - 2.0 * k * 8.0 * steer).abs() < 1e-9, "{wl} {wr}");
        assert!((wp - 0.5 * w_in).abs() < 1e-9 * w_in, "{wp} {w_in}");
        for k in 0..2 {
            let body = r.sys.body(r.sprockets[k]).unwrap().angular_velocity().y;
            let shaft = r.d.sprocket_speed(k, r.shafts());
            assert!((body - shaft).abs() < 1e-9, "side {k}: {body} {shaft}");
        }
        // The propulsion accelerates as the common mode only: the input torque over the
        // inertia reduced to the input, I = 0.5 + r^2 (0.6 + 2 (0.5 + 2)) (the steering
        // shaft is held at its speed; 0.3 s).
        let expected = 100.0 * 0.3 / (0.5 + 0.25 * 5.6);
        assert!((w_in / expected - 1.0).abs() < 1e-6, "{w_in} {expected}");
    }
}

/// Zero steering is straight running even with unequal loads on the two sides (here
/// unequal sprocket inertias, which an open differential would turn at different speeds):
/// the steering motor holds `w_st = 0` and reacts the torque difference, `T_st = k (tau_R -
/// tau_L)`, each `tau` the sprocket side's inertia times its acceleration.
#[test]
fn zero_steering_runs_straight_with_unequal_loads() {
    let mut r = Rig::new(&params(), [1.0, 5.0]);
    for _ in 0..200 {
        r.step(100.0, 0.0, 0.0);
    }
    let (wp, wst, wl, wr) = r.state();
    assert!(wp > 1.0);
    assert!(wst.abs() < 1e-12, "steering shaft {wst}");
    assert!((wl - wr).abs() < 1e-9 * wp, "{wl} {wr}");
    // Constant accelerations: alpha = w / t. tau_j = (J_shaft + J_wheel,j) alpha.
    let alpha = wp / 0.2;
    let (tau_l, tau_r) = (1.5 * alpha, 5.5 * alpha);
    let s = r.shafts();
    assert!(
        (r.d.summing_torque(0, s) / tau_l - 1.0).abs() < 1e-6,
        "{} {tau_l}",
        r.d.summing_torque(0, s)
    );
    let t_st = r.d.steering_torque(s);
    assert!(
        (t_st / (0.5 * (tau_r - tau_l)) - 1.0).abs() < 1e-6,
        "{t_st} against {}",
        0.5 * (tau_r - tau_l)
    );
    // The sprocket torques the couplings pass are the wheels' shares.
    assert!((r.d.sprocket_torque(1, s) / (5.0 * alpha) - 1.0).abs() < 1e-6);
}

/// With the propulsion shaft braked and the steering input on, the tracks counter-rotate:
/// `w_L = -k w_st`, `w_R = +k w_st`, the propulsion at rest (a pivot turn), also against a
/// torque on the input below the brake's limit.
#[test]
fn brake_and_steering_counter_rotate_the_sprockets() {
    let mut r = Rig::new(&params(), [2.0, 2.0]);
    for _ in 0..200 {
        r.step(300.0, 1.0, 1.0);
    }
    let (wp, wst, wl, wr) = r.state();
    assert!(wp.abs() < 1e-12, "propulsion {wp}");
    assert!((wst - 8.0).abs() < 1e-9);
    assert!(
        (wl + 4.0).abs() < 1e-9 && (wr - 4.0).abs() < 1e-9,
        "{wl} {wr}"
    );
    // The brake holds the input's torque reduced to the propulsion shaft, 300 / r.
    let tb = r.d.propulsion_brake_torque(r.shafts());
    assert!((tb + 600.0).abs() < 1e-6, "brake {tb}");
}

/// Power balance over a run with a steering motor at its torque limit (it cannot hold the
/// commanded speed at once): the work of the input torque and of the steering motor equals
/// the gain of kinetic energy of every inertia plus the implicit Euler step's dissipation,
/// step by step `sum_k T_k h w_k' = sum_j J_j w_j' (w_j' - w_j)` (the rows do no work).
/// A wrong sign or factor in the rows or in the reported motor torque breaks it.
#[test]
fn the_input_and_the_steering_motor_power_the_inertias() {
    let mut p = params();
    p.dsu.as_mut().unwrap().max_steering_torque = 50.0;
    let mut r = Rig::new(&p, [1.0, 3.0]);
    let (mut work, mut gain) = (0.0, 0.0);
    let mut saturated = 0;
    for i in 0..400 {
        let before = r.speeds();
        let steer = if i < 200 { 1.0 } else { -0.5 };
        r.step(80.0, 0.0, steer);
        let after = r.speeds();
        let s = r.shafts();
        let t_st = r.d.steering_torque(s);
        if (t_st.abs() - 50.0).abs() < 1e-9 {
            saturated += 1;
        }
        work += H * (80.0 * s.speed(r.input) + r.d.steering_power(s));
        gain += before
            .iter()
            .zip(&after)
            .map(|((j, w0), (_, w1))| j * w1 * (w1 - w0))
            .sum::<f64>();
    }
    assert!(saturated > 20, "the motor saturated on {saturated} steps");
    assert!(work > 100.0, "{work}");
    assert!(
        (work / gain - 1.0).abs() < 1e-9,
        "work {work} J, gain {gain} J"
    );
    // And the motor ended on its command (-4 rad/s) once the limit allowed it.
    let (_, wst, wl, wr) = r.state();
    assert!(
        (wst + 4.0).abs() < 1e-9 && (wr - wl + 4.0).abs() < 1e-9,
        "{wst}"
    );
}

/// Bad DSU data are errors naming the field and value; so is a NaN input, and `steering`
/// = `dsu` without the unit's parameters.
#[test]
fn bad_dsu_inputs_are_errors_naming_the_field() {
    type Edit = fn(&mut DsuParams);
    let cases: [(Edit, &str); 5] = [
        (
            |d| d.steering_ratio = 0.0,
            "driveline.dsu.steering_ratio` = 0",
        ),
        (
            |d| d.steering_shaft_inertia = -1.0,
            "driveline.dsu.steering_shaft_inertia` = -1",
        ),
        (
            |d| d.max_steering_speed = f64::NAN,
            "driveline.dsu.max_steering_speed` = NaN",
        ),
        (
            |d| d.max_steering_torque = f64::INFINITY,
            "driveline.dsu.max_steering_torque` = inf",
        ),
        (
            |d| d.steering_ratio = -0.5,
            "driveline.dsu.steering_ratio` = -0.5",
        ),
    ];
    for (edit, want) in cases {
        let mut p = params();
        edit(p.dsu.as_mut().unwrap());
        let e = p.validate("driveline").unwrap_err().to_string();
        assert!(e.contains(want), "{e}");
    }
    let mut p = params();
    p.dsu = None;
    let e = p.validate("driveline").unwrap_err().to_string();
    assert!(e.contains("`driveline.dsu`"), "{e}");
    let e = "dsuu".parse::<TrackSteering>().unwrap_err().to_string();
    assert!(
        e.contains("driveline.steering") && e.contains("dsuu"),
        "{e}"
    );
    assert_eq!("dsu".parse::<TrackSteering>().unwrap(), TrackSteering::Dsu);
    // The data as JSON: an unknown field and a wrong steering name are named.
    let mut v = serde_json::to_value(params()).unwrap();
    v["dsu"]["steering_gain"] = serde_json::json!(1.0);
    let e = serde_json::from_value::<TrackDrivelineParams>(v)
        .unwrap_err()
        .to_string();
    assert!(e.contains("steering_gain"), "{e}");
    let r = Rig::new(&params(), [2.0, 2.0]);
    let e = r.d.commands_for(f64::NAN, 0.0).unwrap_err().to_string();
    assert!(e.contains("brake"), "{e}");
    let e = r.d.commands_for(0.0, f64::NAN).unwrap_err().to_string();
    assert!(e.contains("steering"), "{e}");
    assert_eq!(r.d.commands_for(2.0, -3.0).unwrap(), (-8.0, 2.0e4));
}
