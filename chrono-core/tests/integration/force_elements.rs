//! Force elements (`chrono_core::force`) stepped by the system: spring-dampers against the
//! analytic oscillator, conservation laws, tables, both contact methods, bad input.

use crate::common::g;
use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::math::Vector3;
use chrono_core::{
    BodyHandle, ContactMethod, Curve, Extrapolation, RigidBodyBuilder, SpringDamper, System,
    SystemSettings,
};

fn system_with(settings: SystemSettings) -> System {
    let s = SolverSettings {
        tolerance: 1e-12,
        max_iterations: 500,
        record_history: false,
    };
    System::new(settings, Box::new(Apgd::new(s))).unwrap()
}

/// A fixed anchor at the origin and a point mass `m` hanging `l` below it.
fn hanging(settings: SystemSettings, m: f64, l: f64) -> (System, BodyHandle, BodyHandle) {
    let mut sys = system_with(settings);
    let anchor = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let bob = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .mass(m)
                .inertia_diagonal(Vector3::repeat(0.1))
                .position(Vector3::new(0.0, 0.0, -l)),
        )
        .unwrap();
    (sys, anchor, bob)
}

/// Times at which `z(t)` crosses `z0` upwards (linear interpolation).
fn up_crossings(ts: &[f64], zs: &[f64], z0: f64) -> Vec<f64> {
    let mut out = Vec::new();
    for i in 1..zs.len() {
        let (a, b) = (zs[i - 1] - z0, zs[i] - z0);
        if a < 0.0 && b >= 0.0 {
            out.push(ts[i - 1] + (ts[i] - ts[i - 1]) * a / (a - b));
        }
    }
    out
}

#[test]
fn undamped_spring_oscillates_at_the_natural_frequency_and_keeps_its_energy() {
    let (m, k, l0) = (2.0, 8000.0, 0.5);
    let (mut sys, anchor, bob) = hanging(SystemSettings::default(), m, l0);
    let spring = SpringDamper::linear(
        "s",
        anchor,
        Vector3::zeros(),
        bob,
        Vector3::new(0.0, 0.0, -l0),
        l0,
        k,
        0.0,
    );
    let hs = sys.add_force_element(Box::new(spring)).unwrap();
    // Released at the rest length: oscillates about l0 + m g / k with amplitude m g / k.
    let z_eq = -(l0 + m * g() / k);
    let h = 1e-4;
    let (mut ts, mut zs) = (Vec::new(), Vec::new());
    let energy = |sys: &System| {
        let b = sys.body(bob).unwrap();
        let x = -b.position().z - l0;
        0.5 * m * b.linear_velocity().norm_squared() + 0.5 * k * x * x + m * g() * b.position().z
    };
    let e0 = energy(&sys);
    let mut max_drift: f64 = 0.0;
    for _ in 0..20_000 {
        sys.step(h).unwrap();
        ts.push(sys.time());
        zs.push(sys.body(bob).unwrap().position().z);
        max_drift = max_drift.max((energy(&sys) - e0).abs());
    }
    let crossings = up_crossings(&ts, &zs, z_eq);
    assert!(crossings.len() >= 20, "{} crossings", crossings.len());
    let period = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    let exact = 2.0 * std::f64::consts::PI * (m / k).sqrt();
    assert!(
        (period - exact).abs() < 1e-3 * exact,
        "period {period} vs {exact}"
    );
    // Symplectic Euler: the energy oscillates by O(h omega) of the oscillation energy.
    let e_osc = 0.5 * k * (m * g() / k).powi(2);
    assert!(
        max_drift < 0.02 * e_osc,
        "energy drift {max_drift} of {e_osc}"
    );
    let s: &SpringDamper = sys.force_element(hs).unwrap();
    assert!((s.length() + zs[zs.len() - 2]).abs() < 1e-9);
}

#[test]
fn damped_spring_decays_at_the_analytic_rate_and_settles_at_the_static_deflection() {
    let (m, k, l0): (f64, f64, f64) = (3.0, 12000.0, 0.4);
    let zeta: f64 = 0.05;
    let c = 2.0 * zeta * (k * m).sqrt();
    let (mut sys, anchor, bob) = hanging(SystemSettings::default(), m, l0);
    sys.add_force_element(Box::new(SpringDamper::linear(
        "s",
        anchor,
        Vector3::zeros(),
        bob,
        Vector3::new(0.0, 0.0, -l0),
        l0,
        k,
        c,
    )))
    .unwrap();
    let z_eq = -(l0 + m * g() / k);
    let h = 1e-4;
    let (mut ts, mut zs) = (Vec::new(), Vec::new());
    for _ in 0..10_000 {
        sys.step(h).unwrap();
        ts.push(sys.time());
        zs.push(sys.body(bob).unwrap().position().z);
    }
    // Peaks of z - z_eq decay by exp(-zeta wn T_d) per period.
    let mut peaks = Vec::new();
    for i in 1..zs.len() - 1 {
        if zs[i] > zs[i - 1] && zs[i] >= zs[i + 1] {
            peaks.push(zs[i] - z_eq);
        }
    }
    assert!(peaks.len() >= 5);
    let wn = (k / m).sqrt();
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let expected = (-zeta * wn * 2.0 * std::f64::consts::PI / wd).exp();
    let ratio = peaks[4] / peaks[3];
    assert!(
        (ratio - expected).abs() < 0.01 * expected,
        "decay ratio {ratio} vs {expected}"
    );
    for _ in 0..40_000 {
        sys.step(h).unwrap();
    }
    let z = sys.body(bob).unwrap().position().z;
    assert!((z - z_eq).abs() < 1e-9, "rest {z} vs {z_eq}");
}

#[test]
fn a_table_with_free_travel_acts_as_a_bump_stop() {
    // Zero force within 5 cm of the rest length, then 1e5 N/m: the mass falls through the
    // free travel and rests where 1e5 (x - 0.05) = m g.
    let (m, l0) = (10.0, 0.3);
    let stop = Curve::new(
        "stop",
        vec![[-0.05, 0.0], [0.05, 0.0], [0.06, 1e3]],
        Extrapolation::Linear,
    )
    .unwrap();
    let (mut sys, anchor, bob) = hanging(SystemSettings::default(), m, l0);
    sys.add_force_element(Box::new(SpringDamper::new(
        "stop",
        anchor,
        Vector3::zeros(),
        bob,
        Vector3::new(0.0, 0.0, -l0),
        l0,
        stop,
        Curve::linear(200.0),
    )))
    .unwrap();
    for _ in 0..20_000 {
        sys.step(1e-4).unwrap();
    }
    let z = sys.body(bob).unwrap().position().z;
    let expected = -(l0 + 0.05 + m * g() / 1e5);
    assert!((z - expected).abs() < 1e-8, "{z} vs {expected}");
}

#[test]
fn a_spring_between_free_bodies_conserves_momentum_and_angular_momentum() {
    let settings = SystemSettings {
        gravity: Vector3::zeros(),
        ..SystemSettings::default()
    };
    let mut sys = system_with(settings);
    let a = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .mass(2.0)
                .inertia_diagonal(Vector3::new(0.1, 0.2, 0.3))
                .position(Vector3::new(0.0, 0.0, 0.0))
                .linear_velocity(Vector3::new(0.0, 1.0, 0.0))
                .angular_velocity(Vector3::new(0.3, -0.2, 1.0)),
        )
        .unwrap();
    let b = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .mass(5.0)
                .inertia_diagonal(Vector3::new(0.4, 0.2, 0.5))
                .position(Vector3::new(1.0, 0.2, 0.1))
                .linear_velocity(Vector3::new(0.5, -0.3, 0.2)),
        )
        .unwrap();
    // Off-center attachment points: the spring also twists both bodies.
    sys.add_force_element(Box::new(SpringDamper::linear(
        "s",
        a,
        Vector3::new(0.1, 0.05, 0.0),
        b,
        Vector3::new(0.9, 0.1, 0.2),
        0.6,
        300.0,
        4.0,
    )))
    .unwrap();
    let momenta = |sys: &System| {
        let mut p = Vector3::zeros();
        let mut l = Vector3::zeros();
        for h in [a, b] {
            let body = sys.body(h).unwrap();
            let pb = body.mass() * body.linear_velocity();
            p += pb;
            l += body.position().cross(&pb) + body.angular_momentum();
        }
        (p, l)
    };
    let (p0, l0) = momenta(&sys);
    for _ in 0..3000 {
        sys.step(1e-3).unwrap();
    }
    let (p1, l1) = momenta(&sys);
    assert!((p1 - p0).norm() < 1e-12, "momentum {p0} -> {p1}");
    // The force acts at the start-of-step points while the bodies move within the step, so
    // the moment of the pair is balanced to O(h) per step, not exactly.
    assert!(
        (l1 - l0).norm() < 1e-3 * l0.norm(),
        "angular momentum {l0} -> {l1}"
    );
    assert!(sys.body(a).unwrap().angular_velocity().norm() > 0.0);
}

#[test]
fn force_elements_act_in_smc_mode_too() {
    let settings = SystemSettings {
        contact_method: ContactMethod::Smc,
        ..SystemSettings::default()
    };
    let (m, k, l0) = (1.0, 500.0, 0.2);
    let (mut sys, anchor, bob) = hanging(settings, m, l0);
    sys.add_force_element(Box::new(SpringDamper::linear(
        "s",
        anchor,
        Vector3::zeros(),
        bob,
        Vector3::new(0.0, 0.0, -l0),
        l0,
        k,
        20.0,
    )))
    .unwrap();
    for _ in 0..20_000 {
        sys.step(1e-4).unwrap();
    }
    let z = sys.body(bob).unwrap().position().z;
    assert!((z + l0 + m * g() / k).abs() < 1e-9, "{z}");
}

#[test]
fn bad_spring_dampers_are_rejected_with_the_field() {
    let (mut sys, anchor, bob) = hanging(SystemSettings::default(), 1.0, 0.3);
    let e = sys
        .add_force_element(Box::new(SpringDamper::linear(
            "s",
            anchor,
            Vector3::zeros(),
            chrono_core::Bodies::from_bodies(vec![
                chrono_core::RigidBodyBuilder::fixed()
                    .build()
                    .unwrap();
                8
            ])
            .handle(7),
            Vector3::zeros(),
            0.3,
            1.0,
            0.0,
        )))
        .unwrap_err()
        .to_string();
    assert!(e.contains("body_b"), "{e}");
    let e = sys
        .add_force_element(Box::new(SpringDamper::linear(
            "s",
            anchor,
            Vector3::zeros(),
            bob,
            Vector3::zeros(),
            0.3,
            1.0,
            0.0,
        )))
        .unwrap_err()
        .to_string();
    assert!(e.contains("point_b") && e.contains("coincide"), "{e}");
    let e = sys
        .add_force_element(Box::new(SpringDamper::linear(
            "s",
            anchor,
            Vector3::zeros(),
            bob,
            Vector3::new(0.0, 0.0, -0.3),
            -1.0,
            1.0,
            0.0,
        )))
        .unwrap_err()
        .to_string();
    assert!(e.contains("rest_length"), "{e}");
}

#[test]
fn the_bump_damper_acts_only_outside_its_length_range() {
    // A mass moving at constant speed between two bodies without gravity: the damper force
    // is c v inside [l_min, l_max] and c_b v outside.
    let settings = SystemSettings {
        gravity: Vector3::zeros(),
        ..SystemSettings::default()
    };
    let mut sys = system_with(settings);
    let anchor = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let bob = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .mass(1e6)
                .inertia_diagonal(Vector3::repeat(1.0))
                .position(Vector3::new(0.0, 0.0, -0.5))
                .linear_velocity(Vector3::new(0.0, 0.0, -0.1)),
        )
        .unwrap();
    let shock = SpringDamper::new(
        "shock",
        anchor,
        Vector3::zeros(),
        bob,
        Vector3::new(0.0, 0.0, -0.5),
        0.5,
        Curve::constant(0.0),
        Curve::linear(100.0),
    )
    .with_bump_damper(0.4, 0.55, Curve::linear(1000.0));
    let hs = sys.add_force_element(Box::new(shock)).unwrap();
    let mut seen = (false, false);
    for _ in 0..1000 {
        sys.step(1e-3).unwrap();
        let s: &SpringDamper = sys.force_element(hs).unwrap();
        let expected = if s.length() > 0.55 { 1000.0 } else { 100.0 } * s.speed();
        assert!(
            (s.force() + expected).abs() < 1e-9,
            "{} vs {}",
            s.force(),
            -expected
        );
        if s.length() > 0.55 {
            seen.1 = true;
        } else {
            seen.0 = true;
        }
    }
    assert!(seen.0 && seen.1);
}
