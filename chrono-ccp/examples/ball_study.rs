//! Where APGD's error sits when a heavy ball hits a granular bed (NSC): the `granular-ball-drop`
//! scene (ball 6 d, same density, from `H` m), and at the `K`-th solve after the ball's first
//! contact, the error of a capped solve against the converged one, split into the ball's and
//! the grains' share of the kinetic energy of the velocity error `e'N e`.
//!
//! Run: `cargo run --release -p chrono-ccp --example ball_study -- [H] [K] [cap]`

#[path = "common/hooked.rs"]
mod hooked;

use chrono_ccp::{Apgd, CcpSolver, SolverSettings};
use chrono_core::descriptor::CcpProblem;
use chrono_core::granular::{BallDrop, ImpactBed};
use chrono_core::system::ContactMethod;
use chrono_core::{ContactMaterial, System, SystemSettings};
use hooked::Hooked;

fn set(tol: f64, it: usize) -> SolverSettings {
    SolverSettings {
        tolerance: tol,
        max_iterations: it,
        record_history: false,
    }
}

fn study(p: &CcpProblem, warm: &[f64], cap: usize) {
    let mut gs = warm.to_vec();
    let s = Apgd::new(set(1e-9, 50000)).solve(p, &mut gs);
    let fstar = s.objective;
    println!(
        "study: rows {} f* {fstar:.9e} (res {:.2e}, {} it)",
        p.n_rows(),
        s.residual,
        s.iterations
    );
    let ball_off = heaviest(p);
    for c in [cap / 2, cap, 2 * cap, 5 * cap, 20 * cap] {
        let mut g = warm.to_vec();
        let st = Apgd::new(set(1e-9, c)).solve(p, &mut g);
        let e: Vec<f64> = gs.iter().zip(&g).map(|(a, b)| a - b).collect();
        let mut dv = vec![0.0; p.ndof()];
        p.minv_d(&e, &mut dv);
        // D e per dof.
        let mut de = vec![0.0; p.ndof()];
        for (j, &ej) in e.iter().enumerate() {
            for (_, off, d, _) in p.row_entries(j) {
                for (k, &dk) in d.iter().enumerate() {
                    de[off + k] += ej * dk;
                }
            }
        }
        let en: Vec<f64> = dv.iter().zip(&de).map(|(a, b)| a * b).collect();
        let tot: f64 = en.iter().sum();
        let ball: f64 = en[ball_off..].iter().sum();
        println!(
            "study: apgd {c:5}: res {:.2e} (f-f*)/|f*| {:.2e}; e'Ne {:.3e}, ball share {:.3}; ball dv {:.3e} {:.3e} {:.3e} m/s",
            st.residual,
            (st.objective - fstar) / fstar.abs(),
            tot,
            ball / tot,
            dv[ball_off],
            dv[ball_off + 1],
            dv[ball_off + 2]
        );
    }
}

/// Mass of the block at dof `off` seen through a row's `D` and `M^-1 D` (translational part).
fn mass_of(p: &CcpProblem, off: usize) -> f64 {
    for j in 0..p.n_rows() {
        for (_, o, d, md) in p.row_entries(j) {
            if o == off {
                let n: f64 = d[..3].iter().map(|x| x * x).sum::<f64>().sqrt();
                let m: f64 = md[..3].iter().map(|x| x * x).sum::<f64>().sqrt();
                if m > 0.0 {
                    return n / m;
                }
            }
        }
    }
    0.0
}

/// The first dof of the heaviest block touched by a row.
fn heaviest(p: &CcpProblem) -> usize {
    let (mut best, mut at) = (0.0, 0);
    for j in 0..p.n_rows() {
        for (_, o, d, md) in p.row_entries(j) {
            let n: f64 = d[..3].iter().map(|x| x * x).sum::<f64>().sqrt();
            let m: f64 = md[..3].iter().map(|x| x * x).sum::<f64>().sqrt();
            if m > 0.0 && n / m > best {
                best = n / m;
                at = o;
            }
        }
    }
    at
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let height: f64 = a.first().map_or(Ok(0.5), |s| s.parse())?;
    let at: usize = a.get(1).map_or(Ok(5), |s| s.parse())?;
    let cap: usize = a.get(2).map_or(Ok(60), |s| s.parse())?;
    let d = 0.005;
    let ball = 0.03;
    let mat = ContactMaterial::smc(1e7, 0.3, 0.5, 0.5);
    let mut bed = ImpactBed::new(0.5 * 3.5 * ball, 1.75 * ball, d, 2500.0, mat);
    // `H_STEP`: the drop's time step (s; the bed settles at the default 1 ms).
    let h_drop: Option<f64> = std::env::var("H_STEP").ok().and_then(|s| s.parse().ok());
    let settings = SystemSettings {
        envelope: 0.05 * d,
        contact_method: ContactMethod::Nsc,
        ..SystemSettings::default()
    };
    let mut sys = System::new(settings.clone(), Box::new(Apgd::new(set(1e-4, cap))))?;
    let settled = bed.settle(&mut sys)?;
    if let Some(h) = h_drop {
        bed.h = h;
    }
    println!("settled: {} grains", settled.grains.len());
    // Study the `at`-th solve with a row on the ball (the heaviest block, over 100 grain
    // masses).
    let mut ball_solves = 0;
    let solver = Hooked {
        apgd: Apgd::new(set(1e-4, cap)),
        hook: move |p: &CcpProblem, warm: &[f64]| {
            if p.n_rows() == 0 {
                return;
            }
            let ball_off = heaviest(p);
            let touches = (0..p.n_rows()).any(|j| p.row_entries(j).any(|e| e.1 == ball_off))
                && mass_of(p, ball_off) > 100.0 * 2500.0 * 0.005f64.powi(3);
            if touches {
                ball_solves += 1;
                if ball_solves == at {
                    study(p, warm, cap);
                }
            }
        },
    };
    let mut sys = System::new(settings, Box::new(solver))?;
    let drop = BallDrop {
        diameter: ball,
        density: 2500.0,
        height,
        offset: [0.0, 0.0],
        t_drop: 0.15,
        record_dt: 1e-3,
    };
    let p = drop.run(&mut sys, &bed, &settled, |_| {})?;
    println!("depth {:.4} m, steps {}", p.depth, p.steps);
    Ok(())
}
