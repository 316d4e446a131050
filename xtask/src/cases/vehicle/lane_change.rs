//! `hmmwv-lane-change`: the path follower drives the ISO 3888-1 double lane change at a set
//! speed on flat rigid ground.
//!
//! The vehicle accelerates on a straight lead-in to `speed`, then follows the lane-change
//! reference line (`chrono_vehicle::driver::IsoDoubleLaneChange`, vehicle width 2.16 m).
//! Checks: the largest lateral distance of the chassis reference point from the path over
//! the manoeuvre (`max_path_error`, below 0.5 m), no rollover (`max_tilt_deg`: the largest
//! tilt of the chassis' up axis from vertical, roll and pitch together, below 30 degrees),
//! and the run stays stable at `h` (any divergence is an error of the step).

use std::time::Instant;

use chrono_vehicle::driver::{Driver, IsoDoubleLaneChange, PathFollowerDriver, PathFollowerParams};
use serde::{Deserialize, Serialize};

use chrono_vehicle::hmmwv::{PowertrainKind, TireKind};

use super::scene::{hmmwv_flat, hmmwv_max_front_steer};
use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::cases::rigid::{VtkFrames, n_steps};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// The point pure pursuit steers onto the path (`--set pursuit_from=rear_axle`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PursuitFrom {
    /// The chassis reference point, where the path error is measured.
    Reference,
    /// The rear axle (the textbook choice).
    RearAxle,
}

/// Parameters of `hmmwv-lane-change`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct LaneChangeParams {
    /// Target speed, km/h.
    pub speed_kmh: f64,
    /// Straight lead-in before the first lane (accelerating), m.
    pub lead_in: f64,
    /// Look-ahead distance of the pure-pursuit steering, m.
    pub lookahead: f64,
    /// The point pure pursuit steers onto the path: `reference` (the chassis reference
    /// point, where the error is measured) or `rear_axle` (the textbook choice).
    pub pursuit_from: PursuitFrom,
    /// Time step, s.
    pub h: f64,
    /// Tire model: `rigid` or `handling`.
    pub tire: TireKind,
    /// Tire-ground friction coefficient.
    pub mu: f64,
    /// CCP solver.
    pub solver: String,
}

impl Default for LaneChangeParams {
    fn default() -> Self {
        Self {
            speed_kmh: 50.0,
            lead_in: 150.0,
            lookahead: 8.0,
            pursuit_from: PursuitFrom::Reference,
            h: 1e-3,
            tire: TireKind::Handling,
            mu: 0.9,
            solver: "schur".into(),
        }
    }
}

impl CaseParams for LaneChangeParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("speed_kmh", "km/h", "target speed"),
        ParamInfo::new("lead_in", "m", "straight lead-in before the first lane"),
        ParamInfo::new(
            "lookahead",
            "m",
            "look-ahead distance of the steering controller",
        ),
        ParamInfo::new(
            "pursuit_from",
            "-",
            "point steered onto the path: reference | rear_axle",
        ),
        ParamInfo::new("h", "s", "time step"),
        ParamInfo::new("tire", "-", "tire model: rigid | handling"),
        ParamInfo::new("mu", "-", "tire-ground friction coefficient"),
        ParamInfo::new("solver", "-", "CCP solver"),
    ];
    fn apply_mode(&mut self, _mode: Mode) {}
}

/// Vehicle width for the ISO lane widths, m (HMMWV, 85 in track plus tires).
const VEHICLE_WIDTH: f64 = 2.16;

fn run(p: &LaneChangeParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(
        p.speed_kmh > 0.0 && p.speed_kmh.is_finite(),
        "parameter `speed_kmh` must be > 0, got {}",
        p.speed_kmh
    );
    let max_steer = hmmwv_max_front_steer(p.tire, p.mu, &p.solver)?;
    let mut scene = hmmwv_flat(p.tire, PowertrainKind::Chrono, p.mu, &p.solver)?;
    let lane = IsoDoubleLaneChange::new(VEHICLE_WIDTH)?;
    let lead_out = 40.0;
    // The vehicle's reference point starts at x = 0: the path starts there.
    let path = lane.course(p.lead_in, lead_out, 0.5)?;
    let shift = p.lead_in;
    let x_end = lane.course_end(shift, lead_out);
    let mut params = PathFollowerParams::hmmwv(p.speed_kmh / 3.6);
    params.steering.lookahead = p.lookahead;
    params.steering.max_steer_angle = max_steer;
    params.steering.wheelbase = scene.data.axles[0].location[0] - scene.data.axles[1].location[0];
    params.steering.rear_axle_offset = match p.pursuit_from {
        // The error is measured at the chassis reference point: steer that point onto the
        // path (pure pursuit's arc from there; the kinematic formula is then approximate).
        PursuitFrom::Reference => 0.0,
        PursuitFrom::RearAxle => scene.data.axles[1].location[0],
    };
    let mut driver = PathFollowerDriver::new(path.clone(), params)?;
    let v_target = p.speed_kmh / 3.6;
    let t_end = 1.5 * x_end / v_target + 20.0;
    let n = n_steps(p.h, t_end)?;
    let mut series = Series::new(["x", "y", "y_path", "speed_kmh", "steering", "tilt_deg"]);
    let mut vtk = VtkFrames::new(ctx, (0.05 / p.h).round() as u64);
    let (mut max_err, mut max_tilt, mut entry_speed): (f64, f64, Option<f64>) = (0.0, 0.0, None);
    let xb = lane.boundaries();
    let wall0 = Instant::now();
    let mut steps = 0;
    for i in 1..=n {
        let st = scene.vehicle.state(&scene.sys)?;
        let inputs = driver.synchronize(&st);
        scene.vehicle.synchronize(&mut scene.sys, inputs)?;
        scene.sys.step(p.h)?;
        steps = i;
        vtk.record(i, &scene.sys)?;
        let st = scene.vehicle.state(&scene.sys)?;
        let (x, y) = (st.position.x, st.position.y);
        let up = st.rotation * chrono_core::math::Vector3::z();
        let tilt = up.z.clamp(-1.0, 1.0).acos().to_degrees();
        max_tilt = max_tilt.max(tilt);
        let in_manoeuvre = x >= shift + xb[0] && x <= shift + xb[5];
        if in_manoeuvre {
            entry_speed.get_or_insert(3.6 * st.forward_speed());
            let c = path.closest(nalgebra::Vector2::new(x, y));
            max_err = max_err.max(c.offset.abs());
        }
        if i % 20 == 0 {
            series.push(&[
                x,
                y,
                lane.center_y(x - shift),
                3.6 * st.forward_speed(),
                inputs.steering,
                tilt,
            ]);
        }
        ctx.progress(x / x_end);
        if x >= x_end {
            break;
        }
    }
    let wall = wall0.elapsed().as_secs_f64();
    vtk.finish()?;
    let entry_speed =
        entry_speed.ok_or_else(|| anyhow::anyhow!("the vehicle never reached the lane change"))?;
    let mut out = CaseOutput::new();
    out.check(Check::below("max_path_error", max_err, 0.5));
    out.check(Check::below("max_tilt_deg", max_tilt, 30.0));
    out.check(Check::relative(
        "entry_speed_kmh",
        entry_speed,
        p.speed_kmh,
        0.1,
    ));
    out.metric("real_time_factor", steps as f64 * p.h / wall);
    out.series = series;
    out.plot = PlotSpec::new("HMMWV ISO double lane change", "x [m]", "y [m]", &["y"])
        .with_reference(&["y_path"]);
    out.steps = steps;
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<LaneChangeParams>::boxed(
        "hmmwv-lane-change",
        "vehicle",
        "HMMWV driven by the path follower through the ISO 3888-1 double lane change: path error below 0.5 m, no rollover.",
        run,
    )
}
