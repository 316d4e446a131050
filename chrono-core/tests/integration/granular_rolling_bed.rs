//! NSC rolling friction in a bed of grains (the `granular-repose` case's scene): with
//! rolling friction the grains must settle and stay at rest, as they do without it. Before
//! the torque rows were scaled by the contact radius (`chrono_core::contact::nsc`), 48
//! grains of 5 mm with `mu_r = 0.02` gained energy (kinetic energy 0.09 J after 0.6 s, one
//! grain thrown 1.7 m high) while the same bed without rolling friction came to rest.

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::granular::{LatticeFill, Region, add_box_container, add_grains};
use chrono_core::math::{GRAVITY, Vector3};
use chrono_core::{ContactMaterial, System, SystemSettings};

/// Grains of radius in [0.95 r, r], r = 5 mm, fall from a jittered lattice into a 4 x 4 cm
/// box and settle for 0.6 s (APGD, 100 iterations); returns the largest kinetic energy
/// over the last 0.1 s, in units of `n m g d`, and the highest grain centre (m).
fn settle(mu_r: f64, n: usize) -> (f64, f64) {
    let r = 0.005;
    let mat = ContactMaterial::with_friction(0.5).with_rolling_friction(mu_r);
    let solver = Apgd::new(SolverSettings {
        tolerance: 1e-8,
        max_iterations: 100,
        record_history: false,
    });
    let mut sys = System::new(SystemSettings::default(), Box::new(solver)).unwrap();
    let (lower, upper) = (Vector3::zeros(), Vector3::new(0.04, 0.04, 0.2));
    add_box_container(&mut sys, "box", lower, upper, mat).unwrap();
    let fill = LatticeFill {
        region: Region::Box { lower, upper },
        r_min: 0.95 * r,
        r_max: r,
        gap: 0.5 * r,
        jitter: 1.0,
        max_count: n,
        seed: 3,
    };
    let grains = add_grains(&mut sys, &fill.generate().unwrap(), 2500.0, mat).unwrap();
    assert_eq!(grains.len(), n);
    let mgd = 2500.0 * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3) * GRAVITY.norm() * 2.0 * r;
    let mut ke_late: f64 = 0.0;
    for i in 0..600 {
        sys.step(1e-3).unwrap();
        if i >= 500 {
            ke_late = ke_late.max(sys.kinetic_energy() / (n as f64 * mgd));
        }
    }
    let top = grains
        .iter()
        .map(|&b| sys.body(b).unwrap().position().z)
        .fold(0.0, f64::max);
    (ke_late, top)
}

#[test]
fn a_bed_with_rolling_friction_settles_like_one_without() {
    for mu_r in [0.0, 0.02, 0.2] {
        let (ke, top) = settle(mu_r, 48);
        // Three layers of 16 grains: centres below 4 d; the kinetic energy per grain below
        // 1e-3 m g d (the bound of granular-settle).
        assert!(
            ke < 1e-3,
            "mu_r = {mu_r}: kinetic energy {ke:e} m g d per grain"
        );
        assert!(top < 0.04, "mu_r = {mu_r}: highest grain at {top} m");
    }
}
