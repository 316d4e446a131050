//! Step the shoe-by-shoe M113A1 on flat ground (sprockets held) and print each step's cost,
//! contact count, solver residual, chassis height and joint drift: the probe behind the
//! M113 section of `docs/validation-vehicle.md`.
//!
//! `cargo run --release -p chrono-vehicle --example m113_probe -- [h] [steps] [solver]
//! [max_iterations] [compliance] [torsion_preload]`
//!
//! With `RAMP=a` (rad/s^2) in the environment the sprockets are held for 0.5 s, then driven
//! at the prescribed speed `a (t - 0.5)` (both sides): the chassis' forward speed is printed
//! against the sprocket's pitch-circle speed `w r_p`, which shows whether the chain follows
//! the sprocket at every speed.

use std::time::Instant;

use chrono_core::Drive;
use chrono_core::descriptor::SolverSettings;
use chrono_vehicle::m113::m113_data;
use chrono_vehicle::tracked::TrackedFlatScene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let arg = |i: usize, default: &str| args.get(i).cloned().unwrap_or(default.to_string());
    let h: f64 = arg(1, "2e-3").parse()?;
    let n: usize = arg(2, "300").parse()?;
    let solver = arg(3, "apgd");
    let max_iterations: usize = arg(4, "200").parse()?;
    let compliance: f64 = arg(5, "0").parse()?;
    let mut d = m113_data()?;
    d.track.materials.shoe.compliance = compliance;
    d.track.materials.wheel.compliance = compliance;
    if let Some(t) = args.get(6) {
        d.track.road_wheels.torsion_bar.preload = t.parse()?;
    }
    let settings = SolverSettings {
        tolerance: 1e-8,
        max_iterations,
        record_history: false,
    };
    // `schur-mf`: the Schur solver with its contact complement always matrix-free.
    let solver: Box<dyn chrono_core::descriptor::CcpSolver> = if solver == "schur-mf" {
        Box::new(chrono_ccp::Schur::new(settings).with_max_dense_rows(0))
    } else {
        chrono_ccp::by_name(&solver, settings)?
    };
    let mut sc = TrackedFlatScene::new(d, 0.8, solver)?;
    for side in &sc.vehicle.sides {
        println!(
            "side {}: {} shoes, idler offset {:.4} m, loop {:.4} m, closure {:.1e} m",
            side.side,
            side.shoes.len(),
            side.layout.idler_offset,
            side.layout.loop_length,
            side.layout.closure_error
        );
    }
    sc.vehicle
        .set_sprocket_drives(&mut sc.sys, Drive::Speed(0.0))?;
    let ramp: Option<f64> = std::env::var("RAMP").ok().map(|s| s.parse()).transpose()?;
    let r_p = sc.data.track.sprocket.pitch_radius;
    let every = (n / 40).max(1);
    for i in 0..n {
        let w = ramp.map_or(0.0, |a| (a * (sc.sys.time() - 0.5)).max(0.0));
        if ramp.is_some() {
            sc.vehicle
                .set_sprocket_drives(&mut sc.sys, Drive::Speed(w))?;
        }
        let t = Instant::now();
        let r = sc.sys.step(h);
        let dt = t.elapsed().as_secs_f64();
        let c = sc.sys.body(sc.vehicle.chassis)?;
        match r {
            Ok(r) if i % every == 0 || i + 1 == n => println!(
                "step {i}: {dt:.3} s, {} contacts, {} rows, {} iterations, residual {:.1e}, \
                 chassis z {:.4} m, vz {:.4} m/s, vx {:.4} m/s against w r_p {:.4} m/s, \
                 joint drift {:.1e} m",
                r.contacts,
                r.rows,
                r.solve.iterations,
                r.solve.residual,
                c.position().z,
                c.linear_velocity().z,
                c.linear_velocity().x,
                w * r_p,
                sc.sys.max_joint_violation()
            ),
            Ok(_) => {}
            Err(e) => {
                println!("step {i}: {e}");
                break;
            }
        }
    }
    Ok(())
}
