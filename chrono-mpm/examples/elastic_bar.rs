//! The axially vibrating elastic bar (`chrono_mpm::bar`): prints the first frequency
//! against `sqrt(E/rho)/(4L)` and the energy drift over ten periods.
//!
//! `cargo run --release -p chrono-mpm --example elastic_bar [cells_along [cfl [markers_per_cell [poisson [f_bar (0 off, 1 increment, 2 total, 3 plastic)]]]]]`

use chrono_mpm::bar::{BarSpec, ElasticBar};

use chrono_mpm::fbar::FBar;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let cells_along = match std::env::args().nth(1) {
        Some(s) => s.parse()?,
        None => BarSpec::default().cells_along,
    };
    let arg = |i: usize, default: f64| -> Result<f64, Box<dyn std::error::Error>> {
        Ok(match std::env::args().nth(i) {
            Some(s) => s.parse()?,
            None => default,
        })
    };
    let d = BarSpec::default();
    let mut bar = ElasticBar::new(BarSpec {
        cells_along,
        cfl: arg(2, d.cfl)?,
        markers_per_cell: arg(3, d.markers_per_cell as f64)? as usize,
        poisson: arg(4, d.poisson)?,
        f_bar: [
            FBar::Off,
            FBar::Increment,
            FBar::Total,
            FBar::PlasticIncrement,
        ][arg(5, 0.0)? as usize],
        ..d
    })?;
    let start = std::time::Instant::now();
    let r = bar.run(10.0, |_| {})?;
    let f_ref = bar.reference_frequency();
    println!(
        "{} markers, dt {:.3e} s, {} steps in {:.2} s",
        bar.body.markers.len(),
        bar.dt,
        r.steps,
        start.elapsed().as_secs_f64()
    );
    println!(
        "frequency {:.5} Hz, reference {:.5} Hz, error {:+.3} %",
        r.frequency,
        f_ref,
        100.0 * (r.frequency / f_ref - 1.0)
    );
    println!(
        "energy drift over 10 periods {:+.4} %, largest excursion {:.4} %",
        100.0 * r.energy_drift,
        100.0 * r.energy_excursion
    );
    Ok(())
}
