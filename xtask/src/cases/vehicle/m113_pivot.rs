//! The pivot turn of `m113-turn` (`--set mode=pivot`, or `both`, which `--full` sets): the M113A1
//! with the differential steering unit (`chrono_vehicle::driveline::track_dsu`) turns on
//! the spot on flat rigid ground.
//!
//! After `settle` s on the brakes, the brake stays on (the DSU's brake holds the propulsion
//! shaft: zero propulsion speed), the throttle off, and the steering input ramps over
//! `pivot_ramp` s to `pivot_steering`: the steering motor turns the sprockets at `-/+ k
//! w_st` (`k` the DSU's steering ratio, `w_st = s w_max`), the left track backwards and the
//! right one forwards, and the vehicle turns left about its centre. Over the last
//! `pivot_measure` s of `pivot_t_end`:
//!
//! - `pivot_thrust_difference`: `F_o - F_i = (T_R - T_L) / r_p`, the sprockets' torques
//!   over the pitch radius (`T` the torque the driveline applies to each sprocket), N, and
//!   each side's thrust (`pivot_thrust_left`, `pivot_thrust_right`; `F_o = -F_i` for a turn
//!   about the centre, reported as `pivot_thrust_sum_ratio = (F_o + F_i) / (F_o - F_i)`);
//! - `pivot_thrust_difference_theory`: Wong's moment balance (*Theory of Ground Vehicles*,
//!   4th ed., sect. 7.2: `(F_o - F_i) B / 2 - (R_o - R_i) B / 2 = M_r`, `R` the tracks'
//!   motion resistances) with each track's resistance against its own motion: in a pivot
//!   the inner track runs backwards, its resistance changes sign and the two add instead of
//!   cancelling as in a forward turn, `F_o - F_i = 2 M_r / B + R_o + R_i` (magnitudes).
//!   `M_r` is that of the simulated ground contacts (their normal loads and positions each
//!   step, the contact friction), by the same function as the steady turn's check
//!   ([`super::skid_steer::skid_steer`], Wong's general theory with Coulomb contacts, sect.
//!   7.3) with no lateral acceleration; `R` is the simulated one (the rigid ground has no
//!   external motion resistance: it is the running gear's internal resistance), each
//!   track's sprocket thrust less the ground's lengthwise force on it, averaged
//!   (`pivot_motion_resistance`). The check is therefore equivalent to the ground's
//!   lengthwise thrust difference against `2 M_r / B`. Reported: the moment part alone
//!   (`pivot_thrust_difference_moment_theory`, the issue's `(F_o - F_i) B / 2 = M_r`) and
//!   the measured difference over it;
//! - reported alongside: the simple form `2 mu sum N |x| / B` (every contact resisting
//!   laterally with its full friction, sect. 7.2) and the uniform-load formula `M_r = mu W L
//!   / 4`, i.e. `F_o - F_i = mu W L / (2 B)`;
//! - the ground's lengthwise force on each track (`pivot_ground_thrust_*`, from the
//!   contacts) and each track's motion resistance;
//! - the yaw rate against the kinematic one of the sprocket speeds, `(w_R - w_L) r_p / B`
//!   (`pivot_yaw_slip` = 1 - measured / kinematic), and against the general theory's: its
//!   lengthwise slips `u_L`, `u_R` scale with the yaw rate (Coulomb contacts), and `(w_R -
//!   w_L) r_p = omega B - (u_R - u_L)` (`pivot_yaw_rate_theory`, reported); the centre of
//!   mass' horizontal speed (`pivot_centre_speed`), the steering motor's torque and power.
//!
//! The series (`pivot.csv`, and the plot when only the pivot runs) has the moment part of
//! the theory per step (`thrust_difference_theory`).
//!
//! Time step: `pivot_h`, 5 ms by default like the steady turn's `h`. Before the track's
//! spring-dampers became implicit rows (`AxisSpring`, 2026-12-06) the pivot run diverged at
//! 5 ms in the landing for `mu` 0.2, 0.5 and 0.8 (the explicit rear-arm damper past its
//! stability limit) and used 4 ms; with them it runs at 5 ms for all three.
//!
//! Checks: the thrust difference within `rel_tolerance` of the theory (the 10 %),
//! the vehicle turning (`pivot_yaw_slip` below 0.5: the yaw rate above half the kinematic
//! one), no shoe separating and no joint drifting (`pivot_max_joint_violation` below 1 mm
//! over the run, settling included).

use std::time::Instant;

use chrono_core::math::Vector3;
use chrono_vehicle::driveline::TrackSteering;
use chrono_vehicle::m113::m113_data;
use chrono_vehicle::state::DriverInputs;

use super::m113_turn::M113TurnParams;
use super::skid_steer::skid_steer_solution;
use crate::case::{CaseOutput, Check, RunContext, Series};
use crate::cases::rigid::n_steps;

/// Largest joint violation accepted over the pivot run, m (the M113 cases' 1 mm).
const MAX_VIOLATION: f64 = 1e-3;

/// Run the pivot turn and add its metrics and checks (prefixed `pivot_`) to `out`; its
/// time series goes to `pivot.csv` and is returned.
pub(super) fn run_pivot(
    p: &M113TurnParams,
    ctx: &RunContext,
    out: &mut CaseOutput,
) -> anyhow::Result<Series> {
    let h = p.pivot_h;
    anyhow::ensure!(
        h > 0.0 && h.is_finite(),
        "parameter `pivot_h` must be finite and > 0, got {h}"
    );
    let n = n_steps(h, p.pivot_t_end)?;
    let n_settle = (p.settle / h).round() as u64;
    let n_measure = n - (p.pivot_measure / h).round() as u64;
    let mut data = m113_data()?;
    data.driveline.steering = TrackSteering::Dsu;
    data.powertrain.transmission.shift_speed = super::m113_turn::shift_speed(&p.shift_on)?;
    data.validate()?;
    let dsu = data
        .driveline
        .dsu
        .clone()
        .ok_or_else(|| anyhow::anyhow!("the data has no `driveline.dsu`"))?;
    let (solver, _nanos) = super::m113_solver(&p.solver, p.tolerance, p.max_iterations)?;
    let (mut scene, mut drive, ground) = super::m113_turn::turn_scene(data, p.mu, solver)?;
    let (sys, v, d) = (&mut scene.sys, &scene.vehicle, &scene.data);
    let r_p = d.track.sprocket.pitch_radius;
    let tread = 2.0 * d.track_y;
    let mu = p.mu.min(d.track.materials.shoe.friction);
    let mass = d.total_mass();
    let weight = mass * sys.settings().gravity.norm();
    let uniform = mu * weight * d.contact_length() / (2.0 * tread);
    // The steering motor holds a sprocket torque difference of at most T_max / k: a pivot
    // whose uniform-load resistance needs more than 0.9 of that is refused.
    let max_df = dsu.max_sprocket_torque_difference() / r_p;
    anyhow::ensure!(
        uniform < 0.9 * max_df,
        "parameter `mu` ({}): the pivot turn needs a thrust difference of about {uniform:.0} N \
         (mu W L / 2B), more than 0.9 of what the steering motor gives ({max_df:.0} N = \
         driveline.dsu.max_steering_torque / steering_ratio / pitch radius)",
        p.mu
    );
    let yaw_kinematic_cmd =
        2.0 * dsu.steering_ratio * dsu.max_steering_speed * p.pivot_steering * r_p / tread;

    let mut series = Series::new([
        "t",
        "yaw_rate",
        "yaw_rate_kinematic",
        "steering",
        "thrust_left",
        "thrust_right",
        "ground_thrust_left",
        "ground_thrust_right",
        "thrust_difference",
        "thrust_difference_theory",
        "thrust_difference_simple",
        "steering_torque",
        "centre_speed",
        "joint_violation",
    ]);
    #[derive(Default)]
    struct Sums {
        n: f64,
        yaw: f64,
        yaw_kin: f64,
        yaw_th: f64,
        fl: f64,
        fr: f64,
        gl: f64,
        gr: f64,
        th: f64,
        simple: f64,
        t_st: f64,
        p_st: f64,
        centre: f64,
        load_x: f64,
    }
    let mut sum = Sums::default();
    let mut failed = 0usize;
    let mut theory_error = String::new();
    let mut contacts: Vec<[f64; 3]> = Vec::new();
    let mut max_violation: f64 = 0.0;
    let mut max_violation_turning: f64 = 0.0;
    let t0 = Instant::now();
    let mut inputs = DriverInputs {
        throttle: 0.0,
        brake: 1.0,
        steering: 0.0,
    };
    for i in 1..=n {
        drive.synchronize(sys, inputs)?;
        sys.step(h)?;
        if i == n_settle.max(1) {
            v.lock_adjusters(sys, d)?;
        }
        let violation = sys.max_joint_violation();
        max_violation = max_violation.max(violation);
        if i > n_settle {
            max_violation_turning = max_violation_turning.max(violation);
        }
        let t_since = (i as f64 - n_settle as f64) * h;
        if i >= n_settle {
            let ramp = if p.pivot_ramp > 0.0 {
                (t_since / p.pivot_ramp).clamp(0.0, 1.0)
            } else {
                1.0
            };
            inputs = DriverInputs {
                throttle: 0.0,
                brake: 1.0,
                steering: p.pivot_steering * ramp,
            };
        }
        let c = sys.body(v.chassis)?;
        let rot = c.rotation();
        let fwd = rot * Vector3::x();
        let left = rot * Vector3::y();
        let cg = c.position();
        let vel = c.linear_velocity();
        let speed = vel.dot(&fwd);
        let centre = (vel.x * vel.x + vel.y * vel.y).sqrt();
        let yaw = c.angular_velocity().z;
        let shafts = drive
            .shafts(sys)
            .ok_or_else(|| anyhow::anyhow!("the shaft item is missing"))?;
        let dl = drive.driveline();
        let (w_l, w_r) = (dl.sprocket_speed(0, shafts), dl.sprocket_speed(1, shafts));
        let yaw_kin = (w_r - w_l) * r_p / tread;
        let dsu_line = dl
            .as_dsu()
            .ok_or_else(|| anyhow::anyhow!("the driveline is not a DSU"))?;
        let (t_st, p_st) = (
            dsu_line.steering_torque(shafts),
            dsu_line.steering_power(shafts),
        );
        let (f_l, f_r) = (
            dl.sprocket_torque(0, shafts) / r_p,
            dl.sprocket_torque(1, shafts) / r_p,
        );
        // Ground contacts: loads and positions for the theory, and the ground's lengthwise
        // force on each track.
        contacts.clear();
        let (mut g_l, mut g_r, mut m_r) = (0.0, 0.0, 0.0);
        let (mut lx, mut ln) = (0.0, 0.0);
        for g in super::m113_turn::ground_contacts(sys, h, ground, cg, fwd, left) {
            let (x, y, n_c) = (g.x, g.y, g.n);
            contacts.push([x, y, n_c]);
            m_r += mu * n_c * x.abs();
            lx += n_c * x;
            ln += n_c;
            let along = g.on_track.dot(&fwd);
            if y > 0.0 {
                g_l += along;
            } else {
                g_r += along;
            }
        }
        let simple = 2.0 * m_r / tread;
        let mut th = f64::NAN;
        if i > n_measure {
            match skid_steer_solution(&contacts, mu, yaw, mass * speed * yaw) {
                Ok(sol) => {
                    let (th_l, th_r) = (sol.left, sol.right);
                    th = th_r - th_l;
                    // The theory's yaw rate for the measured sprocket speeds: the tracks'
                    // lengthwise slips scale with the yaw rate (Coulomb contacts are
                    // rate-independent), and `(w_R - w_L) r_p = omega B - (u_R - u_L)`.
                    let slip_per_yaw = (sol.u_right - sol.u_left) / yaw;
                    sum.yaw_th += (w_r - w_l) * r_p / (tread - slip_per_yaw);
                    sum.n += 1.0;
                    sum.yaw += yaw;
                    sum.yaw_kin += yaw_kin;
                    sum.fl += f_l;
                    sum.fr += f_r;
                    sum.gl += g_l;
                    sum.gr += g_r;
                    sum.th += th;
                    sum.simple += simple;
                    sum.t_st += t_st;
                    sum.p_st += p_st;
                    sum.centre += centre;
                    sum.load_x += lx / ln.max(1e-9);
                }
                Err(e) => {
                    failed += 1;
                    theory_error = e.to_string();
                }
            }
        }
        series.push(&[
            sys.time(),
            yaw,
            yaw_kin,
            inputs.steering,
            f_l,
            f_r,
            g_l,
            g_r,
            f_r - f_l,
            th,
            simple,
            t_st,
            centre,
            violation,
        ]);
        ctx.progress_steps(i, n);
    }
    let wall = t0.elapsed().as_secs_f64();
    if failed > 0 {
        ctx.note(format!(
            "pivot: the skid-steer theory failed on {failed} steps of the window (last: \
             {theory_error})"
        ));
    }
    let k = sum.n.max(1.0);
    let a = |x: f64| if sum.n > 0.0 { x / k } else { f64::NAN };
    let (yaw, yaw_kin) = (a(sum.yaw), a(sum.yaw_kin));
    let (f_l, f_r, g_l, g_r) = (a(sum.fl), a(sum.fr), a(sum.gl), a(sum.gr));
    // The tracks' motion resistance (each along its own motion, the left track running
    // backwards): the sprocket thrust less the ground's lengthwise force on the track.
    let (res_l, res_r) = (g_l - f_l, f_r - g_r);
    let th_moment = a(sum.th);
    let (df, th) = (f_r - f_l, th_moment + res_l + res_r);
    let yaw_th = a(sum.yaw_th);
    out.metric("pivot_theory_failed_steps", failed as f64);
    out.check(Check::relative(
        "pivot_thrust_difference",
        df,
        th,
        p.rel_tolerance,
    ));
    // The vehicle turns: at least half the yaw rate of the sprockets' speed difference.
    out.check(Check::below("pivot_yaw_slip", 1.0 - yaw / yaw_kin, 0.5));
    out.check(Check::below(
        "pivot_max_joint_violation",
        max_violation,
        MAX_VIOLATION,
    ));
    out.metric("pivot_thrust_difference_theory", th);
    out.metric("pivot_thrust_difference_moment_theory", th_moment);
    out.metric("pivot_thrust_difference_over_moment_theory", df / th_moment);
    out.metric("pivot_motion_resistance", res_l + res_r);
    out.metric("pivot_yaw_rate_theory", yaw_th);
    out.metric("pivot_yaw_rate", yaw);
    out.metric("pivot_yaw_rate_over_theory", yaw / yaw_th);
    out.metric("pivot_thrust_difference_simple", a(sum.simple));
    out.metric("pivot_thrust_difference_uniform_load", uniform);
    out.metric("pivot_turning_moment_uniform_load", uniform * tread / 2.0);
    out.metric("pivot_thrust_left", f_l);
    out.metric("pivot_thrust_right", f_r);
    out.metric("pivot_thrust_sum_ratio", (f_r + f_l) / df);
    out.metric("pivot_ground_thrust_left", g_l);
    out.metric("pivot_ground_thrust_right", g_r);
    out.metric("pivot_ground_thrust_difference", g_r - g_l);
    out.metric("pivot_motion_resistance_left", res_l);
    out.metric("pivot_motion_resistance_right", res_r);
    out.metric("pivot_yaw_rate_kinematic", yaw_kin);
    out.metric("pivot_yaw_rate_commanded_kinematic", yaw_kinematic_cmd);
    out.metric("pivot_steering_torque", a(sum.t_st));
    out.metric("pivot_steering_power", a(sum.p_st));
    out.metric("pivot_centre_speed", a(sum.centre));
    out.metric("pivot_load_centre_from_cg", a(sum.load_x));
    out.metric("pivot_max_joint_violation", max_violation);
    out.metric("pivot_max_joint_violation_turning", max_violation_turning);
    out.metric("pivot_wall_s", wall);
    ctx.note(format!(
        "M113A1 pivot turn (DSU, steering {:.2}, mu {mu}): yaw rate {yaw:.4} rad/s against \
         {yaw_th:.4} of the theory's slips ({:+.1} %; sprockets' kinematic {yaw_kin:.4}); \
         sprocket thrusts {f_l:.0} N left, {f_r:.0} N right, difference {df:.0} N against \
         Wong's pivot balance {th:.0} N ({:+.1} %: 2 M_r / B of his general theory over the \
         simulated loads {th_moment:.0} N, {:+.1} % without the tracks' motion resistance \
         {:.0} N), simple form {:.0} N, uniform-load mu W L / 2B {uniform:.0} N; ground \
         thrusts {g_l:.0} / {g_r:.0} N; steering motor {:.0} N m, {:.1} kW; centre speed \
         {:.3} m/s; joint drift {max_violation:.1e} m (turning {max_violation_turning:.1e} m); \
         {wall:.1} s wall",
        p.pivot_steering,
        100.0 * (yaw / yaw_th - 1.0),
        100.0 * (df / th - 1.0),
        100.0 * (df / th_moment - 1.0),
        res_l + res_r,
        a(sum.simple),
        a(sum.t_st),
        a(sum.p_st) * 1e-3,
        a(sum.centre)
    ));
    let mut csv = String::new();
    csv.push_str(&series.columns.join(","));
    csv.push('\n');
    for row in &series.rows {
        let cells: Vec<String> = row.iter().map(|x| format!("{x}")).collect();
        csv.push_str(&cells.join(","));
        csv.push('\n');
    }
    std::fs::write(ctx.out_file("pivot.csv"), csv)?;
    out.steps += n;
    Ok(series)
}
