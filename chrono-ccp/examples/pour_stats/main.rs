//! The granular pour of `granular-settle` (grains on a jittered lattice falling into an open
//! box, NSC, APGD warm-started) with per-step solver statistics: contacts, iterations,
//! `apply_n`-equivalents, residual, and the deepest penetration; for profiling the solve
//! (e.g. under callgrind) and comparing solver options at the case's tolerance.
//!
//! Run: `cargo run --release -p chrono-ccp --example pour_stats -- [n] [steps] [radius] [h]
//! [solver] [cap]` (defaults: 2000 grains, 40 steps, r = 0.01 m, h = 1/240 s, `apgd`, 100;
//! `TOL=x` sets the solver's tolerance, m/s, 1e-5 by default; `solver` is `apgd`, `bb`,
//! `psor`, `psor-par` (coloured sweeps), `psor-sym`, `psor-x` / `psor-xsym` (the exact
//! triplet step), `psor-xpar` / `psor-xsympar`, `apsor` (the accelerated PSOR;
//! `apsor-serial` without parts, `apsor-explicit` without the matrix-free triplets,
//! `apsor-sym` with symmetric sweeps;
//! `CHECK=k` its residual check every k iterations, `OMEGA=w` its relaxation), `2l:K` (APGD cycles of K iterations
//! with a coarse correction, [`two_level`]) or `study` (APGD, and on the warm start of solve
//! `STUDY_STEP` the error study of docs/performance.md, "is the pour's slow error a smooth
//! (coarse) mode?")).

#[path = "../common/hooked.rs"]
mod hooked;
mod two_level;

use chrono_ccp::{
    Apgd, BarzilaiBorwein, CcpSolver, Psor, SolverSettings, TimedSolver, TripletStep,
};
use chrono_core::granular::probe::max_penetration;
use chrono_core::granular::{GrainBed, Region, add_box_container};
use chrono_core::math::Vector3;
use chrono_core::system::ContactMethod;
use chrono_core::{ContactMaterial, System, SystemSettings};
use hooked::Hooked;
use two_level::TwoLevel;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, d: &str| a.get(i).cloned().unwrap_or_else(|| d.to_string());
    let n: usize = arg(0, "2000").parse()?;
    let steps: usize = arg(1, "40").parse()?;
    let radius: f64 = arg(2, "0.01").parse()?;
    let h: f64 = arg(3, "0.0041666666667").parse()?;
    let which = arg(4, "apgd");
    let cap: usize = arg(5, "100").parse()?;
    // `TOL=x`: the solver's tolerance, m/s (the case's 1e-5 by default).
    let tolerance: f64 = std::env::var("TOL")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1e-5);
    // `CHECK=k`: PSOR's residual check every k sweeps.
    let check_every: Option<usize> = std::env::var("CHECK").ok().and_then(|s| s.parse().ok());
    // `OMEGA=w`: PSOR's relaxation factor.
    let omega: f64 = std::env::var("OMEGA")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0);
    let settings = SolverSettings {
        tolerance,
        max_iterations: cap,
        record_history: false,
    };
    let solver: Box<dyn CcpSolver> = match which.as_str() {
        "bb" => Box::new(BarzilaiBorwein::new(settings)),
        "psor" => Box::new(Psor::new(settings)),
        "psor-par" => Box::new(Psor::new(settings).with_parallel(true)),
        "psor-sym" => Box::new(Psor::new(settings).with_symmetric(true)),
        "psor-x" => Box::new(Psor::new(settings).with_triplet_step(TripletStep::Exact)),
        "psor-xsym" => Box::new(
            Psor::new(settings)
                .with_triplet_step(TripletStep::Exact)
                .with_symmetric(true)
                .with_omega(omega)
                .with_check_every(check_every.unwrap_or(1)),
        ),
        "apsor" | "apsor-serial" | "apsor-explicit" | "apsor-sym" => {
            let mut p = Psor::accelerated(settings).with_omega(omega);
            p.options_mut().symmetric = which == "apsor-sym";
            p.options_mut().partitioned = which != "apsor-serial";
            p.options_mut().matrix_free = which != "apsor-explicit";
            if let Some(k) = check_every {
                p = p.with_check_every(k);
            }
            Box::new(p)
        }
        "psor-xpar" => Box::new(
            Psor::new(settings)
                .with_triplet_step(TripletStep::Exact)
                .with_parallel(true)
                .with_check_every(check_every.unwrap_or(1)),
        ),
        "psor-xsympar" => Box::new(
            Psor::new(settings)
                .with_triplet_step(TripletStep::Exact)
                .with_symmetric(true)
                .with_parallel(true)
                .with_check_every(check_every.unwrap_or(1)),
        ),
        // `2l` / `2l:K`: APGD cycles of K iterations with a coarse correction between.
        w if w.starts_with("2l") => {
            let k = w
                .strip_prefix("2l:")
                .and_then(|k| k.parse().ok())
                .unwrap_or(10);
            Box::new(TwoLevel::new(settings, k))
        }
        "study" => {
            let at: usize = std::env::var("STUDY_STEP")
                .ok()
                .and_then(|s| s.parse().ok())
                .unwrap_or(100);
            let mut step = 0;
            Box::new(Hooked {
                apgd: Apgd::new(settings.clone()),
                hook: move |p: &chrono_core::descriptor::CcpProblem, warm: &[f64]| {
                    step += 1;
                    if step == at {
                        study(p, warm);
                    }
                },
            })
        }
        _ => Box::new(Apgd::new(settings)),
    };
    let solve_nanos = std::sync::Arc::new(std::sync::atomic::AtomicU64::new(0));
    let solver: Box<dyn CcpSolver> = Box::new(TimedSolver {
        inner: solver,
        nanos: solve_nanos.clone(),
    });
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
        "total: {steps} steps, {:.1} it/step, {:.1} apply_n/step, {capped} not converged, {:.2} s (solver {:.2} s)",
        it_sum as f64 / steps as f64,
        an_sum as f64 / steps as f64,
        t0.elapsed().as_secs_f64(),
        solve_nanos.load(std::sync::atomic::Ordering::Relaxed) as f64 * 1e-9
    );
    Ok(())
}

/// `STUDY_STEP=k`: solve step k's problem from a cold start by several solvers and print the
/// objective's distance to the optimum and the residual against the work.
fn study(p: &chrono_core::descriptor::CcpProblem, warm: &[f64]) {
    let set = |tol: f64, it: usize| SolverSettings {
        tolerance: tol,
        max_iterations: it,
        record_history: false,
    };
    let mut g = vec![0.0; p.n_rows()];
    let s = Apgd::new(set(1e-9, 20000)).solve(p, &mut g);
    let fstar = s.objective;
    println!(
        "study: rows {} f* {fstar:.9e} (res {:.2e}, {} it)",
        p.n_rows(),
        s.residual,
        s.iterations
    );
    for cap in [10, 25, 50, 100, 200] {
        let mut g1 = warm.to_vec();
        Apgd::new(set(1e-9, cap)).solve(p, &mut g1);
        let e: Vec<f64> = g.iter().zip(&g1).map(|(a, b)| a - b).collect();
        let c = TwoLevel::new(set(1e-9, 10), 10).capture(p, &g1, &e);
        let c2 = TwoLevel::new(set(1e-9, 10), 10).capture(p, &g, &e);
        {
            let fr = p.sections().friction.clone();
            let mu = p.friction_mu();
            let mut cls = [(0usize, 0.0f64); 3];
            for (c, t) in fr.clone().step_by(3).enumerate() {
                let gn = g[t];
                let gt = (g[t + 1] * g[t + 1] + g[t + 2] * g[t + 2]).sqrt();
                let k = if gn <= 1e-12 {
                    0
                } else if gt < 0.999 * mu[c] * gn {
                    1
                } else {
                    2
                };
                cls[k].0 += 1;
                cls[k].1 += (t..t + 3).map(|j| e[j] * e[j]).sum::<f64>();
            }
            let tot: f64 = cls.iter().map(|c| c.1).sum();
            println!(
                "study: contacts at g*: open {} stick {} slide {}; |e|^2 share open {:.2} stick {:.2} slide {:.2}",
                cls[0].0,
                cls[1].0,
                cls[2].0,
                cls[0].1 / tot,
                cls[1].1 / tot,
                cls[2].1 / tot
            );
        }
        let mut dv = vec![0.0; p.ndof()];
        p.minv_d(&e, &mut dv);
        let mut per: Vec<f64> = dv
            .chunks(6)
            .map(|c| c[..3].iter().map(|x| x * x).sum::<f64>())
            .collect();
        per.sort_by(|a, b| b.partial_cmp(a).unwrap());
        let tot: f64 = per.iter().sum();
        let share = |k: usize| per[..k.min(per.len())].iter().sum::<f64>() / tot;
        println!(
            "study: dv of apgd {cap}: rms {:.2e} m/s, top 1% bodies {:.2} 10% {:.2} 30% {:.2}; max {:.2e}",
            (tot / per.len() as f64).sqrt(),
            share(per.len() / 100),
            share(per.len() / 10),
            share(3 * per.len() / 10),
            per[0].sqrt()
        );
        println!(
            "study: error after apgd {cap}: share captured normal {:.3} scaling(g) {:.3} scaling(g*) {:.3}",
            c[0], c[1], c2[1]
        );
    }
    for name in ["apgd", "2l:5", "2l:10", "2l:20"] {
        for cap in [25, 50, 100, 200] {
            let mut sol: Box<dyn CcpSolver> = match name {
                "apgd" => Box::new(Apgd::new(set(1e-9, cap))),
                w => Box::new(TwoLevel::new(set(1e-9, cap), w[3..].parse().unwrap_or(10))),
            };
            let mut g = warm.to_vec();
            let s = sol.solve(p, &mut g);
            println!(
                "study: {name:6} cap {cap:4} apply_n {:5} res {:.3e} (f-f*)/|f*| {:.3e}",
                s.apply_n,
                s.residual,
                (s.objective - fstar) / fstar.abs()
            );
        }
    }
}
