//! Granular validation cases and benches: DEM-C (NSC, complementarity) and DEM-P (SMC,
//! penalty) on the same scenes, so the report shows both methods' error and wall time.
//!
//! - `smc-bounce`: restitution of one sphere on a plate (SMC, both force laws);
//! - `granular-settle`: grains settling in a box stay at rest (validation) and its
//!   throughput (bench);
//! - `granular-hopper`: silo discharge through a circular orifice against Beverloo's law;
//! - `granular-ball-drop`: a ball dropped into a bed, penetration depth against Uehara et
//!   al.'s scaling.
//! - `granular-shear`: a direct shear box of glass beads, peak and residual friction angles.
//! - `granular-repose`: the angle of repose of a heap left on a plate after discharge,
//!   against Zhou et al.'s (2002) DEM correlation and glass-bead experiments.
//! - `granular-vs-rapier` (bench, cargo feature `rapier`): `granular-settle`'s pour by our
//!   NSC step and by rapier3d-f64 side by side.
//!
//! The scenes are the library's (`chrono_core::granular`: `GrainBed`, `Silo`, `ShearTest`,
//! `HeapSlot`, `ImpactBed`, `BallDrop`); the cases hold their parameters, references,
//! checks and reports.

pub mod ball_drop;
mod ball_drop_scene;
pub mod hopper;
pub mod repose;
mod repose_scene;
pub mod settle;
pub mod shear;
mod shear_params;
pub mod smc_bounce;
#[cfg(feature = "rapier")]
pub mod vs_rapier;

use chrono_ccp::{Apgd, CcpSolver, SolverSettings};
use chrono_core::io::{Every, FrameSeries, write_grains_vtp};
use chrono_core::system::ContactMethod;
use chrono_core::{System, SystemSettings};

pub use chrono_core::granular::step_size;

/// Error unless a `method` list parameter names at least one contact method.
pub fn ensure_methods(list: &[ContactMethod]) -> anyhow::Result<()> {
    anyhow::ensure!(
        !list.is_empty(),
        "parameter `method` must name at least one of `nsc`, `smc`, got an empty list"
    );
    Ok(())
}

/// The parameter spelling of a contact method (`nsc`, `smc`), for metric names.
pub fn method_name(m: ContactMethod) -> &'static str {
    match m {
        ContactMethod::Nsc => "nsc",
        ContactMethod::Smc => "smc",
    }
}

/// APGD with a tolerance (m/s) and an iteration cap.
pub fn make_solver(tolerance: f64, max_iterations: usize) -> Box<dyn CcpSolver> {
    Box::new(Apgd::new(SolverSettings {
        tolerance,
        max_iterations,
        record_history: false,
    }))
}

/// VTK frames of the grains (`grains_NNNNNN.vtp` and `grains.pvd`) every `every` steps
/// into the case's VTK directory when the run asked for them (`--vtk`).
pub fn grain_frames(ctx: &crate::case::RunContext, every: u64) -> anyhow::Result<FrameSeries> {
    Ok(FrameSeries::new(
        ctx.vtk_dir(),
        "grains",
        "vtp",
        Every::Steps(every),
    )?)
}

/// Writes a frame of the grains of `sys` at `step` if one is due.
pub fn record_grains(frames: &mut FrameSeries, step: u64, sys: &System) -> anyhow::Result<()> {
    frames.record(step, sys.time(), |p| write_grains_vtp(p, sys).map(|_| ()))?;
    Ok(())
}

/// A system for a granular scene: `method` NSC (APGD, warm-started, `tolerance` m/s,
/// `max_iterations`) or SMC; the settings' other fields as given.
pub fn make_system(
    method: ContactMethod,
    settings: SystemSettings,
    tolerance: f64,
    max_iterations: usize,
) -> anyhow::Result<System> {
    let settings = SystemSettings {
        contact_method: method,
        ..settings
    };
    Ok(System::new(
        settings,
        make_solver(tolerance, max_iterations),
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn methods_deserialize_and_reject() {
        let m: Vec<ContactMethod> = serde_json::from_str(r#"["nsc", "smc"]"#).unwrap();
        assert_eq!(m, vec![ContactMethod::Nsc, ContactMethod::Smc]);
        let e = serde_json::from_str::<Vec<ContactMethod>>(r#"["dem"]"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("dem"), "{e}");
        assert!(
            ensure_methods(&[])
                .unwrap_err()
                .to_string()
                .contains("method")
        );
        assert_eq!(method_name(ContactMethod::Smc), "smc");
    }
}
