//! Rolling and spinning friction (6 rows per contact) on a rigid sphere resting on the
//! ground, against the analytic answers: below the rolling / spinning limits an applied
//! torque is cancelled exactly; above them the resisting impulse saturates at
//! `mu_r g_n` / `mu_s g_n` and the sphere turns.

use chrono_ccp::testing::check_complementarity;
use chrono_ccp::{SolverSettings, by_name};
use chrono_core::descriptor::{CcpProblem, ConstraintRows, MassOperator, RowEntry, Variables};
use chrono_core::math::GRAVITY;
use chrono_core::math::Matrix3;

const SOLVERS: [&str; 9] = [
    "jacobi",
    "psor",
    "psor-sym",
    "apgd",
    "bb",
    "two-phase",
    "schur",
    "admm",
    "local-direct",
];
const M: f64 = 2.0;
const R: f64 = 0.1;
const H: f64 = 0.01;
const MU: [f64; 3] = [0.5, 0.02, 0.01];

/// The sphere at rest at the origin (identity orientation), contact point `(0, 0, -R)`,
/// frame `n = z, u = x, w = y`, with torque `tau` (N m, body = world frame) over the step.
fn sphere(tau: [f64; 3]) -> CcpProblem {
    let mut vars = Variables::new();
    let i = 0.4 * M * R * R;
    let b = vars.add(MassOperator::rigid_body(M, Matrix3::from_diagonal_element(i)).unwrap());
    let rows: [[f64; 6]; 6] = [
        [0.0, 0.0, 1.0, 0.0, 0.0, 0.0], // n: contact point velocity along z
        [1.0, 0.0, 0.0, 0.0, -R, 0.0],  // u: v_x + (w x r)_x = v_x - R w_y
        [0.0, 1.0, 0.0, R, 0.0, 0.0],   // w: v_y + R w_x
        [0.0, 0.0, 0.0, 0.0, 0.0, 1.0], // spin about n
        [0.0, 0.0, 0.0, 1.0, 0.0, 0.0], // rolling about u
        [0.0, 0.0, 0.0, 0.0, 1.0, 0.0], // rolling about w
    ];
    let e: Vec<[RowEntry; 1]> = rows
        .iter()
        .map(|c| [RowEntry { block: b, coefs: c }])
        .collect();
    let mut cr = ConstraintRows::new();
    cr.push_rolling_friction(
        MU,
        [&e[0], &e[1], &e[2], &e[3], &e[4], &e[5]],
        [0.0; 6],
        [0.0; 6],
    );
    let k = [
        0.0,
        0.0,
        -M * (-GRAVITY.z) * H,
        tau[0] * H,
        tau[1] * H,
        tau[2] * H,
    ];
    let mut p = CcpProblem::new();
    p.assemble(&vars, &cr, &k).unwrap();
    p
}

fn solve(name: &str, p: &CcpProblem) -> (Vec<f64>, Vec<f64>) {
    let s = SolverSettings {
        tolerance: 1e-12,
        max_iterations: 100_000,
        record_history: false,
    };
    let mut solver = by_name(name, s).unwrap();
    let mut g = vec![0.0; 6];
    let st = solver.solve(p, &mut g);
    assert!(st.converged, "{name}: {st:?}");
    check_complementarity(p, &g, 1e-10).unwrap_or_else(|e| panic!("{name}: {e}"));
    let mut v = vec![0.0; 6];
    p.velocities(&g, &mut v);
    (g, v)
}

#[test]
fn torques_below_the_limits_are_cancelled() {
    let gn = M * (-GRAVITY.z) * H;
    // rolling torque about y and spinning torque about z, each at 80 % of its limit
    let tau = [
        0.0,
        0.8 * MU[2] * M * (-GRAVITY.z),
        0.8 * MU[1] * M * (-GRAVITY.z),
    ];
    let p = sphere(tau);
    for name in SOLVERS {
        let (g, v) = solve(name, &p);
        assert!((g[0] - gn).abs() < 1e-9, "{name}: g_n = {}", g[0]);
        assert!(
            (g[5] + tau[1] * H).abs() < 1e-9,
            "{name}: rolling impulse {}",
            g[5]
        );
        assert!(
            (g[3] + tau[2] * H).abs() < 1e-9,
            "{name}: spinning impulse {}",
            g[3]
        );
        assert!(v.iter().all(|x| x.abs() < 1e-8), "{name}: v+ = {v:?}");
    }
}

#[test]
fn torques_above_the_limits_saturate_the_cones() {
    let tau = [
        0.0,
        5.0 * MU[2] * M * (-GRAVITY.z),
        5.0 * MU[1] * M * (-GRAVITY.z),
    ];
    let p = sphere(tau);
    for name in SOLVERS {
        let (g, v) = solve(name, &p);
        let gn = g[0];
        assert!(gn > 0.0);
        assert!(
            (g[4].hypot(g[5]) - MU[2] * gn).abs() < 1e-9 * gn,
            "{name}: rolling not saturated: {g:?}"
        );
        assert!(
            (g[3].abs() - MU[1] * gn).abs() < 1e-9 * gn,
            "{name}: spin not saturated: {g:?}"
        );
        // resisting the applied torques, and the sphere turns both ways
        assert!(g[5] < 0.0 && g[3] < 0.0, "{name}: {g:?}");
        assert!(v[4] > 0.0 && v[5] > 0.0, "{name}: v+ = {v:?}");
    }
}
