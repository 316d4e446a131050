//! The implicit spring-damper on a joint axis ([`chrono_core::AxisSpring`]): the step is the
//! backward Euler step of `m x'' = f_0 - k x - c x'` (checked against the recursion and the
//! analytic solution), it stays stable where the explicit force element diverges, and bad
//! values name the field.

use chrono_ccp::Schur;
use chrono_core::descriptor::SolverSettings;
use chrono_core::math::Vector3;
use chrono_core::{
    AxisSpring, Drive, JointBuilder, JointHandle, JointKind, RigidBodyBuilder, SpringDamper,
    System, SystemSettings,
};

/// A system without gravity and the Schur solver (the joint rows solved directly).
fn system() -> System {
    let settings = SolverSettings {
        tolerance: 1e-12,
        max_iterations: 200,
        record_history: false,
    };
    System::new(
        SystemSettings {
            gravity: Vector3::zeros(),
            ..SystemSettings::default()
        },
        Box::new(Schur::new(settings)),
    )
    .unwrap()
}

/// A system with a fixed ground and a free body of mass `m` (small inertia).
fn ground_and_body(m: f64) -> (System, chrono_core::BodyHandle, chrono_core::BodyHandle) {
    let mut sys = system();
    let ground = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let b = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .mass(m)
                .inertia_diagonal(Vector3::new(0.1, 0.1, 0.1)),
        )
        .unwrap();
    (sys, ground, b)
}

/// A body of mass `m` on a linear actuator along world z (no drive) from a fixed ground,
/// with the axis spring `sp`. Returns the system, the body and the joint.
fn slider(m: f64, sp: AxisSpring) -> (System, chrono_core::BodyHandle, JointHandle) {
    let (mut sys, ground, b) = ground_and_body(m);
    let kind = JointKind::LinearActuator {
        drive: Drive::Effort(0.0),
        max_force: f64::INFINITY,
    };
    let j = sys
        .add_joint(
            JointBuilder::at_axis(kind, ground, b, Vector3::zeros(), Vector3::z())
                .axis_spring(sp)
                .name("slider"),
        )
        .unwrap();
    (sys, b, j)
}

/// Run the slider of the oscillator test for 0.6 s at step `h`, checking every step against
/// the backward Euler recursion `m (v' - v) = h (f_0 - k x' - c v')`, `x' = x + h v'` (to
/// the solver's round-off) and the reported effort; return the largest distance from the
/// analytic damped oscillation `x(t) = x_s (1 - e^(-z w t) (cos(w_d t) + z w / w_d
/// sin(w_d t)))`.
fn oscillator_error(h: f64) -> f64 {
    let (m, k, c, f0) = (2.0, 800.0, 8.0, 40.0);
    let sp = AxisSpring {
        stiffness: k,
        damping: c,
        preload: f0,
    };
    let (mut sys, b, j) = slider(m, sp);
    let (mut x, mut v) = (0.0f64, 0.0f64);
    let (w, z) = ((k / m).sqrt(), c / (2.0 * (k * m).sqrt()));
    let wd = w * (1.0 - z * z).sqrt();
    let xs = f0 / k;
    let mut worst: f64 = 0.0;
    let n = (0.6 / h).round() as usize;
    for i in 1..=n {
        sys.step(h).unwrap();
        // The recursion solved for v': (m + h c + h^2 k) v' = m v + h (f0 - k x).
        v = (m * v + h * (f0 - k * x)) / (m + h * c + h * h * k);
        x += h * v;
        let body = sys.body(b).unwrap();
        let (zs, vs) = (body.position().z, body.linear_velocity().z);
        assert!((zs - x).abs() < 1e-9 * xs, "step {i}: x {zs} against {x}");
        assert!((vs - v).abs() < 1e-8, "step {i}: v {vs} against {v}");
        // The effort reported is the row's impulse over the step: f0 - k x' - c v'.
        let effort = sys.joint(j).unwrap().axis_spring_effort();
        assert!(
            (effort - (f0 - k * zs - c * vs)).abs() < 1e-6 * f0,
            "{effort}"
        );
        let t = i as f64 * h;
        let exact =
            xs * (1.0 - (-z * w * t).exp() * ((wd * t).cos() + z * w / wd * (wd * t).sin()));
        worst = worst.max((zs - exact).abs());
    }
    worst / xs
}

/// The step is backward Euler (to round-off) and converges to the analytic damped
/// oscillation at first order: halving the step halves the error. (Backward Euler adds the
/// damping ratio `h w / 2`: 1 % at `h` = 1 ms, about 3.5 % of `x_s` after 0.6 s.)
#[test]
fn the_axis_spring_is_the_backward_euler_step_and_follows_the_damped_oscillator() {
    let (e1, e2) = (oscillator_error(1e-3), oscillator_error(5e-4));
    assert!(e1 < 0.05, "error at 1 ms {e1} of x_s");
    assert!(
        e2 < 0.6 * e1 && e2 > 0.4 * e1,
        "errors {e1} at 1 ms, {e2} at 0.5 ms"
    );
}

/// With `c h / m` = 50 the explicit spring-damper (the force element) blows up within a few
/// steps; the axis spring settles at `x = f_0 / k` without overshoot.
#[test]
fn the_axis_spring_is_stable_where_the_explicit_element_diverges() {
    let (m, k, c, f0, h) = (1.0, 1e6, 1e4, 1e3, 5e-3);
    let (mut sys, b, _) = slider(
        m,
        AxisSpring {
            stiffness: k,
            damping: c,
            preload: f0,
        },
    );
    let mut prev = 0.0;
    for _ in 0..200 {
        sys.step(h).unwrap();
        let z = sys.body(b).unwrap().position().z;
        assert!(z >= prev - 1e-12 && z <= f0 / k * (1.0 + 1e-9), "z {z}");
        prev = z;
    }
    assert!((prev - f0 / k).abs() < 1e-6 * f0 / k, "settled at {prev}");

    // The same spring as a force element (explicit): diverges.
    let (mut sys, ground, b) = ground_and_body(m);
    let kind = JointKind::Prismatic;
    sys.add_joint(JointBuilder::at_axis(
        kind,
        ground,
        b,
        Vector3::zeros(),
        Vector3::z(),
    ))
    .unwrap();
    // Anchor 1 m below: the spring's length grows with z, so the same law `f0 - k z - c z'`.
    sys.add_force_element(Box::new(
        SpringDamper::linear(
            "explicit",
            ground,
            Vector3::new(0.0, 0.0, -1.0),
            b,
            Vector3::zeros(),
            1.0,
            k,
            c,
        )
        .with_preload(f0),
    ))
    .unwrap();
    let mut blew_up = false;
    for _ in 0..200 {
        if sys.step(h).is_err() {
            blew_up = true;
            break;
        }
        let z = sys.body(b).unwrap().position().z;
        if !z.is_finite() || z.abs() > 1.0 {
            blew_up = true;
            break;
        }
    }
    assert!(
        blew_up,
        "the explicit element stayed stable: the test shows nothing"
    );
}

/// About a rotational motor's axis: a preload torque `T_0` against `k` settles at
/// `theta = T_0 / k`, the effort then zero; a Position drive in parallel holds the angle
/// and the spring's effort is the spring law at the held angle.
#[test]
fn a_torsion_axis_spring_settles_at_its_preload_angle_and_works_beside_a_lock() {
    let mut sys = system();
    let ground = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let b = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .mass(1.0)
                .inertia_diagonal(Vector3::new(0.5, 0.5, 0.5)),
        )
        .unwrap();
    let (k, c, t0) = (100.0, 5.0, 20.0);
    let kind = JointKind::RotationalMotor {
        drive: Drive::Effort(0.0),
        max_torque: f64::INFINITY,
        limits: None,
    };
    let j = sys
        .add_joint(
            JointBuilder::at_axis(kind, ground, b, Vector3::zeros(), Vector3::z()).axis_spring(
                AxisSpring {
                    stiffness: k,
                    damping: c,
                    preload: t0,
                },
            ),
        )
        .unwrap();
    for _ in 0..5000 {
        sys.step(1e-3).unwrap();
    }
    let w = sys.body(b).unwrap().angular_velocity();
    let angle = |sys: &System| {
        let q = sys.body(b).unwrap().rotation();
        q.scaled_axis().z
    };
    assert!((angle(&sys) - t0 / k).abs() < 1e-6, "angle {}", angle(&sys));
    assert!(w.norm() < 1e-6, "{w}");
    assert!(sys.joint(j).unwrap().axis_spring_effort().abs() < 1e-4);
    // Lock at 0.1 rad: the spring in parallel pulls with t0 - k 0.1 = 10 N m, the lock
    // holds against it.
    sys.joint_mut(j)
        .unwrap()
        .set_drive(Drive::Position(0.1))
        .unwrap();
    for _ in 0..20 {
        sys.step(1e-3).unwrap();
    }
    assert!((angle(&sys) - 0.1).abs() < 1e-9, "angle {}", angle(&sys));
    let effort = sys.joint(j).unwrap().axis_spring_effort();
    assert!(
        (effort - (t0 - k * 0.1)).abs() < 1e-6,
        "spring effort {effort}"
    );
    // The lock balances the spring: the body is at rest.
    let w = sys.body(b).unwrap().angular_velocity();
    assert!(w.norm() < 1e-6, "{w}");
}

#[test]
fn bad_axis_springs_are_rejected_naming_the_field() {
    let mut sys = system();
    let a = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let b = sys.add_body(RigidBodyBuilder::dynamic()).unwrap();
    let good = AxisSpring {
        stiffness: 1.0,
        damping: 0.0,
        preload: 0.0,
    };
    let e = sys
        .add_joint(
            JointBuilder::at_axis(JointKind::Revolute, a, b, Vector3::zeros(), Vector3::z())
                .axis_spring(good)
                .name("hinge"),
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("joint \"hinge\".axis_spring"), "{e}");
    let motor = JointKind::RotationalMotor {
        drive: Drive::Effort(0.0),
        max_torque: 1.0,
        limits: None,
    };
    for (sp, field) in [
        (
            AxisSpring {
                stiffness: -1.0,
                ..good
            },
            "axis_spring.stiffness",
        ),
        (
            AxisSpring {
                damping: f64::NAN,
                ..good
            },
            "axis_spring.damping",
        ),
        (
            AxisSpring {
                stiffness: 0.0,
                ..good
            },
            "axis_spring.stiffness",
        ),
        (
            AxisSpring {
                preload: f64::INFINITY,
                ..good
            },
            "axis_spring.preload",
        ),
    ] {
        let e = sys
            .add_joint(
                JointBuilder::at_axis(motor.clone(), a, b, Vector3::zeros(), Vector3::z())
                    .axis_spring(sp),
            )
            .unwrap_err()
            .to_string();
        assert!(e.contains(field), "{field}: {e}");
    }
}
