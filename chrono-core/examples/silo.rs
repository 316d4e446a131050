//! A silo discharging glass beads through an orifice (NSC): the mass flow rate, against
//! Beverloo's law `W = 0.58 rho_b sqrt(g) (D - 1.5 d)^(5/2)` at a solid fraction of 0.6.
//!
//! `cargo run --release -p chrono-core --example silo`

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::granular::{GrainBed, Recycler, Silo};
use chrono_core::math::GRAVITY;
use chrono_core::{ContactMaterial, System, SystemSettings};

fn main() -> chrono_core::Result<()> {
    let solver = Apgd::new(SolverSettings {
        tolerance: 1e-4,
        max_iterations: 60,
        record_history: false,
    });
    let settings = SystemSettings {
        envelope: 2e-4,
        ..SystemSettings::default()
    };
    let mut sys = System::new(settings, Box::new(solver))?;
    // Beads of 3.6-4 mm, a 4 cm silo with a 2 cm orifice, filled about 3 cm high.
    let (d, density, fill) = (0.004, 2500.0, 0.03);
    let glass = ContactMaterial::smc(1e7, 0.3, 0.5, 0.3);
    let silo = Silo::new(0.04, 0.02, 2.0 * d, glass);
    silo.add(&mut sys)?;
    let region = silo.region(0.25 * d, 2.6 * fill);
    let bed = GrainBed::new(region, 0.45 * d, 0.5 * d, density, glass).pour(&mut sys)?;
    let mut recycler = Recycler::new(&sys, &bed, &silo, d, fill + 2.0 * d)?;
    let (h, t_start, t_end) = (1e-3, 0.25, 0.6);
    let mut at_start = 0.0;
    while sys.time() < t_end - 0.5 * h {
        sys.step(h)?;
        recycler.recycle(&mut sys)?;
        if (sys.time() - t_start).abs() < 0.5 * h {
            at_start = recycler.discharged();
        }
    }
    let flow = (recycler.discharged() - at_start) / (t_end - t_start);
    let (g, big_d, mean_d) = (GRAVITY.norm(), silo.orifice, 0.95 * d);
    let beverloo = 0.58 * 0.6 * density * g.sqrt() * (big_d - 1.5 * mean_d).powf(2.5);
    println!("{} grains, D / d = {:.1}", bed.len(), big_d / d);
    println!(
        "flow rate {:.1} g/s (Beverloo at solid fraction 0.6: {:.1} g/s)",
        flow * 1e3,
        beverloo * 1e3
    );
    Ok(())
}
