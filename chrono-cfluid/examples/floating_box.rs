//! A rigid box of density 500 kg/m^3 floating in a quasi-2D tank of constraint fluid:
//! prints its draft (still-water level beside it minus its bottom) against Archimedes'
//! `(rho_box / rho_water) height`. A coarse, short run (`dp` = 2 cm, 1 s).
//!
//! `cargo run --release -p chrono-cfluid --example floating_box`

use chrono_ccp::Apgd;
use chrono_cfluid::floating_box::{FloatingBox, volume_level};
use chrono_core::descriptor::SolverSettings;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let setup = FloatingBox {
        spacing: 0.02,
        tank_length: 0.4,
        ..FloatingBox::default()
    };
    let solver = Box::new(Apgd::new(SolverSettings {
        tolerance: 1e-4,
        max_iterations: 300,
        record_history: false,
    }));
    let mut scene = setup.build(solver)?;
    for step in 1..=500 {
        scene.sys.step(2e-3)?;
        if step % 100 == 0 {
            let bottom = scene.sys.body(scene.body)?.position().z - 0.5 * setup.box_height;
            let f = scene.fluid()?;
            let volume = f.n_fluid() as f64 * f.particle_mass() / f.settings().rest_density;
            let level = volume_level(volume, scene.ly, setup.tank_length, setup.box_width, bottom);
            println!(
                "t = {:.1} s  draft = {:.4} m",
                step as f64 * 2e-3,
                level - bottom
            );
        }
    }
    println!("Archimedes: {:.4} m", setup.archimedes_draft());
    Ok(())
}
