//! Replay captured solves (`chrono_ccp::Capture`: problem and warm start) with a solver, for
//! solver studies on one step of a long scene: time (best of `REPS`), sweeps or iterations,
//! residual, objective and the largest velocity error of the blocks heavier than
//! `HEAVY_KG` against a reference solve (APGD to 1e-7 from the same warm start, cached
//! next to the capture as `BASE.ref`).
//!
//! Capture steps of a drive (solves counted from 0, the bed's settling included):
//!
//! ```text
//! target/release/xtask validate hmmwv-granular --quick --set method=nsc --set h=0.001 \
//!     --set solver=local-direct --set distance=0.4 --set 'capture=[700,800,900]' --out /tmp/hg
//! cargo run --release -p chrono-ccp --example replay_step -- \
//!     /tmp/hg/hmmwv-granular/capture_700 /tmp/hg/hmmwv-granular/capture_800
//! ```
//!
//! Environment: `SOLVER` (a `chrono_ccp::SOLVER_NAMES` name, default `local-direct`),
//! `TOL` (1e-3 m/s), `CAP` (60), `HOPS`, `RELAX` and `FAR` (local-direct's `hops`,
//! `admm_relaxation` and `far_solver`: `apgd` or `apsor`), `REPS` (3), `HEAVY_KG` (10), `REF` (set: compare with the reference).

use std::time::Instant;

use chrono_ccp::{CcpSolver, LocalDirect, LocalDirectOptions, SolverSettings, load_capture};
use chrono_core::descriptor::{BlockId, CcpProblem, CcpWork, MassOperator};

fn env<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// The solver; local-direct kept by type so its local block's size can be reported.
enum Solver {
    Local(Box<LocalDirect>),
    Other(Box<dyn CcpSolver>),
}

impl Solver {
    fn solve(&mut self, p: &CcpProblem, g: &mut [f64]) -> chrono_ccp::SolveStats {
        match self {
            Solver::Local(s) => s.solve(p, g),
            Solver::Other(s) => s.solve(p, g),
        }
    }

    fn local_rows(&self) -> Option<usize> {
        match self {
            Solver::Local(s) => Some(s.local_rows().len()),
            Solver::Other(_) => None,
        }
    }
}

fn solver() -> Solver {
    let settings = SolverSettings {
        tolerance: env("TOL", 1e-3),
        max_iterations: env("CAP", 60),
        record_history: false,
    };
    let name: String = env("SOLVER", "local-direct".to_string());
    if name == "local-direct" {
        let d = LocalDirectOptions::default();
        let options = LocalDirectOptions {
            hops: env("HOPS", d.hops),
            admm_relaxation: env("RELAX", d.admm_relaxation),
            far_solver: chrono_ccp::FarSolver::from_name(&env("FAR", "apgd".to_string()))
                .expect("FAR: apgd or apsor"),
            ..d
        };
        Solver::Local(Box::new(LocalDirect::new(settings).with_options(options)))
    } else {
        Solver::Other(chrono_ccp::by_name(&name, settings).expect("SOLVER"))
    }
}

/// The velocity dofs of the blocks heavier than `kg`.
fn heavy_dofs(p: &CcpProblem, kg: f64) -> Vec<usize> {
    let vars = p.variables();
    let (mut dofs, mut off) = (Vec::new(), 0);
    for b in 0..vars.len() {
        let m = vars.mass(BlockId(b as u32));
        let mass = match m {
            MassOperator::Particle { mass }
            | MassOperator::Scalar { mass }
            | MassOperator::RigidBody { mass, .. } => *mass,
            MassOperator::Coupled(_) => f64::INFINITY,
        };
        if mass > kg {
            dofs.extend(off..off + m.ndof());
        }
        off += m.ndof();
    }
    dofs
}

fn reference(base: &str, p: &CcpProblem, warm: &[f64]) -> Vec<f64> {
    let path = format!("{base}.ref");
    if let Ok(b) = std::fs::read(&path)
        && b.len() == 8 * p.n_rows()
    {
        return b
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
            .collect();
    }
    let mut g = warm.to_vec();
    let settings = SolverSettings {
        tolerance: 1e-7,
        max_iterations: 200_000,
        record_history: false,
    };
    let st = chrono_ccp::Apgd::new(settings).solve(p, &mut g);
    eprintln!(
        "{base}: reference {} iterations, residual {:.2e}",
        st.iterations, st.residual
    );
    let bytes: Vec<u8> = g.iter().flat_map(|x| x.to_le_bytes()).collect();
    if let Err(e) = std::fs::write(&path, bytes) {
        eprintln!("{path}: not cached ({e})");
    }
    g
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let bases: Vec<String> = std::env::args().skip(1).collect();
    if bases.is_empty() {
        return Err("usage: replay_step PREFIX_n [PREFIX_m ...]".into());
    }
    let reps: usize = env("REPS", 3);
    for base in &bases {
        let (p, warm) = load_capture(base)?;
        let gref = std::env::var("REF")
            .is_ok()
            .then(|| reference(base, &p, &warm));
        let heavy = heavy_dofs(&p, env("HEAVY_KG", 10.0));
        let (mut best, mut g, mut stats, mut local) = (f64::INFINITY, Vec::new(), None, None);
        for _ in 0..reps.max(1) {
            let mut s = solver();
            g = warm.clone();
            let t = Instant::now();
            stats = Some(s.solve(&p, &mut g));
            best = best.min(t.elapsed().as_secs_f64());
            local = s.local_rows();
        }
        let st = stats.expect("one solve");
        let mut work = CcpWork::default();
        let mut grad = vec![0.0; p.n_rows()];
        p.gradient(&g, &mut grad, &mut work);
        let objective = p.objective_from_gradient(&g, &grad, &mut work);
        let dv = gref.map_or(f64::NAN, |r| {
            let e: Vec<f64> = g.iter().zip(&r).map(|(x, y)| x - y).collect();
            let mut dv = vec![0.0; p.ndof()];
            p.minv_d(&e, &mut dv);
            heavy.iter().map(|&k| dv[k].abs()).fold(0.0, f64::max)
        });
        let local = local.map_or(String::new(), |n| format!(" ({n} local)"));
        println!(
            "{base}: {} rows{local}, {} iterations, residual {:.3e}, objective {:.9e}, heavy dv {dv:.2e}, best {:.1} ms",
            p.n_rows(),
            st.iterations,
            st.residual,
            objective,
            best * 1e3
        );
    }
    Ok(())
}
