//! Parameters of `m113-step` (`super::m113_step`) and their checks.

use serde::{Deserialize, Serialize};

use chrono_vehicle::m113::m113_data;

use crate::case::Mode;
use crate::params::{CaseParams, ParamInfo};

/// Parameters of `m113-step`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct M113StepParams {
    /// Height of the step, m.
    pub step_height: f64,
    /// Distance from the vehicle's foremost point to the face at the start, m.
    pub gap: f64,
    /// Length of the step's top, m.
    pub step_length: f64,
    /// Width of the step, m.
    pub step_width: f64,
    /// Approach speed (the speed controller's target), m/s.
    pub speed: f64,
    /// Speed controller's proportional gain, 1/(m/s).
    pub kp: f64,
    /// Speed controller's integral gain, 1/m.
    pub ki: f64,
    /// Ground friction coefficient (combined with the shoes' by the minimum).
    pub mu: f64,
    /// Time step, s.
    pub h: f64,
    /// Settling time with the brakes on, s.
    pub settle: f64,
    /// Simulated time at most (settling included), s.
    pub t_end: f64,
    /// Stop after the vehicle has stood still (moved less than 2 cm) at full drive this long
    /// after touching the step, s: a stalled climb.
    pub stall_time: f64,
    /// How far below its settled height above the ground the chassis reference may be
    /// above the step's top and still count as on top, m.
    pub z_tolerance: f64,
    /// When the vehicle counts as on top: `com` (centre of mass past the face, chassis at
    /// its ride height above the top and level) or `idlers` (both idlers past the face).
    pub until: String,
    /// Largest chassis pitch, either way, at which `until` = `com` counts the vehicle as
    /// level on the top, deg.
    pub level_tolerance: f64,
    /// What turns the sprockets: `grade` (each sprocket driven directly by the speed
    /// controller's output times the torque of the published gradeability,
    /// `published_grade_sprocket_torque`), `powertrain` (engine, converter, gearbox and
    /// braked differential of the data) or `torque` (as `grade` with `drive_torque`).
    pub drive: String,
    /// Largest torque on each sprocket with `drive` = `torque`, N m.
    pub drive_torque: f64,
    /// CCP solver.
    pub solver: String,
    /// Tolerance of the solver's contact iterations.
    pub tolerance: f64,
    /// Iteration cap of the solver's contact iterations.
    pub max_iterations: usize,
    /// Tensioner preload, N (the data file's by default).
    pub preload: f64,
    /// What holds the idlers: `data` (the data file's `track.idler.tensioner.adjuster`),
    /// `spring` (the spring-damper throughout) or `grease` (the spring-damper while
    /// settling, then locked where it stands).
    pub adjuster: String,
    /// Road-wheel arms' rebound stop, rad from the assembled arm (< 0), with `arm_jounce`;
    /// 0: the data file's `arm_travel`.
    pub arm_rebound: f64,
    /// Road-wheel arms' jounce stop, rad from the assembled arm (> 0); 0: the data file's.
    pub arm_jounce: f64,
    /// Check `climbed` (issue 26's criterion) up to 0.8 x the published obstacle height,
    /// with any drive (on by default).
    pub check: bool,
}

impl Default for M113StepParams {
    fn default() -> Self {
        let d = m113_data().expect("the shipped M113 data is valid");
        Self {
            step_height: 0.8 * d.published.vertical_obstacle,
            gap: 0.3,
            step_length: 8.0,
            step_width: 5.0,
            speed: 1.0,
            kp: 1.0,
            ki: 1.0,
            mu: 0.8,
            h: 3e-3,
            settle: 0.5,
            t_end: 12.0,
            stall_time: 1.0,
            z_tolerance: 0.1,
            until: "com".into(),
            level_tolerance: 3.0,
            drive: "grade".into(),
            drive_torque: 1.0e4,
            solver: "schur".into(),
            tolerance: 1e-8,
            max_iterations: 60,
            preload: d.track.idler.tensioner.preload,
            adjuster: "data".into(),
            arm_rebound: 0.0,
            arm_jounce: 0.0,
            check: true,
        }
    }
}

impl CaseParams for M113StepParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("step_height", "m", "height of the step"),
        ParamInfo::new("gap", "m", "distance from the vehicle's front to the face"),
        ParamInfo::new("step_length", "m", "length of the step's top"),
        ParamInfo::new("step_width", "m", "width of the step"),
        ParamInfo::new("speed", "m/s", "approach speed (speed controller target)"),
        ParamInfo::new("kp", "1/(m/s)", "speed controller proportional gain"),
        ParamInfo::new("ki", "1/m", "speed controller integral gain"),
        ParamInfo::new("mu", "-", "ground friction coefficient"),
        ParamInfo::new("h", "s", "time step"),
        ParamInfo::new("settle", "s", "settling time with the brakes on"),
        ParamInfo::new("t_end", "s", "simulated time at most, settling included"),
        ParamInfo::new(
            "stall_time",
            "s",
            "stop after standing still at full drive this long on the step",
        ),
        ParamInfo::new(
            "z_tolerance",
            "m",
            "allowance below the settled ride height for 'on top'",
        ),
        ParamInfo::new(
            "until",
            "-",
            "on top when: com (centre of mass past the face, level at ride height) or idlers",
        ),
        ParamInfo::new(
            "level_tolerance",
            "deg",
            "largest pitch at which until = com counts the vehicle level on the top",
        ),
        ParamInfo::new(
            "drive",
            "-",
            "grade (sprockets driven with the published 60 % grade's torque), powertrain, or torque",
        ),
        ParamInfo::new(
            "drive_torque",
            "N m",
            "largest torque on each sprocket with drive = torque",
        ),
        ParamInfo::new("solver", "-", "CCP solver"),
        ParamInfo::new("tolerance", "-", "contact solve tolerance"),
        ParamInfo::new("max_iterations", "-", "contact solve iteration cap"),
        ParamInfo::new("preload", "N", "tensioner preload"),
        ParamInfo::new(
            "adjuster",
            "-",
            "data, spring, or grease (spring while settling, then locked)",
        ),
        ParamInfo::new(
            "arm_rebound",
            "rad",
            "arms' rebound stop from the assembled arm (< 0; 0: the data's)",
        ),
        ParamInfo::new(
            "arm_jounce",
            "rad",
            "arms' jounce stop from the assembled arm (> 0; 0: the data's)",
        ),
        ParamInfo::new(
            "check",
            "-",
            "check the climb up to 0.8 x the published height",
        ),
    ];
    // The run stops when the vehicle is on top, so the default and `--quick` are the same
    // run; `--full` gives a failing climb more time.
    fn apply_mode(&mut self, mode: Mode) {
        if mode == Mode::Full {
            self.t_end = 20.0;
        }
    }
}

pub(crate) fn validate(p: &M113StepParams) -> anyhow::Result<()> {
    for (name, v) in [
        ("speed", p.speed),
        ("mu", p.mu),
        ("z_tolerance", p.z_tolerance),
        ("level_tolerance", p.level_tolerance),
        ("kp", p.kp),
        ("drive_torque", p.drive_torque),
        ("stall_time", p.stall_time),
    ] {
        anyhow::ensure!(
            v > 0.0 && v.is_finite(),
            "parameter `{name}` must be > 0, got {v}"
        );
    }
    anyhow::ensure!(
        ["grade", "powertrain", "torque"].contains(&p.drive.as_str()),
        "parameter `drive` must be `grade`, `powertrain` or `torque`, got `{}`",
        p.drive
    );
    anyhow::ensure!(
        ["com", "idlers"].contains(&p.until.as_str()),
        "parameter `until` must be `com` or `idlers`, got `{}`",
        p.until
    );
    anyhow::ensure!(
        ["data", "spring", "grease"].contains(&p.adjuster.as_str()),
        "parameter `adjuster` must be `data`, `spring` or `grease`, got `{}`",
        p.adjuster
    );
    anyhow::ensure!(
        p.arm_rebound <= 0.0 && p.arm_rebound.is_finite(),
        "parameter `arm_rebound` must be <= 0 (0: the data's), got {}",
        p.arm_rebound
    );
    anyhow::ensure!(
        p.arm_jounce >= 0.0 && p.arm_jounce.is_finite(),
        "parameter `arm_jounce` must be >= 0 (0: the data's), got {}",
        p.arm_jounce
    );
    anyhow::ensure!(
        p.ki >= 0.0 && p.ki.is_finite(),
        "parameter `ki` must be >= 0, got {}",
        p.ki
    );
    anyhow::ensure!(
        p.settle >= 0.0 && p.settle.is_finite() && p.t_end > p.settle,
        "parameter `t_end` ({}) must exceed `settle` ({})",
        p.t_end,
        p.settle
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_drive_is_the_published_grade_and_the_step_the_criterion() {
        let p = M113StepParams::default();
        assert_eq!(p.drive, "grade");
        assert!(p.check);
        assert_eq!(p.until, "com");
        let d = m113_data().unwrap();
        assert!((p.step_height - 0.8 * d.published.vertical_obstacle).abs() < 1e-12);
        validate(&p).unwrap();
    }

    #[test]
    fn bad_input_names_the_parameter() {
        let p = M113StepParams {
            drive: "engine".into(),
            ..Default::default()
        };
        let e = validate(&p).unwrap_err().to_string();
        assert!(e.contains("`drive`") && e.contains("engine"), "{e}");
        let p = M113StepParams {
            drive_torque: -1.0,
            ..Default::default()
        };
        let e = validate(&p).unwrap_err().to_string();
        assert!(e.contains("`drive_torque`"), "{e}");
        for (p, name) in [
            (
                M113StepParams {
                    until: "rear".into(),
                    ..Default::default()
                },
                "`until`",
            ),
            (
                M113StepParams {
                    adjuster: "hydraulic".into(),
                    ..Default::default()
                },
                "`adjuster`",
            ),
            (
                M113StepParams {
                    arm_jounce: -0.1,
                    ..Default::default()
                },
                "`arm_jounce`",
            ),
            (
                M113StepParams {
                    level_tolerance: 0.0,
                    ..Default::default()
                },
                "`level_tolerance`",
            ),
        ] {
            let e = validate(&p).unwrap_err().to_string();
            assert!(e.contains(name), "{e}");
        }
    }
}
