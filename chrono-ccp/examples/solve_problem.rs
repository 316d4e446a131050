//! Solve one granular-like CCP (particles on a lattice with frictional contacts between
//! neighbours and with the ground, from `chrono_ccp::testing`) by APGD and by PSOR, and
//! print the iterations and the residual each needed.
//!
//! Run: `cargo run --release -p chrono-ccp --example solve_problem`

use chrono_ccp::testing::lattice;
use chrono_ccp::{Apgd, CcpSolver, Psor, SolverSettings};

fn main() -> Result<(), chrono_core::ChronoError> {
    // 8 x 8 x 6 particles (seed 1): one time step's worth of contacts.
    let problem = lattice(8, 8, 6, 1)?;
    let contacts = problem.sections().friction.len() / 3;
    println!("{} rows, {contacts} frictional contacts", problem.n_rows());
    let settings = SolverSettings {
        tolerance: 1e-6, // m/s
        max_iterations: 5000,
        record_history: false,
    };
    let solvers: [Box<dyn CcpSolver>; 2] = [
        Box::new(Apgd::new(settings.clone())),
        Box::new(Psor::new(settings)),
    ];
    for mut solver in solvers {
        let mut gamma = vec![0.0; problem.n_rows()]; // cold start
        let s = solver.solve(&problem, &mut gamma);
        println!(
            "{:>5}: {} iterations, residual {:.2e} m/s, converged: {}",
            solver.name(),
            s.iterations,
            s.residual,
            s.converged
        );
    }
    Ok(())
}
