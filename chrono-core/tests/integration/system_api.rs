//! Integration tests of the public System API with a real solver: bad input is rejected with
//! an error that names the field. (Bit-for-bit reproducibility of whole validation cases is
//! tested in `xtask/tests/case_determinism.rs`.)

use crate::common::{add_ground, sphere, tight_apgd};
use chrono_ccp::{Psor, SolverSettings};
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::{
    ChronoError, ContactMaterial, JointBuilder, JointKind, RigidBodyBuilder, Shape, System,
    SystemSettings,
};

fn system() -> System {
    System::new(SystemSettings::default(), tight_apgd(1000)).unwrap()
}

#[test]
fn joint_naming_a_missing_body_is_rejected() {
    let mut sys = system();
    let a = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let e = sys
        .add_joint(
            JointBuilder::at_axis(
                JointKind::Revolute,
                a,
                chrono_core::Bodies::from_bodies(vec![
                    chrono_core::RigidBodyBuilder::fixed()
                        .build()
                        .unwrap();
                    8
                ])
                .handle(7),
                Vector3::zeros(),
                Vector3::z(),
            )
            .name("hinge"),
        )
        .unwrap_err();
    assert!(
        matches!(e, ChronoError::UnknownHandle { index: 7, .. }),
        "{e}"
    );
    assert!(e.to_string().contains("joint \"hinge\".body_b"), "{e}");
}

#[test]
fn bad_step_size_and_settings_are_rejected() {
    let mut sys = system();
    for h in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
        let e = sys.step(h).unwrap_err().to_string();
        assert!(e.contains("`h`"), "{e}");
    }
    let s = SystemSettings {
        envelope: -0.1,
        ..SystemSettings::default()
    };
    let e = System::new(s, Box::new(Psor::new(SolverSettings::default())))
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("settings.envelope") && e.contains("-0.1"), "{e}");
}

#[test]
fn bad_bodies_and_materials_are_rejected() {
    let mut sys = system();
    let e = sys
        .add_body(RigidBodyBuilder::dynamic().name("b").mass(0.0))
        .unwrap_err()
        .to_string();
    assert!(e.contains("body \"b\".mass"), "{e}");
    let e = sys
        .add_body(RigidBodyBuilder::dynamic().collider(
            Shape::Sphere { radius: 0.1 },
            Isometry3::identity(),
            ContactMaterial::with_friction(-0.5),
        ))
        .unwrap_err()
        .to_string();
    assert!(e.contains("friction") && e.contains("-0.5"), "{e}");
    let e = sys
        .add_body(RigidBodyBuilder::dynamic().collider(
            Shape::Sphere { radius: -1.0 },
            Isometry3::identity(),
            ContactMaterial::default(),
        ))
        .unwrap_err()
        .to_string();
    assert!(e.contains("radius") && e.contains("-1"), "{e}");
}

#[test]
fn a_diverging_state_stops_with_an_error_naming_the_body_and_step() {
    let mut sys = system();
    let b = sys
        .add_body(RigidBodyBuilder::dynamic().name("rocket"))
        .unwrap();
    sys.step(1e-3).unwrap();
    // an enormous but finite force overflows the velocity to infinity
    sys.body_mut(b)
        .unwrap()
        .set_applied_force(Vector3::new(f64::MAX, 0.0, 0.0))
        .unwrap();
    let mut err = None;
    for _ in 0..5 {
        if let Err(e) = sys.step(1.0) {
            err = Some(e);
            break;
        }
    }
    let e = err.expect("the step must fail").to_string();
    assert!(e.contains("rocket") && e.contains("step"), "{e}");
}

#[test]
fn a_finite_but_runaway_state_stops_with_a_diverged_error() {
    let mut sys = system();
    let b = sys
        .add_body(RigidBodyBuilder::dynamic().name("runaway"))
        .unwrap();
    // 1e6 N on 1 kg: passes the speed limit (1e4 m/s) after about 10 ms
    sys.body_mut(b)
        .unwrap()
        .set_applied_force(Vector3::new(1e6, 0.0, 0.0))
        .unwrap();
    let mut err = None;
    for _ in 0..100 {
        if let Err(e) = sys.step(1e-3) {
            err = Some(e);
            break;
        }
    }
    let e = err.expect("the step must fail");
    // v after step k (0-based) is 1e3 (k + 1) m/s: the limit is crossed at step 9 or 10
    assert!(
        matches!(e, ChronoError::Diverged { step: 9..=10, .. }),
        "{e}"
    );
    assert!(
        e.to_string().contains("runaway") && e.to_string().contains("m/s"),
        "{e}"
    );
}

#[test]
fn a_distance_joint_between_two_anchors_holds_its_length() {
    let mut sys = system();
    let pivot = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let bob = sys
        .add_body(RigidBodyBuilder::dynamic().position(Vector3::new(0.6, 0.0, -0.8)))
        .unwrap();
    sys.add_joint(JointBuilder::distance_between(
        pivot,
        bob,
        Vector3::zeros(),
        Vector3::new(0.6, 0.0, -0.8),
    ))
    .unwrap();
    for _ in 0..1000 {
        sys.step(1e-3).unwrap();
        let d = sys.body(bob).unwrap().position().norm();
        assert!((d - 1.0).abs() < 1e-5, "length {d}");
    }
    // it swung through the bottom
    assert!(sys.body(bob).unwrap().position().x < 0.3);
}

#[test]
fn a_ball_settles_on_the_ground() {
    let mut sys = system();
    let mat = ContactMaterial::with_friction(0.4);
    add_ground(&mut sys, "ground", mat);
    let ball = sys
        .add_body(sphere(0.1, 1000.0, Vector3::new(0.0, 0.0, 0.5), mat))
        .unwrap();
    for _ in 0..1000 {
        sys.step(1e-3).unwrap();
    }
    let b = sys.body(ball).unwrap();
    assert!(
        (b.position().z - 0.1).abs() < 1e-6,
        "z = {}",
        b.position().z
    );
    assert!(b.linear_velocity().norm() < 1e-6);
}
