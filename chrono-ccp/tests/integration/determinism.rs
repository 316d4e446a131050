//! Bit-for-bit reproducibility: the same solve twice, and under different rayon thread
//! counts, gives the same `gamma`. The problem is large enough (> 100k rows) that every
//! parallel path of the solvers and of the problem's operations is taken.

use chrono_ccp::testing::lattice;
use chrono_ccp::{Apgd, BarzilaiBorwein, CcpSolver, Jacobi, Psor, SolverSettings, TwoPhase};

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn same_gamma_for_any_thread_count() {
    let problem = lattice(24, 24, 22, 7).unwrap();
    assert!(problem.n_rows() > 100_000, "{} rows", problem.n_rows());
    let settings = SolverSettings {
        tolerance: 0.0,
        max_iterations: 15,
        record_history: false,
    };
    let make: [fn(SolverSettings) -> Box<dyn CcpSolver>; 6] = [
        |s| Box::new(Psor::new(s).with_symmetric(true)),
        |s| Box::new(Psor::new(s).with_parallel(true).with_symmetric(true)),
        |s| Box::new(Apgd::new(s)),
        |s| Box::new(Jacobi::new(s)),
        |s| Box::new(BarzilaiBorwein::new(s)),
        |s| Box::new(TwoPhase::new(s)),
    ];
    for new in make {
        let run = || {
            let mut s = new(settings.clone());
            let mut gamma = vec![0.0; problem.n_rows()];
            let stats = s.solve(&problem, &mut gamma);
            (
                bits(&gamma),
                stats.residual.to_bits(),
                stats.objective.to_bits(),
                s.name(),
            )
        };
        let a = run();
        let b = run();
        assert!(a == b, "{}: two runs differ", a.3);
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let c = pool.install(run);
            assert!(
                a == c,
                "{}: default pool and a {threads}-thread pool differ",
                a.3
            );
        }
    }
}
