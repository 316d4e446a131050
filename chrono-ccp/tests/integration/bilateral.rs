//! Bilateral-only problems: CG and MINRES against a dense solve, and the two-phase strategy.

use chrono_ccp::testing::{check_complementarity, dense_n, gradient, random_problem};
use chrono_ccp::{
    CcpSolver, Cg, KrylovOptions, Minres, SolverSettings, TwoPhase, check_bilateral,
    relative_residual,
};
use chrono_core::descriptor::{
    CcpProblem, CcpWork, ConstraintRows, MassOperator, RowEntry, Variables,
};
use chrono_core::rng::Rng;
use nalgebra::DVector;
use proptest::prelude::*;

/// A particle net (`nx x ny`, spacing 1) with distance rows between neighbours, the corners
/// pinned by point rows (independent rows), random stabilization terms, under gravity:
/// bilateral only, SPD.
pub fn net(nx: usize, ny: usize, eps: f64, seed: u64) -> CcpProblem {
    let mut rng = Rng::splitmix64(seed);
    let mut vars = Variables::new();
    let ids: Vec<_> = (0..nx * ny)
        .map(|_| vars.add(MassOperator::particle(rng.range(0.5, 2.0)).unwrap()))
        .collect();
    let mut rows = ConstraintRows::new();
    for y in 0..ny {
        for x in 0..nx {
            let i = ids[y * nx + x];
            for (dx, dy, d) in [(1, 0, [1.0, 0.0, 0.0]), (0, 1, [0.0, 1.0, 0.0])] {
                if x + dx < nx && y + dy < ny {
                    let j = ids[(y + dy) * nx + x + dx];
                    let nd = [-d[0], -d[1], -d[2]];
                    let e = [
                        RowEntry {
                            block: j,
                            coefs: &d,
                        },
                        RowEntry {
                            block: i,
                            coefs: &nd,
                        },
                    ];
                    rows.push_bilateral(&e, rng.range(-0.01, 0.01), eps);
                }
            }
            // Pins: z at the four corners, x and y at the first one (rows independent).
            if (x == 0 || x == nx - 1) && (y == 0 || y == ny - 1) {
                let first = x == 0 && y == 0;
                for (a, d) in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
                    .iter()
                    .enumerate()
                {
                    if a == 2 || first {
                        rows.push_bilateral(&[RowEntry { block: i, coefs: d }], 0.0, eps);
                    }
                }
            }
        }
    }
    let mut k = vec![0.0; vars.ndof()];
    for (p, kp) in k.chunks_mut(3).enumerate() {
        kp[0] = rng.range(-0.1, 0.1);
        kp[2] = -(p as f64 % 3.0 + 1.0) * 0.01;
    }
    let mut p = CcpProblem::new();
    p.assemble(&vars, &rows, &k).unwrap();
    p
}

fn settings(tol: f64) -> SolverSettings {
    SolverSettings {
        tolerance: tol,
        max_iterations: 20_000,
        record_history: true,
    }
}

#[test]
fn cg_and_minres_match_a_dense_solve() {
    let problem = net(6, 5, 1e-4, 3);
    assert!(check_bilateral(&problem).is_ok());
    let n = dense_n(&problem);
    let exact = n
        .clone()
        .cholesky()
        .unwrap()
        .solve(&(-DVector::from_column_slice(problem.r())));
    let solvers: Vec<Box<dyn CcpSolver>> = vec![
        Box::new(Cg::new(settings(1e-12))),
        Box::new(Minres::new(settings(1e-12))),
    ];
    for mut s in solvers {
        let mut g = vec![0.0; problem.n_rows()];
        let st = s.solve(&problem, &mut g);
        assert!(st.converged, "{}: {st:?}", s.name());
        let err = (DVector::from_column_slice(&g) - &exact).amax();
        assert!(
            err < 1e-9 * exact.amax().max(1.0),
            "{}: error {err:e}",
            s.name()
        );
        assert!(!st.history.is_empty() && st.history.len() == st.iterations);
        assert!(st.history.last().unwrap().residual <= 1e-12);
        assert!(st.apply_n > st.iterations);
    }
}

#[test]
fn krylov_reaches_a_relative_residual_of_1e_8_on_a_larger_net() {
    // 60 x 60 particles: ~7.1k rows, condition number ~1e4 (the full 100k-row run is
    // `cargo xtask validate ccp-solvers`).
    let problem = net(60, 60, 0.0, 5);
    let opts = KrylovOptions {
        relative_tolerance: 1e-8,
        preconditioned: true,
    };
    let solvers: Vec<Box<dyn CcpSolver>> = vec![
        Box::new(Cg::new(settings(0.0)).with_options(opts.clone())),
        Box::new(Minres::new(settings(0.0)).with_options(opts)),
    ];
    for mut s in solvers {
        let mut g = vec![0.0; problem.n_rows()];
        let st = s.solve(&problem, &mut g);
        let c = gradient(&problem, &g);
        let rel = relative_residual(&problem, &c, &mut CcpWork::for_problem(&problem));
        assert!(
            st.converged && rel <= 1e-8,
            "{}: rel {rel:e}, {} its",
            s.name(),
            st.iterations
        );
    }
}

#[test]
fn krylov_refuses_problems_with_cone_rows() {
    let problem = chrono_ccp::testing::particle_on_ground(1.0, 0.5, [0.0; 3], 0.01).unwrap();
    let e = check_bilateral(&problem).unwrap_err();
    assert!(e.to_string().contains("non-bilateral"), "{e}");
    let mut g = vec![0.0; 3];
    let st = Cg::new(settings(1e-8)).solve(&problem, &mut g);
    assert!(!st.converged && st.iterations == 0);
    let st = Minres::new(settings(1e-8)).solve(&problem, &mut g);
    assert!(!st.converged && st.iterations == 0);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    #[test]
    fn two_phase_solves_mixed_problems(seed in any::<u64>()) {
        let problem = random_problem(seed).unwrap();
        let mut g = vec![0.0; problem.n_rows()];
        let st = TwoPhase::new(SolverSettings { tolerance: 1e-11, max_iterations: 100_000, record_history: true })
            .solve(&problem, &mut g);
        prop_assert!(st.converged, "{st:?}");
        prop_assert!(check_complementarity(&problem, &g, 1e-9).is_ok());
        // history numbering continues across the phases
        prop_assert!(st.history.windows(2).all(|w| w[1].iteration > w[0].iteration && w[1].apply_n >= w[0].apply_n));
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    /// The bilateral rows of random problems (others held at zero): CG and MINRES agree with
    /// every CCP solver on the objective and satisfy `N g + r = 0`.
    #[test]
    fn krylov_agrees_with_the_ccp_solvers_on_bilateral_problems(seed in any::<u64>()) {
        let full = random_problem(seed).unwrap();
        let nb = full.sections().bilateral.len();
        prop_assume!(nb > 0);
        let mut p = CcpProblem::new();
        full.subproblem(0..nb, &vec![0.0; full.n_rows()], &mut p).unwrap();
        let s = SolverSettings { tolerance: 1e-11, max_iterations: 200_000, record_history: false };
        let mut objectives = Vec::new();
        for name in ["cg", "minres", "jacobi", "psor", "apgd", "bb"] {
            let mut solver = chrono_ccp::by_name(name, s.clone()).unwrap();
            let mut g = vec![0.0; p.n_rows()];
            let st = solver.solve(&p, &mut g);
            prop_assert!(st.converged, "{name}: {st:?}");
            prop_assert!(check_complementarity(&p, &g, 1e-9).is_ok(), "{name}");
            objectives.push((name, st.objective));
        }
        let f0 = objectives[0].1;
        for (name, f) in &objectives {
            prop_assert!((f - f0).abs() <= 1e-9 * (1.0 + f0.abs()), "{name}: {f} vs cg {f0}");
        }
    }
}
