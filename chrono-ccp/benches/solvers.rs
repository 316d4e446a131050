//! Cost of the building blocks and of every solver's iteration on a granular-like problem:
//! ~10k particles on a lattice with frictional contacts between lattice neighbours and with
//! the ground (~29.6k triplets, ~89k rows), or on a captured problem file given by the
//! environment variable `CCP_BENCH_PROBLEM` (e.g. `target/validation/ccp-solvers/pile_10000.ccp`
//! written by `cargo xtask validate ccp-solvers`).
//!
//! - `apply_n`: one product `N g` (the unit of cost of every iterative solver); `residual`
//!   and `project`, the other per-iteration operations of the problem;
//! - `<solver>/solve_k`: a cold solve capped at k iterations (tolerance 0). A solve has a
//!   fixed cost (projection, the initial and final gradients, power iterations), so the
//!   cost of one iteration is `(t(11) - t(1)) / 10`.
//!
//! Run: `cargo bench -p chrono-ccp --bench solvers`.

use std::hint::black_box;

use chrono_ccp::{SolverSettings, by_name};
use chrono_core::descriptor::{CcpWork, ProblemFile};
use criterion::{Criterion, criterion_group, criterion_main};

fn bench(c: &mut Criterion) {
    let problem = match std::env::var("CCP_BENCH_PROBLEM") {
        Ok(path) => ProblemFile::load_problem(&path).expect("CCP_BENCH_PROBLEM"),
        Err(_) => chrono_ccp::testing::lattice(22, 22, 21, 1).unwrap(),
    };
    let m = problem.n_rows();
    let mut work = CcpWork::for_problem(&problem);
    let gamma: Vec<f64> = (0..m)
        .map(|i| if i % 3 == 0 { 0.01 } else { 0.0 })
        .collect();
    let mut out = vec![0.0; m];
    c.bench_function("apply_n", |b| {
        b.iter(|| problem.apply_n(black_box(&gamma), &mut out, &mut work))
    });
    problem.gradient(&gamma, &mut out, &mut work);
    c.bench_function("residual", |b| {
        b.iter(|| problem.residual(black_box(&gamma), &out, &mut work))
    });
    let mut projected = gamma.clone();
    c.bench_function("project", |b| {
        b.iter(|| problem.project(black_box(&mut projected)))
    });

    for name in ["jacobi", "psor", "apsor", "apgd", "bb"] {
        for k in [1, 11] {
            let settings = SolverSettings {
                tolerance: 0.0,
                max_iterations: k,
                record_history: false,
            };
            let mut solver = by_name(name, settings).expect("known solver");
            let mut g = vec![0.0; m];
            c.bench_function(&format!("{name}/solve_{k}"), |b| {
                b.iter(|| {
                    g.fill(0.0);
                    solver.solve(&problem, &mut g)
                })
            });
        }
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench
}
criterion_main!(benches);
