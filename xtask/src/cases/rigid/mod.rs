//! Rigid-body validation cases (NSC): analytic references for friction, joints, stacking,
//! free fall and torque-free rotation.

pub mod free_fall;
pub mod incline;
pub mod pendulum;
pub mod spin;
pub mod stack;

use chrono_ccp::{CcpSolver, SolverSettings};
use chrono_core::{System, SystemSettings};

/// A CCP solver by name (one of [`chrono_ccp::SOLVER_NAMES`]), with a tolerance (m/s) and an iteration cap.
pub fn make_solver(
    name: &str,
    tolerance: f64,
    max_iterations: usize,
) -> anyhow::Result<Box<dyn CcpSolver>> {
    anyhow::ensure!(
        tolerance.is_finite() && tolerance > 0.0,
        "parameter `tolerance` must be > 0, got {tolerance}"
    );
    anyhow::ensure!(max_iterations > 0, "parameter `max_iterations` must be > 0");
    let settings = SolverSettings {
        tolerance,
        max_iterations,
        record_history: false,
    };
    chrono_ccp::by_name(name, settings).map_err(|e| anyhow::anyhow!("parameter `solver`: {e}"))
}

/// A system with default settings and the named solver.
pub fn make_system(solver: &str, tolerance: f64, max_iterations: usize) -> anyhow::Result<System> {
    Ok(System::new(
        SystemSettings::default(),
        make_solver(solver, tolerance, max_iterations)?,
    )?)
}

/// Number of steps of size `h` to cover `t_end`, checking both.
pub fn n_steps(h: f64, t_end: f64) -> anyhow::Result<u64> {
    anyhow::ensure!(
        h.is_finite() && h > 0.0,
        "parameter `h` must be > 0, got {h}"
    );
    anyhow::ensure!(
        t_end.is_finite() && t_end > 0.0,
        "parameter `t_end` must be > 0, got {t_end}"
    );
    Ok((t_end / h).round().max(1.0) as u64)
}

/// VTK frames of a system's bodies every `every` steps when the run asked for them
/// (`--vtk`), and the `.pvd` collection at the end: the library's
/// [`FrameSeries`](chrono_core::io::FrameSeries) writing
/// [`write_bodies_vtp`](chrono_core::io::write_bodies_vtp) frames into the case's VTK
/// directory.
pub struct VtkFrames(chrono_core::io::FrameSeries);

impl VtkFrames {
    /// Frames every `every` steps into the case's VTK directory, if any.
    pub fn new(ctx: &crate::case::RunContext, every: u64) -> Self {
        let every = chrono_core::io::Every::Steps(every.max(1));
        Self(
            chrono_core::io::FrameSeries::new(ctx.vtk_dir(), "frame", "vtp", every)
                .expect("a step interval is always valid"),
        )
    }

    /// Write a frame if VTK output is on and `step` is a multiple of `every`.
    pub fn record(&mut self, step: u64, sys: &System) -> anyhow::Result<()> {
        (self.0).record(step, sys.time(), |p| {
            chrono_core::io::write_bodies_vtp(p, sys).map(drop)
        })?;
        Ok(())
    }

    /// Write the `.pvd` collection (ParaView opens it as an animation).
    pub fn finish(&self) -> anyhow::Result<()> {
        Ok(self.0.finish()?)
    }
}
