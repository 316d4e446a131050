//! `m113-accel`: the M113A1 (`chrono_vehicle::m113`, every shoe a body, powertrain and
//! braked-differential driveline of `chrono_vehicle::tracked_drive`) settles on flat rigid
//! ground with its brakes on, then accelerates straight ahead at full throttle.
//!
//! Checks (the integrity criteria; the vehicle's published road speed is not a
//! check: the model's ratio chain, Project Chrono's four-speed one, is not the TX100-1's,
//! whose ratios our sources do not publish):
//! - no shoe separates from the chain and no joint drifts: `max_joint_violation` below
//!   1 mm over the run;
//! - the run goes straight: `lateral_offset_ratio` (the chassis' sideways travel over the
//!   distance) below 1 %;
//! - the vehicle does not lose speed at full throttle: `speed_loss` (the top forward speed
//!   after settling minus the speed at the end, over the top speed) below 10 %. On flat
//!   rigid ground the tractive effort of the low gears is far above the resistance, so a
//!   loss means the drive stopped reaching the ground (the chain slipping past the
//!   sprocket teeth did exactly that before the sprocket got its trough-shaped gaps,
//!   docs/validation-vehicle.md), while the joints still held.
//!
//! Reported: speed against time (`speed`, the chassis' forward speed), the gear and its
//! shift times, engine speed and torque, the converter's slip, the sprockets' speeds and
//! the track slip `1 - v / (w r_p)` (`r_p` the sprocket pitch radius), the top speed over
//! the run and what bounds it where a plateau is reached (the engine's cut-off speed or the
//! balance of the power with the resistance); the published road speed alongside. Wall
//! time, steps/s and the CCP solve's share.

use std::sync::atomic::Ordering;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use chrono_vehicle::m113::m113_data;
use chrono_vehicle::state::DriverInputs;
use chrono_vehicle::tracked::TrackedFlatScene;
use chrono_vehicle::tracked_drive::TrackedDrive;

use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::cases::rigid::{VtkFrames, n_steps};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// Parameters of `m113-accel`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct M113AccelParams {
    /// Time step, s.
    pub h: f64,
    /// Settling time with the brakes on before the throttle opens, s.
    pub settle: f64,
    /// Simulated time in all (settling included), s.
    pub t_end: f64,
    /// Throttle after settling, 0..1.
    pub throttle: f64,
    /// Ground friction coefficient (combined with the shoes' by the minimum).
    pub mu: f64,
    /// CCP solver.
    pub solver: String,
    /// Tolerance of the solver's contact iterations.
    pub tolerance: f64,
    /// Iteration cap of the solver's contact iterations.
    pub max_iterations: usize,
    /// Upshift engine speed, rpm (the data file's by default).
    pub upshift_rpm: f64,
    /// Downshift engine speed, rpm (the data file's by default).
    pub downshift_rpm: f64,
    /// Largest joint violation, m.
    pub max_violation: f64,
    /// Largest sideways travel over the distance travelled.
    pub max_lateral_ratio: f64,
    /// Largest loss of forward speed at full throttle, relative to the top speed.
    pub max_speed_loss: f64,
}

impl Default for M113AccelParams {
    fn default() -> Self {
        let d = m113_data().expect("the shipped M113 data is valid");
        Self {
            h: 2e-3,
            settle: 0.5,
            t_end: 3.0,
            throttle: 1.0,
            mu: 0.8,
            solver: "schur".into(),
            tolerance: 1e-8,
            max_iterations: 60,
            upshift_rpm: d.powertrain.transmission.upshift_rpm,
            downshift_rpm: d.powertrain.transmission.downshift_rpm,
            max_violation: 1e-3,
            max_lateral_ratio: 0.01,
            max_speed_loss: 0.1,
        }
    }
}

impl CaseParams for M113AccelParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("h", "s", "time step"),
        ParamInfo::new("settle", "s", "settling time with the brakes on"),
        ParamInfo::new("t_end", "s", "simulated time, settling included"),
        ParamInfo::new("throttle", "-", "throttle after settling"),
        ParamInfo::new("mu", "-", "ground friction coefficient"),
        ParamInfo::new(
            "solver",
            "-",
            "CCP solver (schur: the pin joints directly, its contact complement matrix-free)",
        ),
        ParamInfo::new("tolerance", "-", "contact solve tolerance"),
        ParamInfo::new("max_iterations", "-", "contact solve iteration cap"),
        ParamInfo::new("upshift_rpm", "rpm", "upshift engine speed"),
        ParamInfo::new("downshift_rpm", "rpm", "downshift engine speed"),
        ParamInfo::new("max_violation", "m", "largest joint violation"),
        ParamInfo::new(
            "max_lateral_ratio",
            "-",
            "largest sideways travel over the distance",
        ),
        ParamInfo::new(
            "max_speed_loss",
            "-",
            "largest loss of forward speed relative to the top speed",
        ),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            Mode::Quick => self.t_end = 2.0,
            Mode::Default => {}
            // Long enough for the shifts and, with Project Chrono's ratio chain, the
            // approach to the plateau.
            Mode::Full => self.t_end = 30.0,
        }
    }
}

fn validate(p: &M113AccelParams) -> anyhow::Result<()> {
    anyhow::ensure!(
        p.settle >= 0.0 && p.settle.is_finite(),
        "parameter `settle` must be >= 0, got {}",
        p.settle
    );
    anyhow::ensure!(
        p.t_end > p.settle,
        "parameter `t_end` ({}) must exceed `settle` ({})",
        p.t_end,
        p.settle
    );
    anyhow::ensure!(
        (0.0..=1.0).contains(&p.throttle),
        "parameter `throttle` must be in [0, 1], got {}",
        p.throttle
    );
    for (name, v) in [
        ("mu", p.mu),
        ("max_violation", p.max_violation),
        ("max_lateral_ratio", p.max_lateral_ratio),
        ("max_speed_loss", p.max_speed_loss),
    ] {
        anyhow::ensure!(
            v > 0.0 && v.is_finite(),
            "parameter `{name}` must be > 0, got {v}"
        );
    }
    Ok(())
}

fn run(p: &M113AccelParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    validate(p)?;
    let n = n_steps(p.h, p.t_end)?;
    let n_settle = (p.settle / p.h).round() as u64;
    let mut data = m113_data()?;
    data.powertrain.transmission.upshift_rpm = p.upshift_rpm;
    data.powertrain.transmission.downshift_rpm = p.downshift_rpm;
    let (solver, nanos) = super::m113_solver(&p.solver, p.tolerance, p.max_iterations)?;
    let mut scene = TrackedFlatScene::new(data, p.mu, solver)?;
    let mut drive = TrackedDrive::build(&mut scene.sys, &scene.vehicle, &scene.data)?;
    let (sys, v, d) = (&mut scene.sys, &scene.vehicle, &scene.data);
    let r_p = d.track.sprocket.pitch_radius;

    let mut series = Series::new([
        "t",
        "speed",
        "engine_rpm",
        "engine_torque",
        "gear",
        "converter_slip",
        "sprocket_left",
        "sprocket_right",
        "track_slip",
        "sprocket_torque_left",
        "sprocket_torque_right",
        "tensioner_left",
        "tensioner_right",
        "published_road_speed",
    ]);
    let mut vtk = VtkFrames::new(ctx, (0.05 / p.h).round().max(1.0) as u64);
    let mut max_violation: f64 = 0.0;
    let mut top_speed: f64 = 0.0;
    let mut shifts: Vec<(f64, i32)> = Vec::new();
    let mut gear = 0;
    let mut start = [f64::NAN; 2];
    let mut max_rpm: f64 = 0.0;
    let t0 = Instant::now();
    for i in 1..=n {
        let driving = i > n_settle;
        let inputs = if driving {
            DriverInputs {
                throttle: p.throttle,
                brake: 0.0,
                steering: 0.0,
            }
        } else {
            DriverInputs {
                throttle: 0.0,
                brake: 1.0,
                steering: 0.0,
            }
        };
        drive.synchronize(sys, inputs)?;
        sys.step(p.h)?;
        vtk.record(i, sys)?;
        if i == n_settle.max(1) {
            // Settled: a grease adjuster holds the idler from here (the data's adjuster).
            v.lock_adjusters(sys, d)?;
        }
        let c = sys.body(v.chassis)?;
        let (pos, vel) = (c.position(), c.linear_velocity());
        let fwd = c.rotation() * chrono_core::math::Vector3::x();
        let speed = vel.dot(&fwd);
        if i == n_settle.max(1) {
            start = [pos.x, pos.y];
        }
        max_violation = max_violation.max(sys.max_joint_violation());
        let pt = drive.powertrain();
        let g = pt.current_gear();
        if driving && g != gear {
            shifts.push((sys.time(), g));
        }
        gear = g;
        let (wl, wr) = (drive.sprocket_speed(sys, 0), drive.sprocket_speed(sys, 1));
        let w = 0.5 * (wl + wr);
        let slip = if w.abs() * r_p > 0.05 {
            1.0 - speed / (w * r_p)
        } else {
            f64::NAN
        };
        if driving {
            top_speed = top_speed.max(speed);
            max_rpm = max_rpm.max(pt.engine_speed_rpm());
        }
        series.push(&[
            sys.time(),
            speed,
            pt.engine_speed_rpm(),
            pt.engine_torque(),
            g as f64,
            pt.converter_slip(),
            wl,
            wr,
            slip,
            drive.sprocket_torque(sys, 0),
            drive.sprocket_torque(sys, 1),
            v.sides[0].tensioner_force(sys),
            v.sides[1].tensioner_force(sys),
            d.published.road_speed,
        ]);
        ctx.progress_steps(i, n);
    }
    let wall = t0.elapsed().as_secs_f64();
    vtk.finish()?;
    let solve_s = nanos.load(Ordering::Relaxed) as f64 * 1e-9;
    let c = sys.body(v.chassis)?;
    let end = c.position();
    let distance = (end.x - start[0]).abs();
    let lateral = (end.y - start[1]).abs();

    let mut out = CaseOutput::new();
    out.check(Check::below(
        "max_joint_violation",
        max_violation,
        p.max_violation,
    ));
    out.check(Check::below(
        "lateral_offset_ratio",
        lateral / distance.max(1e-9),
        p.max_lateral_ratio,
    ));
    let speed_end = c
        .linear_velocity()
        .dot(&(c.rotation() * chrono_core::math::Vector3::x()));
    out.check(Check::below(
        "speed_loss",
        (top_speed - speed_end) / top_speed.max(1e-9),
        p.max_speed_loss,
    ));
    out.metric("speed_end", speed_end);
    out.metric("top_speed", top_speed);
    out.metric("published_road_speed", d.published.road_speed);
    out.metric("top_over_published", top_speed / d.published.road_speed);
    out.metric("distance", distance);
    out.metric("lateral_offset", lateral);
    out.metric("gear_end", gear as f64);
    out.metric("engine_rpm_max", max_rpm);
    for (k, (t, g)) in shifts.iter().enumerate() {
        out.metric(format!("shift_{}_time", k + 1), *t);
        out.metric(format!("shift_{}_gear", k + 1), *g as f64);
    }
    // The chain from engine to track: forward speed at the engine's rated speed in the
    // gear reached, v = w_e r_gear r_conical r_p (no converter or track slip).
    let tr = &d.powertrain.transmission;
    if gear >= 1 {
        let rg = tr.forward_ratios[(gear - 1) as usize];
        let w_rated = d.published.engine_speed * std::f64::consts::TAU / 60.0;
        out.metric(
            "speed_at_rated_rpm_in_gear_end",
            w_rated * rg * d.driveline.conical_ratio * r_p,
        );
    }
    let top_gear = tr.forward_ratios.len();
    let w_rated = d.published.engine_speed * std::f64::consts::TAU / 60.0;
    out.metric(
        "speed_at_rated_rpm_top_gear",
        w_rated * tr.forward_ratios[top_gear - 1] * d.driveline.conical_ratio * r_p,
    );
    out.metric("max_joint_violation", max_violation);
    out.metric("wall_s", wall);
    out.metric("steps_per_s", n as f64 / wall);
    out.metric("real_time_factor", p.t_end / wall);
    out.metric("ccp_solve_share", solve_s / wall);
    ctx.note(format!(
        "M113A1 full throttle from rest: {:.2} m/s ({:.1} km/h) after {:.1} s of driving, \
         top {:.2} m/s, gear {gear}, {} shifts, engine up to {max_rpm:.0} rpm; published road \
         speed {:.1} m/s (reported: the model's ratio chain is Project Chrono's, not the \
         TX100-1's); joint violation {:.1e} m; {:.0} steps/s, CCP solve {:.0} % of the wall time",
        speed_end,
        3.6 * speed_end,
        p.t_end - p.settle,
        top_speed,
        shifts.len(),
        d.published.road_speed,
        max_violation,
        n as f64 / wall,
        100.0 * solve_s / wall
    ));
    out.series = series;
    out.plot = PlotSpec::new(
        "M113 full-throttle acceleration",
        "t [s]",
        "forward speed [m/s]",
        &["speed"],
    )
    .with_reference(&["published_road_speed"]);
    out.steps = n;
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<M113AccelParams>::boxed(
        "m113-accel",
        "vehicle",
        "M113A1 (shoe by shoe, powertrain and braked-differential driveline) at full throttle \
         from rest on flat rigid ground: no joint drift above 1 mm, straight run; speed, \
         shifts, engine speed, slip and the top speed reported against the published road \
         speed (not checked: the ratio chain is a model's).",
        run,
    )
}
