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

pub mod ball_drop;
mod ball_drop_scene;
pub mod forces;
pub mod hopper;
pub mod repose;
mod repose_scene;
pub mod settle;
pub mod shear;
mod shear_curve;
mod shear_params;
pub mod smc_bounce;

use chrono_ccp::{Apgd, CcpSolver, SolverSettings};
use chrono_core::system::{ContactMethod, RollingModel, SmcModel};
use chrono_core::{System, SystemSettings};

/// The contact method of a case parameter (`nsc` or `smc`).
pub fn parse_method(method: &str) -> anyhow::Result<ContactMethod> {
    match method {
        "nsc" => Ok(ContactMethod::Nsc),
        "smc" => Ok(ContactMethod::Smc),
        other => anyhow::bail!("parameter `method` must be `nsc` or `smc`, got `{other}`"),
    }
}

/// The contact methods of a `method` list parameter (`["nsc", "smc"]`, `["smc"]` ...); an
/// error names the parameter when the list is empty or holds an unknown method.
pub fn parse_methods(list: &[String]) -> anyhow::Result<Vec<ContactMethod>> {
    anyhow::ensure!(
        !list.is_empty(),
        "parameter `method` must name at least one of `nsc`, `smc`, got an empty list"
    );
    list.iter().map(|m| parse_method(m.trim())).collect()
}

/// The parameter spelling of a contact method (`nsc`, `smc`), for metric names.
pub fn method_name(m: ContactMethod) -> &'static str {
    match m {
        ContactMethod::Nsc => "nsc",
        ContactMethod::Smc => "smc",
    }
}

/// The SMC force law of a case parameter (`hooke` or `hertz`).
pub fn parse_model(model: &str) -> anyhow::Result<SmcModel> {
    match model {
        "hooke" => Ok(SmcModel::Hooke),
        "hertz" => Ok(SmcModel::Hertz),
        other => anyhow::bail!("parameter `model` must be `hooke` or `hertz`, got `{other}`"),
    }
}

/// The SMC rolling resistance model of a case parameter (`relative` or `per_body`).
pub fn parse_rolling_model(model: &str) -> anyhow::Result<RollingModel> {
    match model {
        "relative" => Ok(RollingModel::Relative),
        "per_body" => Ok(RollingModel::PerBody),
        other => anyhow::bail!(
            "parameter `rolling_model` must be `relative` or `per_body`, got `{other}`"
        ),
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

/// Deepest penetration (m) among the contacts of the last step (NSC or SMC), 0 if none.
pub fn max_penetration(sys: &System) -> f64 {
    let nsc = sys
        .contacts()
        .iter()
        .map(|c| -c.point.distance)
        .fold(0.0, f64::max);
    let smc = sys
        .smc_contacts()
        .iter()
        .map(|c| c.overlap)
        .fold(0.0, f64::max);
    nsc.max(smc)
}

/// Writes VTK frames of the grains (positions, radii, velocities) every `every` steps when
/// the run asked for them (`--vtk`), and the `.pvd` collection at the end.
pub struct GrainFrames {
    dir: Option<std::path::PathBuf>,
    every: u64,
    frames: Vec<(f64, String)>,
}

impl GrainFrames {
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
        let name = format!("grains_{:06}.vtp", self.frames.len());
        chrono_core::io::write_grains_vtp(dir.join(&name), sys)?;
        self.frames.push((sys.time(), name));
        Ok(())
    }

    /// Write the `.pvd` collection (ParaView opens it as an animation).
    pub fn finish(&self) -> anyhow::Result<()> {
        let Some(dir) = &self.dir else { return Ok(()) };
        let frames: Vec<(f64, &str)> = self.frames.iter().map(|(t, n)| (*t, n.as_str())).collect();
        chrono_core::io::vtk::write_pvd(dir.join("grains.pvd"), &frames)?;
        Ok(())
    }
}

/// The time step of a granular scene (s): `h` if set (> 0), else 1 ms for NSC and the SMC
/// limit of `sys` ([`System::smc_max_step`]; 1e-4 s without grains) for SMC.
pub fn step_size(h: f64, method: ContactMethod, sys: &System) -> f64 {
    if h > 0.0 {
        h
    } else if method == ContactMethod::Nsc {
        1e-3
    } else {
        sys.smc_max_step().map(|(h, _)| h).unwrap_or(1e-4)
    }
}

/// A system for a granular scene: `method` NSC (APGD, warm-started, `tolerance` m/s,
/// `max_iterations`) or SMC (`model`); the settings' other fields as given.
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
    fn methods_parse_and_reject() {
        let list = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        assert_eq!(
            parse_methods(&list(&["nsc", " smc"])).unwrap(),
            vec![ContactMethod::Nsc, ContactMethod::Smc]
        );
        let e = parse_methods(&list(&["dem"])).unwrap_err().to_string();
        assert!(e.contains("method") && e.contains("dem"), "{e}");
        assert!(
            parse_methods(&[])
                .unwrap_err()
                .to_string()
                .contains("method")
        );
        assert_eq!(method_name(ContactMethod::Smc), "smc");
    }
}
