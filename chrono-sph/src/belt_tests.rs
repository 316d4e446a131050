//! Moving-belt walls ([`crate::WallBelt`]): plane Couette flow between two tank walls
//! that keep their places and carry `+U` and `-U`.

use crate::{SphBuilder, SphSettings, SphSystem, WallBelt, sound_speed_for};
use chrono_core::particles::lattice::wall_layers;

/// The Couette cell: periodic in x and y (`8 dp` each), walls at `z = 0` (group 4,
/// velocity `-u` along x) and `z = H` (group 5, `+u`), `H = n dp`, fluid at rest.
fn couette(n: usize, u: f64, belts: Vec<WallBelt>) -> crate::Result<SphSystem> {
    let dp = 1e-3;
    let (l, h) = (8.0 * dp, n as f64 * dp);
    let (rho, mu) = (1000.0, 0.1);
    let nu = mu / rho;
    let settings = SphSettings {
        spacing: dp,
        rho0: rho,
        viscosity: mu,
        sound_speed: sound_speed_for(u, h, 0.0, nu, 0.01)?,
        artificial_viscosity: 0.0,
        xsph: 0.0,
        gravity: [0.0; 3],
        domain_lower: [0.0; 3],
        domain_upper: [l, l, h],
        periodic: [true, true, false],
        clamp_wall_pressure: false,
        wall_belts: belts,
        ..SphSettings::default()
    };
    let layers = wall_layers(settings.h_over_dp);
    let mut b = SphBuilder::new(settings)?;
    b.add_fluid_box([0.0; 3], [l, l, h], None)?;
    b.add_tank(
        [0.0; 3],
        [l, l, h],
        layers,
        [false, false, false, false, true, true],
        0,
    )?;
    b.build()
}

fn belts(u: f64) -> Vec<WallBelt> {
    vec![
        WallBelt {
            group: 4,
            velocity: [-u, 0.0, 0.0],
        },
        WallBelt {
            group: 5,
            velocity: [u, 0.0, 0.0],
        },
    ]
}

/// Runs the cell of `n` spacings from rest for 12 slowest viscous times `H^2 / (pi^2
/// nu)` (the start-up transient decays to `e^-12`, 6e-6); returns the largest deviation of a
/// fluid particle's x velocity from `u (2 z / H - 1)` over `u`, the top wall's shear
/// force over `mu (2 u / H)` times its area, and the fluid's x momentum over `rho u` and
/// the cell volume.
fn developed(n: usize) -> (f64, f64, f64) {
    let u = 0.01;
    let mut s = couette(n, u, belts(u)).unwrap();
    let h = n as f64 * 1e-3;
    let (mu, rho, l) = (0.1, 1000.0, 8e-3);
    let t_end = 12.0 * h * h / (std::f64::consts::PI.powi(2) * mu / rho);
    s.advance_to(t_end).unwrap();
    let d = s.data();
    let mut worst: f64 = 0.0;
    for i in 0..d.len() {
        if d.kind[i] == crate::data::FLUID {
            let exact = u * (2.0 * d.z[i] / h - 1.0);
            worst = worst.max((d.vx[i] - exact).abs() / u);
        }
    }
    let tau = mu * 2.0 * u / h;
    let top = s.wall_force(5);
    let bottom = s.wall_force(4);
    // the fluid drags the faster top wall back and the bottom one forward
    assert!(
        (top.x + bottom.x).abs() < 1e-6 * tau * l * l,
        "{top} {bottom}"
    );
    let momentum = s.fluid_momentum().x / (rho * u * l * l * h);
    (worst, -top.x / (tau * l * l), momentum)
}

#[test]
fn couette_flow_between_belts_converges_to_the_linear_profile() {
    // The linear no-slip extrapolation is exact for a linear profile, so the profile is
    // right at any resolution (measured: within 8e-5 u at 10 spacings, 3e-4 u at 20); the
    // wall stress (a sum over the kernel) converges with the spacing: measured -0.11 % at
    // 10 spacings, -0.02 % at 20.
    let mut last = f64::INFINITY;
    for n in [10, 20] {
        let (worst, stress, momentum) = developed(n);
        eprintln!(
            "H = {n} dp: profile error {worst:.2e} u, wall stress / (mu 2u/H) {stress:.5}, momentum {momentum:.1e}"
        );
        assert!(worst < 1e-3, "H = {n} dp: {worst}");
        assert!((stress - 1.0).abs() < 5e-3, "H = {n} dp: {stress}");
        assert!(momentum.abs() < 1e-9, "H = {n} dp: {momentum}");
        assert!(
            (stress - 1.0).abs() < last,
            "H = {n} dp: {stress} after {last}"
        );
        last = (stress - 1.0).abs();
    }
}

#[test]
fn bad_belts_are_named() {
    let u = 0.01;
    // along the walls' normal: not a belt
    let e = couette(
        10,
        u,
        vec![WallBelt {
            group: 4,
            velocity: [0.0, 0.0, u],
        }],
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("settings.wall_belts[0].velocity"), "{e}");
    // a group without tank walls
    let e = couette(
        10,
        u,
        vec![WallBelt {
            group: 9,
            velocity: [u, 0.0, 0.0],
        }],
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("settings.wall_belts[0].group"), "{e}");
    let mut b = belts(u);
    b[1].velocity[1] = f64::NAN;
    let e = couette(10, u, b).unwrap_err().to_string();
    assert!(e.contains("settings.wall_belts[1].velocity"), "{e}");
    let mut b = belts(u);
    b[1].group = 4;
    let e = couette(10, u, b).unwrap_err().to_string();
    assert!(e.contains("settings.wall_belts[1].group"), "{e}");
}
