//! Problems with a known answer, for both solvers.

use chrono_ccp::testing::{check_complementarity, dense_n, particle_on_ground, rigid_coefs};
use chrono_ccp::{Apgd, CcpSolver, Psor, SolverSettings};
use chrono_core::descriptor::{CcpProblem, ConstraintRows, MassOperator, RowEntry, Variables};
use chrono_core::math::GRAVITY;
use chrono_core::math::{Matrix3, Vector3};
use nalgebra::DVector;

const TOL: f64 = 1e-12;

fn solvers() -> Vec<Box<dyn CcpSolver>> {
    let s = SolverSettings {
        tolerance: TOL,
        max_iterations: 10_000,
        record_history: false,
    };
    vec![Box::new(Psor::new(s.clone())), Box::new(Apgd::new(s))]
}

fn solve(solver: &mut dyn CcpSolver, problem: &CcpProblem) -> Vec<f64> {
    let mut gamma = vec![0.0; problem.n_rows()];
    let stats = solver.solve(problem, &mut gamma);
    assert!(stats.converged, "{}: {stats:?}", solver.name());
    assert!(stats.residual <= TOL);
    check_complementarity(problem, &gamma, 1e-10).unwrap();
    gamma
}

#[test]
fn particle_resting_on_ground() {
    let (m, h) = (2.0, 0.01);
    let problem = particle_on_ground(m, 0.5, [0.0; 3], h).unwrap();
    for mut s in solvers() {
        let g = solve(s.as_mut(), &problem);
        assert!(
            (g[0] - m * (-GRAVITY.z) * h).abs() < 1e-10,
            "{}: g_n = {}",
            s.name(),
            g[0]
        );
        assert!(
            g[1].abs() < 1e-10 && g[2].abs() < 1e-10,
            "{}: {g:?}",
            s.name()
        );
    }
}

#[test]
fn sliding_particle_friction_saturates_against_the_slip() {
    // Sliding at 1 m/s along +x: the momentum m v = 2 N s far exceeds the friction available in
    // one step, so the friction impulse is on the cone surface, along -x. The CCP (Anitescu's
    // convexification) also gives the sliding contact a separating normal velocity
    // c_n = mu |v_t+|, so with v_t+ = v - mu g_n / m:  g_n = m (g h + mu v) / (1 + mu^2).
    let (m, h, mu, v) = (2.0, 0.01, 0.3, 1.0);
    let problem = particle_on_ground(m, mu, [v, 0.0, 0.0], h).unwrap();
    let gn = m * ((-GRAVITY.z) * h + mu * v) / (1.0 + mu * mu);
    for mut s in solvers() {
        let g = solve(s.as_mut(), &problem);
        assert!(
            (g[0] - gn).abs() < 1e-10,
            "{}: g_n = {} expected {gn}",
            s.name(),
            g[0]
        );
        assert!(
            (g[1] + mu * g[0]).abs() < 1e-10,
            "{}: g_u = {} expected {}",
            s.name(),
            g[1],
            -mu * g[0]
        );
        assert!(g[2].abs() < 1e-10);
        let mut vel = vec![0.0; 3];
        problem.velocities(&g, &mut vel);
        assert!(
            vel[0] > 0.0 && (vel[0] - (v + g[1] / m)).abs() < 1e-12,
            "still sliding forward: {vel:?}"
        );
        assert!(
            (vel[2] - mu * vel[0]).abs() < 1e-10,
            "CCP separation velocity mu |v_t|: {vel:?}"
        );
    }
}

#[test]
fn particle_pushed_less_than_friction_sticks() {
    // m v = 0.02 N s < mu m g h = 0.0491 N s: friction stops it within the step.
    let (m, h, mu, v) = (2.0, 0.01, 0.5, 0.01);
    let problem = particle_on_ground(m, mu, [v, -0.5 * v, 0.0], h).unwrap();
    for mut s in solvers() {
        let g = solve(s.as_mut(), &problem);
        assert!(
            (g[0] - m * (-GRAVITY.z) * h).abs() < 1e-10,
            "{}: {g:?}",
            s.name()
        );
        assert!(
            (g[1] + m * v).abs() < 1e-10 && (g[2] - 0.5 * m * v).abs() < 1e-10,
            "{}: {g:?}",
            s.name()
        );
        let mut vel = vec![0.0; 3];
        problem.velocities(&g, &mut vel);
        assert!(
            vel.iter().all(|x| x.abs() < 1e-10),
            "{}: v+ = {vel:?}",
            s.name()
        );
        assert!(g[1].hypot(g[2]) < mu * g[0], "strictly inside the cone");
    }
}

#[test]
fn bilateral_only_matches_a_dense_linear_solve() {
    // A rigid body hanging from a spherical joint at a point off its center of mass (3 rows),
    // and a particle attached to the body by a distance constraint (1 row), with compliance
    // on one row and stabilization terms b: the answer is N g = -r.
    let h = 0.01;
    let mut vars = Variables::new();
    let j = Matrix3::new(0.4, 0.02, 0.0, 0.02, 0.3, 0.01, 0.0, 0.01, 0.5);
    let body = vars.add(MassOperator::rigid_body(3.0, j).unwrap());
    let part = vars.add(MassOperator::particle(0.7).unwrap());
    let mut rows = ConstraintRows::new();
    let pivot = Vector3::new(0.1, -0.2, 0.6); // joint point from the body's center of mass
    let coefs: Vec<[f64; 6]> = [Vector3::x(), Vector3::y(), Vector3::z()]
        .iter()
        .map(|d| rigid_coefs(pivot, -d)) // ground-fixed point: v_point = 0
        .collect();
    for (k, c) in coefs.iter().enumerate() {
        rows.push_bilateral(
            &[RowEntry {
                block: body,
                coefs: c,
            }],
            0.01 * k as f64,
            if k == 1 { 1e-3 } else { 0.0 },
        );
    }
    let attach = Vector3::new(0.0, 0.3, -0.5);
    let dir = Vector3::new(0.3, 0.5, -1.0).normalize();
    let body_c = rigid_coefs(attach, -dir);
    let part_c = [dir.x, dir.y, dir.z];
    rows.push_bilateral(
        &[
            RowEntry {
                block: body,
                coefs: &body_c,
            },
            RowEntry {
                block: part,
                coefs: &part_c,
            },
        ],
        -0.02,
        0.0,
    );
    let k = [
        0.3,
        0.0,
        3.0 * GRAVITY.z * h,
        0.1,
        -0.2,
        0.05,
        0.0,
        0.1,
        0.7 * GRAVITY.z * h,
    ];
    let mut problem = CcpProblem::new();
    problem.assemble(&vars, &rows, &k).unwrap();

    let n = dense_n(&problem);
    let rhs = -DVector::from_column_slice(problem.r());
    let exact = n.lu().solve(&rhs).expect("N is invertible");
    for mut s in solvers() {
        let g = solve(s.as_mut(), &problem);
        for i in 0..4 {
            assert!(
                (g[i] - exact[i]).abs() < 1e-9 * (1.0 + exact[i].abs()),
                "{}: {g:?} vs {exact}",
                s.name()
            );
        }
    }
}

#[test]
fn box_and_unilateral_rows_on_one_particle() {
    // A particle moving at (1, -2, -3) m/s: a motor row along x with impulse bounds
    // [-0.5, 0.5] N s (saturates: it would need -1), a box row along y that can do it
    // ([-10, 10]: y velocity driven to 0), and a unilateral row along z (stops the fall).
    let m = 1.0;
    let mut vars = Variables::new();
    let p = vars.add(MassOperator::particle(m).unwrap());
    let mut rows = ConstraintRows::new();
    rows.push_box(
        &[RowEntry {
            block: p,
            coefs: &[1.0, 0.0, 0.0],
        }],
        0.0,
        0.0,
        -0.5,
        0.5,
    );
    rows.push_box(
        &[RowEntry {
            block: p,
            coefs: &[0.0, 1.0, 0.0],
        }],
        0.0,
        0.0,
        -10.0,
        10.0,
    );
    rows.push_unilateral(
        &[RowEntry {
            block: p,
            coefs: &[0.0, 0.0, 1.0],
        }],
        0.0,
        0.0,
    );
    let mut problem = CcpProblem::new();
    problem.assemble(&vars, &rows, &[1.0, -2.0, -3.0]).unwrap();
    for mut s in solvers() {
        let g = solve(s.as_mut(), &problem);
        assert_eq!(g[0], -0.5, "{}", s.name());
        assert!(
            (g[1] - 2.0).abs() < 1e-10 && (g[2] - 3.0).abs() < 1e-10,
            "{}: {g:?}",
            s.name()
        );
    }
}

#[test]
fn empty_problem_returns_at_once() {
    let mut vars = Variables::new();
    vars.add(MassOperator::particle(1.0).unwrap());
    let mut problem = CcpProblem::new();
    problem
        .assemble(&vars, &ConstraintRows::new(), &[0.0, 0.0, 1.0])
        .unwrap();
    for mut s in solvers() {
        let stats = s.solve(&problem, &mut []);
        assert!(
            stats.converged && stats.iterations == 0 && stats.residual == 0.0,
            "{stats:?}"
        );
    }
}

#[test]
fn non_finite_data_stops_the_solve() {
    // A finite but absurd momentum over a tiny mass overflows M^-1 k to infinity.
    let mut vars = Variables::new();
    let p = vars.add(MassOperator::particle(1e-10).unwrap());
    let mut rows = ConstraintRows::new();
    rows.push_unilateral(
        &[RowEntry {
            block: p,
            coefs: &[0.0, 0.0, 1.0],
        }],
        0.0,
        0.0,
    );
    rows.push_bilateral(
        &[RowEntry {
            block: p,
            coefs: &[1.0, 0.0, 0.0],
        }],
        0.0,
        0.0,
    );
    let mut problem = CcpProblem::new();
    if problem
        .assemble(&vars, &rows, &[1e300, 0.0, -1e300])
        .is_err()
    {
        return; // rejected at assembly: also acceptable
    }
    for mut s in solvers() {
        let mut gamma = vec![f64::NAN, 1.0];
        let stats = s.solve(&problem, &mut gamma);
        assert!(!stats.converged, "{}: {stats:?}", s.name());
        assert!(
            gamma.iter().all(|g| g.is_finite()),
            "{}: {gamma:?}",
            s.name()
        );
    }
}

#[test]
fn history_is_recorded_when_asked() {
    let problem = chrono_ccp::testing::box_stack(2, 0.5, 0.01).unwrap();
    let s = SolverSettings {
        tolerance: 1e-8,
        max_iterations: 5,
        record_history: true,
    };
    let solvers: Vec<Box<dyn CcpSolver>> =
        vec![Box::new(Psor::new(s.clone())), Box::new(Apgd::new(s))];
    for mut s in solvers {
        let mut gamma = vec![0.0; problem.n_rows()];
        let stats = s.solve(&problem, &mut gamma);
        assert_eq!(stats.history.len(), stats.iterations, "{}", s.name());
        assert!(
            stats
                .history
                .windows(2)
                .all(|w| w[1].time_s >= w[0].time_s && w[1].iteration == w[0].iteration + 1)
        );
        let best = stats
            .history
            .iter()
            .map(|r| r.residual)
            .fold(f64::INFINITY, f64::min);
        assert!(
            stats.residual <= best + 1e-15,
            "{}: returned {} but saw {best}",
            s.name(),
            stats.residual
        );
    }
}

#[test]
fn psor_triplet_step_is_safe_where_the_averaged_step_diverges() {
    // One particle, a "contact" whose tangent rows are nearly parallel to the normal row:
    // lambda_max(N_tt) is close to 3 mean(diag N_tt), so Chrono's averaged step 1/mean(diag)
    // overshoots (projected gradient needs h < 2/lambda_max) and PSOR cycles forever, while
    // the MaxEigen step descends and converges. APGD is unaffected.
    let mut vars = Variables::new();
    let p = vars.add(MassOperator::particle(1.0).unwrap());
    let (a, s) = (0.9, (1.0f64 - 0.81).sqrt());
    let (cu, cw) = ([a, s, 0.0], [a, 0.0, s]);
    let n = [RowEntry {
        block: p,
        coefs: &[1.0, 0.0, 0.0],
    }];
    let u = [RowEntry {
        block: p,
        coefs: &cu,
    }];
    let w = [RowEntry {
        block: p,
        coefs: &cw,
    }];
    let mut rows = ConstraintRows::new();
    rows.push_friction(0.5, [&n, &u, &w], [0.0; 3], [0.0; 3]);
    let mut problem = CcpProblem::new();
    problem.assemble(&vars, &rows, &[-1.0, 0.3, -0.2]).unwrap();
    let settings = SolverSettings {
        tolerance: 1e-10,
        max_iterations: 5000,
        record_history: false,
    };
    let mut gamma = vec![0.0; 3];
    let safe = Psor::new(settings.clone()).solve(&problem, &mut gamma);
    assert!(safe.converged, "{safe:?}");
    check_complementarity(&problem, &gamma, 1e-8).unwrap();
    let mut g2 = vec![0.0; 3];
    let avg = Psor::new(settings.clone())
        .with_triplet_step(chrono_ccp::TripletStep::Average)
        .solve(&problem, &mut g2);
    assert!(!avg.converged && avg.residual > 0.1, "{avg:?}");
    let mut g3 = vec![0.0; 3];
    assert!(Apgd::new(settings).solve(&problem, &mut g3).converged);
}
