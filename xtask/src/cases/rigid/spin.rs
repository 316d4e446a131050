//! `rigid-spin`: a torque-free asymmetric body spun about its intermediate principal axis.
//!
//! References: conservation of the world angular momentum `R J w` and of the kinetic
//! energy (no torque, no dissipation), and the intermediate-axis (Dzhanibekov) instability:
//! the spin about the middle axis flips sign periodically.

use chrono_core::RigidBodyBuilder;
use chrono_core::math::Vector3;
use serde::{Deserialize, Serialize};

use super::{VtkFrames, make_system, n_steps};
use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// Parameters of `rigid-spin`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SpinParams {
    /// Spin rate about the intermediate axis, rad/s.
    pub spin: f64,
    /// Relative perturbation about the other two axes.
    pub perturbation: f64,
    /// Time step, s (0: [`SpinParams::step`]).
    pub h: f64,
    /// Simulated time, s (0: [`SpinParams::duration`]).
    pub t_end: f64,
    /// The automatic duration's time at the default spin, s (20; 10 in `--quick`).
    pub t_ref: f64,
}

/// The default run's spin rate, rad/s: the reference of the automatic step and duration.
const SPIN_REF: f64 = 2.0;

impl SpinParams {
    /// The time step: `h` if set, else `1e-3 min(1, 2 / |spin|)` s, so that `h |w|` stays
    /// at most the default run's (2e-3): the first-order step's energy error per flip is
    /// `O(h w)`.
    pub fn step(&self) -> f64 {
        if self.h != 0.0 {
            return self.h;
        }
        1e-3 * (SPIN_REF / self.spin.abs()).min(1.0)
    }

    /// The simulated time: `t_end` if set, else `t_ref * 2 / |spin|` (`t_ref` 20 s, 10 s
    /// in `--quick`): the same number of flips as the default run at any spin (the flip
    /// period scales as `1 / |w|`).
    pub fn duration(&self) -> f64 {
        if self.t_end != 0.0 {
            return self.t_end;
        }
        self.t_ref * SPIN_REF / self.spin.abs()
    }
}

impl Default for SpinParams {
    fn default() -> Self {
        Self {
            spin: 2.0,
            perturbation: 0.01,
            h: 0.0,
            t_end: 0.0,
            t_ref: 20.0,
        }
    }
}

impl CaseParams for SpinParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("spin", "rad/s", "spin rate about the intermediate axis"),
        ParamInfo::new(
            "perturbation",
            "-",
            "relative perturbation about the other axes",
        ),
        ParamInfo::new(
            "h",
            "s",
            "time step (0: 1 ms, times 2 / |spin| above 2 rad/s)",
        ),
        ParamInfo::new("t_end", "s", "simulated time (0: t_ref x 2 / |spin|)"),
        ParamInfo::new(
            "t_ref",
            "s",
            "the automatic simulated time at the default spin 2 rad/s",
        ),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        if mode == Mode::Quick {
            self.t_ref = 10.0;
        }
    }
}

fn run(p: &SpinParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(
        p.spin.is_finite() && p.spin != 0.0,
        "parameter `spin` must be non-zero, got {}",
        p.spin
    );
    anyhow::ensure!(
        p.t_ref.is_finite() && p.t_ref > 0.0,
        "parameter `t_ref` must be > 0, got {}",
        p.t_ref
    );
    let h = p.step();
    let n = n_steps(h, p.duration())?;
    let mut sys = make_system("psor", 1e-9, 100)?;
    let mut settings = sys.settings().clone();
    settings.gravity = Vector3::zeros();
    sys.set_settings(settings)?;
    let w0 = Vector3::new(p.perturbation * p.spin, p.spin, p.perturbation * p.spin);
    let body = sys.add_body(
        RigidBodyBuilder::dynamic()
            .name("tumbler")
            .mass(1.0)
            .inertia_diagonal(Vector3::new(1.0, 2.0, 3.0))
            .angular_velocity(w0),
    )?;
    let l0 = sys.body(body)?.angular_momentum();
    let e0 = sys.body(body)?.kinetic_energy();
    let mut series = Series::new(["t", "w_x", "w_y", "w_z", "momentum_error", "energy_error"]);
    let (mut l_drift, mut e_drift) = (0.0f64, 0.0f64);
    let mut flips = 0usize;
    let mut sign = w0.y.signum();
    let mut vtk = VtkFrames::new(ctx, (0.05 / h).round().max(1.0) as u64);
    for i in 1..=n {
        sys.step(h)?;
        vtk.record(i, &sys)?;
        let b = sys.body(body)?;
        let w = b.angular_velocity_body();
        let dl = (b.angular_momentum() - l0).norm() / l0.norm();
        let de = (b.kinetic_energy() - e0).abs() / e0;
        l_drift = l_drift.max(dl);
        e_drift = e_drift.max(de);
        if w.y.signum() != sign && w.y.abs() > 0.5 * p.spin.abs() {
            flips += 1;
            sign = w.y.signum();
        }
        series.push(&[sys.time(), w.x, w.y, w.z, dl, de]);
        ctx.progress_steps(i, n);
    }
    vtk.finish()?;
    let mut out = CaseOutput::new();
    // the angular update conserves R J w by construction: round-off only
    out.check(Check::below("momentum_drift", l_drift, 1e-9));
    // first-order stepper: the energy error grows O(h) at each flip (0.7% after 3 flips at 1 ms)
    out.check(Check::below("energy_drift", e_drift, 1e-2));
    out.check(Check::absolute(
        "flipped",
        if flips >= 1 { 1.0 } else { 0.0 },
        1.0,
        0.0,
    ));
    out.metric("flips", flips as f64);
    out.series = series;
    out.plot = PlotSpec::new(
        "torque-free tumbling",
        "t [s]",
        "body angular velocity [rad/s]",
        &["w_x", "w_y", "w_z"],
    );
    out.steps = n;
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<SpinParams>::boxed(
        "rigid-spin",
        "rigid",
        "Torque-free asymmetric body spun about its intermediate axis: angular momentum and energy conserved, the axis flips.",
        run,
    )
}
