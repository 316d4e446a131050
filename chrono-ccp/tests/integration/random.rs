//! Random small CCPs (friction, rolling/spinning cones of both models, bilateral, box,
//! unilateral and mixed rows): at convergence every solver satisfies the complementarity
//! conditions `g ∈ K`, `N g + r ∈ K*`, `g'(N g + r) = 0`, and all reach the same objective
//! value (the problem is a convex QP).

use chrono_ccp::testing::{check_complementarity, objective, random_problem};
use chrono_ccp::{CcpSolver, SolverSettings, by_name};
use proptest::prelude::*;

/// Stopping tolerance of the solvers (RMS residual, m/s).
const SOLVE_TOL: f64 = 1e-11;
/// Tolerance of the explicit complementarity checks (m/s; impulses scaled by `1/N_ii`).
const CHECK_TOL: f64 = 1e-9;

/// The CCP solvers (CG and MINRES only take bilateral problems: see `bilateral.rs`).
const SOLVERS: [&str; 11] = [
    "jacobi",
    "psor",
    "psor-sym",
    "psor-par",
    "apsor",
    "apgd",
    "bb",
    "two-phase",
    "schur",
    "admm",
    "local-direct",
];

fn settings() -> SolverSettings {
    SolverSettings {
        tolerance: SOLVE_TOL,
        max_iterations: 200_000,
        record_history: false,
    }
}

fn run(solver: &mut dyn CcpSolver, seed: u64) -> Result<(Vec<f64>, f64), TestCaseError> {
    let problem = random_problem(seed).unwrap();
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
    prop_assert!(
        (f - stats.objective).abs() <= 1e-12 * (1.0 + f.abs()),
        "{}: objective {} reported {} ({:?})",
        solver.name(),
        f,
        stats.objective,
        (stats.iterations, stats.residual, stats.converged)
    );
    prop_assert!(
        stats.apply_n >= stats.iterations,
        "{}: apply_n {} < iterations {}",
        solver.name(),
        stats.apply_n,
        stats.iterations
    );
    Ok((gamma, f))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn every_solver_satisfies_complementarity_and_they_agree(seed in any::<u64>()) {
        let mut objectives = Vec::new();
        for name in SOLVERS {
            let mut s = by_name(name, settings()).unwrap();
            objectives.push((name, run(s.as_mut(), seed)?.1));
        }
        let mut plain = chrono_ccp::Apgd::new(settings()).with_preconditioning(false);
        objectives.push(("apgd unpreconditioned", run(&mut plain, seed)?.1));
        let mut implicit = chrono_ccp::Schur::new(settings()).with_max_dense_rows(0);
        objectives.push(("schur implicit", run(&mut implicit, seed)?.1));
        let mut scalar = chrono_ccp::Psor::new(settings()).with_block_bilateral(false).with_omega(1.3);
        objectives.push(("psor scalar omega 1.3", run(&mut scalar, seed)?.1));
        let f0 = objectives[0].1;
        for (name, f) in &objectives {
            prop_assert!(
                (f - f0).abs() <= 1e-8 * (1.0 + f0.abs()),
                "objective of {} = {} vs {} {}", name, f, objectives[0].0, f0
            );
        }
    }

    #[test]
    fn warm_start_from_the_solution_needs_no_iteration(seed in any::<u64>()) {
        let problem = random_problem(seed).unwrap();
        for name in SOLVERS {
            let mut s = by_name(name, settings()).unwrap();
            let mut gamma = vec![0.0; problem.n_rows()];
            let cold = s.solve(&problem, &mut gamma);
            prop_assert!(cold.converged);
            let warm = s.solve(&problem, &mut gamma);
            prop_assert!(warm.converged && warm.iterations <= 1, "{}: {} iterations", s.name(), warm.iterations);
        }
    }
}
