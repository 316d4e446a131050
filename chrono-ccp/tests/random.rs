//! Random small CCPs: at convergence both solvers satisfy the complementarity conditions
//! and reach the same objective value (the problem is a convex QP).

mod common;

use chrono_ccp::{Apgd, CcpSolver, Psor, SolverSettings};
use common::{check_complementarity, objective, random_problem};
use proptest::prelude::*;

/// Stopping tolerance of the solvers (RMS residual, m/s).
const SOLVE_TOL: f64 = 1e-11;
/// Tolerance of the explicit complementarity checks (m/s; impulses scaled by `1/N_ii`).
const CHECK_TOL: f64 = 1e-9;

fn settings() -> SolverSettings {
    SolverSettings {
        tolerance: SOLVE_TOL,
        max_iterations: 200_000,
        record_history: false,
    }
}

fn run(solver: &mut dyn CcpSolver, seed: u64) -> Result<(Vec<f64>, f64), TestCaseError> {
    let problem = random_problem(seed);
    let mut gamma = vec![0.0; problem.n_rows()];
    let stats = solver.solve(&problem, &mut gamma);
    prop_assert!(
        stats.converged,
        "{} did not converge: {:?}",
        solver.name(),
        (stats.iterations, stats.residual)
    );
    if let Err(e) = check_complementarity(&problem, &gamma, CHECK_TOL) {
        return Err(TestCaseError::fail(format!(
            "{}: {e}\ngamma = {gamma:?}",
            solver.name()
        )));
    }
    let f = objective(&problem, &gamma);
    prop_assert!((f - stats.objective).abs() <= 1e-12 * (1.0 + f.abs()));
    Ok((gamma, f))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn both_solvers_satisfy_complementarity_and_agree(seed in any::<u64>()) {
        let (_, f_psor) = run(&mut Psor::new(settings()), seed)?;
        let (_, f_sym) = run(&mut Psor::new(settings()).with_symmetric(true).with_omega(1.3), seed)?;
        let (_, f_apgd) = run(&mut Apgd::new(settings()), seed)?;
        let (_, f_plain) = run(&mut Apgd::new(settings()).with_preconditioning(false), seed)?;
        for (name, f) in [("psor symmetric", f_sym), ("apgd", f_apgd), ("apgd unpreconditioned", f_plain)] {
            prop_assert!(
                (f - f_psor).abs() <= 1e-8 * (1.0 + f_psor.abs()),
                "objective of {} = {} vs psor {}", name, f, f_psor
            );
        }
    }

    #[test]
    fn warm_start_from_the_solution_needs_no_iteration(seed in any::<u64>()) {
        let problem = random_problem(seed);
        let solvers: Vec<Box<dyn CcpSolver>> = vec![Box::new(Psor::new(settings())), Box::new(Apgd::new(settings()))];
        for mut s in solvers {
            let mut gamma = vec![0.0; problem.n_rows()];
            let cold = s.solve(&problem, &mut gamma);
            prop_assert!(cold.converged);
            let warm = s.solve(&problem, &mut gamma);
            prop_assert!(warm.converged && warm.iterations <= 1, "{}: {} iterations", s.name(), warm.iterations);
        }
    }
}
