//! `hmmwv-turn`: a constant-radius turn at low speed on flat rigid ground.
//!
//! A path follower (pure pursuit, speed PID) drives the HMMWV around a circle of radius
//! `radius` at `speed`. Once steady (the last `measure` seconds), the mean front-wheel steer
//! angle is compared with the kinematic (Ackermann) angle `atan(L / R)` of a bicycle with the
//! wheelbase `L` turning about the circle's centre (`R` the radius of the rear-axle path, the
//! circle), and the lateral acceleration `v * yaw_rate` with `v^2 / R`. At low speed the
//! tires barely slip, so both must agree within 5 %.

use std::time::Instant;

use chrono_vehicle::driver::{Driver, Path, PathFollowerDriver, PathFollowerParams};
use serde::{Deserialize, Serialize};

use chrono_vehicle::hmmwv::{PowertrainKind, TireKind};

use super::scene::{hmmwv_flat, hmmwv_max_front_steer};
use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::cases::rigid::{VtkFrames, n_steps};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// Parameters of `hmmwv-turn`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TurnParams {
    /// Radius of the circle the rear axle follows, m.
    pub radius: f64,
    /// Target speed, m/s.
    pub speed: f64,
    /// Time step, s.
    pub h: f64,
    /// Simulated time, s.
    pub t_end: f64,
    /// Averaging window at the end, s.
    pub measure: f64,
    /// Tire model: `rigid` or `handling`.
    pub tire: TireKind,
    /// Tire-ground friction coefficient.
    pub mu: f64,
    /// CCP solver.
    pub solver: String,
}

impl Default for TurnParams {
    fn default() -> Self {
        Self {
            radius: 20.0,
            speed: 3.0,
            h: 1e-3,
            t_end: 40.0,
            measure: 10.0,
            tire: TireKind::Handling,
            mu: 0.9,
            solver: "schur".into(),
        }
    }
}

impl CaseParams for TurnParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("radius", "m", "radius of the circle (rear axle path)"),
        ParamInfo::new("speed", "m/s", "target speed"),
        ParamInfo::new("h", "s", "time step"),
        ParamInfo::new("t_end", "s", "simulated time"),
        ParamInfo::new("measure", "s", "averaging window at the end"),
        ParamInfo::new("tire", "-", "tire model: rigid | handling"),
        ParamInfo::new("mu", "-", "tire-ground friction coefficient"),
        ParamInfo::new("solver", "-", "CCP solver"),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        if mode == Mode::Quick {
            self.t_end = 20.0;
            self.measure = 5.0;
        }
    }
}

fn run(p: &TurnParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(
        p.radius > 5.0 && p.radius.is_finite(),
        "parameter `radius` must be > 5 m, got {}",
        p.radius
    );
    anyhow::ensure!(
        p.speed > 0.0 && p.speed.is_finite(),
        "parameter `speed` must be > 0, got {}",
        p.speed
    );
    anyhow::ensure!(
        p.measure > 0.0 && p.measure < p.t_end,
        "parameter `measure` must be in (0, t_end), got {}",
        p.measure
    );
    let n = n_steps(p.h, p.t_end)?;
    let max_steer = hmmwv_max_front_steer(p.tire, p.mu, &p.solver)?;
    let mut scene = hmmwv_flat(p.tire, PowertrainKind::Chrono, p.mu, &p.solver)?;
    let wheelbase = scene.data.axles[0].location[0] - scene.data.axles[1].location[0];
    let rear_x = scene.data.axles[1].location[0];
    // The rear axle starts on the circle, heading +X, turning left about (rear_x, R).
    let path = Path::turn_circle(rear_x, p.radius)?;
    let mut params = PathFollowerParams::hmmwv(p.speed);
    params.steering.wheelbase = wheelbase;
    params.steering.rear_axle_offset = rear_x;
    params.steering.max_steer_angle = max_steer;
    let mut driver = PathFollowerDriver::new(path, params)?;
    let mut series = Series::new([
        "t",
        "speed",
        "steer",
        "steer_ackermann",
        "lat_acc",
        "lat_acc_ref",
    ]);
    let mut vtk = VtkFrames::new(ctx, (0.1 / p.h).round() as u64);
    let ackermann = (wheelbase / p.radius).atan();
    let (mut sum_steer, mut sum_acc, mut sum_ref, mut count) = (0.0, 0.0, 0.0, 0usize);
    let t_measure = p.t_end - p.measure;
    let wall0 = Instant::now();
    for i in 1..=n {
        let st = scene.vehicle.state(&scene.sys)?;
        let inputs = driver.synchronize(&st);
        scene.vehicle.synchronize(&mut scene.sys, inputs)?;
        scene.sys.step(p.h)?;
        vtk.record(i, &scene.sys)?;
        let st = scene.vehicle.state(&scene.sys)?;
        let v = st.forward_speed();
        let acc = v * st.angular_velocity.z;
        let acc_ref = v * v / p.radius;
        let a = scene.steer_angles()?;
        let steer = 0.5 * (a[0] + a[1]);
        if scene.sys.time() > t_measure {
            sum_steer += steer;
            sum_acc += acc;
            sum_ref += acc_ref;
            count += 1;
        }
        if i % 20 == 0 {
            series.push(&[scene.sys.time(), v, steer, ackermann, acc, acc_ref]);
        }
        ctx.progress_steps(i, n);
    }
    let wall = wall0.elapsed().as_secs_f64();
    vtk.finish()?;
    anyhow::ensure!(count > 0, "no step in the measuring window");
    let c = count as f64;
    let mut out = CaseOutput::new();
    out.check(Check::relative(
        "steer_angle_error",
        sum_steer / c,
        ackermann,
        0.05,
    ));
    out.check(Check::relative(
        "lateral_accel",
        sum_acc / c,
        sum_ref / c,
        0.05,
    ));
    out.metric("max_front_steer_deg", max_steer.to_degrees());
    out.metric("real_time_factor", p.t_end / wall);
    out.series = series;
    out.plot = PlotSpec::new(
        "HMMWV constant-radius turn",
        "t [s]",
        "steer [rad]",
        &["steer"],
    )
    .with_reference(&["steer_ackermann"]);
    out.steps = n;
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<TurnParams>::boxed(
        "hmmwv-turn",
        "vehicle",
        "HMMWV on a constant-radius circle at low speed: front steer angle against Ackermann, lateral acceleration against v^2/R.",
        run,
    )
}
