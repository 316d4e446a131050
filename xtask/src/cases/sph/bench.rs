//! The `sph-dam-break` bench: whole-step throughput of a 3D dam break.
//!
//! Scene (default): the SPHERIC benchmark 2 geometry without its obstacle (Kleefsman,
//! Fekken, Veldman, Iwanowski and Buchner, "A volume-of-fluid based simulation method for
//! wave impact problems", J. Comput. Phys. 206 (2005) 363-393): a tank
//! `3.22 x 1.0 x 1.0 m`, a water column `1.228 x 1.0 x 0.55 m` against the left wall,
//! released from hydrostatic rest; marker walls on five sides (open top), `c_s = 10
//! sqrt(2 g H)`, the solver's defaults otherwise. The spacing follows from the requested
//! fluid particle count `n` (`dp = (V_column / n)^(1/3)`) unless `spacing` is set, so
//! the same scene can be run in another SPH code with the same `dp` and `h / dp`.
//!
//! Timed window: `steps` (default 200) after `warmup_steps` (5), so it reaches into the
//! collapse and holds neighbour-list rebuilds (`list_builds_in_window`); `dt_mean` and
//! `simulated_s_per_wall_s` allow a comparison with a code at another time step.
//!
//! Metrics: particles (fluid, wall markers), `particle_steps_per_s` (all particles,
//! the usual figure), `fluid_particle_steps_per_s`, neighbour-list entries per fluid
//! particle (inside `2 h (1 + skin)`) and per particle inside the support `2 h`, the
//! pair evaluations per second of the interaction passes (the continuity and force passes
//! visit every list entry of each fluid particle, the wall extrapolation every entry of
//! each wall marker, whose list holds its fluid neighbours only), and the shares of the
//! step in neighbour search, density work (continuity, equation of state, wall
//! extrapolation), forces and integration.

use chrono_core::math::GRAVITY_MAGNITUDE;
use std::time::Instant;

use chrono_sph::{SphBuilder, SphSettings, SphSystem};
use serde::{Deserialize, Serialize};

use crate::case::{Case, CaseOutput, Mode, RunContext};
use crate::params::{CaseParams, ParamCase, ParamInfo};
use chrono_core::particles::lattice::wall_layers;

/// `g` = [`GRAVITY_MAGNITUDE`], m/s^2.
const G: f64 = GRAVITY_MAGNITUDE;

/// Parameters of the `sph-dam-break` bench.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct DamBreakBenchParams {
    /// Requested number of fluid particles (sets the spacing when `spacing` is 0).
    pub n: usize,
    /// Particle spacing, m (0: from `n`).
    pub spacing: f64,
    /// Smoothing length over spacing.
    pub h_over_dp: f64,
    /// Tank length (x), m.
    pub tank_length: f64,
    /// Tank width (y), m.
    pub tank_width: f64,
    /// Tank height (z), m.
    pub tank_height: f64,
    /// Column length (x), m.
    pub column_width: f64,
    /// Column height (z), m.
    pub column_height: f64,
    /// Steps before timing (first list build, caches).
    pub warmup_steps: u64,
    /// Timed steps.
    pub steps: u64,
}

impl Default for DamBreakBenchParams {
    fn default() -> Self {
        Self {
            n: 100_000,
            spacing: 0.0,
            h_over_dp: SphSettings::default().h_over_dp,
            tank_length: 3.22,
            tank_width: 1.0,
            tank_height: 1.0,
            column_width: 1.228,
            column_height: 0.55,
            warmup_steps: 5,
            // the window runs 200 steps into the collapse, so it holds neighbour-list
            // rebuilds (the metrics count them) and the figure is not that of the
            // still column's first instants
            steps: 200,
        }
    }
}

impl CaseParams for DamBreakBenchParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("n", "-", "fluid particles (sets dp when spacing = 0)"),
        ParamInfo::new("spacing", "m", "particle spacing dp (0: from n)"),
        ParamInfo::new("h_over_dp", "-", "smoothing length over spacing"),
        ParamInfo::new("tank_length", "m", "tank length (x)"),
        ParamInfo::new("tank_width", "m", "tank width (y), also the column's"),
        ParamInfo::new("tank_height", "m", "tank height (z)"),
        ParamInfo::new("column_width", "m", "water column length (x)"),
        ParamInfo::new("column_height", "m", "water column height (z)"),
        ParamInfo::new("warmup_steps", "-", "untimed steps first"),
        ParamInfo::new("steps", "-", "timed steps"),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        if mode == Mode::Quick {
            self.n = 20_000;
            self.steps = 20;
        }
    }
}

fn build(p: &DamBreakBenchParams) -> anyhow::Result<SphSystem> {
    for (name, v) in [
        ("tank_length", p.tank_length),
        ("tank_width", p.tank_width),
        ("tank_height", p.tank_height),
        ("column_width", p.column_width),
        ("column_height", p.column_height),
    ] {
        anyhow::ensure!(
            v > 0.0 && v.is_finite(),
            "parameter `{name}` must be > 0, got {v}"
        );
    }
    anyhow::ensure!(
        p.column_width <= p.tank_length && p.column_height <= p.tank_height,
        "the column ({} x {}) must fit in the tank ({} x {})",
        p.column_width,
        p.column_height,
        p.tank_length,
        p.tank_height
    );
    anyhow::ensure!(p.steps > 0, "parameter `steps` must be > 0");
    let volume = p.column_width * p.tank_width * p.column_height;
    let dp = if p.spacing > 0.0 {
        p.spacing
    } else {
        anyhow::ensure!(p.n > 0, "parameter `n` must be > 0 when `spacing` is 0");
        (volume / p.n as f64).cbrt()
    };
    let upper = [p.tank_length, p.tank_width, p.tank_height];
    let settings = SphSettings {
        spacing: dp,
        h_over_dp: p.h_over_dp,
        sound_speed: 10.0 * (2.0 * G * p.column_height).sqrt(),
        domain_lower: [0.0; 3],
        domain_upper: upper,
        ..SphSettings::default()
    };
    let mut b = SphBuilder::new(settings)?;
    b.add_fluid_box(
        [0.0; 3],
        [p.column_width, p.tank_width, p.column_height],
        Some(p.column_height),
    )?;
    b.add_tank(
        [0.0; 3],
        upper,
        wall_layers(p.h_over_dp),
        [true, true, true, true, true, false],
        0,
    )?;
    Ok(b.build()?)
}

fn run(p: &DamBreakBenchParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    let t_build = Instant::now();
    let mut sys = build(p)?;
    let build_s = t_build.elapsed().as_secs_f64();
    for _ in 0..p.warmup_steps {
        sys.step()?;
    }
    sys.reset_timings();
    let (builds0, t0) = (sys.stats().list_builds, sys.time());
    let start = Instant::now();
    for i in 1..=p.steps {
        sys.step()?;
        ctx.progress_steps(i, p.steps);
    }
    let total = start.elapsed().as_secs_f64();
    let tm = *sys.timings();
    let builds = sys.stats().list_builds - builds0;
    let sim_time = sys.time() - t0;
    // Neighbour statistics of the last list.
    let d = sys.data();
    let list = sys.neighbor_list();
    let support2 = sys.kernel().support().powi(2);
    let (mut fluid_entries, mut wall_entries, mut inside) = (0usize, 0usize, 0usize);
    for i in 0..d.len() {
        let nb = list.neighbors(i);
        if d.kind[i] == chrono_sph::data::FLUID {
            fluid_entries += nb.len();
            let pi = [d.x[i], d.y[i], d.z[i]];
            inside += nb
                .iter()
                .filter(|&&j| {
                    let j = j as usize;
                    let x = sys.grid().displacement(pi, [d.x[j], d.y[j], d.z[j]]);
                    x[0] * x[0] + x[1] * x[1] + x[2] * x[2] <= support2
                })
                .count();
        } else {
            wall_entries += nb.len();
        }
    }
    let n_fluid = sys.num_fluid();
    let n_all = sys.len();
    let steps = p.steps as f64;
    // The continuity pass visits every fluid list entry, the force pass only the in-support
    // neighbours the continuity pass kept (since issue 23's second round; before, it
    // visited the whole list too and this counted 2 per fluid entry), the wall
    // extrapolation every wall entry.
    let pair_evals = (fluid_entries + inside + wall_entries) as f64;
    let mut out = CaseOutput::new();
    out.metric("spacing", sys.settings().spacing)
        .metric("fluid_particles", n_fluid as f64)
        .metric("wall_markers", (n_all - n_fluid) as f64)
        .metric("threads", rayon::current_num_threads() as f64)
        .metric("build_s", build_s)
        .metric("step_s_mean", total / steps)
        .metric("particle_steps_per_s", n_all as f64 * steps / total)
        .metric("fluid_particle_steps_per_s", n_fluid as f64 * steps / total)
        .metric(
            "list_entries_per_fluid_particle",
            fluid_entries as f64 / n_fluid as f64,
        )
        .metric(
            "neighbours_in_support_per_fluid_particle",
            inside as f64 / n_fluid as f64,
        )
        .metric("pair_evaluations_per_s", pair_evals * steps / total)
        .metric("ns_per_pair_evaluation", total / steps / pair_evals * 1e9)
        .metric("list_builds", sys.stats().list_builds as f64)
        .metric("list_builds_in_window", builds as f64)
        .metric("dt_mean", sim_time / steps)
        .metric("simulated_s_per_wall_s", sim_time / total)
        .metric("share_neighbor_search", tm.neighbor_search / total)
        .metric("share_density", tm.density / total)
        .metric("share_forces", tm.forces / total)
        .metric("share_integration", tm.integration / total);
    out.steps = p.steps;
    Ok(out)
}

/// The bench.
pub fn bench() -> Box<dyn Case> {
    ParamCase::<DamBreakBenchParams>::boxed(
        "sph-dam-break",
        "sph",
        "3D dam break (SPHERIC test 2 tank, no obstacle): particle-steps/s, neighbours, pair evaluations/s, shares of neighbour search, density, forces, integration.",
        run,
    )
}
