//! `m113-granular`: the M113A1 (shoe by shoe, powertrain, braked-differential driveline)
//! drives straight on a moving patch of SMC grains at a speed held by the speed controller.
//!
//! The scene is `chrono_vehicle::tracked_granular::TrackedGranularScene`: a bed of spheres
//! (`chrono_vehicle::terrain::GranularPatch`, the rear slab moved to the front as the
//! vehicle advances, so the grain count is fixed) settles, the vehicle is set down on it
//! and rests `vehicle_settle` s on its brakes, then starts rolling at `initial_speed`
//! (`TrackedDrive::set_forward_speed`: chains, wheels and shafts at their geared speeds)
//! while a PI speed controller (`chrono_vehicle::driver::SpeedController`) holds `speed`.
//! The shift schedule watches the turbine speed (as in `m113-turn` and `m113-step`).
//!
//! Contact is SMC by default (`method`). With SMC, grain on grain, grain on shoe and the
//! vehicle's own contacts (shoe on road wheel, pin on sprocket) are Hertz penalty forces from
//! the materials (the grains' from the parameters below, the same as `hmmwv-granular`'s; the
//! vehicle's from `data/m113.json`, every value with its source there); the pin joints, the
//! suspension's joints and the driveline's shafts are rows of the CCP (Schur solver).
//! `h` = 2.5e-4 s ([`SMC_H`]): the step `hmmwv-granular` found stable for these grains.
//!
//! With `method = nsc` every contact is a complementarity row of the CCP beside the joints
//! (Anitescu-Tasora; the same materials: friction, rolling friction, grain size and
//! density; only the contact law differs). Under the loaded tracks that is a heavy-on-light
//! problem (18 kg shoes and a 10 t chassis on 0.67 kg grains), solved by `local-direct`
//! (`chrono_ccp::LocalDirect`: the rows around the shoes and wheels by ADMM, the rest by
//! APGD), at `h` = [`NSC_H`]. Measured runs, the step's choice and the cost are in
//! `docs/validation-vehicle.md` ("`m113-granular` by NSC").
//!
//! Checks:
//! - the mean forward speed from `t_start` s after the start to the end within 10 % of
//!   `speed` (the speed controller's job on this ground);
//! - no grain passes through a shoe: no grain centre ever inside a shoe's plate
//!   (`grains_inside_shoes`, counted geometrically every `inside_every` steps), and the
//!   largest penetration of a grain into a shoe, checked every step (SMC: the penalty
//!   overlap; NSC: the contact rows' `-distance` at the step's start), stays below the grain
//!   radius (at that depth its centre reaches the plate's face);
//! - no instability: a diverging body stops the system with an error naming the body and the
//!   step; the case also stops with an error naming the chassis and the step if it tilts
//!   past 45 deg or leaves the bed by more than a metre.
//!
//! Reported: sinkage (settled surface minus the lower runs' ground faces, mean of the second
//! half of the drive), slip `1 - v / (w r_p)` (track speed from the sprockets' spin against
//! the vehicle's), grain count and relocations, joint drift, wall time, steps/s, the CCP
//! share and the CCP's convergence (largest residual, unconverged steps, mean iterations
//! and products per step).

use std::sync::atomic::Ordering;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use chrono_core::math::Vector3;
use chrono_core::{ContactMethod, SystemSettings};
use chrono_vehicle::driver::{PidGains, SpeedController};
use chrono_vehicle::m113::m113_data;
use chrono_vehicle::powertrain::ShiftSpeed;
use chrono_vehicle::state::DriverInputs;
use chrono_vehicle::terrain::GranularPatchParams;
use chrono_vehicle::tracked_drive::TrackedDrive;
use chrono_vehicle::tracked_granular::TrackedGranularScene;

use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::cases::rigid::{VtkFrames, n_steps};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// Parameters of `m113-granular`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct M113GranularParams {
    /// Target speed of the speed controller, m/s.
    pub speed: f64,
    /// Speed the vehicle starts rolling at (chains and shafts at their geared speeds), m/s.
    pub initial_speed: f64,
    /// Driving time after the start, s.
    pub t_drive: f64,
    /// The mean speed is taken from this long after the start, s.
    pub t_start: f64,
    /// Speed controller's proportional gain, 1/(m/s).
    pub kp: f64,
    /// Speed controller's integral gain, 1/m.
    pub ki: f64,
    /// Grain diameter, m.
    pub grain_diameter: f64,
    /// Grain density, kg/m^3.
    pub grain_density: f64,
    /// Grain Young's modulus (Hertz), Pa.
    pub grain_young_modulus: f64,
    /// Grain friction coefficient (grains and walls; against a shoe the lower of the two).
    pub mu: f64,
    /// Grain rolling friction coefficient.
    pub rolling_friction: f64,
    /// Grain restitution coefficient (against a shoe the lower of the two).
    pub restitution: f64,
    /// Patch length (X), m.
    pub patch_length: f64,
    /// Patch width (Y), m.
    pub patch_width: f64,
    /// Bed depth before settling, m.
    pub depth: f64,
    /// Time step, s; 0 = the method's ([`SMC_H`] for SMC, [`NSC_H`] for NSC).
    pub h: f64,
    /// Settling time of the bed before the vehicle is set down, s.
    pub settle: f64,
    /// Time the vehicle rests on the bed, braked, before it starts rolling, s.
    pub vehicle_settle: f64,
    /// Contact method: `smc` (Hertz penalty forces) or `nsc` (complementarity: the contacts
    /// are rows of the CCP with the joints).
    pub method: ContactMethod,
    /// CCP solver by name (`chrono_ccp::SOLVER_NAMES`), or `auto`: the method's, `schur`
    /// (joints by direct elimination, contact complement matrix-free) for SMC, `local-direct`
    /// (the heavy-on-light path: the rows around the shoes and wheels by ADMM, the rest by
    /// APGD) for NSC.
    pub solver: String,
    /// Tolerance of the CCP solve, m/s; 0 = the method's ([`SMC_TOLERANCE`],
    /// [`NSC_TOLERANCE`]).
    pub tolerance: f64,
    /// Iteration cap of the CCP solve; 0 = the method's ([`SMC_MAX_ITERATIONS`],
    /// [`NSC_MAX_ITERATIONS`]).
    pub max_iterations: usize,
    /// Count the grains inside shoes every this many steps (geometric, grains x shoes).
    pub inside_every: usize,
}

impl Default for M113GranularParams {
    fn default() -> Self {
        Self {
            speed: 2.0,
            initial_speed: 2.0,
            t_drive: 1.0,
            t_start: 0.3,
            kp: 1.0,
            ki: 0.5,
            grain_diameter: 0.08,
            grain_density: 2500.0,
            grain_young_modulus: 2e7,
            mu: 0.8,
            rolling_friction: 0.2,
            restitution: 0.3,
            patch_length: 6.0,
            patch_width: 3.0,
            depth: 0.16,
            h: 0.0,
            settle: 0.3,
            vehicle_settle: 0.1,
            method: ContactMethod::Smc,
            solver: "auto".into(),
            tolerance: 0.0,
            max_iterations: 0,
            inside_every: 40,
        }
    }
}

impl CaseParams for M113GranularParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("speed", "m/s", "target speed of the speed controller"),
        ParamInfo::new(
            "initial_speed",
            "m/s",
            "speed the vehicle starts rolling at",
        ),
        ParamInfo::new("t_drive", "s", "driving time after the start"),
        ParamInfo::new(
            "t_start",
            "s",
            "mean speed taken from this long after the start",
        ),
        ParamInfo::new("kp", "1/(m/s)", "speed controller proportional gain"),
        ParamInfo::new("ki", "1/m", "speed controller integral gain"),
        ParamInfo::new("grain_diameter", "m", "grain diameter"),
        ParamInfo::new("grain_density", "kg/m^3", "grain density"),
        ParamInfo::new("grain_young_modulus", "Pa", "grain Young's modulus (Hertz)"),
        ParamInfo::new("mu", "-", "grain friction coefficient"),
        ParamInfo::new(
            "rolling_friction",
            "-",
            "grain rolling friction coefficient",
        ),
        ParamInfo::new("restitution", "-", "grain restitution coefficient"),
        ParamInfo::new("patch_length", "m", "length of the moving patch"),
        ParamInfo::new("patch_width", "m", "width of the patch"),
        ParamInfo::new("depth", "m", "bed depth before settling"),
        ParamInfo::new(
            "h",
            "s",
            "time step (0: the method's, 2.5e-4 smc, 1e-3 nsc)",
        ),
        ParamInfo::new("settle", "s", "settling time of the bed"),
        ParamInfo::new(
            "vehicle_settle",
            "s",
            "time the braked vehicle rests on the bed before it rolls",
        ),
        ParamInfo::new("method", "-", "contact method: smc | nsc"),
        ParamInfo::new(
            "solver",
            "-",
            "CCP solver: auto (schur for smc, local-direct for nsc) | chrono_ccp::SOLVER_NAMES",
        ),
        ParamInfo::new("tolerance", "m/s", "CCP solve tolerance (0: the method's)"),
        ParamInfo::new(
            "max_iterations",
            "-",
            "CCP solve iteration cap (0: the method's)",
        ),
        ParamInfo::new(
            "inside_every",
            "-",
            "count grains inside shoes every this many steps",
        ),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            Mode::Quick => self.t_drive = 0.6,
            Mode::Full => {
                // 20 s of driving (issue 26) on a longer patch.
                self.t_drive = 20.0;
                self.patch_length = 7.0;
                self.settle = 0.4;
            }
            Mode::Default => {}
        }
    }
}

/// SMC's step, s: the one `hmmwv-granular` found stable for these grains (5e-4 diverged).
pub const SMC_H: f64 = 2.5e-4;
/// SMC's CCP tolerance (the rows are the joints and shafts only, solved directly).
pub const SMC_TOLERANCE: f64 = 1e-8;
/// SMC's CCP iteration cap.
pub const SMC_MAX_ITERATIONS: usize = 60;
/// NSC's step, s (see `docs/validation-vehicle.md`, "m113-granular by NSC").
pub const NSC_H: f64 = 1e-3;
/// NSC's CCP tolerance, m/s (the RMS residual of the whole problem, as `hmmwv-granular`).
pub const NSC_TOLERANCE: f64 = 1e-3;
/// NSC's CCP iteration cap (the far block's APGD iterations summed over the sweeps).
pub const NSC_MAX_ITERATIONS: usize = 60;

/// The step, solver and solver settings of a run, the method's where the parameter is 0
/// (`auto` for the solver).
#[derive(Clone, Debug, PartialEq)]
pub struct Resolved {
    /// Time step, s.
    pub h: f64,
    /// CCP solver name.
    pub solver: String,
    /// CCP tolerance, m/s.
    pub tolerance: f64,
    /// CCP iteration cap.
    pub max_iterations: usize,
}

/// The run's step and solver settings (see [`Resolved`]); errors name the parameter.
pub fn resolve(p: &M113GranularParams) -> anyhow::Result<Resolved> {
    let nsc = p.method == ContactMethod::Nsc;
    for (name, v) in [("h", p.h), ("tolerance", p.tolerance)] {
        anyhow::ensure!(
            v.is_finite() && v >= 0.0,
            "parameter `{name}` must be finite and >= 0 (0: the method's), got {v}"
        );
    }
    let solver = match p.solver.as_str() {
        "auto" if nsc => "local-direct".to_string(),
        "auto" => "schur".to_string(),
        name => {
            anyhow::ensure!(
                chrono_ccp::SOLVER_NAMES.contains(&name),
                "parameter `solver` = `{name}` is not auto or one of {}",
                chrono_ccp::SOLVER_NAMES.join(", ")
            );
            name.to_string()
        }
    };
    let pick = |v: f64, smc: f64, nsc_v: f64| {
        if v > 0.0 {
            v
        } else if nsc {
            nsc_v
        } else {
            smc
        }
    };
    Ok(Resolved {
        h: pick(p.h, SMC_H, NSC_H),
        solver,
        tolerance: pick(p.tolerance, SMC_TOLERANCE, NSC_TOLERANCE),
        max_iterations: match (p.max_iterations, nsc) {
            (0, true) => NSC_MAX_ITERATIONS,
            (0, false) => SMC_MAX_ITERATIONS,
            (n, _) => n,
        },
    })
}

fn validate(p: &M113GranularParams) -> anyhow::Result<()> {
    for (name, v) in [("speed", p.speed), ("t_drive", p.t_drive), ("kp", p.kp)] {
        anyhow::ensure!(
            v.is_finite() && v > 0.0,
            "parameter `{name}` must be finite and > 0, got {v}"
        );
    }
    for (name, v) in [
        ("initial_speed", p.initial_speed),
        ("t_start", p.t_start),
        ("ki", p.ki),
        ("settle", p.settle),
        ("vehicle_settle", p.vehicle_settle),
    ] {
        anyhow::ensure!(
            v.is_finite() && v >= 0.0,
            "parameter `{name}` must be finite and >= 0, got {v}"
        );
    }
    anyhow::ensure!(
        p.t_start < p.t_drive,
        "parameter `t_start` ({}) must be below `t_drive` ({})",
        p.t_start,
        p.t_drive
    );
    anyhow::ensure!(p.inside_every >= 1, "parameter `inside_every` must be >= 1");
    Ok(())
}

fn run(p: &M113GranularParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    validate(p)?;
    let rs = resolve(p)?;
    let h = rs.h;
    let mut data = m113_data()?;
    // At low speed the turbine's speed keeps the gear (m113-turn).
    data.powertrain.transmission.shift_speed = ShiftSpeed::InputShaft;
    let r = 0.5 * p.grain_diameter;
    let patch = GranularPatchParams {
        length: p.patch_length,
        width: p.patch_width,
        depth: p.depth,
        grain_radius: r,
        density: p.grain_density,
        friction: p.mu,
        young_modulus: p.grain_young_modulus,
        restitution: p.restitution,
        rolling_friction: p.rolling_friction,
        compliance: 0.0,
        slab: (0.1 * p.patch_length).max(2.0 * p.grain_diameter),
        seed: 7,
        lanes: Vec::new(),
    };
    let settings = SystemSettings {
        contact_method: p.method,
        ..SystemSettings::default()
    };
    let (solver, nanos) = super::m113_solver(&rs.solver, rs.tolerance, rs.max_iterations)?;
    let wall0 = Instant::now();
    let mut scene = TrackedGranularScene::new(data, &patch, settings, solver, h, p.settle)
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let settle_wall = wall0.elapsed().as_secs_f64();
    ctx.progress(0.1);
    let mut drive = TrackedDrive::build(&mut scene.sys, &scene.vehicle, &scene.data)?;
    let (is_shoe, is_grain) = scene.body_masks();
    let surface = scene.patch.surface();
    let r_p = scene.data.track.sprocket.pitch_radius;
    let brakes = DriverInputs {
        throttle: 0.0,
        brake: 1.0,
        steering: 0.0,
    };
    let n_rest = if p.vehicle_settle > 0.0 {
        n_steps(h, p.vehicle_settle)?
    } else {
        0
    };
    for _ in 0..n_rest {
        drive.synchronize(&mut scene.sys, brakes)?;
        scene.sys.step(h)?;
    }
    // Set down: a grease adjuster holds the idler from here (the data's adjuster).
    scene.vehicle.lock_adjusters(&mut scene.sys, &scene.data)?;
    drive.set_forward_speed(&mut scene.sys, &scene.vehicle, &scene.data, p.initial_speed)?;
    let mut ctl = SpeedController::new(
        PidGains {
            kp: p.kp,
            ki: p.ki,
            kd: 0.0,
        },
        p.speed,
    )?;
    let n = n_steps(h, p.t_drive)?;
    // A series sample every 0.01 s (40 SMC steps).
    let sample_every = (0.01 / h).round().max(1.0) as u64;
    let mut series = Series::new([
        "t",
        "x",
        "speed",
        "track_speed",
        "throttle",
        "sinkage",
        "max_grain_overlap",
        "joint_violation",
        "target",
        "residual",
        "iterations",
        "apply_n",
    ]);
    let mut vtk = VtkFrames::new(ctx, (0.05 / h).round().max(1.0) as u64);
    let t0 = scene.sys.time();
    let x0 = scene.reference()?.x;
    let (mut sum_v, mut sum_w, mut n_v) = (0.0, 0.0, 0usize);
    let (mut sum_sink, mut n_sink) = (0.0, 0usize);
    let (mut max_overlap, mut max_inside, mut max_violation) = (0.0_f64, 0usize, 0.0_f64);
    let mut shoe_grain_contacts = 0usize;
    let mut throttle = 0.0;
    let mut distance = 0.0;
    let drive_wall = Instant::now();
    let solve0 = nanos.load(Ordering::Relaxed);
    let mut steps = 0;
    // The CCP solve: the largest residual of the drive, m/s, and the summed iterations.
    let (mut max_residual, mut sum_iterations, mut unconverged) = (0.0_f64, 0usize, 0usize);
    let mut sum_apply_n = 0usize;
    for i in 1..=n {
        scene.advance()?;
        let c = scene.sys.body(scene.vehicle.chassis)?;
        let fwd = c.rotation() * Vector3::x();
        let speed = c.linear_velocity().dot(&fwd);
        let u = ctl.advance(scene.sys.time(), speed);
        let (th, brake) = SpeedController::pedals(u);
        throttle = th;
        drive.synchronize(
            &mut scene.sys,
            DriverInputs {
                throttle,
                brake,
                steering: 0.0,
            },
        )?;
        let report = scene.sys.step(h)?;
        max_residual = max_residual.max(report.solve.residual);
        sum_iterations += report.solve.iterations;
        unconverged += usize::from(!report.solve.converged);
        sum_apply_n += report.solve.apply_n;
        steps = i;
        vtk.record(i, &scene.sys)?;
        let t = scene.sys.time() - t0;
        let c = scene.sys.body(scene.vehicle.chassis)?;
        let up = c.rotation() * Vector3::z();
        let fwd = c.rotation() * Vector3::x();
        let speed = c.linear_velocity().dot(&fwd);
        let reference = scene.reference()?;
        // A vehicle tipped past 45 deg or thrown off the bed has gone unstable even if no
        // body reached the system's speed limits.
        if up.z < std::f64::consts::FRAC_1_SQRT_2 || reference.z > surface + 2.0 {
            anyhow::bail!(
                "unstable: body \"chassis\" at step {} (t = {:.4} s): tilt {:.1} deg, \
                 reference {:.3} m above the bed's surface",
                scene.sys.step_count(),
                scene.sys.time(),
                up.z.clamp(-1.0, 1.0).acos().to_degrees(),
                reference.z - surface
            );
        }
        distance = reference.x - x0;
        let w = 0.5 * (drive.sprocket_speed(&scene.sys, 0) + drive.sprocket_speed(&scene.sys, 1));
        let (overlap, contacts) = scene.grain_shoe_overlap(&is_shoe, &is_grain);
        max_overlap = max_overlap.max(overlap);
        shoe_grain_contacts = shoe_grain_contacts.max(contacts);
        max_violation = max_violation.max(scene.sys.max_joint_violation());
        if i % p.inside_every as u64 == 0 || i == n {
            max_inside = max_inside.max(scene.grains_inside_shoes()?);
        }
        if t >= p.t_start {
            sum_v += speed;
            sum_w += w * r_p;
            n_v += 1;
        }
        let sampled = i % sample_every == 0 || i == n;
        if sampled {
            let sink = scene.sinkage()?;
            if t >= 0.5 * p.t_drive && sink.is_finite() {
                sum_sink += sink;
                n_sink += 1;
            }
            series.push(&[
                t,
                distance,
                speed,
                w * r_p,
                throttle,
                sink,
                overlap,
                scene.sys.max_joint_violation(),
                p.speed,
                report.solve.residual,
                report.solve.iterations as f64,
                report.solve.apply_n as f64,
            ]);
        }
        ctx.progress(0.1 + 0.9 * i as f64 / n as f64);
    }
    let drive_s = drive_wall.elapsed().as_secs_f64();
    let wall = wall0.elapsed().as_secs_f64();
    let solve_s = (nanos.load(Ordering::Relaxed) - solve0) as f64 * 1e-9;
    vtk.finish()?;
    let mean_speed = if n_v > 0 {
        sum_v / n_v as f64
    } else {
        f64::NAN
    };
    let track_speed = if n_v > 0 {
        sum_w / n_v as f64
    } else {
        f64::NAN
    };
    let slip = 1.0 - mean_speed / track_speed;
    let sinkage = if n_sink > 0 {
        sum_sink / n_sink as f64
    } else {
        f64::NAN
    };
    let mut out = CaseOutput::new();
    out.check(Check::relative("mean_speed", mean_speed, p.speed, 0.1));
    out.check(Check::below("grains_inside_shoes", max_inside as f64, 0.0));
    out.check(Check::below(
        "max_grain_overlap_over_radius",
        max_overlap / r,
        1.0,
    ));
    out.metric("track_speed", track_speed);
    out.metric("slip", slip);
    out.metric("sinkage", sinkage);
    out.metric("distance", distance);
    out.metric("max_grain_overlap", max_overlap);
    out.metric("shoe_grain_contacts_max", shoe_grain_contacts as f64);
    out.metric("grains", scene.patch.grains().len() as f64);
    out.metric("relocations", scene.patch.relocations() as f64);
    out.metric("max_joint_violation", max_violation);
    out.metric("last_throttle", throttle);
    out.metric("wall_s", wall);
    out.metric("settle_wall_s", settle_wall);
    out.metric("drive_steps_per_s", steps as f64 / drive_s);
    out.metric("real_time_factor", steps as f64 * h / drive_s);
    out.metric("h", h);
    out.metric("ccp_max_residual", max_residual);
    out.metric("ccp_unconverged_steps", unconverged as f64);
    out.metric("ccp_mean_apply_n", sum_apply_n as f64 / steps.max(1) as f64);
    out.metric(
        "ccp_mean_iterations",
        sum_iterations as f64 / steps.max(1) as f64,
    );
    out.metric("ccp_solve_share", solve_s / drive_s);
    ctx.note(format!(
        "M113A1 on {} {} grains ({} m, h = {h} s, solver {}): mean speed {mean_speed:.3} m/s after {} s (target {}), \
         track speed {track_speed:.3} m/s (slip {slip:.3}), sinkage {sinkage:.4} m, {distance:.2} m \
         in {} s with {} relocations; largest grain overlap into a shoe {:.2e} m ({:.3} r), \
         grains inside shoes {max_inside}; joint drift {max_violation:.1e} m; {:.3} steps/s \
         ({:.2e} x real time), CCP {:.0} %",
        scene.patch.grains().len(),
        if p.method == ContactMethod::Nsc {
            "NSC"
        } else {
            "SMC"
        },
        p.grain_diameter,
        rs.solver,
        p.t_start,
        p.speed,
        p.t_drive,
        scene.patch.relocations(),
        max_overlap,
        max_overlap / r,
        steps as f64 / drive_s,
        steps as f64 * h / drive_s,
        100.0 * solve_s / drive_s,
    ));
    out.series = series;
    out.plot = PlotSpec::new(
        "M113 on a granular patch",
        "t [s]",
        "speed [m/s]",
        &["speed", "track_speed"],
    )
    .with_reference(&["target"]);
    out.steps = steps + n_rest + (p.settle / h).round() as u64;
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<M113GranularParams>::boxed(
        "m113-granular",
        "vehicle",
        "M113A1 (shoe by shoe, powertrain) holding 2 m/s with a speed controller on a moving \
         patch of SMC grains (`--set method=nsc`: NSC grains, local-direct solver): mean speed \
         within 10 %, no grain through a shoe, no instability; sinkage, slip, wall time reported.",
        run,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_method_gets_its_step_and_solver_unless_set() {
        let smc = resolve(&M113GranularParams::default()).unwrap();
        assert_eq!(
            smc,
            Resolved {
                h: SMC_H,
                solver: "schur".into(),
                tolerance: SMC_TOLERANCE,
                max_iterations: SMC_MAX_ITERATIONS,
            }
        );
        let nsc = M113GranularParams {
            method: ContactMethod::Nsc,
            ..Default::default()
        };
        let r = resolve(&nsc).unwrap();
        assert_eq!((r.h, r.solver.as_str()), (NSC_H, "local-direct"));
        assert_eq!(
            (r.tolerance, r.max_iterations),
            (NSC_TOLERANCE, NSC_MAX_ITERATIONS)
        );
        let set = M113GranularParams {
            h: 5e-4,
            solver: "schur".into(),
            tolerance: 1e-4,
            max_iterations: 200,
            ..nsc
        };
        let r = resolve(&set).unwrap();
        assert_eq!(
            (r.h, r.solver.as_str(), r.tolerance, r.max_iterations),
            (5e-4, "schur", 1e-4, 200)
        );
    }

    #[test]
    fn bad_input_names_the_parameter() {
        let err = |p: M113GranularParams| format!("{:#}", resolve(&p).unwrap_err());
        let e = err(M113GranularParams {
            method: ContactMethod::Nsc,
            solver: "gauss".into(),
            ..Default::default()
        });
        assert!(e.contains("`solver`") && e.contains("gauss"), "{e}");
        assert!(e.contains("local-direct"), "{e}");
        let e = err(M113GranularParams {
            h: -1e-3,
            ..Default::default()
        });
        assert!(e.contains("`h`"), "{e}");
        let e = err(M113GranularParams {
            tolerance: f64::NAN,
            ..Default::default()
        });
        assert!(e.contains("`tolerance`"), "{e}");
        let e = format!(
            "{:#}",
            validate(&M113GranularParams {
                t_start: 2.0,
                ..Default::default()
            })
            .unwrap_err()
        );
        assert!(e.contains("`t_start`"), "{e}");
    }
}
