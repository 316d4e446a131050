//! A rigid strip footing pushed into weightless von Mises clay (`chrono_mpm::footing`):
//! prints the load-settlement curve and the limit pressure against Prandtl's
//! `(2 + pi) c_u`.
//!
//! `cargo run --release -p chrono-mpm --example footing [cells_half_width [poisson [speed [markers_per_cell [final_settlement [f_bar (0 off, 1 increment, 2 total, 3 plastic) [friction_angle_deg [domain_width]]]]]]]]`

use chrono_mpm::footing::{Footing, FootingSpec};

use chrono_mpm::fbar::FBar;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize, default: f64| -> Result<f64, Box<dyn std::error::Error>> {
        Ok(match std::env::args().nth(i) {
            Some(s) => s.parse()?,
            None => default,
        })
    };
    let spec = FootingSpec {
        footing_width: 1.0,
        cohesion: 1e4,
        friction_angle_deg: arg(7, 0.0)?,
        young: 5e6,
        poisson: arg(2, 0.3)?,
        density: 1800.0,
        cells_half_width: arg(1, 4.0)? as usize,
        markers_per_cell: arg(4, 2.0)? as usize,
        domain_width: arg(8, 2.5)?,
        domain_depth: 1.5,
        speed: arg(3, 0.05)?,
        ramp_time: 0.2,
        final_settlement: arg(5, 0.1)?,
        cfl: 0.4,
        f_bar: [
            FBar::Off,
            FBar::Increment,
            FBar::Total,
            FBar::PlasticIncrement,
        ][arg(6, 0.0)? as usize],
    };
    let mut f = Footing::new(spec)?;
    let start = std::time::Instant::now();
    let samples = f.run(40, |_| {})?;
    let q = spec.prandtl_pressure();
    for s in &samples {
        println!(
            "settlement/B {:.4}  q/q_u {:.4}  kinetic/elastic {:.3e}",
            s.settlement / spec.footing_width,
            s.pressure / q,
            s.kinetic / s.elastic.max(1e-300)
        );
    }
    println!(
        "{} markers, {} steps in {:.2} s",
        f.body.markers.len(),
        f.body.steps(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
