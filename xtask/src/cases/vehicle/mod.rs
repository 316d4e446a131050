//! Vehicle cases: the HMMWV and the M113 of `chrono-vehicle`.

pub mod accel;
pub mod granular;
pub mod lane_change;
pub mod m113_accel;
pub mod m113_granular;
pub mod m113_pivot;
pub mod m113_static;
pub mod m113_step;
pub mod m113_step_params;
pub mod m113_turn;
pub mod scene;
pub mod skid_steer;
pub mod static_settle;
pub mod turn;

use std::sync::Arc;
use std::sync::atomic::AtomicU64;

use chrono_core::descriptor::{CcpSolver, SolverSettings};

use crate::cases::rigid::make_solver;
use crate::cases::timed_solver::TimedSolver;

/// The M113 cases' solver, timed (the counter holds the solve's nanoseconds): `schur` is the
/// Schur solver with its contact complement always matrix-free (the dense complement costs
/// `O(n_B n_C^2)` a step: with ~800 joint rows and ~1500 contact rows that is a second;
/// matrix-free it is 15-20 ms), any other name the solver of that name.
pub(crate) fn m113_solver(
    name: &str,
    tolerance: f64,
    max_iterations: usize,
) -> anyhow::Result<(Box<dyn CcpSolver>, Arc<AtomicU64>)> {
    let inner: Box<dyn CcpSolver> = if name == "schur" {
        let settings = SolverSettings {
            tolerance,
            max_iterations,
            record_history: false,
        };
        Box::new(chrono_ccp::Schur::new(settings).with_max_dense_rows(0))
    } else {
        make_solver(name, tolerance, max_iterations)?
    };
    let nanos = Arc::new(AtomicU64::new(0));
    let solver = Box::new(TimedSolver {
        inner,
        nanos: nanos.clone(),
    });
    Ok((solver, nanos))
}
