//! Still water in a tank of constraint fluid: a quasi-2D tank filled to `H` at rest on
//! its lattice; after a few steps the pressure near the bottom (the density rows'
//! impulses over the step) is printed against the hydrostatic `rho g (H - z)`.
//!
//! `cargo run --release -p chrono-cfluid --example tank`

use chrono_ccp::Apgd;
use chrono_cfluid::CfluidSettings;
use chrono_cfluid::scene::TankScene;
use chrono_core::descriptor::SolverSettings;
use chrono_core::math::GRAVITY;
use chrono_core::particles::lattice::SlabTank;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (dp, depth, length) = (0.01, 0.1, 0.1); // m
    let settings = CfluidSettings::default();
    let tank = SlabTank::sloshing(dp, settings.h_over_dp, length, depth, 1.5 * depth);
    let solver = Box::new(Apgd::new(SolverSettings {
        tolerance: 1e-6,
        max_iterations: 500,
        record_history: false,
    }));
    let mut scene = TankScene::new(settings, &tank, solver)?;
    let (z, steps) = (2.5 * dp, 50);
    let probe = [0.5 * length, 0.5 * scene.ly, z];
    let mut p_sum = 0.0;
    for _ in 0..steps {
        scene.sys.step(2e-3)?;
        p_sum += scene.fluid()?.pressure_at(probe)?.unwrap_or(f64::NAN);
    }
    let f = scene.fluid()?;
    let expected = f.settings().rest_density * -GRAVITY.z * (depth - z);
    let p = p_sum / steps as f64;
    println!("pressure at z = {z:.3} m over {steps} steps: {p:.1} Pa");
    println!(
        "hydrostatic rho g (H - z) = {expected:.1} Pa ({:+.1} %)",
        100.0 * (p / expected - 1.0)
    );
    println!("largest compression: {:.2e}", f.max_compression());
    Ok(())
}
