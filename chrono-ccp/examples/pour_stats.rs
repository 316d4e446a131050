//! The granular pour of `granular-settle` (grains on a jittered lattice falling into an open
//! box, NSC, APGD warm-started) with per-step solver statistics: contacts, iterations,
//! `apply_n`-equivalents, residual, and the deepest penetration; for profiling the solve
//! (e.g. under callgrind) and comparing solver options at the case's tolerance.
//!
//! Run: `cargo run --release -p chrono-ccp --example pour_stats -- [n] [steps] [radius] [h]
//! [solver] [cap]` (defaults: 2000 grains, 40 steps, r = 0.01 m, h = 1/240 s, `apgd`, 100;
//! `solver` is `apgd`, `bb`, `psor`, `psor-par` (coloured sweeps) or `psor-sym`).

use chrono_ccp::{Apgd, BarzilaiBorwein, CcpSolver, Psor, SolverSettings};
use chrono_core::granular::probe::max_penetration;
use chrono_core::granular::{GrainBed, Region, add_box_container};
use chrono_core::math::Vector3;
use chrono_core::system::ContactMethod;
use chrono_core::{ContactMaterial, System, SystemSettings};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, d: &str| a.get(i).cloned().unwrap_or_else(|| d.to_string());
    let n: usize = arg(0, "2000").parse()?;
    let steps: usize = arg(1, "40").parse()?;
    let radius: f64 = arg(2, "0.01").parse()?;
    let h: f64 = arg(3, "0.0041666666667").parse()?;
    let which = arg(4, "apgd");
    let cap: usize = arg(5, "100").parse()?;
    let settings = SolverSettings {
        tolerance: 1e-5,
        max_iterations: cap,
        record_history: false,
    };
    let solver: Box<dyn CcpSolver> = match which.as_str() {
        "bb" => Box::new(BarzilaiBorwein::new(settings)),
        "psor" => Box::new(Psor::new(settings)),
        "psor-par" => Box::new(Psor::new(settings).with_parallel(true)),
        "psor-sym" => Box::new(Psor::new(settings).with_symmetric(true)),
        _ => Box::new(Apgd::new(settings)),
    };
    let sys_settings = SystemSettings {
        envelope: 0.1 * radius,
        contact_method: ContactMethod::Nsc,
        // `WARM=0`: cold starts (to measure what the warm start buys).
        warm_start: std::env::var("WARM").map_or(true, |v| v != "0"),
        ..SystemSettings::default()
    };
    let mut sys = System::new(sys_settings, solver)?;
    let mat = ContactMaterial::smc(1e7, 0.3, 0.5, 0.5);
    let pitch = 2.2 * radius;
    let side = ((n as f64).cbrt() * 1.3).ceil();
    let layers = (n as f64 / (side * side)).ceil() + 1.0;
    let lower = Vector3::zeros();
    let upper = Vector3::new(side * pitch, side * pitch, (layers + 1.0) * pitch);
    let bed = GrainBed {
        gap: 0.2 * radius,
        count: Some(n),
        kick: None,
        seed: 1,
        ..GrainBed::new(
            Region::Box { lower, upper },
            0.8 * radius,
            radius,
            2500.0,
            mat,
        )
    };
    add_box_container(&mut sys, "box", lower, upper, mat)?;
    bed.pour(&mut sys)?;
    let (mut it_sum, mut an_sum, mut capped) = (0usize, 0usize, 0usize);
    // `HIST_STEP=k`: print the residual history of step k's solve.
    let hist: usize = std::env::var("HIST_STEP")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    // `granular-settle`'s unit of kinetic energy per grain: m g d of the mean grain.
    let ke_unit = 2500.0 * 4.0 / 3.0
        * std::f64::consts::PI
        * (0.9 * radius).powi(3)
        * sys.settings().gravity.norm()
        * 2.0
        * radius;
    let t0 = std::time::Instant::now();
    for i in 1..=steps {
        sys.solver_mut().settings_mut().record_history = i == hist;
        let r = sys.step(h)?;
        for rec in &r.solve.history {
            println!(
                "  it {:4} apply_n {:4} res {:.3e}",
                rec.iteration, rec.apply_n, rec.residual
            );
        }
        it_sum += r.solve.iterations;
        an_sum += r.solve.apply_n;
        capped += usize::from(!r.solve.converged);
        println!(
            "step {i:4} contacts {:6} mf {:6} it {:4} apply_n {:4} res {:.2e} conv {} pen/r {:.4} ke/mgd {:.3e}",
            r.contacts,
            sys.last_problem().n_matrix_free(),
            r.solve.iterations,
            r.solve.apply_n,
            r.solve.residual,
            r.solve.converged,
            max_penetration(&sys) / (0.8 * radius),
            sys.kinetic_energy() / n as f64 / ke_unit
        );
    }
    // A fingerprint of the final state (to compare code paths bit for bit).
    let fp = sys.bodies().iter().fold(0u64, |h, b| {
        let p = b.position();
        [p.x, p.y, p.z]
            .iter()
            .fold(h, |h, x| h.rotate_left(5) ^ x.to_bits())
    });
    println!("state fingerprint {fp:016x}");
    println!(
        "total: {steps} steps, {:.1} it/step, {:.1} apply_n/step, {capped} not converged, {:.2} s",
        it_sum as f64 / steps as f64,
        an_sum as f64 / steps as f64,
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}
