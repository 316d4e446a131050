//! The towed cylinder of `fsi-active-domain`, run alone with the full domain or with an
//! active domain of radius `R` cylinder diameters: wall time, particle-steps and the
//! fluid's phase times, for profiling one of the two runs at a time.
//!
//! `cargo run --release -p chrono-fsi --example towed -- [RADIUS_IN_D|full] [T_END]`

use std::time::Instant;

use chrono_ccp::Psor;
use chrono_fsi::towed::{TowedParams, towed};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let active_radius = match args.get(1).map(String::as_str) {
        None | Some("full") => None,
        Some(s) => Some(s.parse::<f64>()?),
    };
    let t_end: f64 = args.get(2).map_or(Ok(0.5), |s| s.parse())?;
    let p = TowedParams {
        active_radius,
        ..TowedParams::default()
    };
    let mut scene = towed(&p, Box::new(Psor::new(Default::default())))?;
    let h = 2e-3;
    let n = (t_end / h).round() as usize;
    let start = Instant::now();
    for _ in 0..n {
        scene.step(h)?;
    }
    let wall = start.elapsed().as_secs_f64();
    let sph = scene.fluid().sph();
    let t = sph.timings();
    println!(
        "{}: {n} steps, {} sub-steps, {} fluid particle-steps ({} particles), wall {wall:.3} s; \
         phases neighbours {:.3} density {:.3} forces {:.3} markers {:.3} integration {:.3} s; \
         C_D at the end {:.4}",
        active_radius.map_or("full".to_string(), |s| format!("active {s} D")),
        sph.steps(),
        sph.stats().fluid_steps,
        sph.num_fluid(),
        t.neighbor_search,
        t.density,
        t.forces,
        t.markers,
        t.integration,
        scene.drag_coefficient(scene.force().x)
    );
    Ok(())
}
