//! Tests of [`crate::jeffery`]: the reference orbit, the orbit fit, bad input and the
//! scene's start.

use std::f64::consts::PI;

use chrono_ccp::Psor;

use crate::jeffery::*;

#[test]
fn the_orbit_is_jefferys() {
    let (r, gamma) = (2.5, 0.7);
    let t_p = jeffery_period(r, gamma);
    assert!((t_p - 2.0 * PI / gamma * (r + 1.0 / r)).abs() < 1e-12);
    // tan theta = tan(psi) / r, quarter and half periods, and continuity
    for k in 0..200 {
        let t = k as f64 * t_p / 137.0;
        let th = jeffery_angle(t, t_p, r);
        let psi = 2.0 * PI * t / t_p;
        let d = (th.sin() * psi.cos() * r - th.cos() * psi.sin()).abs();
        assert!(d < 1e-12, "t {t}: {d}");
        // d theta / dt = gamma (cos^2 + r^2 sin^2) / (r^2 + 1)
        let e = 1e-6 * t_p;
        let rate = (jeffery_angle(t + e, t_p, r) - jeffery_angle(t - e, t_p, r)) / (2.0 * e);
        let exact = gamma * (th.cos().powi(2) + r * r * th.sin().powi(2)) / (r * r + 1.0);
        assert!(
            (rate / exact - 1.0).abs() < 1e-7,
            "t {t}: {rate} vs {exact}"
        );
    }
    assert!((jeffery_angle(0.25 * t_p, t_p, r) - 0.5 * PI).abs() < 1e-12);
    assert!((jeffery_angle(0.5 * t_p, t_p, r) - PI).abs() < 1e-12);
    assert!((jeffery_angle(t_p, t_p, r) - 2.0 * PI).abs() < 1e-12);
    // a sphere turns with half the vorticity
    assert!((jeffery_angle(1.0, jeffery_period(1.0, gamma), 1.0) - 0.5 * gamma).abs() < 1e-12);
}

/// A synthetic record of `theta(t - t0)` over `[0, span_t]`, plus `wiggle` (rad) at a
/// frequency unrelated to the orbit.
fn record(t_p: f64, r: f64, t0: f64, span_t: f64, wiggle: f64) -> (Vec<f64>, Vec<f64>) {
    let n = 300;
    let t: Vec<f64> = (0..n).map(|i| span_t * i as f64 / (n - 1) as f64).collect();
    let th = t
        .iter()
        .map(|&ti| jeffery_angle(ti - t0, t_p, r) + wiggle * (37.0 * ti / t_p).sin())
        .collect();
    (t, th)
}

#[test]
fn the_fit_recovers_a_synthetic_orbit() {
    let (t_p, r, t0) = (15.7, 2.3, 0.04);
    // a quarter-and-a-bit orbit, from guesses 25 % off
    let (t, th) = record(t_p, r, t0, 0.3 * t_p, 0.0);
    let f = fit_jeffery_orbit(&t, &th, 1.25 * t_p, 0.8 * r, true).unwrap();
    assert_eq!(f.parameters, 3);
    assert!((f.period / t_p - 1.0).abs() < 1e-8, "{f:?}");
    assert!((f.aspect_ratio / r - 1.0).abs() < 1e-8, "{f:?}");
    assert!((f.t0 - t0).abs() < 1e-8 * t_p, "{f:?}");
    assert!(f.residual < 1e-9, "{f:?}");
    // with a 0.01 rad wiggle on top: the period within 0.5 %, the residual the wiggle's rms
    let (t, th) = record(t_p, r, t0, 0.3 * t_p, 0.01);
    let f = fit_jeffery_orbit(&t, &th, t_p * 0.8, r * 1.2, true).unwrap();
    assert!((f.period / t_p - 1.0).abs() < 5e-3, "{f:?}");
    assert!((f.residual - 0.01 / 2f64.sqrt()).abs() < 2e-3, "{f:?}");
    // a short record (an eighth of the orbit, 0.25 rad at r = 2.3): r held, T from the
    // starting rate; exact when r is right
    let (t, th) = record(t_p, r, t0, 0.125 * t_p, 0.0);
    let f = fit_jeffery_orbit(&t, &th, 1.2 * t_p, r, true).unwrap();
    assert_eq!(f.parameters, 2);
    assert_eq!(f.aspect_ratio, r);
    assert!((f.period / t_p - 1.0).abs() < 1e-8, "{f:?}");
    // and a wrong period guess alone cannot fit a record of another period
    let (t, th) = record(t_p, r, t0, 0.3 * t_p, 0.0);
    let f = fit_jeffery_orbit(&t, &th, t_p, r, false).unwrap();
    assert!((f.period / t_p - 1.0).abs() < 1e-8);
    let (t, th) = record(1.1 * t_p, r, t0, 0.3 * t_p, 0.0);
    let f = fit_jeffery_orbit(&t, &th, t_p, r, true).unwrap();
    assert!((f.period / (1.1 * t_p) - 1.0).abs() < 1e-8, "{f:?}");
}

#[test]
fn a_record_without_an_orbit_is_refused() {
    let t: Vec<f64> = (0..20).map(|i| i as f64).collect();
    let flat = vec![0.3; 20];
    let e = fit_jeffery_orbit(&t, &flat, 10.0, 2.0, true).unwrap_err();
    assert!(e.to_string().contains("record"), "{e}");
    let e = fit_jeffery_orbit(&t[..5], &flat[..5], 10.0, 2.0, true).unwrap_err();
    assert!(e.to_string().contains("record"), "{e}");
    let mut back = t.clone();
    back[3] = 1.0;
    let th: Vec<f64> = t.iter().map(|x| 0.1 * x).collect();
    let e = fit_jeffery_orbit(&back, &th, 10.0, 2.0, true).unwrap_err();
    assert!(e.to_string().contains("record"), "{e}");
    let e = fit_jeffery_orbit(&t, &th, -1.0, 2.0, true).unwrap_err();
    assert!(e.to_string().contains("period_guess"), "{e}");
}

#[test]
fn bad_parameters_are_named() {
    let base = JefferyParams::default();
    for (field, p) in [
        (
            "aspect_ratio",
            JefferyParams {
                aspect_ratio: 0.0,
                ..base.clone()
            },
        ),
        (
            "aspect_ratio",
            JefferyParams {
                aspect_ratio: -2.0,
                ..base.clone()
            },
        ),
        (
            "shear_rate",
            JefferyParams {
                shear_rate: 0.0,
                ..base.clone()
            },
        ),
        (
            "shear_rate",
            JefferyParams {
                shear_rate: -1.0,
                ..base.clone()
            },
        ),
        (
            "viscosity",
            JefferyParams {
                viscosity: 0.0,
                ..base.clone()
            },
        ),
        (
            "viscosity",
            JefferyParams {
                viscosity: f64::NAN,
                ..base.clone()
            },
        ),
        (
            "gap",
            JefferyParams {
                gap: 4.5,
                ..base.clone()
            },
        ),
        (
            "length",
            JefferyParams {
                length: 1.0,
                ..base.clone()
            },
        ),
        (
            "spacing",
            JefferyParams {
                spacing: -0.001,
                ..base.clone()
            },
        ),
    ] {
        let e = p.validate().unwrap_err().to_string();
        assert!(e.contains(field), "{field}: {e}");
        assert!(jeffery_scene(&p, Box::new(Psor::new(Default::default()))).is_err());
    }
    // a spacing that does not resolve the spheroid's minor axis names the body
    let p = JefferyParams {
        spacing: 0.004,
        ..base
    };
    let e = jeffery_scene(&p, Box::new(Psor::new(Default::default())))
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("spheroid"), "{e}");
}

/// The coarse default scene over its first steps: the fluid is on the Couette profile
/// (the walls' stress `mu gamma`), the spheroid spins up in the vorticity's sense and
/// stays on the mid-plane.
#[test]
fn the_spheroid_spins_up_in_the_shear() {
    let p = JefferyParams::default();
    let mut s = jeffery_scene(&p, Box::new(Psor::new(Default::default()))).unwrap();
    let h = p.spin_time();
    for _ in 0..40 {
        s.system.step(h).unwrap();
    }
    let w = s.angular_velocity();
    let r = p.aspect_ratio;
    let jeffery = p.shear_rate / (r * r + 1.0);
    eprintln!(
        "after {:.3} s: spin {w}, Jeffery's {jeffery}; centre moved {:e} m; wall stress / mu gamma {}",
        s.system.time(),
        (s.centre() - s.centre0).norm(),
        s.wall_shear_stress() / (p.viscosity * p.shear_rate)
    );
    assert!(w.y > 0.5 * jeffery && w.y < 2.0 * jeffery, "{w}");
    assert!(w.x.abs() < 0.05 * w.y && w.z.abs() < 0.05 * w.y, "{w}");
    assert!((s.centre() - s.centre0).norm() < 0.01 * p.spacing);
    let tau = s.wall_shear_stress() / (p.viscosity * p.shear_rate);
    assert!((tau - 1.0).abs() < 0.1, "{tau}");
}
