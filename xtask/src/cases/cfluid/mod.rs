//! Constraint-fluid validation cases (chrono-cfluid): the incompressibility test of the
//! seed ("Incompressibility Test" table), the dam break against Martin and Moyce (1952)
//! and a floating box against Archimedes.
//! See `docs/validation-cfluid.md`.

pub mod dam_break;
pub mod decay_fit;
pub mod floating_box;
pub mod incompressibility;
pub mod sloshing;
pub mod sloshing_decay;
pub mod still_water;
pub mod timestep;

use chrono_cfluid::CfluidSettings;
use chrono_cfluid::ConstraintFluid;
use chrono_cfluid::scene::TankScene;
use chrono_core::descriptor::{CcpSolver, SolverSettings};
use chrono_core::particles::lattice::SlabTank;

use crate::params::ParamInfo;

/// The parameter of [`CfluidSettings::gradient_correction`], shared by the cases that take it.
pub(super) const GRADIENT_CORRECTION: ParamInfo = ParamInfo::new(
    "gradient_correction",
    "-",
    "density rows' gradient correction (0 off, else min eigenvalue of M_i)",
);
/// The parameter of [`CfluidSettings::density_projection`].
pub(super) const DENSITY_PROJECTION: ParamInfo = ParamInfo::new(
    "density_projection",
    "-",
    "iteration cap of the CCP density projection (0 off)",
);
/// The parameter of [`CfluidSettings::density_projection_tolerance`].
pub(super) const DENSITY_PROJECTION_TOLERANCE: ParamInfo = ParamInfo::new(
    "density_projection_tolerance",
    "-",
    "residual at which the density projection stops (C_i)",
);

/// The CCP solver named `name` (chrono-ccp spelling) at `tolerance` and
/// `max_iterations`; an unknown name is an error naming the parameter `solver`.
pub fn solver_by_name(
    name: &str,
    tolerance: f64,
    max_iterations: usize,
) -> anyhow::Result<Box<dyn CcpSolver>> {
    chrono_ccp::by_name(
        name,
        SolverSettings {
            tolerance,
            max_iterations,
            record_history: false,
        },
    )
    .map_err(|e| anyhow::anyhow!("parameter `solver`: {e}"))
}

/// The cases' quasi-2D tank ([`TankScene`]): a block `column = [width, height]` (m) in a
/// tank `tank_length` (m) long with walls `top` (m) high, at the spacing and `h / dp` of
/// `settings`, solved by the chrono-ccp solver `solver` at `tolerance` and
/// `max_iterations`.
pub fn tank_scene(
    settings: CfluidSettings,
    tank_length: f64,
    top: f64,
    column: [f64; 2],
    solver: &str,
    tolerance: f64,
    max_iterations: usize,
) -> anyhow::Result<TankScene> {
    let name = solver;
    let solver = solver_by_name(solver, tolerance, max_iterations)?;
    let tank = SlabTank::dam_break(
        settings.spacing,
        settings.h_over_dp,
        column,
        tank_length,
        top,
    );
    let mut scene = TankScene::new(settings, &tank, solver)?;
    projection_solver(scene.fluid_mut()?, name)?;
    Ok(scene)
}

/// Gives `fluid` the chrono-ccp solver `name` for its density projection when the
/// projection is on (`CfluidSettings::density_projection`; its tolerance and cap are
/// the settings'); nothing otherwise.
pub fn projection_solver(fluid: &mut ConstraintFluid, name: &str) -> anyhow::Result<()> {
    let s = fluid.settings();
    if s.density_projection > 0 {
        let solver = solver_by_name(
            name,
            s.density_projection_tolerance,
            s.density_projection as usize,
        )?;
        fluid.set_projection_solver(solver);
    }
    Ok(())
}

/// Fluid particles outside the tank `[0, tank_length] x [0, ..)` by more than `dp / 2`.
pub fn left_tank(f: &ConstraintFluid, dp: f64, tank_length: f64) -> usize {
    (0..f.n_fluid())
        .filter(|&i| {
            let x = f.position(i);
            x[0] < -0.5 * dp || x[0] > tank_length + 0.5 * dp || x[2] < -0.5 * dp
        })
        .count()
}

/// Settles the tank's fluid at rest for `time` s in steps of `h` with XSPH `xsph`
/// (velocities kept, so the particles reach the packing the kernel sum prefers), then
/// zeroes the velocities and sets XSPH to `run_xsph`: a start from the model's own packing
/// instead of the lattice (docs/validation-cfluid.md, "A settled start"). Nothing happens
/// for `time = 0`; the errors name the case parameters `settle_time` and `settle_xsph`.
pub fn settle(
    scene: &mut TankScene,
    time: f64,
    xsph: f64,
    run_xsph: f64,
    h: f64,
) -> anyhow::Result<()> {
    anyhow::ensure!(
        time >= 0.0 && time.is_finite(),
        "parameter `settle_time` must be >= 0, got {time}"
    );
    anyhow::ensure!(
        (0.0..=1.0).contains(&xsph),
        "parameter `settle_xsph` must be in [0, 1], got {xsph}"
    );
    let n = (time / h).round() as u64;
    if n == 0 {
        return Ok(());
    }
    scene.fluid_mut()?.set_xsph(xsph)?;
    for _ in 0..n {
        scene.sys.step(h)?;
    }
    let f = scene.fluid_mut()?;
    f.set_velocities(&vec![[0.0; 3]; f.n_fluid()])?;
    f.set_xsph(run_xsph)?;
    Ok(())
}
