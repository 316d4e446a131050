//! Bit-for-bit reproducibility: the same solve twice, and under different rayon thread
//! counts, gives the same `gamma`. The problem is large enough (> 100k rows) that every
//! parallel path of the solvers and of the problem's operations is taken.

mod common;

use chrono_ccp::{Apgd, CcpSolver, Psor, SolverSettings};
use chrono_core::descriptor::{CcpProblem, ConstraintRows, MassOperator, RowEntry, Variables};
use common::{G, Rng};

/// Particles on a lattice (spacing 1), frictional contacts between lattice neighbours and
/// with the ground, random small gaps `b` and random velocities.
fn lattice(nx: usize, ny: usize, nz: usize, seed: u64) -> CcpProblem {
    let mut rng = Rng(seed);
    let mut vars = Variables::new();
    let idx = |x: usize, y: usize, z: usize| (z * ny + y) * nx + x;
    let mut ids = Vec::new();
    for _ in 0..nx * ny * nz {
        ids.push(vars.add(MassOperator::particle(rng.uniform(0.5, 1.5)).unwrap()));
    }
    let axes: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let neg = |a: [f64; 3]| [-a[0], -a[1], -a[2]];
    let frame = |a: usize| (axes[a], axes[(a + 1) % 3], axes[(a + 2) % 3]);
    let mut rows = ConstraintRows::new();
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                let i = ids[idx(x, y, z)];
                let gap = |rng: &mut Rng| rng.uniform(-0.01, 0.01);
                if z == 0 {
                    let (n, u, w) = frame(2);
                    let rn = [RowEntry { block: i, coefs: &n }];
                    let ru = [RowEntry { block: i, coefs: &u }];
                    let rw = [RowEntry { block: i, coefs: &w }];
                    rows.push_friction(0.5, [&rn, &ru, &rw], [gap(&mut rng), 0.0, 0.0], [0.0; 3]);
                }
                for (a, (dx, dy, dz)) in [(1, 0, 0), (0, 1, 0), (0, 0, 1)].into_iter().enumerate() {
                    let (x2, y2, z2) = (x + dx, y + dy, z + dz);
                    if x2 >= nx || y2 >= ny || z2 >= nz {
                        continue;
                    }
                    let j = ids[idx(x2, y2, z2)];
                    let (n, u, w) = frame(a);
                    let (nn, nu, nw) = (neg(n), neg(u), neg(w));
                    let rn = [RowEntry { block: j, coefs: &n }, RowEntry { block: i, coefs: &nn }];
                    let ru = [RowEntry { block: j, coefs: &u }, RowEntry { block: i, coefs: &nu }];
                    let rw = [RowEntry { block: j, coefs: &w }, RowEntry { block: i, coefs: &nw }];
                    rows.push_friction(0.3, [&rn, &ru, &rw], [gap(&mut rng), 0.0, 0.0], [0.0, 1e-6, 1e-6]);
                }
            }
        }
    }
    let mut k = vec![0.0; vars.ndof()];
    for (p, kp) in k.chunks_mut(3).enumerate() {
        let m = match vars.mass(ids[p]) {
            MassOperator::Particle { mass } => *mass,
            _ => unreachable!(),
        };
        kp[0] = m * rng.uniform(-0.1, 0.1);
        kp[1] = m * rng.uniform(-0.1, 0.1);
        kp[2] = m * (rng.uniform(-0.1, 0.1) - G * 0.01);
    }
    let mut problem = CcpProblem::new();
    problem.assemble(&vars, &rows, &k).unwrap();
    problem
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn same_gamma_for_any_thread_count() {
    let problem = lattice(24, 24, 22, 7);
    assert!(problem.n_rows() > 100_000, "{} rows", problem.n_rows());
    let settings = SolverSettings { tolerance: 0.0, max_iterations: 15, record_history: false };
    let make: [fn(SolverSettings) -> Box<dyn CcpSolver>; 2] =
        [|s| Box::new(Psor::new(s).with_symmetric(true)), |s| Box::new(Apgd::new(s))];
    for new in make {
        let run = || {
            let mut s = new(settings.clone());
            let mut gamma = vec![0.0; problem.n_rows()];
            let stats = s.solve(&problem, &mut gamma);
            (bits(&gamma), stats.residual.to_bits(), stats.objective.to_bits(), s.name())
        };
        let a = run();
        let b = run();
        assert!(a == b, "{}: two runs differ", a.3);
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let c = pool.install(run);
            assert!(a == c, "{}: default pool and a {threads}-thread pool differ", a.3);
        }
    }
}
