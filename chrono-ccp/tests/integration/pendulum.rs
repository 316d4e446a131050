//! Regression for PSOR on a stiff joint (foundation issue): `rigid-pendulum` with PSOR
//! diverged. A bob of inertia 4e-5 kg m^2 on a 1 m revolute arm gives the 5 joint rows a
//! block `N_bb` whose scalar Gauss–Seidel contraction per sweep is only ~2e-4: 1000 sweeps
//! left the joint impulses unconverged, the joint drifted and the stabilization pumped
//! energy in. Relaxing the joint's rows as one block (the default) solves it exactly.

use chrono_ccp::{CcpSolver, Psor, SolverSettings};
use chrono_core::math::{GRAVITY, Vector3};
use chrono_core::{JointBuilder, JointKind, RigidBodyBuilder, System, SystemSettings};

fn pendulum(solver: Psor) -> (System, f64) {
    let mut sys = System::new(SystemSettings::default(), Box::new(solver)).unwrap();
    let a0: f64 = 60f64.to_radians();
    let ground = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let bob = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .mass(1.0)
                .inertia_diagonal(Vector3::repeat(4e-5))
                .position(Vector3::new(a0.sin(), 0.0, -a0.cos())),
        )
        .unwrap();
    sys.add_joint(JointBuilder::at_axis(
        JointKind::Revolute,
        ground,
        bob,
        Vector3::zeros(),
        Vector3::y(),
    ))
    .unwrap();
    let e0 = -GRAVITY.z * sys.body(bob).unwrap().position().z;
    (sys, e0)
}

fn settings() -> SolverSettings {
    SolverSettings {
        tolerance: 1e-10,
        max_iterations: 1000,
        record_history: false,
    }
}

fn energy(sys: &System) -> f64 {
    let b = &sys.bodies()[1];
    b.kinetic_energy() - GRAVITY.z * b.position().z
}

#[test]
fn psor_keeps_the_stiff_pendulum_stable() {
    let (mut sys, e0) = pendulum(Psor::new(settings()));
    let mut worst_iterations = 0;
    for _ in 0..1500 {
        let rep = sys.step(1e-3).expect("PSOR pendulum must not diverge");
        assert!(
            rep.solve.converged,
            "joint solve not converged: {:?}",
            rep.solve
        );
        worst_iterations = worst_iterations.max(rep.solve.iterations);
    }
    // one block, exact: a couple of sweeps per step
    assert!(worst_iterations <= 3, "{worst_iterations} sweeps");
    let de = (energy(&sys) - e0).abs() / (-GRAVITY.z * 0.5);
    assert!(de < 0.005, "energy drift {de}");
    assert!(sys.max_joint_violation() < 1e-5);
}

#[test]
fn scalar_gauss_seidel_is_what_failed() {
    // The cause, shown on one step's problem: scalar sweeps barely reduce the residual.
    let (mut sys, _) = pendulum(Psor::new(settings()));
    sys.step(1e-3).unwrap();
    let problem = sys.last_problem().clone();
    let mut scalar = Psor::new(SolverSettings {
        tolerance: 1e-10,
        max_iterations: 1000,
        record_history: true,
    })
    .with_block_bilateral(false);
    let mut g = vec![0.0; problem.n_rows()];
    let st = scalar.solve(&problem, &mut g);
    let first = st.history.first().unwrap().residual;
    assert!(
        !st.converged && st.residual > 0.5 * first,
        "scalar PSOR: {} -> {}",
        first,
        st.residual
    );
    let mut g = vec![0.0; problem.n_rows()];
    let st = Psor::new(settings()).solve(&problem, &mut g);
    assert!(st.converged && st.iterations <= 2, "{st:?}");
}
