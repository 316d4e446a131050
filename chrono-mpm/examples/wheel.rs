//! A rigid wheel driven at fixed slip on MPM sand (`chrono_mpm::wheel`): prints the
//! steady sinkage, drawbar pull and driving torque and their ratios to the load.
//!
//! `cargo run --release -p chrono-mpm --example wheel [cells_radius [slip [young [load [radius [rim_travel [flip [cohesion [contact_mass_fraction]]]]]]]]]`

use chrono_mpm::soil_bin::SoilSpec;
use chrono_mpm::wheel::{Wheel, WheelSpec};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize, default: f64| -> Result<f64, Box<dyn std::error::Error>> {
        Ok(match std::env::args().nth(i) {
            Some(s) => s.parse()?,
            None => default,
        })
    };
    let d = WheelSpec::default();
    let spec = WheelSpec {
        soil: SoilSpec {
            young: arg(3, d.soil.young)?,
            flip: arg(7, d.soil.flip)?,
            cohesion: arg(8, d.soil.cohesion)?,
            ..d.soil
        },
        cells_radius: arg(1, d.cells_radius as f64)? as usize,
        slip: arg(2, d.slip)?,
        load: arg(4, d.load)?,
        wheel_radius: arg(5, d.wheel_radius)?,
        rim_travel: arg(6, d.rim_travel)?,
        contact_mass_fraction: arg(9, d.contact_mass_fraction)?,
        ..d
    };
    let mut wheel = Wheel::new(spec)?;
    let r = wheel.run(|_| {})?;
    let (w, wr) = (spec.load, spec.load * spec.wheel_radius);
    println!(
        "{} markers, {} steps: sinkage {:.5} m (static {:.5} m), DP {:.2} N = {:.4} W, T {:.3} N m = {:.4} W R, F_z {:.4} W",
        wheel.body.markers.len(),
        r.steps,
        r.sinkage,
        r.static_sinkage,
        r.drawbar_pull,
        r.drawbar_pull / w,
        r.torque,
        r.torque / wr,
        r.vertical_force / w
    );
    Ok(())
}
