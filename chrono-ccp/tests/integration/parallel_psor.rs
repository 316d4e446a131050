//! The coloured parallel PSOR sweep converges to the solution (same objective as APGD) on
//! a lattice large enough that colours have hundreds of units (the parallel path). PSOR is
//! slow on lattices (~8k sweeps to 1e-7, sequential or coloured), so the tolerance is
//! loose to keep the test cheap; `determinism.rs` checks the parallel path bit for bit.

use chrono_ccp::testing::{check_complementarity, lattice};
use chrono_ccp::{Apgd, CcpSolver, Psor, SolverSettings};

#[test]
fn coloured_sweeps_reach_the_same_solution() {
    let problem = lattice(10, 10, 8, 3).unwrap();
    let triplets = problem.sections().friction.len() / 3;
    assert!(triplets > 2000, "{triplets} triplets");
    let s = SolverSettings {
        tolerance: 1e-5,
        max_iterations: 20_000,
        record_history: false,
    };
    let mut g_par = vec![0.0; problem.n_rows()];
    let par = Psor::new(s.clone())
        .with_parallel(true)
        .solve(&problem, &mut g_par);
    let mut g_ref = vec![0.0; problem.n_rows()];
    let reference = Apgd::new(s).solve(&problem, &mut g_ref);
    assert!(
        par.converged && reference.converged,
        "{par:?} {reference:?}"
    );
    check_complementarity(&problem, &g_par, 1e-3).unwrap();
    let (f, f0) = (par.objective, reference.objective);
    assert!((f - f0).abs() <= 1e-5 * f0.abs(), "{f} vs {f0}");
}
