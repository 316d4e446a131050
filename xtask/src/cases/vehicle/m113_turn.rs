//! `m113-turn`: a steady skid-steer turn of the M113A1 on flat rigid ground, against Wong's
//! theory of skid steering.
//!
//! After 0.5 s on the brakes the vehicle drives off; a speed controller sets the throttle
//! and a yaw-rate controller the steering (the braked-differential driveline brakes the
//! inner track) so that the vehicle turns left at `speed` on a circle of `radius`
//! (lateral acceleration `speed^2 / radius`, kept below 0.05 g so that the theory's
//! low-speed assumptions hold). Over the last `measure` seconds:
//!
//! - `thrust_difference`: the outer sprocket's thrust minus the inner one's, `(T_o - T_i) /
//!   r_p` (`T` the driveline's net torque on each sprocket, drive minus brake, `r_p` the
//!   pitch radius), N;
//! - `thrust_difference_theory`: Wong's steady-state moment balance for skid steering at
//!   low speed (*Theory of Ground Vehicles*, 4th ed., Wiley 2008, sect. 7.2): the thrust
//!   difference times half the tread `B` balances the moment of turning resistance,
//!   `(F_o - F_i) B / 2 = M_r`, with the lateral resistance of every ground contact equal to
//!   the friction coefficient times its normal load and pointing against its lateral
//!   sliding, reversing at the vehicle's centre of mass (no lateral acceleration):
//!   `M_r = mu sum_c N_c |x_c - x_G|`, summed over the simulated ground contacts (normal
//!   loads `N_c` at longitudinal positions `x_c` in the vehicle frame) — "integrated over the
//!   simulated normal-load distribution with the contact friction";
//!   That is `thrust_difference_simple`, reported: it takes every contact's lateral
//!   resistance as the full `mu N_c`, which holds only where the tracks hardly slip
//!   lengthwise. With Coulomb friction a contact's force is `mu N_c` along its sliding
//!   velocity, and a track that must deliver a thrust slides lengthwise too, so part of
//!   each contact's friction goes into thrust and less into lateral resistance;
//! - `thrust_difference_theory`: the same theory with that friction law (Wong's general
//!   theory of skid steering, sect. 7.3, with a rigid-plastic shear law: the shear stress
//!   is `mu p` along the sliding direction at any slip): each contact on track `j` slides
//!   at `(u_j, omega x_c + v_y)` (`u_j` the track's lengthwise slip velocity, the same along
//!   the track; `v_y` the lateral velocity of the centre of mass) and receives `-mu N_c`
//!   along it; `u_L`, `u_R`, `v_y` solve the steady balance (`sum F_x = 0` on flat ground,
//!   `sum F_y = m V omega`, yaw moment 0) by Newton's method ([`skid_steer`]), and the
//!   thrust difference is `F_R - F_L`, each the lengthwise ground force on a track;
//! - reported alongside: the uniform-load formula `M_r = mu W L / 4` (`W` the weight, `L`
//!   the ground contact length), i.e. `F_o - F_i = mu W L / (2 B)`, the measured yaw rate,
//!   speed and radius, and the load distribution's centre.
//!
//! Modes (`mode`): `steady` (this turn, the default and `--quick`), `pivot` (the pivot turn
//! with the differential steering unit, [`super::m113_pivot`]) or `both` (the steady turn,
//! then the pivot; `--full`). The pivot's metrics and checks are prefixed `pivot_`. The steady turn's steering
//! (`steering`) is the braked differential (the data's default) or the DSU (`--set
//! steering=dsu`: the steering input sets the sprockets' speed difference; the controller
//! feeds forward the input of the target yaw rate without track slip and corrects with PI).
//!
//! Check: `thrust_difference` within 10 % of `thrust_difference_theory` (issue 26; the
//! issue names Wong's theory over the simulated loads: the simple form assumes no
//! lengthwise slip, which a Coulomb track cannot have while it pulls, so the check uses
//! the general form and reports the simple one, docs/validation-vehicle.md). The
//! contact friction `mu` is the minimum of the ground's and the shoes' coefficients. The
//! braked differential can hold a thrust difference of at most the inner brake's torque
//! over the pitch radius (40.6 kN for the M113's 10 kN m; the DSU's is its steering motor's
//! torque limit over its steering ratio and the pitch radius, 81 kN): a friction whose
//! uniform-load estimate needs more than 0.9 of that is refused. Near that bound the engine cannot drive the
//! outer track against the braked inner one (at 0.5, 33.8 kN, the vehicle stalls in the
//! turn at full throttle in first gear): the default 0.3 needs 20.3 kN.

use std::sync::atomic::Ordering;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use chrono_core::math::{GRAVITY_MAGNITUDE, Vector3};
use chrono_vehicle::driveline::TrackSteering;
use chrono_vehicle::m113::m113_data;
use chrono_vehicle::powertrain::ShiftSpeed;
use chrono_vehicle::state::DriverInputs;
use chrono_vehicle::tracked::{TrackedFlatScene, TrackedVehicleData, contact_forces};
use chrono_vehicle::tracked_drive::TrackedDrive;

use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::cases::rigid::{VtkFrames, n_steps};
use crate::params::{CaseParams, ParamCase, ParamInfo};

pub use super::skid_steer::skid_steer;

/// Parameters of `m113-turn`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct M113TurnParams {
    /// Radius of the turn (the centre of mass' path), m.
    pub radius: f64,
    /// Forward speed, m/s.
    pub speed: f64,
    /// Ground friction coefficient (combined with the shoes' by the minimum).
    pub mu: f64,
    /// Time step, s.
    pub h: f64,
    /// Simulated time, settling included, s.
    pub t_end: f64,
    /// Averaging window at the end, s.
    pub measure: f64,
    /// Settling time with the brakes on, s.
    pub settle: f64,
    /// CCP solver.
    pub solver: String,
    /// Tolerance of the solver's contact iterations.
    pub tolerance: f64,
    /// Iteration cap of the solver's contact iterations.
    pub max_iterations: usize,
    /// Relative tolerance of the thrust difference against the theory.
    pub rel_tolerance: f64,
    /// The speed the shift schedule watches: `input_shaft` (the turbine) or `engine`
    /// (the data file's, Project Chrono's).
    pub shift_on: String,
    /// What runs: `steady` (the steady turn), `pivot` (the pivot turn,
    /// [`super::m113_pivot`]) or `both`.
    pub mode: String,
    /// The steady turn's steering mechanism: `braked_differential` (the data's) or `dsu`
    /// (the pivot turn always has the DSU).
    pub steering: String,
    /// Steering input of the pivot turn, in (0, 1].
    pub pivot_steering: f64,
    /// Simulated time of the pivot turn, settling included, s.
    pub pivot_t_end: f64,
    /// The pivot turn's averaging window at the end, s.
    pub pivot_measure: f64,
    /// Time over which the pivot's steering input ramps up after settling, s.
    pub pivot_ramp: f64,
    /// Time step of the pivot turn, s (see [`super::m113_pivot`] for why not `h`).
    pub pivot_h: f64,
}

impl Default for M113TurnParams {
    fn default() -> Self {
        Self {
            radius: 10.0,
            speed: 1.0,
            mu: 0.3,
            h: 5e-3,
            t_end: 6.0,
            measure: 2.0,
            settle: 0.5,
            solver: "schur".into(),
            tolerance: 1e-8,
            max_iterations: 60,
            rel_tolerance: 0.1,
            shift_on: "input_shaft".into(),
            mode: "both".into(),
            steering: "braked_differential".into(),
            pivot_steering: 0.5,
            pivot_t_end: 4.0,
            pivot_measure: 1.5,
            pivot_ramp: 0.5,
            pivot_h: 5e-3,
        }
    }
}

impl CaseParams for M113TurnParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("radius", "m", "radius of the turn"),
        ParamInfo::new("speed", "m/s", "forward speed"),
        ParamInfo::new("mu", "-", "ground friction coefficient"),
        ParamInfo::new("h", "s", "time step"),
        ParamInfo::new("t_end", "s", "simulated time, settling included"),
        ParamInfo::new("measure", "s", "averaging window at the end"),
        ParamInfo::new("settle", "s", "settling time with the brakes on"),
        ParamInfo::new("solver", "-", "CCP solver"),
        ParamInfo::new("tolerance", "-", "contact solve tolerance"),
        ParamInfo::new("max_iterations", "-", "contact solve iteration cap"),
        ParamInfo::new(
            "rel_tolerance",
            "-",
            "relative tolerance of the thrust difference",
        ),
        ParamInfo::new(
            "shift_on",
            "-",
            "speed the shift schedule watches: input_shaft or engine",
        ),
        ParamInfo::new("mode", "-", "what runs: steady, pivot or both"),
        ParamInfo::new(
            "steering",
            "-",
            "steady turn's steering: braked_differential or dsu",
        ),
        ParamInfo::new("pivot_steering", "-", "steering input of the pivot turn"),
        ParamInfo::new("pivot_t_end", "s", "pivot turn's simulated time"),
        ParamInfo::new("pivot_measure", "s", "pivot turn's averaging window"),
        ParamInfo::new("pivot_ramp", "s", "pivot turn's steering ramp"),
        ParamInfo::new("pivot_h", "s", "pivot turn's time step"),
    ];
    // The default (6 s, the last 2 averaged, then the pivot turn: 4 s, the last 1.5
    // averaged) is also `--quick`: the turn is steady from about 3 s on. `--full` averages
    // 4 s of a 12 s run and 4 s of an 8 s pivot. Both at 5 ms fit the case's budget
    // (xtask/src/budget.rs, docs/validation-vehicle.md "The pivot turn at 5 ms").
    fn apply_mode(&mut self, mode: Mode) {
        if mode == Mode::Full {
            self.t_end = 12.0;
            self.measure = 4.0;
            self.mode = "both".into();
            self.pivot_t_end = 8.0;
            self.pivot_measure = 4.0;
        }
    }
}

/// The vehicle on flat ground with friction `mu`, its drive, and the ground's dense body
/// index (whose contact impulses are the ground's forces on the tracks): the set-up of
/// both turns.
pub(super) fn turn_scene(
    data: TrackedVehicleData,
    mu: f64,
    solver: Box<dyn chrono_core::descriptor::CcpSolver>,
) -> anyhow::Result<(TrackedFlatScene, TrackedDrive, usize)> {
    let mut scene = TrackedFlatScene::new(data, mu, solver)?;
    let drive = TrackedDrive::build(&mut scene.sys, &scene.vehicle, &scene.data)?;
    let ground = scene
        .sys
        .body_set()
        .dense_index(scene.ground)
        .ok_or_else(|| anyhow::anyhow!("the ground body is missing"))?;
    Ok((scene, drive, ground))
}

/// One contact of the tracks on the ground at the last step.
pub(super) struct GroundContact {
    /// Lengthwise and lateral position from the centre of mass (along the chassis' `x`
    /// and `y`), m.
    pub x: f64,
    pub y: f64,
    /// The normal load the ground carries there, N (> 0).
    pub n: f64,
    /// The ground's force on the track, N (world).
    pub on_track: Vector3<f64>,
}

/// The last step's loaded contacts of the ground (dense index `ground`) with the
/// vehicle, positioned from `cg` along `fwd` and `left` (unit vectors of the chassis).
pub(super) fn ground_contacts(
    sys: &chrono_core::system::System,
    h: f64,
    ground: usize,
    cg: Vector3<f64>,
    fwd: Vector3<f64>,
    left: Vector3<f64>,
) -> impl Iterator<Item = GroundContact> {
    contact_forces(sys, h).into_iter().filter_map(move |f| {
        let on_ground = if f.owner_b == ground {
            f.on_b
        } else if f.owner_a == ground {
            -f.on_b
        } else {
            return None;
        };
        let n = -on_ground.z;
        (n > 0.0).then(|| GroundContact {
            x: (f.point - cg).dot(&fwd),
            y: (f.point - cg).dot(&left),
            n,
            on_track: -on_ground,
        })
    })
}

fn validate(p: &M113TurnParams) -> anyhow::Result<()> {
    for (name, v) in [
        ("radius", p.radius),
        ("speed", p.speed),
        ("mu", p.mu),
        ("measure", p.measure),
        ("rel_tolerance", p.rel_tolerance),
    ] {
        anyhow::ensure!(
            v > 0.0 && v.is_finite(),
            "parameter `{name}` must be > 0, got {v}"
        );
    }
    let a_lat = p.speed * p.speed / p.radius;
    anyhow::ensure!(
        a_lat <= 0.05 * GRAVITY_MAGNITUDE,
        "parameters `speed` ({}) and `radius` ({}) give a lateral acceleration of {a_lat:.3} \
         m/s^2, over the 0.05 g of the low-speed theory",
        p.speed,
        p.radius
    );
    anyhow::ensure!(
        p.settle >= 0.0 && p.t_end > p.settle + p.measure,
        "parameter `t_end` ({}) must exceed `settle` + `measure` ({})",
        p.t_end,
        p.settle + p.measure
    );
    anyhow::ensure!(
        ["steady", "pivot", "both"].contains(&p.mode.as_str()),
        "parameter `mode` must be `steady`, `pivot` or `both`, got `{}`",
        p.mode
    );
    p.steering.parse::<TrackSteering>().map_err(|_| {
        anyhow::anyhow!(
            "parameter `steering` must be `braked_differential` or `dsu`, got `{}`",
            p.steering
        )
    })?;
    anyhow::ensure!(
        p.pivot_steering > 0.0 && p.pivot_steering <= 1.0,
        "parameter `pivot_steering` must be in (0, 1], got {}",
        p.pivot_steering
    );
    anyhow::ensure!(
        p.pivot_ramp >= 0.0 && p.pivot_ramp.is_finite(),
        "parameter `pivot_ramp` must be finite and >= 0, got {}",
        p.pivot_ramp
    );
    anyhow::ensure!(
        p.pivot_measure > 0.0
            && p.pivot_t_end.is_finite()
            && p.pivot_t_end > p.settle + p.pivot_ramp + p.pivot_measure,
        "parameters `pivot_t_end` ({}) and `pivot_measure` ({}): the window must be > 0 and \
         end after `settle` + `pivot_ramp` + `pivot_measure` ({})",
        p.pivot_t_end,
        p.pivot_measure,
        p.settle + p.pivot_ramp + p.pivot_measure
    );
    Ok(())
}

/// The shift schedule's speed from the `shift_on` parameter.
pub(super) fn shift_speed(shift_on: &str) -> anyhow::Result<ShiftSpeed> {
    Ok(match shift_on {
        "input_shaft" => ShiftSpeed::InputShaft,
        "engine" => ShiftSpeed::Engine,
        other => {
            anyhow::bail!("parameter `shift_on` must be `input_shaft` or `engine`, got `{other}`")
        }
    })
}

/// Proportional-integral controller with its output clamped (and the integral frozen while
/// clamped, so it does not wind up).
struct Pi {
    kp: f64,
    ki: f64,
    lo: f64,
    hi: f64,
    integral: f64,
}

impl Pi {
    fn update(&mut self, error: f64, dt: f64) -> f64 {
        let trial = self.kp * error + self.ki * (self.integral + error * dt);
        if trial > self.lo && trial < self.hi {
            self.integral += error * dt;
        }
        (self.kp * error + self.ki * self.integral).clamp(self.lo, self.hi)
    }
}

fn run(p: &M113TurnParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    validate(p)?;
    let mut out = if p.mode == "pivot" {
        CaseOutput::new()
    } else {
        run_steady(p, ctx)?
    };
    if p.mode != "steady" {
        let series = super::m113_pivot::run_pivot(p, ctx, &mut out)?;
        if p.mode == "pivot" {
            out.series = series;
            out.plot = PlotSpec::new(
                "M113 pivot turn",
                "t [s]",
                "thrust difference [N]",
                &["thrust_difference"],
            )
            .with_reference(&["thrust_difference_theory"]);
        }
    }
    Ok(out)
}

/// The steady turn.
fn run_steady(p: &M113TurnParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    let n = n_steps(p.h, p.t_end)?;
    let n_settle = (p.settle / p.h).round() as u64;
    let n_measure = n - (p.measure / p.h).round() as u64;
    let mut data = m113_data()?;
    // A turn loads the converter towards stall (its stall speed, ~1550 rpm, is above the
    // 1500 rpm upshift speed): a schedule on the engine speed then shifts up and never
    // back down, and the vehicle stalls in the turn in second gear (radius 20 m at 1.5
    // m/s). On the turbine's speed (the vehicle's speed through the gearbox) it holds the
    // gear the road speed asks for.
    data.powertrain.transmission.shift_speed = shift_speed(&p.shift_on)?;
    data.driveline.steering = p.steering.parse()?;
    data.validate()?;
    let (solver, nanos) = super::m113_solver(&p.solver, p.tolerance, p.max_iterations)?;
    let (mut scene, mut drive, ground) = turn_scene(data, p.mu, solver)?;
    let (sys, v, d) = (&mut scene.sys, &scene.vehicle, &scene.data);
    let r_p = d.track.sprocket.pitch_radius;
    let tread = 2.0 * d.track_y;
    let mu = p.mu.min(d.track.materials.shoe.friction);
    let weight = d.total_mass() * sys.settings().gravity.norm();
    let yaw_target = p.speed / p.radius;
    // The braked differential's largest thrust difference: the open differential splits the
    // drive torque equally, so the difference is the inner brake's torque over the pitch
    // radius. The DSU's is the steering motor's torque limit over its ratio and the pitch
    // radius. A turn whose uniform-load resistance needs more cannot be held.
    let uniform = mu * weight * d.contact_length() / (2.0 * tread);
    let dsu = match d.driveline.steering {
        TrackSteering::Dsu => d.driveline.dsu.clone(),
        TrackSteering::BrakedDifferential => None,
    };
    let (max_df, what) = match &dsu {
        Some(u) => (
            u.max_sprocket_torque_difference() / r_p,
            "the DSU's steering motor gives (its torque limit / steering ratio / pitch radius)",
        ),
        None => (
            d.driveline.brake_max_torque / r_p,
            "the braked differential gives (brake torque / pitch radius)",
        ),
    };
    anyhow::ensure!(
        uniform < 0.9 * max_df,
        "parameter `mu` ({}): the turn needs a thrust difference of about {uniform:.0} N (mu W L \
         / 2B), more than 0.9 of what {what}, {max_df:.0} N: lower the friction",
        p.mu
    );
    // The DSU sets the sprockets' speed difference: the steering input that gives the
    // target yaw rate without track slip, `s = omega B / (2 k w_max r_p)`, is fed forward
    // and the PI controller corrects for the slip.
    let feed_forward = dsu.as_ref().map_or(0.0, |u| {
        yaw_target * tread / (2.0 * u.steering_ratio * u.max_steering_speed * r_p)
    });

    let mut throttle_pi = Pi {
        kp: 1.0,
        ki: 1.0,
        lo: 0.0,
        hi: 1.0,
        integral: 0.0,
    };
    // Steering input per yaw-rate error (1/(rad/s)): full steering brakes the inner track
    // with 10 kN m, far more than a gentle turn needs. The DSU's full steering is a yaw
    // rate of about 0.9 rad/s: a proportional gain of 1 corrects an error by ~0.9 of it.
    let mut steer_pi = Pi {
        kp: if dsu.is_some() { 1.0 } else { 2.0 },
        ki: 4.0,
        lo: -1.0 - feed_forward,
        hi: 1.0 - feed_forward,
        integral: 0.0,
    };
    let mut series = Series::new([
        "t",
        "speed",
        "yaw_rate",
        "yaw_rate_target",
        "steering",
        "throttle",
        "thrust_difference",
        "thrust_difference_theory",
        "thrust_difference_simple",
    ]);
    let mut vtk = VtkFrames::new(ctx, (0.1 / p.h).round().max(1.0) as u64);
    let (mut sum_df, mut sum_th, mut sum_yaw, mut sum_v, mut sum_x) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let mut sum_simple = 0.0;
    let mut theory_error: Option<String> = None;
    let mut contacts: Vec<[f64; 3]> = Vec::new();
    let mass = d.total_mass();
    let mut count = 0usize;
    let mut max_violation: f64 = 0.0;
    let t0 = Instant::now();
    let mut inputs = DriverInputs {
        throttle: 0.0,
        brake: 1.0,
        steering: 0.0,
    };
    for i in 1..=n {
        drive.synchronize(sys, inputs)?;
        sys.step(p.h)?;
        vtk.record(i, sys)?;
        if i == n_settle.max(1) {
            // Settled: a grease adjuster holds the idler from here (the data's adjuster).
            v.lock_adjusters(sys, d)?;
        }
        let c = sys.body(v.chassis)?;
        let rot = c.rotation();
        let fwd = rot * Vector3::x();
        let speed = c.linear_velocity().dot(&fwd);
        let yaw = c.angular_velocity().z;
        max_violation = max_violation.max(sys.max_joint_violation());
        if i >= n_settle {
            let t = p.h;
            inputs = DriverInputs {
                throttle: throttle_pi.update(p.speed - speed, t),
                brake: 0.0,
                steering: feed_forward + steer_pi.update(yaw_target - yaw, t),
            };
        }
        // Outer (right, side 1) minus inner (left, side 0) sprocket thrust.
        let df = (drive.sprocket_torque(sys, 1) - drive.sprocket_torque(sys, 0)) / r_p;
        // Moment of turning resistance of the ground contacts about the centre of mass.
        let cg = c.position();
        let left = rot * Vector3::y();
        let mut m_r = 0.0;
        let mut load_x = (0.0, 0.0);
        contacts.clear();
        for g in ground_contacts(sys, p.h, ground, cg, fwd, left) {
            let (x, n_c) = (g.x, g.n);
            contacts.push([x, g.y, n_c]);
            m_r += mu * n_c * x.abs();
            load_x.0 += n_c * x;
            load_x.1 += n_c;
        }
        let simple = 2.0 * m_r / tread;
        let th = if i > n_measure {
            match skid_steer(&contacts, mu, yaw, mass * speed * yaw) {
                Ok((fl, fr)) => fr - fl,
                Err(e) => {
                    theory_error = Some(e.to_string());
                    f64::NAN
                }
            }
        } else {
            f64::NAN
        };
        if i > n_measure && th.is_finite() {
            sum_df += df;
            sum_th += th;
            sum_simple += simple;
            sum_yaw += yaw;
            sum_v += speed;
            sum_x += load_x.0 / load_x.1.max(1e-9);
            count += 1;
        }
        series.push(&[
            sys.time(),
            speed,
            yaw,
            yaw_target,
            inputs.steering,
            inputs.throttle,
            df,
            th,
            simple,
        ]);
        ctx.progress_steps(i, n);
    }
    let wall = t0.elapsed().as_secs_f64();
    vtk.finish()?;
    let solve_s = nanos.load(Ordering::Relaxed) as f64 * 1e-9;
    let window = (n - n_measure) as usize;
    if count < window {
        // The theory has no solution where the vehicle does not turn (no lateral sliding
        // to resist): the checks then fail on the yaw rate and the steps are reported.
        ctx.note(format!(
            "the skid-steer theory failed on {} of {window} steps of the window (last: {})",
            window - count,
            theory_error.clone().unwrap_or_default()
        ));
    }
    let k = count as f64;
    let (df, th, yaw, speed) = (sum_df / k, sum_th / k, sum_yaw / k, sum_v / k);
    let out_steps_failed = window - count;

    let mut out = CaseOutput::new();
    out.metric("theory_failed_steps", out_steps_failed as f64);
    // The case is a steady turn at the set radius: the yaw rate must have been held.
    out.check(Check::relative("yaw_rate", yaw, yaw_target, 0.1));
    out.check(Check::relative(
        "thrust_difference",
        df,
        th,
        p.rel_tolerance,
    ));
    out.metric("thrust_difference_theory", th);
    out.metric("thrust_difference_simple", sum_simple / k);
    out.metric("simple_over_measured", sum_simple / k / df);
    out.metric("thrust_difference_uniform_load", uniform);
    out.metric("yaw_rate_target", yaw_target);
    out.metric("speed", speed);
    out.metric("turn_radius", speed / yaw);
    out.metric(
        "lateral_acceleration_over_g",
        speed * yaw / GRAVITY_MAGNITUDE,
    );
    out.metric("load_centre_from_cg", sum_x / k);
    out.metric("max_joint_violation", max_violation);
    out.metric("wall_s", wall);
    out.metric("steps_per_s", n as f64 / wall);
    out.metric("real_time_factor", p.t_end / wall);
    out.metric("ccp_solve_share", solve_s / wall);
    ctx.note(format!(
        "M113A1 skid-steer turn: {speed:.3} m/s at yaw rate {yaw:.4} rad/s (radius {:.2} m); \
         thrust difference {df:.0} N against Wong's general theory {th:.0} N over the \
         simulated loads ({:+.1} %), his simple form {:.0} N, the uniform-load formula \
         {uniform:.0} N; {:.0} steps/s, CCP {:.0} %",
        speed / yaw,
        100.0 * (df / th - 1.0),
        sum_simple / k,
        n as f64 / wall,
        100.0 * solve_s / wall
    ));
    out.series = series;
    out.plot = PlotSpec::new(
        "M113 skid-steer turn",
        "t [s]",
        "thrust difference [N]",
        &["thrust_difference"],
    )
    .with_reference(&["thrust_difference_theory"]);
    out.steps = n;
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<M113TurnParams>::boxed(
        "m113-turn",
        "vehicle",
        "M113A1 steady skid-steer turn and pivot turn (differential steering unit) on flat \
         rigid ground: the sprockets' thrust difference against Wong's theory integrated over \
         the simulated ground loads (10 %); the uniform-load formula reported.",
        run,
    )
}
