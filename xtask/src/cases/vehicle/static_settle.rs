//! `hmmwv-static`: the HMMWV is set down on flat rigid ground and settles.
//!
//! Checks: the sum of the four vertical tire forces equals the vehicle's weight `m g` within
//! 0.5 % (the tires carry everything; a joint or contact force leaking elsewhere would show
//! here), and the vehicle comes to rest (`settle_time`: the last time the chassis' vertical
//! speed exceeded 1 mm/s, before the end of the run). Metrics: the ride height (chassis
//! reference above the ground), the tires' loaded radius (spindle over the lowest tread
//! point), the front and rear axle loads, the joint drift, and the real-time factor
//! (simulated over wall time). `tire = ancf` runs the pressurized shell tires (their
//! carcass' stiffness and damping slow the settling: `h = 4e-3` s keeps it affordable).

use std::time::Instant;

use serde::{Deserialize, Serialize};

use chrono_vehicle::hmmwv::{PowertrainKind, TireKind, hmmwv_data_variant};

use super::scene::hmmwv_flat_with;
use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::cases::rigid::{VtkFrames, n_steps};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// Parameters of `hmmwv-static`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StaticParams {
    /// Time step, s.
    pub h: f64,
    /// Simulated time, s.
    pub t_end: f64,
    /// Tire model: `rigid` or `handling`.
    pub tire: TireKind,
    /// Tire–ground friction coefficient.
    pub mu: f64,
    /// CCP solver.
    pub solver: String,
    /// Stiffness-proportional damping `beta` of the ANCF tire's carcass, s (negative = the
    /// data's).
    pub tire_damping: f64,
}

impl Default for StaticParams {
    fn default() -> Self {
        Self {
            h: 1e-3,
            t_end: 4.0,
            tire: TireKind::Rigid,
            mu: 0.9,
            solver: "schur".into(),
            tire_damping: -1.0,
        }
    }
}

impl CaseParams for StaticParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("h", "s", "time step"),
        ParamInfo::new("t_end", "s", "simulated time"),
        ParamInfo::new("tire", "-", "tire model: rigid | handling | ancf"),
        ParamInfo::new("mu", "-", "tire-ground friction coefficient"),
        ParamInfo::new(
            "solver",
            "-",
            "CCP solver (schur handles the suspension joints directly)",
        ),
        ParamInfo::new(
            "tire_damping",
            "s",
            "ANCF tire's stiffness damping beta (negative: the data's)",
        ),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        if mode == Mode::Quick {
            self.t_end = 2.0;
        }
    }
}

/// Vertical speed below which the chassis counts as settled, m/s.
const SETTLED_SPEED: f64 = 1e-3;

fn run(p: &StaticParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    let n = n_steps(p.h, p.t_end)?;
    let mut data = hmmwv_data_variant(p.tire, PowertrainKind::Chrono)?;
    super::scene::set_tire_damping(&mut data, p.tire_damping)?;
    let mut scene = hmmwv_flat_with(data, p.mu, &p.solver)?;
    let (sys, v) = (&mut scene.sys, &mut scene.vehicle);
    let mut series = Series::new(["t", "ride_height", "vz", "load_sum", "weight"]);
    let weight = scene.data.total_mass() * sys.settings().gravity.norm();
    let mut vtk = VtkFrames::new(ctx, (0.02 / p.h).round() as u64);
    let mut settle_time = 0.0;
    let mut max_violation: f64 = 0.0;
    let t0 = Instant::now();
    let mut forces = Vec::new();
    for i in 1..=n {
        v.synchronize(sys, Default::default())?;
        sys.step(p.h)?;
        vtk.record(i, sys)?;
        let st = v.state(sys)?;
        forces = v.tire_forces(sys, p.h);
        let sum: f64 = forces.iter().map(|f| f.z).sum();
        series.push(&[sys.time(), st.position.z, st.velocity.z, sum, weight]);
        if st.velocity.z.abs() > SETTLED_SPEED {
            settle_time = sys.time();
        }
        max_violation = max_violation.max(sys.max_joint_violation());
        ctx.progress_steps(i, n);
    }
    let wall = t0.elapsed().as_secs_f64();
    vtk.finish()?;
    let st = v.state(sys)?;
    let sum: f64 = forces.iter().map(|f| f.z).sum();
    let mut out = CaseOutput::new();
    out.check(Check::relative("wheel_load_sum_error", sum, weight, 5e-3));
    out.check(Check::below("settle_time", settle_time, p.t_end - 0.5));
    out.metric("ride_height", st.position.z);
    // Spindle height over the tire's lowest tread point: the loaded radius (the rigid
    // tire's radius; an ANCF carcass' deflected one).
    let radius = scene.data.wheel.tire.radius();
    let mut loaded = 0.0;
    for (i, w) in v.wheels().iter().enumerate() {
        loaded += sys.body(w.spindle)?.position().z - v.tire_bottom(sys, i, radius)?;
    }
    out.metric("tire_loaded_radius", loaded / v.wheels().len() as f64);
    out.metric("front_axle_load", forces[0].z + forces[1].z);
    out.metric("rear_axle_load", forces[2].z + forces[3].z);
    out.metric("max_joint_violation", max_violation);
    out.metric("real_time_factor", p.t_end / wall);
    out.series = series;
    out.plot = PlotSpec::new(
        "HMMWV settling",
        "t [s]",
        "tire load sum [N]",
        &["load_sum"],
    )
    .with_reference(&["weight"]);
    out.steps = n;
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<StaticParams>::boxed(
        "hmmwv-static",
        "vehicle",
        "HMMWV set down on flat rigid ground: the tire loads sum to m g within 0.5 % and it settles.",
        run,
    )
}
