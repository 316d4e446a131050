//! `LocalDirect` (block Gauss–Seidel: heavy bodies' rows by ADMM, the rest by APGD): on
//! random problems with the split forced (every body at or above the median mass counts as
//! heavy), the answer satisfies complementarity and has APGD's objective; without heavy
//! bodies it is APGD; a heavy box on a bed, warm-started as between steps, converges in a
//! few sweeps with the box's velocity right.

use chrono_ccp::testing::{check_complementarity, heavy_on_bed, objective, random_problem};
use chrono_ccp::{Apgd, CcpSolver, LocalDirect, LocalDirectOptions, SolverSettings};
use proptest::prelude::*;

fn settings(tolerance: f64, max_iterations: usize) -> SolverSettings {
    SolverSettings {
        tolerance,
        max_iterations,
        record_history: false,
    }
}

fn forced_split(tolerance: f64) -> LocalDirect {
    LocalDirect::new(settings(tolerance, 200_000)).with_options(LocalDirectOptions {
        heavy_ratio: 1.0,
        hops: 0,
        ..LocalDirectOptions::default()
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn forced_split_satisfies_complementarity_and_matches_apgd(seed in any::<u64>()) {
        let problem = random_problem(seed).unwrap();
        let mut s = forced_split(1e-11);
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
    }
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

/// A box of 1000 sphere masses on the middle 2 x 2 columns of a 6 x 6 x 3 bed, warm-started
/// as in a time step: the previous answer with every impulse 10 % low (the load grew). The
/// warm start's load path (the box's columns down to the ground) enters the local block, so
/// a few sweeps bring the box's velocity within 1e-5 m/s of the converged answer (a cold
/// start is the stack limit in docs/validation-rigid.md: thousands of sweeps).
#[test]
fn heavy_box_on_a_bed_from_a_warm_start_converges_in_a_few_sweeps() {
    let (problem, reference) = heavy_on_bed(6, 3, 2, 1000.0, 3).unwrap();
    let mut s = LocalDirect::new(settings(1e-7, 2000));
    let mut g: Vec<f64> = reference.iter().map(|x| 0.9 * x).collect();
    let stats = s.solve(&problem, &mut g);
    assert!(stats.converged, "{stats:?}");
    assert!(stats.iterations <= 20, "{} sweeps", stats.iterations);
    let local = s.local_rows().len();
    assert!(
        local > 0 && local < problem.n_rows(),
        "both blocks: {local} local of {}",
        problem.n_rows()
    );
    check_complementarity(&problem, &g, 1e-5).unwrap();
    let (f, fr) = (objective(&problem, &g), objective(&problem, &reference));
    assert!((f - fr).abs() <= 1e-6 * fr.abs(), "{f} vs ADMM's {fr}");
    // The box (the last block) moves as in the converged answer.
    let e: Vec<f64> = g.iter().zip(&reference).map(|(x, y)| x - y).collect();
    let mut v = vec![0.0; problem.ndof()];
    problem.minv_d(&e, &mut v);
    let dv = v[problem.ndof() - 6..]
        .iter()
        .fold(0.0_f64, |m, x| m.max(x.abs()));
    assert!(dv < 1e-5, "box velocity error {dv:.1e}");
}
