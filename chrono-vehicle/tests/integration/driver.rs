//! Tests of the drivers on tiny plants: a point mass for the speed PID, a kinematic bicycle
//! for the path follower.

use chrono_core::math::{UnitQuaternion, Vector3};
use chrono_core::{Curve, Extrapolation};
use chrono_vehicle::driver::{
    Driver, IsoDoubleLaneChange, OpenLoopDriver, Path, PathFollowerDriver, PathFollowerParams,
    PidGains, PurePursuit, SpeedController,
};
use chrono_vehicle::{DriverInputs, VehicleState};
use nalgebra::Vector2;

const DT: f64 = 0.01;

/// Longitudinal point mass: 2500 kg, 8 kN at full throttle, 20 kN at full brake, drag
/// 1.5 v^2 N and 300 N rolling resistance.
fn accel(v: f64, i: &DriverInputs) -> f64 {
    let m = 2500.0;
    let resist = if v > 1e-3 { 1.5 * v * v + 300.0 } else { 0.0 };
    let brake = if v > 1e-3 { 20000.0 * i.brake } else { 0.0 };
    (8000.0 * i.throttle - brake - resist) / m
}

#[test]
fn speed_pid_settles_a_point_mass_without_windup_and_brakes_to_slow_down() {
    let gains = PidGains {
        kp: 0.6,
        ki: 0.2,
        kd: 0.02,
    };
    let mut c = SpeedController::new(gains, 10.0).unwrap();
    let (mut v, mut t, mut vmax) = (0.0f64, 0.0, 0.0f64);
    for _ in 0..4000 {
        let u = c.advance(t, v);
        let (throttle, brake) = SpeedController::pedals(u);
        assert!((0.0..=1.0).contains(&throttle) && (0.0..=1.0).contains(&brake));
        v += accel(
            v,
            &DriverInputs {
                throttle,
                brake,
                steering: 0.0,
            },
        ) * DT;
        t += DT;
        vmax = vmax.max(v);
    }
    assert!((v - 10.0).abs() < 1e-3, "v = {v}");
    // the output saturates for the first ~3.5 s; a wound-up integral would overshoot by
    // several m/s
    assert!(vmax < 10.3, "overshoot to {vmax}");
    // steady state: the integral supplies the throttle against drag and rolling resistance
    let need = (1.5 * 100.0 + 300.0) / 8000.0;
    assert!(
        (c.output() - need).abs() < 1e-3,
        "u = {}, need {need}",
        c.output()
    );
    // slow down to 5 m/s: the brake is used
    c.set_target(5.0);
    let mut braked = false;
    for _ in 0..4000 {
        let u = c.advance(t, v);
        let (throttle, brake) = SpeedController::pedals(u);
        braked |= brake > 0.1;
        v += accel(
            v,
            &DriverInputs {
                throttle,
                brake,
                steering: 0.0,
            },
        ) * DT;
        t += DT;
    }
    assert!(braked);
    assert!((v - 5.0).abs() < 1e-3, "v = {v}");
}

/// A kinematic bicycle (rear-axle reference) with the point-mass longitudinal dynamics.
struct Bicycle {
    x: f64,
    y: f64,
    psi: f64,
    v: f64,
    t: f64,
    wheelbase: f64,
    max_angle: f64,
}

impl Bicycle {
    /// The state a driver sees: the chassis reference between the axles.
    fn state(&self) -> VehicleState {
        let (c, s) = (self.psi.cos(), self.psi.sin());
        VehicleState {
            time: self.t,
            position: Vector3::new(
                self.x + 0.5 * self.wheelbase * c,
                self.y + 0.5 * self.wheelbase * s,
                0.5,
            ),
            rotation: UnitQuaternion::from_euler_angles(0.0, 0.0, self.psi),
            velocity: Vector3::new(self.v * c, self.v * s, 0.0),
            angular_velocity: Vector3::zeros(),
        }
    }

    fn step(&mut self, i: &DriverInputs) {
        let delta = i.steering * self.max_angle;
        self.x += self.v * self.psi.cos() * DT;
        self.y += self.v * self.psi.sin() * DT;
        self.psi += self.v * delta.tan() / self.wheelbase * DT;
        self.v += accel(self.v, i) * DT;
        self.t += DT;
    }
}

fn params(target: f64) -> PathFollowerParams {
    let mut p = PathFollowerParams::hmmwv(target);
    p.speed = PidGains {
        kp: 0.6,
        ki: 0.2,
        kd: 0.0,
    };
    p
}

fn bicycle(x: f64, y: f64, v: f64, p: &PathFollowerParams) -> Bicycle {
    Bicycle {
        x,
        y,
        psi: 0.0,
        v,
        t: 0.0,
        wheelbase: p.steering.wheelbase,
        max_angle: p.steering.max_steer_angle,
    }
}

#[test]
fn path_follower_returns_to_a_straight_line_from_a_two_meter_offset() {
    let p = params(10.0);
    let path = Path::straight([-10.0, 0.0], 0.0, 1000.0).unwrap();
    let mut d = PathFollowerDriver::new(path, p).unwrap();
    let mut b = bicycle(0.0, 2.0, 10.0, &p);
    let mut ymin = f64::MAX;
    for _ in 0..4000 {
        let i = d.synchronize(&b.state());
        b.step(&i);
        ymin = ymin.min(b.y);
    }
    assert!(
        b.y.abs() < 1e-3 && b.psi.abs() < 1e-4,
        "y {}, psi {}",
        b.y,
        b.psi
    );
    // linearized pure pursuit on a kinematic bicycle: y'' = -(2 v^2/l^2) y - (2 v/l) y',
    // damping ratio 1/sqrt(2), so the overshoot is exp(-pi) of the initial offset
    let expected = -2.0 * (-std::f64::consts::PI).exp();
    assert!(
        (ymin - expected).abs() < 0.1 * expected.abs(),
        "overshoot to y = {ymin} vs {expected}"
    );
    assert!((b.v - 10.0).abs() < 1e-3, "v {}", b.v);
}

#[test]
fn path_follower_tracks_a_circle() {
    let p = params(8.0);
    let r = 30.0;
    let path = Path::circle([0.0, 0.0], r, 400, true).unwrap();
    let mut d = PathFollowerDriver::new(path, p).unwrap();
    // start 1 m outside the circle, heading along it
    let mut b = bicycle(0.0, -r - 1.0, 8.0, &p);
    let mut err = 0.0f64;
    for k in 0..5000 {
        let i = d.synchronize(&b.state());
        assert!(
            i.steering > 0.0 || k < 300,
            "a left circle needs left steering"
        );
        b.step(&i);
        if k >= 3000 {
            err = err.max(((b.x * b.x + b.y * b.y).sqrt() - r).abs());
        }
    }
    // the rear axle stays on the circle (polyline sagitta 0.9 mm, Euler steps of 8 cm)
    assert!(err < 0.01, "radial error {err}");
    // and goes around it counter-clockwise: 5000 steps * 8 cm = 400 m > 2 laps
    assert!((b.v - 8.0).abs() < 1e-2);
}

#[test]
fn iso_lane_change_has_the_published_dimensions() {
    let b = 2.0;
    let dlc = IsoDoubleLaneChange::new(b).unwrap();
    let w = dlc.lane_widths();
    assert_eq!(w, [1.1 * b + 0.25, b + 1.0, 1.3 * b + 0.25]);
    assert_eq!(dlc.boundaries(), [0.0, 15.0, 45.0, 70.0, 95.0, 110.0]);
    // right-hand cone lines of lanes 1 and 3 are 3.5 m apart
    let y3 = dlc.side_lane_center();
    assert!(((y3 - 0.5 * w[1]) - (-0.5 * w[0]) - 3.5).abs() < 1e-12);
    let path = dlc.path(20.0, 30.0, 0.5).unwrap();
    let len = path_len_between(&path, -20.0, 140.0);
    assert!(
        len > 160.0 && (path.length() - len).abs() < 1e-9,
        "length {}",
        path.length()
    );
    let pts = path.points();
    assert_eq!(pts[0], Vector2::new(-20.0, 0.0));
    assert_eq!(pts.last().unwrap().x, 140.0);
    for q in pts {
        let y = q.y;
        if q.x <= 15.0 || q.x >= 95.0 {
            assert_eq!(y, 0.0, "at x = {}", q.x);
        } else if (45.0..=70.0).contains(&q.x) {
            assert!((y - y3).abs() < 1e-12, "at x = {}", q.x);
        } else {
            assert!(y > 0.0 && y < y3);
        }
    }
    // the section boundaries are path points
    for xb in dlc.boundaries() {
        assert!(pts.iter().any(|p| p.x == xb), "no point at x = {xb}");
    }
    // closest-point query: 0.5 m left of the side lane's center line
    let c = path.closest(Vector2::new(50.0, y3 + 0.5));
    assert!((c.offset - 0.5).abs() < 1e-12 && (c.point.x - 50.0).abs() < 1e-12);
    assert!((c.s - (20.0 + 15.0 + path_len_between(&path, 15.0, 50.0))).abs() < 1e-9);
}

/// Arc length of the polyline between two x values (the test's own sum).
fn path_len_between(path: &Path, x0: f64, x1: f64) -> f64 {
    path.points()
        .windows(2)
        .filter(|w| w[0].x >= x0 && w[1].x <= x1)
        .map(|w| (w[1] - w[0]).norm())
        .sum()
}

#[test]
fn open_loop_driver_follows_its_tables_and_clamps() {
    let c = |pts: Vec<[f64; 2]>| Curve::new("c", pts, Extrapolation::Constant).unwrap();
    let mut d = OpenLoopDriver::new(
        c(vec![[0.0, 0.0], [2.0, 1.0]]),
        c(vec![[0.0, 0.0], [5.0, 0.0], [6.0, 2.0]]),
        c(vec![[0.0, 0.0], [1.0, -1.5]]),
    )
    .unwrap();
    let mut s = bicycle(0.0, 0.0, 0.0, &params(1.0)).state();
    s.time = 1.0;
    let i = d.synchronize(&s);
    assert_eq!((i.throttle, i.brake, i.steering), (0.5, 0.0, -1.0));
    s.time = 7.0;
    let i = d.synchronize(&s);
    assert_eq!((i.throttle, i.brake), (1.0, 1.0));
    let json = r#"{"throttle": {"points": [[0, 0]]}, "brake": {"points": [[1, 0], [0, 1]]},
                   "steering": {"points": [[0, 0]]}}"#;
    let d: OpenLoopDriver = serde_json::from_str(json).unwrap();
    let e = d.validate().unwrap_err().to_string();
    assert!(e.contains("open_loop_driver.brake.points[1]"), "{e}");
    let e = PathFollowerDriver::new(
        Path::straight([0.0, 0.0], 0.0, 10.0).unwrap(),
        PathFollowerParams {
            steering: PurePursuit {
                lookahead: -2.0,
                ..params(1.0).steering
            },
            ..params(1.0)
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("pure_pursuit.lookahead") && e.contains("-2"),
        "{e}"
    );
}

#[test]
fn path_follower_drives_the_iso_lane_change_inside_the_lanes_at_36_kmh() {
    let b = 2.2;
    let dlc = IsoDoubleLaneChange::new(b).unwrap();
    let path = dlc.path(50.0, 50.0, 0.5).unwrap();
    let p = params(10.0);
    let mut d = PathFollowerDriver::new(path, p).unwrap();
    let mut bike = bicycle(-50.0, 0.0, 10.0, &p);
    let w = dlc.lane_widths();
    let y3 = dlc.side_lane_center();
    let mut worst = [0.0f64; 3];
    while bike.x < 120.0 {
        let i = d.synchronize(&bike.state());
        bike.step(&i);
        let s = bike.state();
        let (x, y) = (s.position.x, s.position.y);
        if (0.0..=15.0).contains(&x) {
            worst[0] = worst[0].max(y.abs());
        } else if (45.0..=70.0).contains(&x) {
            worst[1] = worst[1].max((y - y3).abs());
        } else if (95.0..=110.0).contains(&x) {
            worst[2] = worst[2].max(y.abs());
        }
    }
    // the reference point keeps a vehicle of width b inside the lanes (lateral margins
    // (w - b)/2); back on lane 1's line after the manoeuvre within the entry lane's margin
    let (m1, m3) = (0.5 * (w[0] - b), 0.5 * (w[1] - b));
    assert!(
        worst[0] < m1 && worst[1] < m3 && worst[2] < m1,
        "{worst:?} vs {m1}, {m3}"
    );
}
