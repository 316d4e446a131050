//! NSC rolling and spinning friction (six-row contacts, Tasora and Anitescu 2013) through the
//! public `System` API, against the rigid-body solutions of a solid sphere (`I = 2/5 m R^2`)
//! with a resisting torque of at most `mu_r R F_n` (rolling) or `mu_s R F_n` (spinning),
//! for both rolling models (`RollingModel::Relative`, the default, and `PerBody`, ten-row
//! contacts against each body's own rotation, Zhou et al. 1999).

use crate::common::{add_ground, g, incline_gravity, sphere, tight_apgd};
use chrono_core::math::{Isometry3, UnitQuaternion, Vector3};
use chrono_core::system::RollingModel;
use chrono_core::{BodyHandle, ContactMaterial, RigidBodyBuilder, Shape, System, SystemSettings};

const R: f64 = 0.05;
const H: f64 = 1e-3;

/// A system whose gravity is tilted by `angle` about Y (an incline of that angle with the
/// ground plane z = 0): the slope runs down along +x.
fn system(angle: f64) -> System {
    system_with(angle, RollingModel::Relative)
}

/// [`system`] with the rolling model `model`.
fn system_with(angle: f64, model: RollingModel) -> System {
    system_in(incline_gravity(angle), model)
}

/// A system with `gravity`, the rolling model `model` and a tight APGD solve.
fn system_in(gravity: Vector3<f64>, model: RollingModel) -> System {
    let settings = SystemSettings {
        gravity,
        rolling_model: model,
        ..SystemSettings::default()
    };
    System::new(settings, tight_apgd(2000)).unwrap()
}

fn scene(
    angle: f64,
    mat: ContactMaterial,
    v: Vector3<f64>,
    w: Vector3<f64>,
) -> (System, BodyHandle) {
    scene_with(RollingModel::Relative, angle, mat, v, w)
}

/// [`scene`] with the rolling model `model`.
fn scene_with(
    model: RollingModel,
    angle: f64,
    mat: ContactMaterial,
    v: Vector3<f64>,
    w: Vector3<f64>,
) -> (System, BodyHandle) {
    let mut sys = system_with(angle, model);
    add_ground(&mut sys, "ground", mat);
    let b = sys
        .add_body(
            sphere(R, 2500.0, Vector3::new(0.0, 0.0, R), mat)
                .rotation(UnitQuaternion::from_euler_angles(0.3, 0.2, -0.4))
                .linear_velocity(v)
                .angular_velocity(w),
        )
        .unwrap();
    (sys, b)
}

fn run(sys: &mut System, t: f64) {
    for _ in 0..(t / H).round() as usize {
        sys.step(H).unwrap();
    }
}

/// World angular velocity of the ball (the body is rotated, so body and world frames
/// differ).
fn omega_world(sys: &System, b: BodyHandle) -> Vector3<f64> {
    sys.body(b).unwrap().angular_velocity()
}

#[test]
fn rolling_resistance_decelerates_a_rolling_sphere_at_five_sevenths_mu_r_g_by_both_models() {
    let (mu_r, v0) = (0.05, 1.0);
    let mat = ContactMaterial::with_friction(0.5).with_rolling_friction(mu_r);
    // Rolling without slip about world Y.
    let w_roll = Vector3::new(0.0, v0 / R, 0.0);
    // Against a fixed plane a body's own rotation is the relative rotation: both models
    // decelerate alike (different rows, the same solution).
    let mut end = Vec::new();
    for (model, rows) in [(RollingModel::Relative, 6), (RollingModel::PerBody, 10)] {
        let (mut sys, b) = scene_with(model, 0.0, mat, Vector3::new(v0, 0.0, 0.0), w_roll);
        run(&mut sys, 0.05);
        let (t0, v1) = (sys.time(), sys.body(b).unwrap().linear_velocity().x);
        run(&mut sys, 0.5);
        let (t1, v2) = (sys.time(), sys.body(b).unwrap().linear_velocity().x);
        let a = (v1 - v2) / (t1 - t0);
        let expect = 5.0 / 7.0 * mu_r * g();
        assert!(
            (a - expect).abs() < 0.02 * expect,
            "{model:?}: deceleration {a} vs {expect}"
        );
        // Still rolling without slip.
        let w = omega_world(&sys, b);
        assert!(
            (w.y * R - v2).abs() < 1e-3 * v0,
            "{model:?}: slip: {} vs {v2}",
            w.y * R
        );
        assert_eq!(sys.last_problem().n_rows(), rows, "{model:?}");
        end.push(v2);
    }
    assert!((end[0] - end[1]).abs() < 1e-6, "the models differ: {end:?}");
    // Without rolling friction it keeps its speed.
    let (mut free, bf) = scene(
        0.0,
        ContactMaterial::with_friction(0.5),
        Vector3::new(v0, 0.0, 0.0),
        w_roll,
    );
    run(&mut free, 0.5);
    let vf = free.body(bf).unwrap().linear_velocity().x;
    assert!((vf - v0).abs() < 1e-6, "free rolling speed {vf}");
}

#[test]
fn rolling_friction_holds_a_sphere_on_a_slope_below_mu_r_and_not_above() {
    let mu_r = 0.1;
    let mat = ContactMaterial::with_friction(0.8).with_rolling_friction(mu_r);
    // tan(0.08) = 0.080 < mu_r: at rest.
    let (mut sys, b) = scene(0.08, mat, Vector3::zeros(), Vector3::zeros());
    run(&mut sys, 1.0);
    let body = sys.body(b).unwrap();
    assert!(
        body.linear_velocity().norm() < 1e-6,
        "v = {}",
        body.linear_velocity()
    );
    assert!(body.position().x.abs() < 1e-5, "x = {}", body.position().x);
    // The torque impulse is warm-started: a resting step needs (almost) no iteration.
    let warm = sys.step(H).unwrap().solve.iterations;
    let mut settings = sys.settings().clone();
    settings.warm_start = false;
    sys.set_settings(settings).unwrap();
    let cold = sys.step(H).unwrap().solve.iterations;
    assert!(
        4 * warm <= cold,
        "warm start: {warm} iterations, cold {cold}"
    );
    // tan(0.2) = 0.203 > mu_r: rolls down at a = 5/7 g (sin a - mu_r cos a).
    let angle: f64 = 0.2;
    let (mut sys, b) = scene(angle, mat, Vector3::zeros(), Vector3::zeros());
    run(&mut sys, 0.05);
    let (t0, v1) = (sys.time(), sys.body(b).unwrap().linear_velocity().x);
    run(&mut sys, 0.5);
    let (t1, v2) = (sys.time(), sys.body(b).unwrap().linear_velocity().x);
    let a = (v2 - v1) / (t1 - t0);
    let expect = 5.0 / 7.0 * g() * (angle.sin() - mu_r * angle.cos());
    assert!(
        (a - expect).abs() < 0.02 * expect,
        "acceleration {a} vs {expect}"
    );
}

/// The rate (rad/s^2) at which the ball's spin about world Z falls between 0.05 and
/// 0.25 s.
fn spin_down_rate(sys: &mut System, b: BodyHandle) -> f64 {
    run(sys, 0.05);
    let (t0, w1) = (sys.time(), omega_world(sys, b).z);
    run(sys, 0.2);
    let (t1, w2) = (sys.time(), omega_world(sys, b).z);
    (w1 - w2) / (t1 - t0)
}

#[test]
fn spinning_friction_stops_a_spinning_sphere_at_five_halves_mu_s_g_over_r() {
    let (mu_s, w0) = (0.02, 20.0);
    let mat = ContactMaterial::with_friction(0.5).with_spinning_friction(mu_s);
    let (mut sys, b) = scene(0.0, mat, Vector3::zeros(), Vector3::new(0.0, 0.0, w0));
    let alpha = spin_down_rate(&mut sys, b);
    // I dw/dt = -mu_s R m g with I = 2/5 m R^2.
    let expect = 2.5 * mu_s * g() / R;
    assert!(
        (alpha - expect).abs() < 0.02 * expect,
        "spin-down {alpha} vs {expect}"
    );
    // It stops and stays stopped (the torque does not reverse the spin).
    // Stops at t = w0 / alpha ~ 2.0 s.
    run(&mut sys, 2.5);
    let w = omega_world(&sys, b);
    let v = sys.body(b).unwrap().linear_velocity();
    assert!(w.norm() < 1e-6 && v.norm() < 1e-6, "w = {w:?}, v = {v:?}");
}

#[test]
fn a_box_on_the_ground_keeps_plain_triplets() {
    // Flat contacts have no curvature radius: rolling friction does not apply, no error.
    let mat = ContactMaterial::with_friction(0.5).with_rolling_friction(0.1);
    let mut sys = system(0.0);
    add_ground(&mut sys, "ground", mat);
    let s = Shape::Box {
        half_extents: Vector3::new(0.1, 0.1, 0.1),
    };
    let b = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .mass_from_shape(&s, 1000.0)
                .unwrap()
                .position(Vector3::new(0.0, 0.0, 0.1))
                .collider(s, Isometry3::identity(), mat),
        )
        .unwrap();
    run(&mut sys, 0.1);
    assert!(sys.body(b).unwrap().linear_velocity().norm() < 1e-6);
    let p = sys.last_problem();
    assert_eq!(p.n_rows(), 12, "four corner triplets");
}

#[test]
fn per_body_rolling_stops_a_spin_about_the_normal_at_five_halves_mu_r_g_over_r() {
    // Zhou's torque opposes the body's whole angular velocity, its normal part included:
    // without spinning friction the relative model leaves the spin alone, the per-body
    // model stops it at I dw/dt = -mu_r R m g.
    let (mu_r, w0) = (0.02, 20.0);
    let mat = ContactMaterial::with_friction(0.5).with_rolling_friction(mu_r);
    let spin = Vector3::new(0.0, 0.0, w0);
    let (mut rel, b) = scene_with(RollingModel::Relative, 0.0, mat, Vector3::zeros(), spin);
    run(&mut rel, 0.25);
    let w = omega_world(&rel, b).z;
    assert!((w - w0).abs() < 1e-6 * w0, "relative model: spin {w}");
    let (mut sys, b) = scene_with(RollingModel::PerBody, 0.0, mat, Vector3::zeros(), spin);
    let alpha = spin_down_rate(&mut sys, b);
    let expect = 2.5 * mu_r * g() / R;
    assert!(
        (alpha - expect).abs() < 0.02 * expect,
        "spin-down {alpha} vs {expect}"
    );
}

/// Two spheres in zero gravity approach along x at `v` each, both spinning at `w0` about
/// z, frictionless but with rolling friction `mu_r`: the spin of each after the impact.
fn spins_after_a_head_on_impact(model: RollingModel, mu_r: f64, v: f64, w0: f64) -> [f64; 2] {
    let mut sys = system_in(Vector3::zeros(), model);
    let mat = ContactMaterial::with_friction(0.0).with_rolling_friction(mu_r);
    let spin = Vector3::new(0.0, 0.0, w0);
    let mut ball = |x: f64, vx: f64| {
        sys.add_body(
            sphere(R, 2500.0, Vector3::new(x, 0.0, 0.0), mat)
                .linear_velocity(Vector3::new(vx, 0.0, 0.0))
                .angular_velocity(spin),
        )
        .unwrap()
    };
    let (a, b) = (ball(-1.5 * R, v), ball(1.5 * R, -v));
    // They meet after (R / 2) / v and stop against each other (NSC impacts are plastic).
    run(&mut sys, 0.5 * R / v + 0.05);
    let va = sys.body(a).unwrap().linear_velocity().x;
    assert!(
        va.abs() < 1e-6,
        "{model:?}: not at rest after the impact, v = {va}"
    );
    [omega_world(&sys, a).z, omega_world(&sys, b).z]
}

#[test]
fn per_body_rolling_resists_two_spheres_turning_together_and_the_relative_model_does_not() {
    let (mu_r, v, w0) = (0.1, 0.1, 1.0);
    // Relative: omega_B - omega_A = 0, no resistance.
    let rel = spins_after_a_head_on_impact(RollingModel::Relative, mu_r, v, w0);
    assert!(rel.iter().all(|w| (w - w0).abs() < 1e-9), "{rel:?}");
    // Per body: the impact's normal impulse m v bounds each torque impulse by
    // mu_r (R / 2) m v (effective radius R / 2), so each spin drops by
    // mu_r (R / 2) m v / (2/5 m R^2) = 1.25 mu_r v / R (0.25 rad/s here, < w0).
    let pb = spins_after_a_head_on_impact(RollingModel::PerBody, mu_r, v, w0);
    let expect = w0 - 1.25 * mu_r * v / R;
    for w in pb {
        assert!(
            (w - expect).abs() < 0.01 * (w0 - expect),
            "{pb:?} vs {expect}"
        );
    }
}

/// NSC has no rolling spring: `RollingModel::Spring` (SMC's type C) gets the relative rows,
/// bit for bit, on a sphere rolling, slowing and spinning on an incline.
#[test]
fn nsc_treats_the_rolling_spring_as_the_relative_rows() {
    let mat = ContactMaterial::with_friction(0.6)
        .with_rolling_friction(0.05)
        .with_spinning_friction(0.02);
    let (v, w) = (Vector3::new(0.3, 0.1, 0.0), Vector3::new(-1.0, 6.0, 4.0));
    let run = |model| {
        let (mut sys, b) = scene_with(model, 0.02, mat, v, w);
        for _ in 0..200 {
            sys.step(H).unwrap();
        }
        let body = sys.body(b).unwrap();
        (
            body.position(),
            body.linear_velocity(),
            body.angular_velocity(),
        )
    };
    let relative = run(RollingModel::Relative);
    assert_eq!(relative, run(RollingModel::Spring));
    // and the spin and roll were resisted (the test is not about a body at rest)
    assert!(relative.2.norm() > 0.1 && relative.2.norm() < w.norm());
}
