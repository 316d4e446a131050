//! Schäfer and Turek's (1996) case 2D-1, flow past a cylinder in a channel at Re = 20:
//! the drag and lift coefficients over time against the benchmark's bounds.
//!
//! `cargo run --release -p chrono-fsi --example cylinder_flow [rows_across_the_height] [t_end] [ramp_time] [absorbing_outlet: 1 | 0]`
//!
//! Diagnostics by environment: `CF_DIAG=1` prints the zone counts, the mean density and the
//! mass flux at four stations over the inflow's; `CF_DUMP=file` writes the fluid particles
//! (x, z, rho, vx, vz) at the end; `CF_SHIFT=A` sets the shifting coefficient.

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
    if let Some(a) = args.next() {
        p.absorbing_outlet = a != "0";
    }
    if let Ok(a) = std::env::var("CF_SHIFT") {
        p.shifting = a.parse()?;
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
        if i % 10 == 0 && std::env::var("CF_DIAG").is_ok() {
            // zone counts, mean density and mass fluxes at three stations
            let s = scene.fluid().sph();
            let d = s.data();
            let (b, l) = (p.buffer(), p.length);
            let mut line = String::new();
            let (mut nin, mut nf, mut nout, mut rho) = (0, 0, 0, 0.0);
            for k in 0..d.len() {
                if d.kind[k] != chrono_sph::data::FLUID {
                    continue;
                }
                if d.x[k] < 0.0 {
                    nin += 1
                } else if d.x[k] < l {
                    nf += 1;
                    rho += d.rho[k];
                } else {
                    nout += 1
                }
            }
            let q_in = p.rho * p.u_mean * p.height * p.width();
            for x0 in [0.1, 0.6, 1.2, 2.0] {
                let w = 0.1;
                let mut m = 0.0;
                for k in 0..d.len() {
                    if d.kind[k] == chrono_sph::data::FLUID && d.x[k] >= x0 && d.x[k] < x0 + w {
                        m += d.mass[k] * d.vx[k];
                    }
                }
                line += &format!(" q({x0}) {:.3}", m / w / q_in);
            }
            println!(
                "diag t {:.2} in {nin} fluid {nf} out {nout} rho {:.5} buffer {b}{line}",
                scene.system.time(),
                rho / nf as f64
            );
        }
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
    if let Ok(path) = std::env::var("CF_DUMP") {
        // positions, density and velocity of the fluid particles at the end
        let d = scene.fluid().sph().data();
        let mut out = String::new();
        for k in 0..d.len() {
            if d.kind[k] == chrono_sph::data::FLUID {
                out += &format!(
                    "{} {} {} {} {}\n",
                    d.x[k], d.z[k], d.rho[k], d.vx[k], d.vz[k]
                );
            }
        }
        std::fs::write(path, out)?;
    }
    Ok(())
}
