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

/// Writes VTK frames of a system's bodies every `every` steps when the run asked for them
/// (`--vtk`), and the `.pvd` collection at the end.
pub struct VtkFrames {
    dir: Option<std::path::PathBuf>,
    every: u64,
    frames: Vec<(f64, String)>,
}

impl VtkFrames {
    /// Frames every `every` steps into the case's VTK directory, if any.
    pub fn new(ctx: &crate::case::RunContext, every: u64) -> Self {
        Self {
            dir: ctx.vtk_dir(),
            every: every.max(1),
            frames: Vec::new(),
        }
    }

    /// Write a frame if VTK output is on and `step` is a multiple of `every`.
    pub fn record(&mut self, step: u64, sys: &System) -> anyhow::Result<()> {
        let Some(dir) = &self.dir else { return Ok(()) };
        if !step.is_multiple_of(self.every) {
            return Ok(());
        }
        let shapes: Vec<_> = sys
            .bodies()
            .iter()
            .enumerate()
            .flat_map(|(i, b)| {
                b.colliders()
                    .iter()
                    .map(move |c| (b.pose() * c.local_pose, &c.shape, i as u32))
            })
            .collect();
        let name = format!("frame_{:06}.vtp", self.frames.len());
        chrono_core::io::vtk::write_shapes_vtp(dir.join(&name), &shapes)?;
        self.frames.push((sys.time(), name));
        Ok(())
    }

    /// Write the `.pvd` collection (ParaView opens it as an animation).
    pub fn finish(&self) -> anyhow::Result<()> {
        let Some(dir) = &self.dir else { return Ok(()) };
        let frames: Vec<(f64, &str)> = self.frames.iter().map(|(t, n)| (*t, n.as_str())).collect();
        chrono_core::io::vtk::write_pvd(dir.join("frames.pvd"), &frames)?;
        Ok(())
    }
}
