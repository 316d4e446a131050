//! SMC (penalty) contact through the public `System` API, against analytic results.

use crate::common::{add_ground, sphere};
use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::contact::smc::{RollingModel, SmcPair, contact_duration};
use chrono_core::material::effective_young_modulus;
use chrono_core::math::Vector3;
use chrono_core::system::{ContactMethod, SmcModel, SmcSettings};
use chrono_core::{BodyHandle, ContactMaterial, System, SystemSettings};

fn smc_system(model: SmcModel, gravity: f64) -> System {
    let settings = SystemSettings {
        gravity: Vector3::new(0.0, 0.0, -gravity),
        envelope: 0.0,
        contact_method: ContactMethod::Smc,
        smc: SmcSettings {
            model,
            ..SmcSettings::default()
        },
        ..SystemSettings::default()
    };
    System::new(settings, Box::new(Apgd::new(SolverSettings::default()))).unwrap()
}

fn plate(sys: &mut System, mat: ContactMaterial) {
    add_ground(sys, "plate", mat);
}

fn ball(sys: &mut System, r: f64, z: f64, v: Vector3<f64>, mat: ContactMaterial) -> BodyHandle {
    sys.add_body(sphere(r, 2500.0, Vector3::new(0.0, 0.0, z), mat).linear_velocity(v))
        .unwrap()
}

#[test]
fn elastic_hertz_impact_has_hertz_contact_time_and_keeps_energy() {
    let (r, v) = (0.01, 0.5);
    let mat = ContactMaterial::smc(1e7, 0.3, 1.0, 0.0);
    let mut sys = smc_system(SmcModel::Hertz, 0.0);
    plate(&mut sys, mat);
    let b = ball(&mut sys, r, r + 1e-6, Vector3::new(0.0, 0.0, -v), mat);
    let m = sys.body(b).unwrap().mass();
    let pair = SmcPair {
        radius: r,
        mass: m,
        inertia: 0.0,
        rolling_inertia: 0.0,
        young: effective_young_modulus(&mat, &mat),
        shear: 0.0,
        alpha: 0.0,
        friction: 0.0,
        rolling_friction: 0.0,
        spinning_friction: 0.0,
        rolling_model: RollingModel::Relative,
        rolling_damping: 0.0,
    };
    let tc = contact_duration(SmcModel::Hertz, &pair, v);
    let h = tc / 1000.0;
    let (mut touching, mut max_overlap) = (0u32, 0.0f64);
    for _ in 0..3000 {
        sys.step(h).unwrap();
        let z = sys.body(b).unwrap().position().z;
        if z < r {
            touching += 1;
            max_overlap = max_overlap.max(r - z);
        } else if touching > 0 {
            break;
        }
    }
    let t_meas = touching as f64 * h;
    assert!(
        (t_meas - tc).abs() < 0.01 * tc,
        "contact time {t_meas} vs {tc}"
    );
    // Maximum overlap (15 m v^2 / (16 E* sqrt R))^(2/5).
    let dmax = (15.0 * m * v * v / (16.0 * pair.young * r.sqrt())).powf(0.4);
    assert!(
        (max_overlap - dmax).abs() < 0.01 * dmax,
        "{max_overlap} vs {dmax}"
    );
    let vz = sys.body(b).unwrap().linear_velocity().z;
    assert!((vz - v).abs() < 1e-3 * v, "rebound speed {vz}");
}

#[test]
fn too_large_step_is_an_error_naming_the_body() {
    let mat = ContactMaterial::smc(1e9, 0.3, 0.5, 0.5);
    let mut sys = smc_system(SmcModel::Hertz, crate::common::g());
    plate(&mut sys, mat);
    ball(&mut sys, 0.001, 0.01, Vector3::zeros(), mat);
    let (hmax, body) = sys.smc_max_step().unwrap();
    assert_eq!(body, sys.body_handles().nth(1).unwrap());
    let e = sys.step(2.0 * hmax).unwrap_err().to_string();
    assert!(e.contains("body 1") && e.contains("\"ball\""), "{e}");
    assert!(sys.step(0.5 * hmax).is_ok());
}

/// A sphere launched sliding without spin on a plate: friction `mu m g` decelerates it and
/// spins it up until it rolls, at `v = 5/7 v0` (solid sphere), after `t = 2 v0 / (7 mu g)`.
#[test]
fn sliding_sphere_starts_rolling_at_five_sevenths() {
    for model in [SmcModel::Hooke, SmcModel::Hertz] {
        let (r, v0, mu, g) = (0.01, 1.0, 0.3, crate::common::g());
        let mat = ContactMaterial::smc(1e7, 0.3, 0.5, mu);
        let mut sys = smc_system(model, g);
        plate(&mut sys, mat);
        let b = ball(&mut sys, r, r, Vector3::new(v0, 0.0, 0.0), mat);
        let h = sys.smc_max_step().unwrap().0 / 5.0;
        let t_roll = 2.0 * v0 / (7.0 * mu * g);
        let n = (1.5 * t_roll / h) as usize;
        for _ in 0..n {
            sys.step(h).unwrap();
        }
        let body = sys.body(b).unwrap();
        let vx = body.linear_velocity().x;
        let wy = body.angular_velocity().y;
        assert!(
            (vx - 5.0 / 7.0 * v0).abs() < 0.01 * v0,
            "{model:?}: vx {vx}"
        );
        assert!(
            (wy * r - vx).abs() < 0.01 * v0,
            "{model:?}: rolls: {} vs {vx}",
            wy * r
        );
    }
}

/// A rolling sphere with rolling resistance `mu_r`: the torque `mu_r R m g` decelerates
/// it at `a = 5/7 mu_r g` (solid sphere, rolling without slip).
#[test]
fn rolling_resistance_decelerates_at_five_sevenths_mu_r_g() {
    let (r, v0, mu_r, g) = (0.01, 0.5, 0.05, crate::common::g());
    let mat = ContactMaterial::smc(1e7, 0.3, 0.5, 0.5).with_rolling_friction(mu_r);
    let mut sys = smc_system(SmcModel::Hertz, g);
    plate(&mut sys, mat);
    let b = sys
        .add_body(
            sphere(r, 2500.0, Vector3::new(0.0, 0.0, r), mat)
                .linear_velocity(Vector3::new(v0, 0.0, 0.0))
                .angular_velocity(Vector3::new(0.0, v0 / r, 0.0)),
        )
        .unwrap();
    let h = sys.smc_max_step().unwrap().0 / 5.0;
    // Let the contact settle, then measure over 0.3 s.
    let n0 = (0.05 / h) as usize;
    for _ in 0..n0 {
        sys.step(h).unwrap();
    }
    let (t0, v1) = (sys.time(), sys.body(b).unwrap().linear_velocity().x);
    let n1 = (0.3 / h) as usize;
    for _ in 0..n1 {
        sys.step(h).unwrap();
    }
    let (t1, v2) = (sys.time(), sys.body(b).unwrap().linear_velocity().x);
    let a = (v1 - v2) / (t1 - t0);
    let expect = 5.0 / 7.0 * mu_r * g;
    assert!(
        (a - expect).abs() < 0.05 * expect,
        "deceleration {a} vs {expect}"
    );
}

/// The rolling resistance's limiter (`|M_r| <= I |w_r| / h`) makes it a viscous torque
/// below its cap, so it cannot hold a static moment: a sphere on a slope with `tan(theta)
/// < mu_r` (which the rigid-limit model, NSC's rolling rows, holds at rest) rolls down
/// steadily at the fixed point `M_r = m g sin(theta) R = I w / h`, i.e. `v = w R = 5/2 g
/// sin(theta) h`: a creep proportional to the step (docs/validation-vehicle.md, "Small
/// grains in lanes"; under a loaded tire the moment, and the creep, are hundreds of times
/// larger).
#[test]
fn rolling_resistance_below_its_cap_creeps_at_five_halves_g_sin_theta_h() {
    let (r, mu_r, g, theta) = (0.01, 0.1, crate::common::g(), 0.05_f64);
    let mat = ContactMaterial::smc(1e7, 0.3, 0.8, 0.5).with_rolling_friction(mu_r);
    let mut speeds = Vec::new();
    let mut steps = Vec::new();
    for divide in [5.0, 10.0] {
        let settings = SystemSettings {
            gravity: Vector3::new(g * theta.sin(), 0.0, -g * theta.cos()),
            envelope: 0.0,
            contact_method: ContactMethod::Smc,
            ..SystemSettings::default()
        };
        let mut sys =
            System::new(settings, Box::new(Apgd::new(SolverSettings::default()))).unwrap();
        plate(&mut sys, mat);
        let b = ball(&mut sys, r, r, Vector3::zeros(), mat);
        let h = sys.smc_max_step().unwrap().0 / divide;
        for _ in 0..(0.05 / h) as usize {
            sys.step(h).unwrap();
        }
        let x0 = sys.body(b).unwrap().position().x;
        let t0 = sys.time();
        for _ in 0..(0.2 / h) as usize {
            sys.step(h).unwrap();
        }
        let v = (sys.body(b).unwrap().position().x - x0) / (sys.time() - t0);
        let expect = 2.5 * g * theta.sin() * h;
        assert!(
            (v - expect).abs() < 0.05 * expect,
            "h = {h}: creep {v} m/s vs {expect}"
        );
        speeds.push(v);
        steps.push(h);
    }
    // Proportional to the step.
    let ratio = speeds[1] / speeds[0];
    assert!(
        (ratio - steps[1] / steps[0]).abs() < 0.05,
        "creep ratio {ratio} for a step ratio {}",
        steps[1] / steps[0]
    );
}

/// A sphere on a plane tilted by `theta` with rolling friction `mu_r` under `model`, stepped
/// at the SMC step limit over `divide`: its mean speed (m/s) and mean acceleration (m/s^2)
/// down the slope over 0.2 s after `settle` s.
fn rolling_speed_on_a_slope(
    model: RollingModel,
    theta: f64,
    mu_r: f64,
    divide: f64,
    settle: f64,
) -> (f64, f64) {
    let (r, g) = (0.01, crate::common::g());
    let mat = ContactMaterial::smc(1e7, 0.3, 0.8, 0.5).with_rolling_friction(mu_r);
    let settings = SystemSettings {
        gravity: Vector3::new(g * theta.sin(), 0.0, -g * theta.cos()),
        envelope: 0.0,
        contact_method: ContactMethod::Smc,
        rolling_model: model,
        ..SystemSettings::default()
    };
    let mut sys = System::new(settings, Box::new(Apgd::new(SolverSettings::default()))).unwrap();
    plate(&mut sys, mat);
    let b = ball(&mut sys, r, r, Vector3::zeros(), mat);
    let h = sys.smc_max_step().unwrap().0 / divide;
    for _ in 0..(settle / h) as usize {
        sys.step(h).unwrap();
    }
    let (x0, v0, t0) = {
        let body = sys.body(b).unwrap();
        (body.position().x, body.linear_velocity().x, sys.time())
    };
    for _ in 0..(0.2 / h) as usize {
        sys.step(h).unwrap();
    }
    let body = sys.body(b).unwrap();
    let dt = sys.time() - t0;
    (
        (body.position().x - x0) / dt,
        (body.linear_velocity().x - v0) / dt,
    )
}

/// The elastic-plastic rolling spring (Ai et al. 2011, type C) holds a sphere on a slope
/// gentler than its rolling resistance (`tan(theta) < mu_r`) at every step, where the
/// limited model creeps at `5/2 g sin(theta) h`; on a steeper slope both roll with
/// `a = 5/7 g (sin(theta) - mu_r cos(theta))` (rolling without slip, `I = 2/5 m r^2`).
/// The spring's rocking mode (`sqrt(k_r / I_r)` ~ 90 rad/s here, damping ratio 0.3) has
/// died out after 0.5 s.
#[test]
fn the_rolling_spring_holds_a_gentle_slope_and_rolls_down_a_steep_one() {
    let (mu_r, g) = (0.1, crate::common::g());
    let gentle = 0.05_f64;
    for divide in [5.0, 10.0] {
        let (v, _) = rolling_speed_on_a_slope(RollingModel::Spring, gentle, mu_r, divide, 0.5);
        let (creep, _) =
            rolling_speed_on_a_slope(RollingModel::Relative, gentle, mu_r, divide, 0.05);
        assert!(
            v.abs() < 1e-3 * creep,
            "spring: {v} m/s on a slope it should hold (the limiter creeps at {creep})"
        );
    }
    let steep = 0.2_f64;
    let expect = 5.0 / 7.0 * g * (steep.sin() - mu_r * steep.cos());
    for model in [RollingModel::Spring, RollingModel::Relative] {
        let (_, a) = rolling_speed_on_a_slope(model, steep, mu_r, 5.0, 0.05);
        assert!(
            (a - expect).abs() < 0.01 * expect,
            "{model:?}: acceleration {a} m/s^2 vs {expect}"
        );
    }
}

/// A 1 cm box on the ground with the rolling spring: its four corner contacts are flat
/// (`R` = `flat_contact_radius`, 1 m), where the uncapped spring's rocking mode (`omega_r h`
/// ~ 7 at the SMC step limit) would blow the box up; the step's cap on `k_r` keeps it at
/// rest (checked to fail without the cap).
#[test]
fn a_small_box_rests_on_flat_rolling_springs() {
    let mat = ContactMaterial::smc(1e7, 0.3, 0.5, 0.3).with_rolling_friction(0.3);
    let settings = SystemSettings {
        gravity: Vector3::new(0.0, 0.0, -crate::common::g()),
        envelope: 0.0,
        contact_method: ContactMethod::Smc,
        rolling_model: RollingModel::Spring,
        ..SystemSettings::default()
    };
    let mut sys = System::new(settings, Box::new(Apgd::new(SolverSettings::default()))).unwrap();
    plate(&mut sys, mat);
    let shape = chrono_core::Shape::Box {
        half_extents: Vector3::new(0.005, 0.005, 0.005),
    };
    let b = sys
        .add_body(
            chrono_core::RigidBodyBuilder::dynamic()
                .name("box")
                .mass_from_shape(&shape, 1000.0)
                .unwrap()
                .position(Vector3::new(0.0, 0.0, 0.005))
                // a rocking disturbance
                .angular_velocity(Vector3::new(0.3, -0.2, 0.0))
                .collider(shape, Default::default(), mat),
        )
        .unwrap();
    let h = sys.smc_max_step().unwrap().0;
    for _ in 0..(0.3 / h) as usize {
        sys.step(h).unwrap();
    }
    let body = sys.body(b).unwrap();
    let (v, w) = (
        body.linear_velocity().norm(),
        body.angular_velocity().norm(),
    );
    assert!(
        v < 1e-3 && w < 1e-2,
        "box at {v} m/s, {w} rad/s after 0.3 s"
    );
    assert!((body.position().z - 0.005).abs() < 1e-4);
}

#[test]
fn smc_runs_are_deterministic() {
    let run = || {
        let mat = ContactMaterial::smc(1e7, 0.3, 0.5, 0.5);
        let mut sys = smc_system(SmcModel::Hertz, crate::common::g());
        plate(&mut sys, mat);
        for k in 0..30 {
            let x = (k % 5) as f64 * 0.021 + 0.001 * (k as f64).sin();
            let z = 0.01 + (k / 5) as f64 * 0.021;
            sys.add_body(sphere(
                0.01,
                2500.0,
                Vector3::new(x, 0.001 * k as f64, z),
                mat,
            ))
            .unwrap();
        }
        let h = sys.smc_max_step().unwrap().0;
        for _ in 0..500 {
            sys.step(h).unwrap();
        }
        sys.bodies()
            .iter()
            .map(|b| b.position())
            .collect::<Vec<_>>()
    };
    assert_eq!(run(), run());
}

/// The SMC step keeps the collision poses of its fused body pass for the next step: a body
/// moved with `body_mut` between steps must still be seen (many grains: the parallel path).
#[test]
fn body_moved_between_smc_steps_is_collided_where_it_was_put() {
    let mat = ContactMaterial::smc(1e7, 0.3, 0.5, 0.3);
    let mut sys = smc_system(SmcModel::Hertz, 0.0);
    let r = 0.01;
    let grains: Vec<BodyHandle> = (0..1200)
        .map(|i| {
            let p = Vector3::new(3.0 * r * (i % 40) as f64, 3.0 * r * (i / 40) as f64, 0.0);
            sys.add_body(sphere(r, 2500.0, p, mat)).unwrap()
        })
        .collect();
    sys.step(1e-5).unwrap();
    assert!(sys.smc_contacts().is_empty());
    // Put grain 1 half a radius into grain 0.
    let x0 = sys.body(grains[0]).unwrap().position();
    let rot = sys.body(grains[1]).unwrap().rotation();
    (sys.body_mut(grains[1]).unwrap())
        .set_pose(x0 + Vector3::new(1.5 * r, 0.0, 0.0), rot)
        .unwrap();
    sys.step(1e-5).unwrap();
    let c = sys.smc_contacts();
    assert_eq!(c.len(), 1);
    assert_eq!(
        (
            c[0].owner_a.min(c[0].owner_b),
            c[0].owner_a.max(c[0].owner_b)
        ),
        (0, 1)
    );
    assert!((c[0].overlap - 0.5 * r).abs() < 1e-9);
}
