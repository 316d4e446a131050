//! Per-body friction overrides (`System::set_contact_friction`) through the public API,
//! against the rigid-body solutions of a solid sphere on a plate: while it slides, friction
//! decelerates it at `mu g`; on an incline of angle `a` it rolls without slipping, at
//! `5/7 g sin a`, iff `mu >= 2/7 tan a`, and otherwise slips at `g (sin a - mu cos a)`; once
//! it rolls, rolling resistance decelerates it at `5/7 mu_r g`. The plate carries
//! coefficients larger than the ball's, which the minimum combination rule cannot produce.

use crate::common::{add_ground, g, incline_gravity, sphere, tight_apgd};
use chrono_core::math::Vector3;
use chrono_core::system::{ContactMethod, SmcModel, SmcSettings};
use chrono_core::{BodyHandle, ContactFriction, ContactMaterial, System, SystemSettings};

const R: f64 = 0.01;

/// A fixed plate (half-space z = 0) and a ball of radius `R` resting on it with velocity
/// `v` and angular velocity `w`; both colliders have material `mat`.
fn scene(
    method: ContactMethod,
    mat: ContactMaterial,
    v: Vector3<f64>,
    w: Vector3<f64>,
) -> (System, BodyHandle, BodyHandle) {
    tilted_scene(method, mat, v, w, 0.0)
}

/// [`scene`] on an incline of angle `a` (gravity tilted about Y: downhill is +x).
fn tilted_scene(
    method: ContactMethod,
    mat: ContactMaterial,
    v: Vector3<f64>,
    w: Vector3<f64>,
    a: f64,
) -> (System, BodyHandle, BodyHandle) {
    let settings = SystemSettings {
        gravity: incline_gravity(a),
        envelope: if method == ContactMethod::Smc {
            0.0
        } else {
            0.1 * R
        },
        contact_method: method,
        smc: SmcSettings {
            model: SmcModel::Hertz,
            ..SmcSettings::default()
        },
        ..SystemSettings::default()
    };
    let mut sys = System::new(settings, tight_apgd(2000)).unwrap();
    let plate = add_ground(&mut sys, "plate", mat);
    let ball = sys
        .add_body(
            sphere(R, 2500.0, Vector3::new(0.0, 0.0, R), mat)
                .linear_velocity(v)
                .angular_velocity(w),
        )
        .unwrap();
    (sys, plate, ball)
}

fn step_size(sys: &System, method: ContactMethod) -> f64 {
    match method {
        ContactMethod::Nsc => 1e-3,
        ContactMethod::Smc => sys.smc_max_step().unwrap().0 / 5.0,
    }
}

/// Mean deceleration of the ball along x between `t0` and `t1` (s).
fn deceleration(sys: &mut System, ball: BodyHandle, h: f64, t0: f64, t1: f64) -> f64 {
    while sys.time() < t0 {
        sys.step(h).unwrap();
    }
    let (ta, va) = (sys.time(), sys.body(ball).unwrap().linear_velocity().x);
    while sys.time() < t1 {
        sys.step(h).unwrap();
    }
    let (tb, vb) = (sys.time(), sys.body(ball).unwrap().linear_velocity().x);
    (va - vb) / (tb - ta)
}

fn friction(mu: f64, mu_r: f64) -> ContactFriction {
    ContactFriction {
        friction: mu,
        rolling_friction: mu_r,
        spinning_friction: 0.0,
    }
}

#[test]
fn plate_friction_override_sets_the_sliding_deceleration() {
    // SMC only: NSC's cone complementarity lifts a ball sliding at 1 m/s off the plate at
    // `mu |v_t|` per step (the convex relaxation), so its mean deceleration is below `mu g`
    // (measured: 0.21 g at mu = 0.3); the incline test below checks NSC.
    let v0 = 1.0;
    let method = ContactMethod::Smc;
    // Ball and plate: mu = 0.1. Sliding lasts 2 v0 / (7 mu g) (97 ms at 0.3); measured from
    // 10 ms to 60 % of that.
    let mat = ContactMaterial::smc(1e7, 0.3, 0.5, 0.1);
    for (plate_mu, ball_mu, expect) in [
        (None, None, 0.1),
        (Some(0.3), None, 0.3),
        (Some(0.3), Some(0.2), 0.2),
    ] {
        let (mut sys, plate, ball) =
            scene(method, mat, Vector3::new(v0, 0.0, 0.0), Vector3::zeros());
        sys.set_contact_friction(plate, plate_mu.map(|m| friction(m, 0.0)))
            .unwrap();
        sys.set_contact_friction(ball, ball_mu.map(|m| friction(m, 0.0)))
            .unwrap();
        let h = step_size(&sys, method);
        let t1 = (0.6 * 2.0 * v0 / (7.0 * expect * g())).min(0.06);
        let a = deceleration(&mut sys, ball, h, 0.01, t1);
        assert!(
            (a - expect * g()).abs() < 0.02 * expect * g(),
            "plate {plate_mu:?}, ball {ball_mu:?}: deceleration {a} vs {}",
            expect * g()
        );
    }
}

#[test]
fn plate_friction_override_makes_a_slipping_ball_roll_on_an_incline_by_both_methods() {
    // tan a = 0.5: rolling needs mu >= 1/7. The materials have mu = 0.1 (the ball slips at
    // g (sin a - 0.1 cos a) = 0.358 g); the plate's override 0.3 makes it roll at
    // 5/7 g sin a = 0.319 g.
    let a = 0.5f64.atan();
    let (roll, slip) = (5.0 / 7.0 * g() * a.sin(), g() * (a.sin() - 0.1 * a.cos()));
    for method in [ContactMethod::Nsc, ContactMethod::Smc] {
        let mat = ContactMaterial::smc(1e7, 0.3, 0.5, 0.1);
        for (plate_mu, expect) in [(None, slip), (Some(0.3), roll)] {
            let (mut sys, plate, ball) =
                tilted_scene(method, mat, Vector3::zeros(), Vector3::zeros(), a);
            sys.set_contact_friction(plate, plate_mu.map(|m| friction(m, 0.0)))
                .unwrap();
            let h = step_size(&sys, method);
            let acc = -deceleration(&mut sys, ball, h, 0.02, 0.2);
            assert!(
                (acc - expect).abs() < 0.02 * expect,
                "{method:?}, plate {plate_mu:?}: acceleration {acc} vs {expect} (roll {roll}, slip {slip})"
            );
        }
    }
}

#[test]
fn plate_rolling_friction_override_sets_the_rolling_deceleration_by_both_methods() {
    let (v0, mu_r) = (0.5, 0.05);
    for method in [ContactMethod::Nsc, ContactMethod::Smc] {
        // The materials have no rolling resistance; the plate's override has mu_r.
        let mat = ContactMaterial::smc(1e7, 0.3, 0.5, 0.5);
        let (mut sys, plate, ball) = scene(
            method,
            mat,
            Vector3::new(v0, 0.0, 0.0),
            Vector3::new(0.0, v0 / R, 0.0),
        );
        sys.set_contact_friction(plate, Some(friction(0.5, mu_r)))
            .unwrap();
        assert_eq!(sys.contact_friction(plate), Some(friction(0.5, mu_r)));
        assert_eq!(sys.contact_friction(ball), None);
        let h = step_size(&sys, method);
        let a = deceleration(&mut sys, ball, h, 0.05, 0.35);
        let expect = 5.0 / 7.0 * mu_r * g();
        assert!(
            (a - expect).abs() < 0.05 * expect,
            "{method:?}: deceleration {a} vs {expect}"
        );
    }
}

#[test]
fn bad_friction_override_is_an_error_naming_the_field() {
    let mat = ContactMaterial::with_friction(0.5);
    let (mut sys, plate, _) = scene(ContactMethod::Nsc, mat, Vector3::zeros(), Vector3::zeros());
    let e = sys
        .set_contact_friction(plate, Some(friction(-0.3, 0.0)))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("contact_friction.friction") && e.contains("-0.3"),
        "{e}"
    );
    let e = sys
        .set_contact_friction(
            chrono_core::Bodies::from_bodies(vec![
                chrono_core::RigidBodyBuilder::fixed()
                    .build()
                    .unwrap();
                8
            ])
            .handle(7),
            Some(friction(0.3, 0.0)),
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("body") && e.contains('7'), "{e}");
}
