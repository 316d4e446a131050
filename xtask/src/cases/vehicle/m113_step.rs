//! `m113-step`: the M113A1 (`chrono_vehicle::m113`, shoe by shoe, with its hull's
//! collision plates) climbs a rigid vertical step (`chrono_vehicle::obstacle::
//! TrackedStepScene`) at low speed.
//!
//! After `settle` s on the brakes, a speed controller (`chrono_vehicle::driver::
//! SpeedController`, PI) drives the vehicle at `speed` towards the step's face, `gap` m
//! ahead of its foremost point. The step's friction is the data's `obstacle` material
//! (0.8, with the shoes' 0.8 and the hull's 0.7 the pairs' minimum applies), fixed in the
//! data before the case was run.
//!
//! What turns the sprockets (`drive`):
//!
//! - `grade` (the default, the drive of the check): each sprocket is driven directly with
//!   the controller's output times the torque the published gradeability needs,
//!   [`chrono_vehicle::tracked::TrackedVehicleData::published_grade_sprocket_torque`]:
//!   `m g sin(atan 0.6) r_p / 2` with the model's mass, the sprocket's pitch radius and
//!   the published 60 % grade (`published.max_grade`), 6.94 kN m a side for the M113A1.
//!   The gradeability is the published figure of what the vehicle delivers at its
//!   sprockets at low speed; the engine-to-sprocket ratio chain is not published (the
//!   data's is Project Chrono's, uncited, and gives 0.33 of the weight in thrust where
//!   the 60 % grade needs 0.51), so the check asks whether the model's running gear,
//!   hull and contacts climb the step with the drive the real vehicle is published to
//!   have, not whether an uncited gearbox does. (It is the least such a drive gives:
//!   the grade's own rolling resistance is not in it.)
//! - `powertrain`: the data's engine, converter, gearbox and braked differential, the
//!   shift schedule on the turbine speed (as in `m113-turn`) holding first gear. With the
//!   spring tensioner it stalled the converter at about 4.5 kN m a side on a 0.488 m
//!   step; with the grease adjusters it climbs it at 3-4.3 kN m a side
//!   (docs/validation-vehicle.md, "`m113-step`: the track adjuster").
//! - `torque`: as `grade` with a given largest torque `drive_torque` per side.
//!
//! The track adjusters are the data's (`track.idler.tensioner.adjuster`; `adjuster`
//! overrides it): the M113's grease cylinders are locked where the settling left them
//! (the track adjusted at the data's preload), so the chain's pull on the idlers is then
//! whatever the loop needs; `adjuster` = `spring` keeps Project Chrono's spring-damper,
//! which yields about 3.4 cm under the drive and the step and stalls the climb
//! (docs/validation-vehicle.md, "`m113-step`: the track adjuster").
//!
//! `climbed` = 1 when, within `t_end`, the vehicle is on top (`until`):
//!
//! - `com` (the default): the chassis's centre of mass is past the face, the chassis
//!   reference point (the sprocket centre) stands at least its settled height above flat
//!   ground, less `z_tolerance`, above the step's top, and the chassis is level within
//!   `level_tolerance`: the vehicle's weight rests on the top, its nose come down again;
//!   the rest is driving on the top while the rear of the tracks runs over the edge;
//! - `idlers`: as before 2026-12-06, both idlers (the rear of the tracks) past the face
//!   by an idler radius plus a shoe thickness (so they can only be over the top) and the
//!   reference at its height above the top: the whole vehicle on the step, about 1 s of
//!   driving later.
//!
//! The run stops there, or when the vehicle has stood still at full drive for
//! `stall_time` after touching the step.
//!
//! Check (issue 26: "climbs a step of 0.8 x the published height"; the published vertical
//! obstacle of the M113 is 24 in = 0.61 m, Hunnicutt's data sheet as tabulated at
//! afvdatabase.com, `published.vertical_obstacle` of `data/m113.json`): `climbed` = 1 for
//! any `step_height` up to 0.8 x 0.61 = 0.488 m (the default), whatever the drive. The
//! check is on by default (`--set check=false` reports `climbed` only). Above 0.488 m the
//! outcome is reported with what stopped the vehicle. A diverging run stops
//! with the system's error naming the body and the step. Reported: the highest chassis
//! pitch, the largest joint drift, the sprocket torques, the largest contact forces of the
//! step on the hull and on the tracks, how far the vehicle got past the face, where the
//! first road wheels got (past the face, their lift on the arms), the track slip, engine
//! speed and gear (powertrain), and the settled ground clearance against the published
//! 16.1 in.

use std::sync::atomic::Ordering;
use std::time::Instant;

use chrono_core::math::Vector3;
use chrono_vehicle::driver::{PidGains, SpeedController};
use chrono_vehicle::m113::m113_data;
use chrono_vehicle::obstacle::{StepParams, TrackedStepScene};
use chrono_vehicle::powertrain::ShiftSpeed;
use chrono_vehicle::state::DriverInputs;
use chrono_vehicle::track::AdjusterKind;
use chrono_vehicle::tracked::contact_forces;
use chrono_vehicle::tracked_drive::TrackedDrive;

use crate::case::{Case, CaseOutput, Check, PlotSpec, RunContext, Series};
use crate::cases::rigid::{VtkFrames, n_steps};
use crate::params::ParamCase;

pub use super::m113_step_params::M113StepParams;
use super::m113_step_params::validate;

fn run(p: &M113StepParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    validate(p)?;
    let n = n_steps(p.h, p.t_end)?;
    let n_settle = (p.settle / p.h).round() as u64;
    let mut data = m113_data()?;
    // At low speed the turbine's speed keeps first gear; on the engine's speed the
    // converter's stall speed (~1550 rpm, above the 1500 rpm upshift) would shift up on
    // the step (m113-turn).
    data.powertrain.transmission.shift_speed = ShiftSpeed::InputShaft;
    data.track.idler.tensioner.preload = p.preload;
    match p.adjuster.as_str() {
        "spring" => data.track.idler.tensioner.adjuster = AdjusterKind::Spring,
        "grease" => data.track.idler.tensioner.adjuster = AdjusterKind::Grease,
        _ => {}
    }
    if p.arm_rebound < 0.0 || p.arm_jounce > 0.0 {
        let [lo, hi] = data.track.road_wheels.arm_travel.unwrap_or([-1.0, 1.0]);
        data.track.road_wheels.arm_travel = Some([
            if p.arm_rebound < 0.0 {
                p.arm_rebound
            } else {
                lo
            },
            if p.arm_jounce > 0.0 { p.arm_jounce } else { hi },
        ]);
    }
    let step = StepParams {
        height: p.step_height,
        gap: p.gap,
        length: p.step_length,
        width: p.step_width,
    };
    let (solver, nanos) = super::m113_solver(&p.solver, p.tolerance, p.max_iterations)?;
    let scene = TrackedStepScene::new(data, p.mu, step, solver)?;
    let face_x = scene.face_x;
    let mut flat = scene.flat;
    let mut drive = if p.drive == "powertrain" {
        Some(TrackedDrive::build(
            &mut flat.sys,
            &flat.vehicle,
            &flat.data,
        )?)
    } else {
        None
    };
    let (sys, v, d) = (&mut flat.sys, &flat.vehicle, &flat.data);
    let weight = d.total_mass() * sys.settings().gravity.norm();
    // The torque of the published gradeability (reported whatever the drive) and the
    // largest torque of a direct drive, N m per sprocket.
    let grade_torque = d.published_grade_sprocket_torque(sys.settings().gravity.norm())?;
    let direct_torque = match p.drive.as_str() {
        "grade" => grade_torque,
        "torque" => p.drive_torque,
        _ => f64::NAN,
    };
    let set = sys.body_set();
    let dense = |b| {
        set.dense_index(b)
            .ok_or_else(|| anyhow::anyhow!("a body of the scene is missing"))
    };
    let step_i = dense(scene.step)?;
    let chassis_i = dense(v.chassis)?;
    let shoes_i: Vec<usize> = v.shoes().into_iter().map(dense).collect::<Result<_, _>>()?;
    let running_i: Vec<usize> = v
        .sides
        .iter()
        .flat_map(|s| s.running_gear())
        .map(dense)
        .collect::<Result<_, _>>()?;
    let com = Vector3::from(d.chassis.com);
    let r_p = d.track.sprocket.pitch_radius;
    let idler_clear = d.track.idler.radius + d.track.shoe.thickness;
    let hull_bottom = d.hull.as_ref().map(|h| h.bottom_z());
    let mut ctl = SpeedController::new(
        PidGains {
            kp: p.kp,
            ki: p.ki,
            kd: 0.0,
        },
        p.speed,
    )?;

    let mut series = Series::new([
        "t",
        "x_ref_past_face",
        "z_ref",
        "pitch_deg",
        "speed",
        "throttle",
        "gear",
        "engine_rpm",
        "sprocket_torque_left",
        "sprocket_torque_right",
        "step_on_hull",
        "step_on_tracks",
        "front_wheel_past_face",
        "front_wheel_z",
        "front_wheel_lift",
        "front_arm_angle",
        "adjuster_force",
        "adjuster_travel",
        "step_height",
    ]);
    let mut vtk = VtkFrames::new(ctx, (0.1 / p.h).round().max(1.0) as u64);
    let mut inputs = DriverInputs {
        throttle: 0.0,
        brake: 1.0,
        steering: 0.0,
    };
    let (mut max_pitch, mut max_violation, mut max_hull_f, mut max_tracks_f) =
        (f64::NEG_INFINITY, 0.0_f64, 0.0_f64, 0.0_f64);
    let mut max_torque: f64 = 0.0;
    let mut max_past: f64 = f64::NEG_INFINITY;
    // The first road wheels' settled heights in the chassis frame, their largest lift
    // from there and how far their centres got past the face.
    let mut front_settled = [0.0; 2];
    let (mut max_front_lift, mut max_front_past) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    let mut first_touch = f64::NAN;
    let mut first_hull_touch = f64::NAN;
    let mut ride_height = f64::NAN;
    let mut clearance = f64::NAN;
    let mut climbed_at = f64::NAN;
    let mut steps = 0;
    // The last second's track slip and engine state (what a stalled climb looks like).
    let window = (1.0 / p.h).round() as usize;
    let mut tail: Vec<[f64; 5]> = Vec::with_capacity(window);
    let t0 = Instant::now();
    let mut u = 0.0;
    // Time at full drive within 2 cm of the position in `.1`.
    let mut still = (0.0, f64::NAN);
    // The adjusters (mean of the sides): force and travel at the lock (end of settling)
    // and their extremes while driving; the first arms' largest jounce and rebound.
    let mut locked = false;
    let (mut adj_f_settled, mut adj_x_settled) = (f64::NAN, f64::NAN);
    let (mut adj_f_max, mut adj_f_min) = (f64::NEG_INFINITY, f64::INFINITY);
    let (mut adj_x_max, mut adj_x_min) = (f64::NEG_INFINITY, f64::INFINITY);
    let (mut arm_max, mut arm_min) = (f64::NEG_INFINITY, f64::INFINITY);
    let mut stalled_at = f64::NAN;
    for i in 1..=n {
        match drive.as_mut() {
            Some(dr) => dr.synchronize(sys, inputs)?,
            // Held while settling, then the controller's share of the largest torque.
            None if i <= n_settle => v.set_sprocket_drives(sys, chrono_core::Drive::Speed(0.0))?,
            None => v.set_sprocket_drives(sys, chrono_core::Drive::Effort(u * direct_torque))?,
        }
        sys.step(p.h)?;
        vtk.record(i, sys)?;
        steps = i;
        let c = sys.body(v.chassis)?;
        let rot = c.rotation();
        let fwd = rot * Vector3::x();
        let speed = c.linear_velocity().dot(&fwd);
        let c_pos = c.position();
        let reference = c_pos - rot * com;
        let pitch = fwd.z.atan2(fwd.x.hypot(fwd.y)).to_degrees();
        max_violation = max_violation.max(sys.max_joint_violation());
        let (mut adj_f, mut adj_x, mut arm0) = (0.0, 0.0, 0.0);
        for s in &v.sides {
            adj_f += 0.5 * s.adjuster_force(sys)?;
            adj_x += 0.5 * s.adjuster_travel(sys)?;
            arm0 += 0.5 * s.arm_angle(sys, 0)?;
        }
        if i == n_settle.max(1) {
            adj_f_settled = adj_f;
            adj_x_settled = adj_x;
            // The adjustment is done: a grease adjuster holds its length from here.
            locked = v.lock_adjusters(sys, d)?;
        }
        if i > n_settle {
            adj_f_max = adj_f_max.max(adj_f);
            adj_f_min = adj_f_min.min(adj_f);
            adj_x_max = adj_x_max.max(adj_x);
            adj_x_min = adj_x_min.min(adj_x);
            arm_max = arm_max.max(arm0);
            arm_min = arm_min.min(arm0);
        }
        if i == n_settle.max(1) {
            ride_height = reference.z;
            if let Some(zb) = hull_bottom {
                clearance = reference.z + zb;
            }
        }
        let driving = i > n_settle;
        if driving {
            u = ctl.advance(sys.time(), speed);
            let (throttle, brake) = SpeedController::pedals(u);
            inputs = DriverInputs {
                throttle,
                brake,
                steering: 0.0,
            };
        }
        // The step's contact forces on the hull and on the running gear and shoes, N.
        let (mut on_hull, mut on_tracks) = (Vector3::zeros(), Vector3::zeros());
        for f in contact_forces(sys, p.h) {
            let (other, force) = if f.owner_a == step_i {
                (f.owner_b, f.on_b)
            } else if f.owner_b == step_i {
                (f.owner_a, -f.on_b)
            } else {
                continue;
            };
            if other == chassis_i {
                on_hull += force;
            } else if shoes_i.contains(&other) || running_i.contains(&other) {
                on_tracks += force;
            }
        }
        let (fh, ft) = (on_hull.norm(), on_tracks.norm());
        if ft > 0.0 && first_touch.is_nan() {
            first_touch = sys.time();
        }
        if fh > 0.0 && first_hull_touch.is_nan() {
            first_hull_touch = sys.time();
        }
        max_hull_f = max_hull_f.max(fh);
        max_tracks_f = max_tracks_f.max(ft);
        max_pitch = max_pitch.max(pitch);
        max_past = max_past.max(reference.x - face_x);
        let (tl, tr, w, rpm, gear) = match drive.as_ref() {
            Some(dr) => (
                dr.sprocket_torque(sys, 0),
                dr.sprocket_torque(sys, 1),
                0.5 * (dr.sprocket_speed(sys, 0) + dr.sprocket_speed(sys, 1)),
                dr.powertrain().engine_speed_rpm(),
                dr.powertrain().current_gear() as f64,
            ),
            None => {
                let t = if driving { u * direct_torque } else { f64::NAN };
                // The sprockets' spin relative to the chassis about its Y axis.
                let wc = sys.body(v.chassis)?.angular_velocity();
                let y = rot * Vector3::y();
                let mut ws = 0.0;
                for s in &v.sides {
                    ws += 0.5 * (sys.body(s.sprocket)?.angular_velocity() - wc).dot(&y);
                }
                (t, t, ws, f64::NAN, f64::NAN)
            }
        };
        if driving {
            max_torque = max_torque.max(tl.abs()).max(tr.abs());
        }
        if tail.len() == window {
            tail.remove(0);
        }
        tail.push([w * r_p, speed, rpm, gear, tl + tr]);
        // The first road wheels' centres (mean of the sides): past the face, above the
        // ground, and lifted relative to the chassis from their settled place (the arm's
        // swing on its torsion bar).
        let (mut fw_x, mut fw_z, mut fw_lift) = (0.0, 0.0, 0.0);
        for (k, s) in v.sides.iter().enumerate() {
            let w = sys.body(s.road_wheels[0].wheel)?.position();
            let local = rot.inverse() * (w - c_pos);
            if i == n_settle.max(1) {
                front_settled[k] = local.z;
            }
            fw_x += 0.5 * (w.x - face_x);
            fw_z += 0.5 * w.z;
            fw_lift += 0.5 * (local.z - front_settled[k]);
        }
        max_front_lift = max_front_lift.max(fw_lift);
        max_front_past = max_front_past.max(fw_x);
        series.push(&[
            sys.time(),
            reference.x - face_x,
            reference.z,
            pitch,
            speed,
            inputs.throttle,
            gear,
            rpm,
            tl,
            tr,
            fh,
            ft,
            fw_x,
            fw_z,
            fw_lift,
            arm0,
            adj_f,
            adj_x,
            p.step_height,
        ]);
        ctx.progress_steps(i, n);
        // On top: both idlers past the face (they can only be over the top) and the
        // chassis at its ride height above the top.
        let mut idlers_past = true;
        for s in &v.sides {
            idlers_past &= sys.body(s.idler)?.position().x > face_x + idler_clear;
        }
        // Standing still (within 2 cm) at full drive against the step: the climb has
        // stalled.
        if first_touch.is_finite() && u >= 0.99 && (reference.x - still.1).abs() < 0.02 {
            still.0 += p.h;
        } else {
            still = (0.0, reference.x);
        }
        if still.0 >= p.stall_time {
            stalled_at = sys.time();
            break;
        }
        let at_height = reference.z - p.step_height >= ride_height - p.z_tolerance;
        let on_top = if p.until == "idlers" {
            idlers_past
        } else {
            c_pos.x > face_x && pitch.abs() <= p.level_tolerance
        };
        if driving && on_top && at_height {
            climbed_at = sys.time();
            break;
        }
    }
    let wall = t0.elapsed().as_secs_f64();
    vtk.finish()?;
    let solve_s = nanos.load(Ordering::Relaxed) as f64 * 1e-9;
    let climbed = if climbed_at.is_finite() { 1.0 } else { 0.0 };
    let published = d.published.vertical_obstacle;
    let k = tail.len().max(1) as f64;
    let mean = |j: usize| tail.iter().map(|r| r[j]).sum::<f64>() / k;
    let (track_speed, end_speed, end_rpm, end_gear) = (mean(0), mean(1), mean(2), mean(3));
    // The tracks' thrust over the last second (both sprockets' torque over the pitch
    // radius) against the weight, and what the published 60 % grade needs: W sin(atan
    // 0.6) = 0.51 W.
    let thrust_over_weight = mean(4) / r_p / weight;
    let grade_need = d.published.max_grade.atan().sin();

    let mut out = CaseOutput::new();
    // Issue 26: a step of 0.8 x the published vertical obstacle is climbed; so is any lower
    // one. Higher steps are reported.
    let criterion = 0.8 * published;
    if p.check && p.step_height <= criterion + 1e-9 {
        out.check(Check::absolute("climbed", climbed, 1.0, 0.0));
    } else {
        out.metric("climbed", climbed);
    }
    // Times only where they happened (a metric is a number).
    for (name, t) in [
        ("climb_time", climbed_at - p.settle),
        ("first_track_contact_time", first_touch),
        ("first_hull_contact_time", first_hull_touch),
    ] {
        if t.is_finite() {
            out.metric(name, t);
        }
    }
    out.metric("stalled", if stalled_at.is_finite() { 1.0 } else { 0.0 });
    out.metric("step_height", p.step_height);
    out.metric("step_over_published", p.step_height / published);
    out.metric("published_vertical_obstacle", published);
    out.metric("max_pitch_deg", max_pitch);
    out.metric("max_joint_violation", max_violation);
    out.metric("max_sprocket_torque", max_torque);
    out.metric("max_step_force_on_hull", max_hull_f);
    out.metric("max_step_force_on_tracks", max_tracks_f);
    out.metric("max_reference_past_face", max_past);
    out.metric("max_front_wheel_past_face", max_front_past);
    out.metric("max_front_wheel_lift", max_front_lift);
    out.metric("adjuster_locked", if locked { 1.0 } else { 0.0 });
    out.metric("tensioner_preload", p.preload);
    out.metric("adjuster_force_settled", adj_f_settled);
    out.metric("adjuster_travel_settled", adj_x_settled);
    out.metric("max_adjuster_force", adj_f_max);
    out.metric("min_adjuster_force", adj_f_min);
    out.metric("max_adjuster_travel", adj_x_max);
    out.metric("min_adjuster_travel", adj_x_min);
    out.metric("max_front_arm_jounce", arm_max);
    out.metric("max_front_arm_rebound", arm_min);
    out.metric("last_second_speed", end_speed);
    out.metric("last_second_track_speed", track_speed);
    // Only with the powertrain (`drive` = `torque` has no engine).
    if end_rpm.is_finite() {
        out.metric("last_second_engine_rpm", end_rpm);
        out.metric("last_second_gear", end_gear);
    }
    out.metric("last_second_thrust_over_weight", thrust_over_weight);
    out.metric("published_max_grade_thrust_over_weight", grade_need);
    out.metric("published_max_grade_sprocket_torque", grade_torque);
    if direct_torque.is_finite() {
        out.metric("drive_torque_per_side", direct_torque);
    }
    out.metric("ride_height", ride_height);
    out.metric("ground_clearance", clearance);
    out.metric("published_ground_clearance", d.published.ground_clearance);
    out.metric("wall_s", wall);
    out.metric("steps_per_s", steps as f64 / wall);
    out.metric("ccp_solve_share", solve_s / wall);
    let outcome = if climbed > 0.0 {
        format!("climbed in {:.2} s", climbed_at - p.settle)
    } else {
        let how = if stalled_at.is_finite() {
            format!(
                "stalled (standing still at full drive from {:.2} s)",
                stalled_at - p.stall_time
            )
        } else {
            format!("did not climb within {:.1} s", p.t_end - p.settle)
        };
        let engine = if end_rpm.is_finite() {
            format!(", engine {end_rpm:.0} rpm in gear {end_gear:.0}")
        } else {
            String::new()
        };
        format!(
            "{how}: the sprocket centre got {max_past:+.2} m past the \
             face; last second {end_speed:.2} m/s against the tracks' {track_speed:.2} m/s{engine}, \
             thrust {thrust_over_weight:.2} of the weight; the step pushed on the hull with \
             up to {max_hull_f:.0} N"
        )
    };
    let drive_text = match p.drive.as_str() {
        "grade" => format!(
            "sprockets driven with up to {direct_torque:.0} N m each (the published {:.0} % \
             grade's torque)",
            100.0 * d.published.max_grade
        ),
        "torque" => format!("sprockets driven with up to {direct_torque:.0} N m each"),
        _ => format!(
            "powertrain (the published {:.0} % grade needs {grade_torque:.0} N m a side)",
            100.0 * d.published.max_grade
        ),
    };
    ctx.note(format!(
        "M113A1 at {} m/s against a {:.3} m step ({:.2} x the published {published} m), \
         {drive_text}: {outcome}; pitch up to {max_pitch:.1} deg, joint drift {max_violation:.1e} m, \
         sprocket torque up to {max_torque:.0} N m; ground clearance {clearance:.3} m \
         (published {} m); {:.0} steps/s, CCP {:.0} %",
        p.speed,
        p.step_height,
        p.step_height / published,
        d.published.ground_clearance,
        steps as f64 / wall,
        100.0 * solve_s / wall
    ));
    out.series = series;
    out.plot = PlotSpec::new(
        "M113 climbing a step",
        "t [s]",
        "chassis reference height [m]",
        &["z_ref"],
    )
    .with_reference(&["step_height"]);
    out.steps = steps;
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<M113StepParams>::boxed(
        "m113-step",
        "vehicle",
        "M113A1 (shoe by shoe, hull plates, grease track adjusters, the published 60 % \
         grade's sprocket torque) climbs a rigid vertical step at low speed: climbs 0.8 x \
         the published 0.61 m vertical obstacle (issue 26); higher steps reported with what \
         stops it.",
        run,
    )
}
