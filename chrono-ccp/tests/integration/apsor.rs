//! The accelerated PSOR (`apsor`): the exact block step of a sphere triplet solves a lone
//! contact in one sweep; on a settled granular pile (matrix-free triplets, fused rows,
//! partitioned sweeps) it reaches APGD's solution; the partitioned sweeps are reproducible
//! for a thread count and equal the sequential sweeps on one thread.

use chrono_ccp::testing::{check_complementarity, granular_pile, lattice, objective};
use chrono_ccp::{Apgd, CcpSolver, Psor, SolverSettings, TripletStep};
use chrono_core::descriptor::{CcpProblem, ConstraintRows, MassOperator, RowEntry, Variables};
use chrono_core::math::{Matrix3, Vector3};
use proptest::prelude::*;

fn settings(tolerance: f64, max_iterations: usize) -> SolverSettings {
    SolverSettings {
        tolerance,
        max_iterations,
        record_history: false,
    }
}

/// A fingerprint of `v`'s bits (so a failed comparison does not print the vectors).
fn bits(v: &[f64]) -> u64 {
    v.iter().fold(0u64, |h, x| {
        h.rotate_left(5) ^ x.to_bits().wrapping_mul(0x9e37_79b9_7f4a_7c15)
    })
}

/// A sphere (mass `m`, inertia `j`, radius `radius`) touching a fixed body along the unit
/// normal `n` (pointing into the sphere), friction `mu`, free velocity `v`, `w` (m/s,
/// rad/s): its triplet's block is `diag(1/m, 1/m + R^2/J, 1/m + R^2/J)`.
fn sphere_contact(
    m: f64,
    j: f64,
    radius: f64,
    n: Vector3<f64>,
    mu: f64,
    v: Vector3<f64>,
    w: Vector3<f64>,
) -> CcpProblem {
    let mut vars = Variables::new();
    let b = vars.add(MassOperator::rigid_body(m, Matrix3::identity() * j).unwrap());
    let (u, t) = chrono_core::math::tangent_frame(&n);
    let arm = -radius * n;
    let coefs: Vec<[f64; 6]> = [n, u, t]
        .iter()
        .map(|d| {
            let a = arm.cross(d);
            [d.x, d.y, d.z, a.x, a.y, a.z]
        })
        .collect();
    let entry = |k: usize| {
        [RowEntry {
            block: b,
            coefs: &coefs[k],
        }]
    };
    let mut rows = ConstraintRows::new();
    rows.push_friction(mu, [&entry(0), &entry(1), &entry(2)], [0.0; 3], [0.0; 3]);
    let k = [m * v.x, m * v.y, m * v.z, j * w.x, j * w.y, j * w.z];
    let mut p = CcpProblem::new();
    p.assemble(&vars, &rows, &k).unwrap();
    p
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Exact block minimization: one sweep of `TripletStep::Exact` on a lone sphere
    /// contact lands on the solution, whether it sticks, slides or separates (from a cold
    /// start and from a random warm start).
    #[test]
    fn exact_step_solves_a_lone_sphere_contact_in_one_sweep(
        m in 0.1f64..10.0,
        jr in 0.2f64..0.6,
        radius in 0.005f64..0.5,
        nx in -1.0f64..1.0, ny in -1.0f64..1.0, nz in 0.2f64..1.0,
        mu in 0.0f64..1.5,
        vx in -2.0f64..2.0, vy in -2.0f64..2.0, vz in -3.0f64..1.0,
        wx in -5.0f64..5.0, wy in -5.0f64..5.0, wz in -5.0f64..5.0,
        warm in prop::array::uniform3(-1.0f64..1.0),
    ) {
        let j = jr * m * radius * radius;
        let n = Vector3::new(nx, ny, nz).normalize();
        let p = sphere_contact(m, j, radius, n, mu, Vector3::new(vx, vy, vz), Vector3::new(wx, wy, wz));
        for start in [[0.0; 3], warm] {
            let mut g = start.to_vec();
            let mut s = Psor::new(settings(0.0, 1)).with_triplet_step(TripletStep::Exact);
            s.solve(&p, &mut g);
            // velocities are O(1 m/s): 1e-12 m/s is round-off
            if let Err(e) = check_complementarity(&p, &g, 1e-12) {
                return Err(TestCaseError::fail(format!("{e}: g = {g:?}")));
            }
        }
    }
}

/// The pile's last problem (about 6 000 contacts, enough for two parts of 2 048
/// triplets) and APGD's converged solution.
fn pile() -> (CcpProblem, Vec<f64>, f64) {
    let (p, _, _) = granular_pile(6000, 3, 1e-3).unwrap();
    assert!(
        p.n_matrix_free() > 4096,
        "{} matrix-free",
        p.n_matrix_free()
    );
    let mut g = vec![0.0; p.n_rows()];
    let s = Apgd::new(settings(1e-8, 50_000)).solve(&p, &mut g);
    assert!(s.converged, "{s:?}");
    let f = objective(&p, &g);
    (p, g, f)
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
}

#[test]
fn accelerated_psor_reaches_the_apgd_solution_on_a_granular_pile() {
    let (p, _, f0) = pile();
    for threads in [1, 2] {
        let (g, stats) = pool(threads).install(|| {
            let mut g = vec![0.0; p.n_rows()];
            let stats = Psor::accelerated(settings(1e-7, 20_000)).solve(&p, &mut g);
            (g, stats)
        });
        assert!(stats.converged, "{threads} threads: {stats:?}");
        check_complementarity(&p, &g, 1e-5).unwrap();
        let f = objective(&p, &g);
        assert!(
            (f - f0).abs() <= 1e-6 * f0.abs(),
            "{threads} threads: objective {f} vs APGD {f0}"
        );
        assert!((f - stats.objective).abs() <= 1e-12 * f.abs());
    }
}

#[test]
fn partitioned_sweeps_are_reproducible_and_sequential_on_one_thread() {
    // particles on a lattice (blocks layer by layer): the two parts are the lower and
    // upper layers, the interface the contacts between them, all loaded
    let p = lattice(16, 16, 8, 5).unwrap();
    assert!(p.sections().friction.len() / 3 > 4096);
    let run = |threads: usize, partitioned: bool| {
        pool(threads).install(|| {
            let mut s = Psor::accelerated(settings(0.0, 10));
            s.options_mut().partitioned = partitioned;
            let mut g = vec![0.0; p.n_rows()];
            s.solve(&p, &mut g);
            bits(&g)
        })
    };
    assert_eq!(
        run(2, true),
        run(2, true),
        "two solves on two threads differ"
    );
    assert_eq!(
        run(1, true),
        run(1, false),
        "one thread: parts are not sequential"
    );
    assert_ne!(
        run(2, true),
        run(1, false),
        "two threads swept sequentially"
    );
}

#[test]
fn matrix_free_and_explicit_sweeps_agree_to_rounding() {
    let (p, warm, _) = pile();
    let run = |matrix_free: bool| {
        let mut s = Psor::accelerated(settings(0.0, 3));
        s.options_mut().matrix_free = matrix_free;
        s.options_mut().partitioned = false;
        let mut g: Vec<f64> = warm.iter().map(|g| 0.5 * g).collect();
        s.solve(&p, &mut g);
        g
    };
    let (a, b) = (run(true), run(false));
    let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() <= 1e-9 * scale, "{x} vs {y}");
    }
}
