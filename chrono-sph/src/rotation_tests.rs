//! A rigid carrier turning with the fluid: the no-slip extrapolation of its markers and
//! the torque on it (see `interact::wall_extrapolation` and `SphSystem::carrier_loads`).

use nalgebra::{UnitQuaternion, Vector3};

use crate::{RigidMotion, SphBuilder, SphSettings, SphSystem};

const DP: f64 = 0.01;
const MU: f64 = 1.0;
const RADIUS: f64 = 6.0 * DP;

/// A ball of markers (lattice points within three spacings below a sphere of radius
/// `RADIUS`) turning at `omega` about y, in a periodic box of fluid at the velocity
/// `fluid(x - c)`, evaluated once (no step).
fn ball(omega: f64, fluid: impl Fn(Vector3<f64>) -> Vector3<f64>) -> SphSystem {
    let n = 24;
    let l = n as f64 * DP;
    let c = Vector3::repeat(0.5 * l);
    let settings = SphSettings {
        spacing: DP,
        rho0: 1000.0,
        viscosity: MU,
        sound_speed: 1.0,
        artificial_viscosity: 0.0,
        xsph: 0.0,
        gravity: [0.0; 3],
        domain_lower: [0.0; 3],
        domain_upper: [l; 3],
        periodic: [true; 3],
        clamp_wall_pressure: false,
        ..SphSettings::default()
    };
    let mut b = SphBuilder::new(settings).unwrap();
    let (mut fl, mut markers) = (Vec::new(), Vec::new());
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let x = Vector3::new(i as f64 + 0.5, j as f64 + 0.5, k as f64 + 0.5) * DP;
                let r = (x - c).norm();
                if r > RADIUS {
                    fl.push([x.x, x.y, x.z]);
                } else if r > RADIUS - 3.0 * DP {
                    let d = x - c;
                    markers.push([d.x, d.y, d.z]);
                }
            }
        }
    }
    b.add_fluid_points(&fl, None);
    let motion = RigidMotion {
        angular_velocity: Vector3::new(0.0, omega, 0.0),
        ..RigidMotion::at_rest(c, UnitQuaternion::identity())
    };
    b.add_rigid_markers(motion, &markers, 1).unwrap();
    let mut s = b.build().unwrap();
    s.set_fluid_velocity(|x| {
        let v = fluid(Vector3::new(x[0], x[1], x[2]) - c);
        [v.x, v.y, v.z]
    })
    .unwrap();
    s.initialize().unwrap();
    s
}

#[test]
fn a_carrier_turning_with_its_fluid_feels_no_torque() {
    let omega = 2.0;
    let w = Vector3::new(0.0, omega, 0.0);
    let s = ball(omega, |r| w.cross(&r));
    let [f, t] = s.carrier_load(0);
    // the Stokes torque of the same sphere spinning in fluid at rest, for scale
    let stokes = 8.0 * std::f64::consts::PI * MU * RADIUS.powi(3) * omega;
    eprintln!("co-rotation: force {f}, torque {t} (Stokes scale {stokes:e})");
    // the markers continue the fluid's rigid field exactly, so the viscous pair terms
    // are those of a rigid rotation, whose share the torque leaves out
    assert!(t.norm() < 1e-9 * stokes, "{t}");
    // (the markers' pressure is not zero: it carries their centripetal acceleration,
    // `-a_w . sum rho x W`, the start of the pressure a rotating fluid needs; on the
    // lattice ball its torque cancels)
}

#[test]
fn a_spinning_carrier_in_fluid_at_rest_is_braked() {
    let omega = 2.0;
    let s = ball(omega, |_| Vector3::zeros());
    let [_, t] = s.carrier_load(0);
    let stokes = 8.0 * std::f64::consts::PI * MU * RADIUS.powi(3) * omega;
    eprintln!("spin in fluid at rest: torque {t} (Stokes scale {stokes:e})");
    // an impulsive start: the torque opposes the spin (its size is the start's, not
    // Stokes' steady one)
    assert!(t.y < -0.1 * stokes, "{t}");
    assert!(
        t.x.abs() < 1e-6 * stokes && t.z.abs() < 1e-6 * stokes,
        "{t}"
    );
}
