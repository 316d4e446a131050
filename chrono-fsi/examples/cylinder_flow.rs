//! Schäfer and Turek's (1996) case 2D-1, flow past a cylinder in a channel at Re = 20:
//! the drag and lift coefficients over time against the benchmark's bounds.
//!
//! `cargo run --release -p chrono-fsi --example cylinder_flow [rows_across_the_height] [t_end] [ramp_time]`

use chrono_ccp::Psor;
use chrono_fsi::cylinder_flow::{CylinderFlowParams, DRAG_RANGE, LIFT_RANGE, cylinder_flow};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let rows: f64 = args.next().map_or(Ok(41.0), |s| s.parse())?;
    let t_end: f64 = args.next().map_or(Ok(6.0), |s| s.parse())?;
    let mut p = CylinderFlowParams::default();
    p.spacing = p.height / rows;
    let n = p.diameter / p.spacing;
    if let Some(r) = args.next() {
        p.ramp_time = r.parse()?;
    }
    let mut scene = cylinder_flow(&p, Box::new(Psor::new(Default::default())))?;
    let h = 0.02;
    let steps = (t_end / h).round() as usize;
    let start = std::time::Instant::now();
    println!(
        "D/dp {n}, {} fluid particles; bounds C_D {:?}, C_L {:?}",
        scene.fluid().sph().num_fluid(),
        DRAG_RANGE,
        LIFT_RANGE
    );
    for i in 1..=steps {
        scene.system.step(h)?;
        if i % 10 == 0 {
            let s = scene.fluid().sph();
            println!(
                "t {:.2}  C_D {:.4}  C_L {:+.4}  fluid {}  steps {}  wall {:.0} s",
                scene.system.time(),
                scene.drag_coefficient(),
                scene.lift_coefficient(),
                s.num_fluid(),
                scene.fluid().substeps(),
                start.elapsed().as_secs_f64()
            );
        }
    }
    Ok(())
}
