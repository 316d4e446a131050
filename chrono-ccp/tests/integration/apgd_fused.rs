//! APGD's fused passes for friction-only problems give the same bits as its general path
//! (same iterates, same statistics), on a settled sphere pile (matrix-free triplets, several
//! units of rows, every parallel path), for 1 and 2 threads.

use chrono_ccp::testing::granular_pile;
use chrono_ccp::{Apgd, CcpSolver, SolverSettings};
use chrono_core::descriptor::CcpProblem;

fn solve(
    problem: &CcpProblem,
    fused: bool,
    threads: usize,
    warm: &[f64],
) -> (Vec<u64>, [u64; 3], usize, usize) {
    let settings = SolverSettings {
        tolerance: 1e-9,
        max_iterations: 40,
        record_history: true,
    };
    let mut apgd = Apgd::new(settings);
    apgd.options_mut().fused = fused;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let mut gamma = warm.to_vec();
    let stats = pool.install(|| apgd.solve(problem, &mut gamma));
    let history: Vec<u64> = stats.history.iter().map(|r| r.residual.to_bits()).collect();
    assert_eq!(history.len(), stats.iterations, "one record per iteration");
    let mut bits: Vec<u64> = gamma.iter().map(|x| x.to_bits()).collect();
    bits.extend(history);
    (
        bits,
        [
            stats.residual.to_bits(),
            stats.objective.to_bits(),
            u64::from(stats.converged),
        ],
        stats.iterations,
        stats.apply_n,
    )
}

fn check(problem: &CcpProblem, warm: &[f64]) {
    assert!(problem.is_friction_only());
    let reference = solve(problem, false, 1, warm);
    assert!(
        reference.2 > 5,
        "the solve should iterate: {} iterations",
        reference.2
    );
    for threads in [1, 2] {
        assert_eq!(
            solve(problem, true, threads, warm),
            reference,
            "fused, {threads} threads"
        );
    }
}

#[test]
fn fused_passes_match_the_general_path_on_a_sphere_pile() {
    let (problem, solution, _) = granular_pile(5000, 3, 1e-3).unwrap();
    assert!(problem.n_matrix_free() > 0);
    assert!(
        problem.n_rows() > 2 * chrono_core::descriptor::UNIT_ROWS,
        "{} rows",
        problem.n_rows()
    );
    // Cold and warm-started (from a perturbed solution: the restart and backtracking
    // branches are taken).
    check(&problem, &vec![0.0; problem.n_rows()]);
    let warm: Vec<f64> = solution
        .iter()
        .enumerate()
        .map(|(i, g)| g * (1.0 + 0.3 * ((i % 7) as f64 - 3.0) / 3.0))
        .collect();
    check(&problem, &warm);
}

/// On a problem with other sections `gradient_by_units` gives the plain gradient and visits
/// every unit of rows once, in order.
#[test]
fn gradient_by_units_falls_back_on_mixed_problems() {
    use chrono_core::descriptor::{CcpWork, UNIT_ROWS};
    let problem = chrono_ccp::testing::random_problem(3).unwrap();
    assert!(!problem.is_friction_only());
    let m = problem.n_rows();
    let gamma: Vec<f64> = (0..m).map(|i| 0.1 * (i % 5) as f64).collect();
    let mut work = CcpWork::for_problem(&problem);
    let mut plain = vec![0.0; m];
    problem.gradient(&gamma, &mut plain, &mut work);
    let mut by_units = vec![0.0; m];
    let mut ranges = Vec::new();
    problem.gradient_by_units(
        &gamma,
        &mut by_units,
        &mut work,
        &mut ranges,
        |rows, out| {
            assert_eq!(rows.len(), out.len());
            rows
        },
    );
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&by_units), bits(&plain));
    let expect: Vec<_> = (0..m)
        .step_by(UNIT_ROWS)
        .map(|s| s..(s + UNIT_ROWS).min(m))
        .collect();
    assert_eq!(ranges, expect);
}
