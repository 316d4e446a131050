//! `LocalDirect` (block Gauss–Seidel: heavy bodies' rows by ADMM, the rest by APGD): on
//! random problems with the split forced (every body at or above the median mass counts as
//! heavy), the answer satisfies complementarity and has APGD's objective; on a stack with a
//! mass ratio of 10 per level, it converges where the heavy rows make APGD slow.

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
fn heavy_box_on_a_bed_converges_with_its_columns_direct() {
    // A box of 1000 sphere masses on the middle 2 x 2 columns of a 6 x 6 x 3 bed: the box's
    // rows and two contact hops (its columns down to the ground, and their neighbours) are
    // local, the rest of the bed far. From a cold start to 1e-6 m/s.
    let (problem, reference) = heavy_on_bed(6, 3, 2, 1000.0, 3).unwrap();
    let mut s = LocalDirect::new(settings(1e-6, 100_000));
    let mut g = vec![0.0; problem.n_rows()];
    let stats = s.solve(&problem, &mut g);
    assert!(stats.converged, "{stats:?}");
    let local = s.local_rows().len();
    assert!(
        local > 0 && local < problem.n_rows(),
        "both blocks: {local} local of {}",
        problem.n_rows()
    );
    check_complementarity(&problem, &g, 2e-5).unwrap();
    let mut ga = vec![0.0; problem.n_rows()];
    let sa = Apgd::new(settings(1e-6, 100_000)).solve(&problem, &mut ga);
    assert!(sa.converged);
    let (f, fr) = (objective(&problem, &g), objective(&problem, &reference));
    assert!((f - fr).abs() <= 1e-5 * fr.abs(), "{f} vs ADMM's {fr}");
    // The box (the last block) moves as in the converged answer.
    let dv = |a: &[f64]| {
        let e: Vec<f64> = a.iter().zip(&reference).map(|(x, y)| x - y).collect();
        let mut v = vec![0.0; problem.ndof()];
        problem.minv_d(&e, &mut v);
        v[problem.ndof() - 6..]
            .iter()
            .fold(0.0_f64, |m, x| m.max(x.abs()))
    };
    eprintln!(
        "local-direct: {} sweeps, {} products, {local} local rows of {}, box dv {:.1e}; apgd {} iterations, {} products, box dv {:.1e}",
        stats.iterations,
        stats.apply_n,
        problem.n_rows(),
        dv(&g),
        sa.iterations,
        sa.apply_n,
        dv(&ga)
    );
    assert!(dv(&g) < 1e-4, "box velocity error {:.1e}", dv(&g));
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
