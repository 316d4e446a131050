//! `cfluid-still-water`: a tank of still water (quasi-2D constraint fluid, the tank of
//! `sph-hydrostatic`: `depth x tank_length`, slab periodic in y) run at a **large** time
//! step for a long time: it must stay still (issue 6, the "stable hard case").
//!
//! The column starts at rest on its lattice (the constraint takes the load in the first
//! step) and runs for `t_end` (20 s by default, 2 s with `--quick`) at the step `h`
//! (default 4 ms, of the order of the step `cfluid-timestep` finds for 0.1 % compression
//! in the dam break, and ~100 times WCSPH's at that compression). Reference: hydrostatics
//! (the fluid at rest, the surface at its initial height). Metrics:
//!
//! - `rms_speed`: the RMS particle speed `sqrt(2 KE / M)`, largest over the second half
//!   of the run, m/s, checked below `1 % sqrt(g H)` (the speed criterion of
//!   `sph-hydrostatic`, applied to the RMS);
//! - `max_speed`: the largest particle speed over the second half, m/s (reported beside
//!   `g h`: at a large step a free-surface particle whose row is slack, a density deficit
//!   under the one-sided surface treatment, falls freely for a step before its row
//!   catches it, so single surface particles chatter at `~ g h`; 39 mm/s at `h` = 4 ms);
//! - `final_specific_kinetic_energy`: kinetic energy per kg at the end, J/kg (reported);
//! - `surface_drift`: the mean free-surface height at the end (over the columns more
//!   than `2 dp` from the walls, top particle plus `dp / 2`) minus the one after the
//!   start-up settling (at `min(2 s, t_end / 4)`), m, checked below `0.25 dp` in
//!   magnitude (no creep: the fluid neither compacts nor swells over the run);
//! - `settling`: the surface height after the start-up settling minus the initial one
//!   (the lattice's surface layer, whose kernel is truncated, compacts until its density
//!   reaches `rho_0`; reported);
//! - `max_compression_pct`: the worst compression over the run (reported);
//! - `left_tank` (checked 0), `avg_iterations`.

use std::time::Instant;

use chrono_cfluid::{CfluidSettings, ConstraintFluid};
use serde::{Deserialize, Serialize};

use super::{TankScene, left_tank};
use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::params::{CaseParams, ParamCase, ParamInfo};

const G: f64 = 9.81;

/// Speed acceptance as a fraction of `sqrt(g H)` (as `sph-hydrostatic`).
pub const SPEED_FRACTION: f64 = 0.01;
/// Surface drift acceptance as a fraction of the spacing.
pub const DRIFT_FRACTION: f64 = 0.25;

/// Parameters of `cfluid-still-water`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StillWaterParams {
    /// Water depth `H`, m.
    pub depth: f64,
    /// Tank length (x), m.
    pub tank_length: f64,
    /// Particle spacing, m.
    pub spacing: f64,
    /// Time step, s.
    pub h: f64,
    /// Simulated time, s.
    pub t_end: f64,
    /// XSPH viscosity epsilon.
    pub xsph: f64,
    /// Solver tolerance (chrono-ccp residual, 1/s).
    pub tolerance: f64,
    /// CCP solver name.
    pub solver: String,
    /// Iteration cap per step.
    pub max_iterations: usize,
}

impl Default for StillWaterParams {
    fn default() -> Self {
        Self {
            depth: 0.4,
            tank_length: 0.4,
            spacing: 0.02,
            h: 4e-3,
            t_end: 20.0,
            xsph: 0.1,
            tolerance: 1e-4,
            solver: "apgd".into(),
            max_iterations: 500,
        }
    }
}

impl CaseParams for StillWaterParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("depth", "m", "water depth H"),
        ParamInfo::new("tank_length", "m", "tank length (x)"),
        ParamInfo::new("spacing", "m", "particle spacing dp"),
        ParamInfo::new("h", "s", "time step"),
        ParamInfo::new("t_end", "s", "simulated time"),
        ParamInfo::new("xsph", "-", "XSPH viscosity epsilon"),
        ParamInfo::new("tolerance", "1/s", "solver tolerance (chrono-ccp residual)"),
        ParamInfo::new("solver", "-", "CCP solver name (chrono-ccp)"),
        ParamInfo::new("max_iterations", "-", "iteration cap per step"),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            Mode::Quick => {
                self.spacing = 0.04;
                self.t_end = 2.0;
            }
            Mode::Default => {}
            Mode::Full => self.spacing = 0.01,
        }
    }
}

/// Mean height of the free surface over the columns more than `2 dp` from the walls:
/// the top particle of each column plus `dp / 2`, m.
pub fn surface_height(f: &ConstraintFluid, dp: f64, len: f64) -> f64 {
    let n_cols = (len / dp).round() as usize;
    let mut tops = vec![f64::NEG_INFINITY; n_cols];
    for i in 0..f.n_fluid() {
        let q = f.position(i);
        let c = (q[0] / dp).floor();
        if c >= 0.0 && (c as usize) < n_cols {
            let t = &mut tops[c as usize];
            *t = t.max(q[2]);
        }
    }
    let (mut sum, mut count) = (0.0, 0usize);
    for (c, t) in tops.iter().enumerate() {
        let x = (c as f64 + 0.5) * dp;
        if x > 2.0 * dp && x < len - 2.0 * dp && t.is_finite() {
            sum += t + 0.5 * dp;
            count += 1;
        }
    }
    if count == 0 {
        f64::NAN
    } else {
        sum / count as f64
    }
}

fn max_speed(f: &ConstraintFluid) -> f64 {
    f.velocities()
        .iter()
        .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
        .fold(0.0, f64::max)
}

fn run(p: &StillWaterParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(
        p.h > 0.0 && p.h.is_finite(),
        "parameter `h` must be > 0, got {}",
        p.h
    );
    anyhow::ensure!(
        p.t_end >= p.h && p.t_end.is_finite(),
        "parameter `t_end` must be >= h, got {}",
        p.t_end
    );
    let dp = p.spacing;
    anyhow::ensure!(
        dp > 0.0 && dp <= p.depth / 4.0 && dp <= p.tank_length / 6.0,
        "parameter `spacing` must be in (0, min(depth/4, tank_length/6)], got {dp}"
    );
    let settings = CfluidSettings {
        spacing: dp,
        xsph: p.xsph,
        ..CfluidSettings::default()
    };
    let mut scene = TankScene::new(
        settings,
        p.tank_length,
        1.5 * p.depth,
        [p.tank_length, p.depth],
        &p.solver,
        p.tolerance,
        p.max_iterations,
    )?;
    let start = Instant::now();
    let z0 = surface_height(scene.fluid()?, dp, p.tank_length);
    let n = (p.t_end / p.h).round().max(1.0) as u64;
    let half = n / 2;
    let settle = ((2.0f64.min(0.25 * p.t_end) / p.h).round() as u64).clamp(1, n);
    let every = (n / 1000).max(1);
    let mut series = Series::new([
        "t",
        "max_speed",
        "kinetic_energy_per_kg",
        "surface_change",
        "max_compression_pct",
        "iterations",
    ]);
    let (mut iterations, mut late_speed, mut max_c) = (0usize, 0.0f64, 0.0f64);
    let mut late_rms = 0.0f64;
    let (mut z_half, mut z_settled) = (f64::NAN, f64::NAN);
    let mass = {
        let f = scene.fluid()?;
        f.particle_mass() * f.n_fluid() as f64
    };
    for step in 1..=n {
        let report = scene.sys.step(p.h)?;
        iterations += report.solve.iterations;
        let f = scene.fluid()?;
        let c = f.max_compression().max(0.0);
        max_c = max_c.max(c);
        let speed = max_speed(f);
        if step > half {
            late_speed = late_speed.max(speed);
            late_rms = late_rms.max((2.0 * f.kinetic_energy() / mass).sqrt());
        }
        if step == settle {
            z_settled = surface_height(f, dp, p.tank_length);
        }
        if step == half {
            z_half = surface_height(f, dp, p.tank_length);
        }
        if step % every == 0 || step == n {
            series.push(&[
                step as f64 * p.h,
                speed,
                f.kinetic_energy() / mass,
                surface_height(f, dp, p.tank_length) - z0,
                100.0 * c,
                report.solve.iterations as f64,
            ]);
        }
        ctx.progress_steps(step, n);
    }
    let wall = start.elapsed().as_secs_f64();
    let f = scene.fluid()?;
    let z_end = surface_height(f, dp, p.tank_length);
    let mut out = CaseOutput::new();
    out.check(Check::below(
        "rms_speed",
        late_rms,
        SPEED_FRACTION * (G * p.depth).sqrt(),
    ));
    out.check(Check::below(
        "surface_drift_abs",
        (z_end - z_settled).abs(),
        DRIFT_FRACTION * dp,
    ));
    out.check(Check::below(
        "left_tank",
        left_tank(f, dp, p.tank_length) as f64,
        0.0,
    ));
    out.metric("surface_drift", z_end - z_settled)
        .metric("surface_drift_late", z_end - z_half)
        .metric("settling", z_settled - z0)
        .metric("max_speed", late_speed)
        .metric("g_h", G * p.h)
        .metric("final_speed", max_speed(f))
        .metric("final_specific_kinetic_energy", f.kinetic_energy() / mass)
        .metric("max_compression_pct", 100.0 * max_c)
        .metric("avg_iterations", iterations as f64 / n as f64)
        .metric("wall_s", wall);
    out.series = series;
    out.plot = PlotSpec::new(
        "constraint fluid, still water at a large step: surface height change",
        "t [s]",
        "m",
        &["surface_change"],
    );
    out.steps = n;
    Ok(out)
}

/// The `cfluid-still-water` case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<StillWaterParams>::boxed(
        "cfluid-still-water",
        "cfluid",
        "Still water in a tank (quasi-2D constraint fluid) at a large time step for 20 s: largest particle speed, kinetic energy and free-surface drift.",
        run,
    )
}
