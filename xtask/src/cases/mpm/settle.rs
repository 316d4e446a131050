//! The `mpm-settle` bench (issue 25, "the mud bench"): the seed's mud bed at rest in a box
//! under gravity, by the split (density rows for the pressure, MPM with snow plasticity
//! for the shear; `chrono_mpm::mud`), at the seed's parameters with `n` markers.
//!
//! The seed ("Vehicle on Mud: Constraint Fluids", Chrono multi-physics slides): 1 426 663
//! markers of 0.023 kg, rho 1200 kg/m^3, h 0.032 m, E 7e5 Pa, nu 0.2, theta_c = theta_s =
//! 2.5e-2, dt 1e-3 s, 1000 bilateral + 50 full iterations per step, 12 s simulated in
//! 30 h: `1 426 663 * 12 000 / 108 000 s = 1.59e5` marker-steps/s on a many-core machine.
//! Its constraint fluid's density error at solver tolerance 1e-1 is 0.043 %; the
//! tolerance is read as `cfluid-incompressibility` reads it (Chrono's Euclidean norm over
//! the rows, the solver given `tolerance / sqrt(n_rows)`; `docs/validation-cfluid.md`).
//!
//! Timed window: `steps` after `warmup_steps`. Metrics: marker-steps/s, the shares of the
//! step (P2G, grid update, G2P, constitutive update, rows' assembly, solve and the rest),
//! APGD's iterations per step (mean, max, steps at the limit), the density error: the
//! worst marker's compression at each step's start, averaged over the last quarter of the
//! window (`density_error_pct`, the seed's and `cfluid-incompressibility`'s definition), its
//! largest value there, and the markers' mean compression; the mean vertical stress
//! against `-rho g H / 2` (at rest with frictionless walls). Reported, not checked.

use std::time::Instant;

use chrono_mpm::material::SnowHardening;
use chrono_mpm::mud::{MudBed, MudSpec};
use chrono_mpm::{RowsNorm, StrainFrom};
use serde::{Deserialize, Serialize};

use crate::case::{Case, CaseOutput, Mode, RunContext};
use crate::cases::cfluid::incompressibility::ToleranceNorm;
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// The velocity field of the markers' strain update (parameter `strain_from`;
/// [`StrainFrom`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Strain {
    /// The markers' final velocities rasterized to the grid (the default).
    FinalGrid,
    /// The grid's velocity before the rows plus the rows' SPH share (the earlier form).
    GridPlusRows,
}

/// The seed's rate: 1 426 663 markers, 12 s at dt 1e-3 in 30 h, marker-steps/s.
pub const SEED_MARKER_STEPS_PER_S: f64 = 1_426_663.0 * 12_000.0 / (30.0 * 3600.0);
/// The seed's density error at tolerance 1e-1, %.
pub const SEED_DENSITY_ERROR_PCT: f64 = 0.043;

/// Parameters of the `mpm-settle` bench.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SettleBenchParams {
    /// Requested markers (rounded to whole cells).
    pub n: usize,
    /// Time step, s.
    pub dt: f64,
    /// Untimed steps first.
    pub warmup_steps: u64,
    /// Timed steps.
    pub steps: u64,
    /// The rows' solver tolerance, 1/s, in `tolerance_norm`.
    pub tolerance: f64,
    /// `l2` (Chrono's, the seed's) or `rms` (chrono-ccp's).
    pub tolerance_norm: ToleranceNorm,
    /// APGD's iteration limit per step.
    pub max_iterations: usize,
    /// Marker mass, kg.
    pub marker_mass: f64,
    /// Density, kg/m^3.
    pub density: f64,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Poisson's ratio.
    pub poisson: f64,
    /// Critical compression.
    pub theta_c: f64,
    /// Critical stretch.
    pub theta_s: f64,
    /// Hardening coefficient.
    pub xi: f64,
    /// The rows' smoothing length over spacing.
    pub h_over_dp: f64,
    /// The rows' compressibility, 1/Pa.
    pub compressibility: f64,
    /// Markers per cell and axis.
    pub markers_per_cell: usize,
    /// Bed width over depth.
    pub aspect: f64,
    /// The mud's extent in x over the box's (1: a bed; less: a slumping block).
    pub block_fraction: f64,
    /// The markers' volume ratio from the rows' density (`PressureSettings::volume_from_rows`).
    pub volume_from_rows: bool,
    /// The velocity field of the markers' strain update.
    pub strain_from: Strain,
}

impl Default for SettleBenchParams {
    fn default() -> Self {
        let s = MudSpec::seed(0);
        Self {
            n: 4000,
            dt: 1e-3,
            warmup_steps: 10,
            steps: 100,
            tolerance: s.tolerance,
            tolerance_norm: ToleranceNorm::L2,
            max_iterations: s.max_iterations,
            marker_mass: s.marker_mass,
            density: s.density,
            young: s.young,
            poisson: s.poisson,
            theta_c: s.snow.theta_c,
            theta_s: s.snow.theta_s,
            xi: s.snow.xi,
            h_over_dp: s.h_over_dp,
            compressibility: s.compressibility,
            markers_per_cell: s.markers_per_cell,
            aspect: s.aspect,
            block_fraction: s.block_fraction,
            volume_from_rows: s.volume_from_rows,
            strain_from: Strain::FinalGrid,
        }
    }
}

impl CaseParams for SettleBenchParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("n", "-", "requested markers (rounded to whole cells)"),
        ParamInfo::new("dt", "s", "time step (the seed's 1e-3)"),
        ParamInfo::new("warmup_steps", "-", "untimed steps first"),
        ParamInfo::new("steps", "-", "timed steps"),
        ParamInfo::new(
            "tolerance",
            "1/s",
            "rows' solver tolerance (the seed's 1e-1)",
        ),
        ParamInfo::new(
            "tolerance_norm",
            "-",
            "l2 (Chrono's, tolerance / sqrt(rows) to the solver) or rms",
        ),
        ParamInfo::new("max_iterations", "-", "APGD's iteration limit per step"),
        ParamInfo::new("marker_mass", "kg", "marker mass (the seed's 0.023)"),
        ParamInfo::new("density", "kg/m^3", "density (the seed's 1200)"),
        ParamInfo::new("young", "Pa", "Young's modulus (the seed's 7e5)"),
        ParamInfo::new("poisson", "-", "Poisson's ratio (the seed's 0.2)"),
        ParamInfo::new("theta_c", "-", "critical compression (the seed's 2.5e-2)"),
        ParamInfo::new("theta_s", "-", "critical stretch (the seed's 2.5e-2)"),
        ParamInfo::new("xi", "-", "hardening coefficient (Stomakhin 2013's 10)"),
        ParamInfo::new("h_over_dp", "-", "rows' smoothing length over spacing"),
        ParamInfo::new(
            "compressibility",
            "1/Pa",
            "rows' compliance (0: incompressible)",
        ),
        ParamInfo::new("markers_per_cell", "-", "markers per grid cell and axis"),
        ParamInfo::new("aspect", "-", "bed width over depth (x and y)"),
        ParamInfo::new(
            "block_fraction",
            "-",
            "mud extent in x over the box's (1: bed at rest; < 1: a block slumping)",
        ),
        ParamInfo::new(
            "volume_from_rows",
            "-",
            "markers' J set to the rows' rho_0 / rho each step (default false)",
        ),
        ParamInfo::new(
            "strain_from",
            "-",
            "F_E's velocity field: final_grid (markers' final velocities on the grid) or \
             grid_plus_rows (the grid's before the rows plus the rows' SPH share)",
        ),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        if mode == Mode::Quick {
            self.n = 2000;
            self.steps = 50;
        }
    }
}

/// This process's CPU time (user + system, all threads), s, from `/proc/self/stat`
/// (Linux; `None` elsewhere). At 100 ticks/s: 10 ms resolution.
fn process_cpu_s() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // the fields after the command name (which is in parentheses and may hold spaces)
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    // utime, stime: fields 14 and 15 of proc(5), i.e. 11 and 12 after the name
    let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

fn run(p: &SettleBenchParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(p.steps > 0, "parameter `steps` must be > 0, got 0");
    let spec = MudSpec {
        markers: p.n,
        marker_mass: p.marker_mass,
        density: p.density,
        young: p.young,
        poisson: p.poisson,
        snow: SnowHardening::new(p.theta_c, p.theta_s, p.xi)?,
        h_over_dp: p.h_over_dp,
        markers_per_cell: p.markers_per_cell,
        aspect: p.aspect,
        block_fraction: p.block_fraction,
        gravity: chrono_core::math::GRAVITY_MAGNITUDE,
        compressibility: p.compressibility,
        tolerance: p.tolerance,
        tolerance_norm: match p.tolerance_norm {
            ToleranceNorm::L2 => RowsNorm::L2,
            ToleranceNorm::Rms => RowsNorm::Rms,
        },
        max_iterations: p.max_iterations,
        volume_from_rows: p.volume_from_rows,
        strain_from: match p.strain_from {
            Strain::FinalGrid => StrainFrom::FinalGrid,
            Strain::GridPlusRows => StrainFrom::GridPlusRows,
        },
    };
    let t_build = Instant::now();
    let mut bed = MudBed::new(spec)?;
    let build_s = t_build.elapsed().as_secs_f64();
    for _ in 0..p.warmup_steps {
        bed.step(p.dt)?;
    }
    bed.body.reset_timings();
    let window_from = p.steps - (p.steps / 4).max(1);
    let (mut it_sum, mut it_max, mut at_limit) = (0usize, 0usize, 0u64);
    let (mut err_sum, mut err_max, mut mean_sum, mut n_window) = (0.0, 0.0f64, 0.0, 0u32);
    let mut rows_sum = 0usize;
    let cpu0 = process_cpu_s();
    let start = Instant::now();
    for k in 0..p.steps {
        bed.step(p.dt)?;
        let rows = bed.body.pressure_rows().expect("the bed is in the split");
        let it = rows.last_solve().0;
        it_sum += it;
        it_max = it_max.max(it);
        rows_sum += rows.rows();
        if it >= p.max_iterations {
            at_limit += 1;
        }
        if k >= window_from {
            // the rows' densities of this step's start: the end of the step before
            let (max, mean) = bed.compression_pct();
            err_sum += max;
            err_max = err_max.max(max);
            mean_sum += mean;
            n_window += 1;
        }
        ctx.progress_steps(k + 1, p.steps);
    }
    let total = start.elapsed().as_secs_f64();
    let cpu = cpu0.zip(process_cpu_s()).map(|(a, b)| b - a);
    let tm = bed.body.timings();
    let rows = bed.body.pressure_rows().expect("the bed is in the split");
    let n = bed.body.markers.len() as f64;
    let steps = p.steps as f64;
    let rate = n * steps / total;
    let iterations = it_sum as f64 / steps;
    let hydro = p.density * chrono_core::math::GRAVITY_MAGNITUDE * bed.depth() / 2.0;
    let mut out = CaseOutput::new();
    out.metric("markers", n)
        .metric("wall_markers", bed.wall_markers() as f64)
        .metric("rows_per_step", rows_sum as f64 / steps)
        .metric("spacing", bed.spacing())
        .metric("dx", bed.body.spec().dx)
        .metric("depth", bed.depth())
        .metric("threads", rayon::current_num_threads() as f64)
        .metric("build_s", build_s)
        .metric("step_s_mean", total / steps)
        .metric("marker_steps_per_s", rate)
        .metric("seed_marker_steps_per_s", SEED_MARKER_STEPS_PER_S)
        .metric("rate_over_seed", rate / SEED_MARKER_STEPS_PER_S)
        .metric("stable_dt", bed.body.stable_dt())
        .metric("iterations_mean", iterations)
        .metric("iterations_max", it_max as f64)
        .metric("steps_at_iteration_limit", at_limit as f64)
        .metric("tolerance", p.tolerance)
        .metric("solver_tolerance_rms", rows.solver_tolerance())
        .metric("density_error_pct", err_sum / f64::from(n_window))
        .metric("density_error_max_pct", err_max)
        .metric("mean_compression_pct", mean_sum / f64::from(n_window))
        .metric("seed_density_error_pct", SEED_DENSITY_ERROR_PCT)
        .metric(
            "mean_sigma_zz_over_hydrostatic",
            -bed.mean_vertical_stress() / hydro,
        )
        .metric("kinetic_energy", bed.body.kinetic_energy())
        .metric("share_p2g", tm.p2g / total)
        .metric("share_grid_update", tm.grid_update / total)
        .metric("share_g2p", tm.g2p / total)
        .metric("share_constitutive", tm.constitutive / total)
        .metric("share_rows_neighbours", tm.rows_neighbours / total)
        .metric("share_rows_assembly", tm.rows_assembly / total)
        .metric("share_rows_solve", tm.rows_solve / total)
        .metric("share_rows_post", tm.rows_post / total)
        .metric("share_advect", tm.advect / total)
        .metric(
            "ns_per_row_iteration",
            tm.rows_solve / (it_sum.max(1) as f64 * rows_sum as f64 / steps) * 1e9,
        );
    if let Some(cpu) = cpu.filter(|c| *c > 0.0) {
        // the load-independent figure: marker-steps per CPU second of all threads, and
        // twice it, the rate two idle cores would give at perfect parallel scaling (an
        // upper bound)
        out.metric("cpu_s", cpu)
            .metric("marker_steps_per_cpu_s", n * steps / cpu)
            .metric("marker_steps_per_s_2_cores_bound", 2.0 * n * steps / cpu);
    }
    out.steps = p.steps;
    Ok(out)
}

/// The bench.
pub fn bench() -> Box<dyn Case> {
    ParamCase::<SettleBenchParams>::boxed(
        "mpm-settle",
        "mpm",
        "The seed's mud bed at rest in a box by the split (rows + MPM shear, snow plasticity): marker-steps/s against the seed's 1.6e5, shares of the step, APGD iterations, density error at tolerance 1e-1 (Chrono's norm).",
        run,
    )
}
