//! Integration tests of the joints (`chrono_core::joint`) with a real solver: each test checks
//! physics that would fail if the joint's constraint rows were wrong.

use crate::common::{g, tight_apgd};
use chrono_core::math::Vector3;
use chrono_core::{
    BodyHandle, Drive, JointBuilder, JointHandle, JointKind, RigidBodyBuilder, System,
    SystemSettings,
};
use nalgebra::UnitQuaternion;

const H: f64 = 1e-3;

fn system_with(settings: SystemSettings) -> System {
    System::new(settings, tight_apgd(1000)).unwrap()
}

fn system() -> System {
    system_with(SystemSettings::default())
}

fn no_gravity() -> System {
    system_with(SystemSettings {
        gravity: Vector3::zeros(),
        ..SystemSettings::default()
    })
}

fn body(mass: f64, inertia: Vector3<f64>, position: Vector3<f64>) -> RigidBodyBuilder {
    RigidBodyBuilder::dynamic()
        .mass(mass)
        .inertia_diagonal(inertia)
        .position(position)
}

fn step(sys: &mut System) {
    sys.step(H).unwrap();
}

fn pos(sys: &System, b: BodyHandle) -> Vector3<f64> {
    sys.body(b).unwrap().position()
}

#[test]
fn spherical_pendulum_keeps_its_pivot_and_radius() {
    let mut sys = system();
    let ground = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let start = Vector3::new(0.3, 0.2, -0.4);
    let bob = sys
        .add_body(body(2.0, Vector3::new(0.01, 0.02, 0.03), start))
        .unwrap();
    let pivot = Vector3::zeros();
    sys.add_joint(JointBuilder::at_axis(
        JointKind::Spherical,
        ground,
        bob,
        pivot,
        Vector3::z(),
    ))
    .unwrap();
    let r0 = (start - pivot).norm();
    let (mut max_viol, mut max_dr, mut min_z) = (0.0f64, 0.0f64, f64::MAX);
    for _ in 0..2000 {
        step(&mut sys);
        max_viol = max_viol.max(sys.max_joint_violation());
        let p = pos(&sys, bob);
        max_dr = max_dr.max(((p - pivot).norm() - r0).abs());
        min_z = min_z.min(p.z);
    }
    assert!(max_viol < 1e-5, "violation {max_viol}");
    assert!(max_dr < 1e-5, "radius drift {max_dr}");
    // it did swing (down to the bottom, r0 below the pivot)
    assert!(min_z < -0.45, "min z {min_z}");
    assert!((pos(&sys, bob) - start).norm() > 0.01);
}

#[test]
fn prismatic_on_an_incline_slides_at_g_sin_theta() {
    let mut sys = system();
    let ground = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let th = 30f64.to_radians();
    let axis = Vector3::new(th.cos(), 0.0, th.sin());
    let start = Vector3::new(0.1, -0.2, 0.3);
    let slider = sys
        .add_body(body(1.5, Vector3::new(0.1, 0.2, 0.3), start))
        .unwrap();
    sys.add_joint(JointBuilder::at_axis(
        JointKind::Prismatic,
        ground,
        slider,
        start,
        axis,
    ))
    .unwrap();
    let (mut max_perp, mut max_angle) = (0.0f64, 0.0f64);
    let mut v_at = Vec::new();
    for k in 1..=500 {
        step(&mut sys);
        let b = sys.body(slider).unwrap();
        let d = b.position() - start;
        max_perp = max_perp.max((d - axis * axis.dot(&d)).norm());
        max_angle = max_angle.max(b.rotation().angle());
        if k == 100 || k == 500 {
            v_at.push(b.linear_velocity().dot(&axis));
        }
    }
    let a = (v_at[1] - v_at[0]) / (400.0 * H);
    let expected = -g() * th.sin();
    assert!(
        ((a - expected) / expected).abs() < 1e-3,
        "a = {a}, expected {expected}"
    );
    assert!(max_perp < 1e-6, "perpendicular displacement {max_perp}");
    assert!(max_angle < 1e-6, "rotation {max_angle}");
    // the displacement along the axis matches too: s = a t^2/2 (to O(h))
    let s = (pos(&sys, slider) - start).dot(&axis);
    let t = 500.0 * H;
    assert!(
        (s - 0.5 * expected * t * t).abs() < 0.5 * g() * t * H,
        "s = {s}"
    );
}

#[test]
fn revolute_about_x_only_rotates_about_x() {
    let mut sys = system();
    let ground = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let start = Vector3::new(0.0, 0.5, 0.0);
    // unequal principal moments: any rotation leaking into y or z would show
    let arm = sys
        .add_body(body(1.0, Vector3::new(0.05, 0.1, 0.2), start))
        .unwrap();
    sys.add_joint(JointBuilder::at_axis(
        JointKind::Revolute,
        ground,
        arm,
        Vector3::zeros(),
        Vector3::x(),
    ))
    .unwrap();
    let (mut max_wyz, mut max_wx, mut max_viol) = (0.0f64, 0.0f64, 0.0f64);
    for _ in 0..1000 {
        step(&mut sys);
        let w = sys.body(arm).unwrap().angular_velocity();
        max_wyz = max_wyz.max(w.y.abs()).max(w.z.abs());
        max_wx = max_wx.max(w.x.abs());
        max_viol = max_viol.max(sys.max_joint_violation());
    }
    assert!(max_wyz < 1e-6, "w_y, w_z up to {max_wyz}");
    assert!(max_wx > 1.0, "it swings about x: |w_x| up to {max_wx}");
    assert!(max_viol < 1e-5, "violation {max_viol}");
    // the center stays on the circle of radius 0.5 in the y-z plane
    let p = pos(&sys, arm);
    assert!(p.x.abs() < 1e-6 && (p.norm() - 0.5).abs() < 1e-5, "{p}");
}

#[test]
fn universal_keeps_the_cross_perpendicular_and_blocks_the_spin() {
    let mut sys = system();
    let ground = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let start = Vector3::new(0.0, 0.0, -0.5);
    // spun about the pivot (the origin): w = (1, 0.5, 3), the center moving with w x start
    let w0 = Vector3::new(1.0, 0.5, 3.0);
    let b = sys
        .add_body(
            body(1.0, Vector3::new(0.1, 0.15, 0.2), start)
                .angular_velocity(w0)
                .linear_velocity(w0.cross(&start)),
        )
        .unwrap();
    // frame axes = world axes at creation (B at identity rotation): x_A = x, y_B = R_B y
    sys.add_joint(JointBuilder::at_axis(
        JointKind::Universal,
        ground,
        b,
        Vector3::zeros(),
        Vector3::z(),
    ))
    .unwrap();
    let xa = Vector3::x();
    // one step: the spin about z = x_A x y_B is blocked (the center is on that axis, so it is
    // simply removed); the rotations about x_A and y_B pass (gravity is along the pendulum
    // here; only the gyroscopic term changes them, by ~h |w|^2 = 3e-3)
    step(&mut sys);
    let w1 = sys.body(b).unwrap().angular_velocity();
    assert!(w1.z.abs() < 1e-6, "blocked spin left: {:?}", w1.as_slice());
    assert!(
        (w1.x - 1.0).abs() < 1e-2 && (w1.y - 0.5).abs() < 1e-2,
        "free rotations changed: {:?}",
        w1.as_slice()
    );
    let (mut max_dot, mut max_viol, mut max_spin, mut max_angle) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for _ in 0..2000 {
        // the row, built at the start of the step: C = x_A . y_B, d/dt C = -w_B . (x_A x y_B),
        // and the step makes d/dt C = -C/h, i.e. w_B . (x_A x y_B) = C/h (the blocked spin)
        let yb0 = sys.body(b).unwrap().rotation() * Vector3::y();
        let (n, c) = (xa.cross(&yb0), xa.dot(&yb0));
        step(&mut sys);
        let body = sys.body(b).unwrap();
        let yb = body.rotation() * Vector3::y();
        max_dot = max_dot.max(xa.dot(&yb).abs());
        max_viol = max_viol.max(sys.max_joint_violation());
        max_spin = max_spin.max((body.angular_velocity().dot(&n) - c / H).abs());
        max_angle = max_angle.max(body.rotation().angle());
    }
    assert!(max_dot < 1e-5, "x_A . y_B up to {max_dot}");
    assert!(max_viol < 1e-5, "violation {max_viol}");
    assert!(
        max_spin < 1e-6,
        "row residual w_B . (x_A x y_B) - C/h up to {max_spin}"
    );
    // the two free rotations did happen
    assert!(max_angle > 0.15, "rotation up to {max_angle}");
}

#[test]
fn distance_joint_keeps_its_length_while_swinging() {
    let mut sys = system();
    let ground = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    // the joint frame is the same world point on both bodies at creation, so create B at the
    // anchor and move it out to distance L afterwards
    let b = sys
        .add_body(body(1.0, Vector3::new(0.01, 0.01, 0.01), Vector3::zeros()))
        .unwrap();
    let l = 0.5;
    sys.add_joint(JointBuilder::at_axis(
        JointKind::Distance { distance: l },
        ground,
        b,
        Vector3::zeros(),
        Vector3::z(),
    ))
    .unwrap();
    let start = Vector3::new(0.4, 0.0, -0.3);
    sys.body_mut(b)
        .unwrap()
        .set_pose(start, UnitQuaternion::identity())
        .unwrap();
    assert!(sys.max_joint_violation() < 1e-12);
    let (mut max_dl, mut max_viol, mut min_x) = (0.0f64, 0.0f64, f64::MAX);
    for _ in 0..2000 {
        step(&mut sys);
        let p = pos(&sys, b);
        max_dl = max_dl.max((p.norm() - l).abs());
        max_viol = max_viol.max(sys.max_joint_violation());
        min_x = min_x.min(p.x);
    }
    assert!(max_dl < 1e-5, "length drift {max_dl}");
    assert!(max_viol < 1e-5, "violation {max_viol}");
    assert!(
        min_x < -0.3,
        "it swings through to the other side: min x {min_x}"
    );
}

#[test]
fn lock_holds_a_body_under_gravity() {
    let mut sys = system();
    let ground = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let start = Vector3::new(0.3, 0.2, 0.1);
    let b = sys
        .add_body(body(3.0, Vector3::new(0.1, 0.2, 0.3), start))
        .unwrap();
    sys.add_joint(JointBuilder::at_axis(
        JointKind::Lock,
        ground,
        b,
        Vector3::new(-0.2, 0.1, 0.4),
        Vector3::new(1.0, 1.0, 1.0),
    ))
    .unwrap();
    let (mut max_v, mut max_d, mut max_angle) = (0.0f64, 0.0f64, 0.0f64);
    for _ in 0..500 {
        step(&mut sys);
        let body = sys.body(b).unwrap();
        max_v = max_v
            .max(body.linear_velocity().norm())
            .max(body.angular_velocity().norm());
        max_d = max_d.max((body.position() - start).norm());
        max_angle = max_angle.max(body.rotation().angle());
    }
    assert!(max_v < 1e-8, "velocity up to {max_v}");
    assert!(max_d < 1e-8, "displacement up to {max_d}");
    assert!(max_angle < 1e-8, "rotation up to {max_angle}");
}

fn motor(
    sys: &mut System,
    drive: Drive,
    max_torque: f64,
    limits: Option<(f64, f64)>,
) -> (BodyHandle, JointHandle) {
    let ground = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let rotor = sys
        .add_body(body(1.0, Vector3::new(1.0, 1.0, 1.0), Vector3::zeros()))
        .unwrap();
    let kind = JointKind::RotationalMotor {
        drive,
        max_torque,
        limits,
    };
    let j = sys
        .add_joint(JointBuilder::at_axis(
            kind,
            ground,
            rotor,
            Vector3::zeros(),
            Vector3::z(),
        ))
        .unwrap();
    (rotor, j)
}

#[test]
fn rotational_motor_reaches_its_speed() {
    let mut sys = no_gravity();
    let (rotor, _) = motor(&mut sys, Drive::Speed(2.0), 1e6, None);
    for k in 0..20 {
        step(&mut sys);
        if k >= 2 {
            let w = sys.body(rotor).unwrap().angular_velocity();
            assert!((w.z - 2.0).abs() < 1e-6, "step {k}: w_z = {}", w.z);
            assert!(w.x.abs() < 1e-9 && w.y.abs() < 1e-9, "{w}");
        }
    }
}

#[test]
fn rotational_motor_is_limited_by_its_torque() {
    let mut sys = no_gravity();
    let (rotor, _) = motor(&mut sys, Drive::Speed(2.0), 0.1, None);
    let mut w = Vec::new();
    for k in 1..=1000 {
        step(&mut sys);
        if k == 100 || k == 1000 {
            w.push(sys.body(rotor).unwrap().angular_velocity().z);
        }
    }
    let alpha = (w[1] - w[0]) / (900.0 * H);
    assert!(
        ((alpha - 0.1) / 0.1).abs() < 1e-3,
        "angular acceleration {alpha}, expected 0.1"
    );
    assert!(w[1] < 2.0, "still below the target speed");
}

#[test]
fn rotational_motor_stops_at_its_angle_limits() {
    let mut sys = no_gravity();
    let (rotor, j) = motor(&mut sys, Drive::Effort(1.0), 1e6, Some((-0.5, 0.5)));
    let (mut max_angle, mut max_body_angle) = (f64::MIN, f64::MIN);
    for _ in 0..2000 {
        step(&mut sys);
        let a = sys.joint(j).unwrap().angle();
        max_angle = max_angle.max(a);
        // the body's own rotation about z (the joint angle is computed at the start of a step)
        let q = sys.body(rotor).unwrap().rotation();
        max_body_angle = max_body_angle.max(q.scaled_axis().z);
        assert!(a <= 0.5 + 1e-3, "angle {a}");
        assert!(
            q.scaled_axis().z <= 0.5 + 1e-3,
            "body angle {}",
            q.scaled_axis().z
        );
    }
    // without the limit the angle would reach t^2/2 = 2 rad; it reaches the limit instead
    assert!(max_angle > 0.5 - 1e-3, "max angle {max_angle}");
    assert!(
        max_body_angle > 0.5 - 1e-3,
        "max body angle {max_body_angle}"
    );
    let w = sys.body(rotor).unwrap().angular_velocity();
    assert!(w.z.abs() < 1e-6, "resting on the limit: w_z = {}", w.z);
}

#[test]
fn linear_actuator_reaches_its_position_under_gravity() {
    let mut sys = system();
    let ground = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let start = Vector3::new(0.1, 0.2, 0.3);
    let b = sys
        .add_body(body(2.0, Vector3::new(0.1, 0.1, 0.1), start))
        .unwrap();
    let kind = JointKind::LinearActuator {
        drive: Drive::Position(0.2),
        max_force: 1e6,
    };
    sys.add_joint(JointBuilder::at_axis(kind, ground, b, start, Vector3::z()))
        .unwrap();
    for _ in 0..10 {
        step(&mut sys);
    }
    let d = pos(&sys, b) - start;
    assert!((d.z - 0.2).abs() < 1e-6, "displacement along z {}", d.z);
    assert!(d.x.abs() < 1e-9 && d.y.abs() < 1e-9, "{d}");
    assert!(sys.body(b).unwrap().linear_velocity().norm() < 1e-6);
}

#[test]
fn bad_joint_parameters_are_rejected_naming_the_field() {
    let mut sys = system();
    let a = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let b = sys.add_body(RigidBodyBuilder::dynamic()).unwrap();
    for d in [0.0, -1.0, f64::NAN] {
        let kind = JointKind::Distance { distance: d };
        let e = sys
            .add_joint(JointBuilder::at_axis(
                kind,
                a,
                b,
                Vector3::zeros(),
                Vector3::z(),
            ))
            .unwrap_err()
            .to_string();
        assert!(e.contains("joint.distance"), "{d}: {e}");
    }
    let kind = JointKind::RotationalMotor {
        drive: Drive::Speed(f64::NAN),
        max_torque: 1.0,
        limits: None,
    };
    let e = sys
        .add_joint(JointBuilder::at_axis(
            kind,
            a,
            b,
            Vector3::zeros(),
            Vector3::z(),
        ))
        .unwrap_err()
        .to_string();
    assert!(e.contains("joint.drive"), "{e}");
    let e = sys
        .add_joint(JointBuilder::at_axis(
            JointKind::Spherical,
            b,
            b,
            Vector3::zeros(),
            Vector3::z(),
        ))
        .unwrap_err()
        .to_string();
    assert!(e.contains("joint.body_b"), "{e}");
    assert!(sys.joints().is_empty(), "no joint was added");
}
