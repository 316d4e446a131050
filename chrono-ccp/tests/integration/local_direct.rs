//! `LocalDirect` (block Gauss–Seidel: heavy bodies' rows by ADMM, the rest by APGD): on
//! random problems with the split forced (every body at or above the median mass counts as
//! heavy), the answer satisfies complementarity and has APGD's objective; without heavy
//! bodies it is APGD.

use chrono_ccp::testing::{check_complementarity, objective, random_problem};
use chrono_ccp::{
    Apgd, CcpSolver, FarSolver, LocalDirect, LocalDirectOptions, Psor, SolverSettings,
};
use proptest::prelude::*;

fn settings(tolerance: f64, max_iterations: usize) -> SolverSettings {
    SolverSettings {
        tolerance,
        max_iterations,
        record_history: false,
    }
}

fn forced_split_with(tolerance: f64, far_solver: FarSolver) -> LocalDirect {
    LocalDirect::new(settings(tolerance, 200_000)).with_options(LocalDirectOptions {
        heavy_ratio: 1.0,
        hops: 0,
        far_solver,
        ..LocalDirectOptions::default()
    })
}

/// The forced split with the far solver `far` on the random problem of `seed`: converged,
/// complementary, and APGD's objective.
fn check_forced_split(seed: u64, far: FarSolver) -> Result<(), TestCaseError> {
    let problem = random_problem(seed).unwrap();
    let mut s = forced_split_with(1e-11, far);
    let mut g = vec![0.0; problem.n_rows()];
    let stats = s.solve(&problem, &mut g);
    prop_assert!(stats.converged, "{stats:?}");
    if let Err(e) = check_complementarity(&problem, &g, 1e-9) {
        return Err(TestCaseError::fail(format!("{e}\ngamma = {g:?}")));
    }
    let mut ga = vec![0.0; problem.n_rows()];
    let sa = Apgd::new(settings(1e-11, 200_000)).solve(&problem, &mut ga);
    prop_assert!(sa.converged);
    let (f, fa) = (objective(&problem, &g), objective(&problem, &ga));
    prop_assert!((f - fa).abs() <= 1e-8 * (1.0 + fa.abs()), "{f} vs {fa}");
    prop_assert!((f - stats.objective).abs() <= 1e-12 * (1.0 + f.abs()));
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn forced_split_satisfies_complementarity_and_matches_apgd(seed in any::<u64>()) {
        check_forced_split(seed, FarSolver::Apgd)?;
    }

    /// The same with accelerated PSOR on the far block: the block Gauss-Seidel's answer
    /// does not depend on the far block's solver.
    #[test]
    fn forced_split_with_apsor_far_satisfies_complementarity_and_matches_apgd(seed in any::<u64>()) {
        check_forced_split(seed, FarSolver::Apsor)?;
    }
}

#[test]
fn without_heavy_bodies_the_apsor_far_solver_is_apsor_bit_for_bit() {
    let problem = random_problem(7).unwrap();
    let mut g = vec![0.0; problem.n_rows()];
    let options = LocalDirectOptions {
        far_solver: FarSolver::Apsor,
        ..LocalDirectOptions::default()
    };
    let s = LocalDirect::new(settings(1e-9, 10_000))
        .with_options(options)
        .solve(&problem, &mut g);
    let mut ga = vec![0.0; problem.n_rows()];
    let sa = Psor::accelerated(settings(1e-9, 10_000)).solve(&problem, &mut ga);
    assert_eq!(s.iterations, sa.iterations);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&g), bits(&ga));
}

#[test]
fn without_heavy_bodies_it_is_apgd_bit_for_bit() {
    let problem = random_problem(7).unwrap();
    let mut g = vec![0.0; problem.n_rows()];
    let s = LocalDirect::new(settings(1e-9, 10_000)).solve(&problem, &mut g);
    let mut ga = vec![0.0; problem.n_rows()];
    let sa = Apgd::new(settings(1e-9, 10_000)).solve(&problem, &mut ga);
    assert_eq!(s.iterations, sa.iterations);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&g), bits(&ga));
}
