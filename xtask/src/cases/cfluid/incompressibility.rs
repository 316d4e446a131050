//! `cfluid-incompressibility`: a column of water settling at rest in a tank (quasi-2D slab,
//! periodic along y), solved as a constraint fluid in the system's CCP.
//!
//! Reference: the seed's "Incompressibility Test" table (Mazhar, constraint fluids in
//! Chrono::Parallel): for solver tolerances 1e-1, 1e-2, 1e-6, 1e-8, the average
//! iterations per step, the final density, the density error and the final kinetic
//! energy. The case runs the column once per tolerance of `sweep_tolerances` (and once
//! at `tolerance` if it is not among them), prints our table beside the seed's and
//! writes it to `table.md`. Checks, per swept tolerance (issue 6): density error no worse
//! than the seed's and average iterations at most the seed's.
//!
//! Definitions (ours): `density_error_pct` is the worst particle's compression
//! `100 max_i (rho_i / rho_0 - 1)` (SPH summation at the positions at the end of a step;
//! the free-surface deficit is not counted as an error), **averaged over the steps of the
//! last `window` of the run**, and `final_density = rho_0 (1 + density_error_pct / 100)`.
//! The worst particle of one frame is a chaotic statistic at a loose tolerance (it jumps
//! from step to step by a factor 2-5: at tolerance 1e-1 the solver stops after a few
//! iterations and leaves a residual spread over the particles), so one frame is not a
//! measure; the snapshot at `t_end` and the largest value over the window are reported
//! beside it (`density_error_end_pct`, `density_error_max_pct`). `avg_iterations` is the
//! mean solver iterations per step; `final_kinetic_energy` the fluid's kinetic energy at
//! `t_end` (J; it depends on the amount of fluid, so `final_specific_kinetic_energy` in
//! J/kg is reported too).
//!
//! Tolerance: the seed's numbers are Chrono::Multicore tolerances, and Chrono's APGD stops
//! when the **Euclidean norm** over all rows of the projected gradient (constraint
//! velocities, 1/s for density rows) is below it (`ChSolverMulticoreAPGD`, residual
//! `sqrt(sum_i r_i^2)`). chrono-ccp's common residual is the RMS of the same quantity
//! (`sqrt(sum_i r_i^2 / n)`), `sqrt(n)` times looser at the same number. With
//! `tolerance_norm = "l2"` (the default) the case gives the solver `tolerance / sqrt(n)`
//! (`n` the rows of the previous step: the fluid's density rows, and the wall markers'
//! when they have rows), i.e. it stops by Chrono's rule;
//! `"rms"` passes the tolerance through unchanged (chrono-ccp's rule).

use std::fmt::Write as _;
use std::time::Instant;

use chrono_cfluid::{CfluidSettings, SurfaceMode};
use serde::{Deserialize, Serialize};

use super::{left_tank, tank_scene};
use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series, SweepPoint};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// The seed's table: tolerance, average iterations, final density (kg/m^3), density
/// error (%), final kinetic energy (J).
pub const SEED_TABLE: [(f64, f64, f64, f64, f64); 4] = [
    (1e-1, 43.0, 1000.43, 0.043, 0.85),
    (1e-2, 114.0, 1000.2, 0.02, 0.82),
    (1e-6, 531.0, 1000.15, 0.015, 0.59),
    (1e-8, 639.0, 1000.13, 0.013, 0.44),
];

/// How the case reads its `tolerance` (the parameter `tolerance_norm`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ToleranceNorm {
    /// Chrono's: the Euclidean norm of the residual over all rows (the solver gets
    /// `tolerance / sqrt(n_rows)`).
    L2,
    /// chrono-ccp's RMS residual.
    Rms,
}

impl std::fmt::Display for ToleranceNorm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::L2 => "l2",
            Self::Rms => "rms",
        })
    }
}

/// Parameters of `cfluid-incompressibility`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct IncompressibilityParams {
    /// Solver tolerance of the main run (residual, 1/s for density rows).
    pub tolerance: f64,
    /// Tolerances of the table sweep (the seed's: 1e-1, 1e-2, 1e-6, 1e-8); empty: none.
    pub sweep_tolerances: Vec<f64>,
    /// Particle spacing, m.
    pub spacing: f64,
    /// Time step, s.
    pub h: f64,
    /// Simulated time, s.
    pub t_end: f64,
    /// Water depth, m.
    pub depth: f64,
    /// Tank length (x), m.
    pub tank_length: f64,
    /// Smoothing length over spacing.
    pub h_over_dp: f64,
    /// Compressibility `1/K` of the rows' compliance, 1/Pa.
    pub compressibility: f64,
    /// XSPH viscosity epsilon.
    pub xsph: f64,
    /// Free-surface treatment: `one_sided`, `unilateral` or `clamped`.
    pub surface: SurfaceMode,
    /// CCP solver (chrono-ccp name: apgd, bb, psor, ...).
    pub solver: String,
    /// Iteration cap per step.
    pub max_iterations: usize,
    /// How `tolerance` is read: `l2` (Chrono's: Euclidean norm of the residual over all
    /// rows; the solver gets `tolerance / sqrt(n_rows)`) or `rms` (chrono-ccp's RMS).
    pub tolerance_norm: ToleranceNorm,
    /// Final fraction of the run over which the density error is averaged.
    pub window: f64,
}

impl Default for IncompressibilityParams {
    fn default() -> Self {
        Self {
            tolerance: 1e-6,
            sweep_tolerances: SEED_TABLE.iter().map(|r| r.0).collect(),
            spacing: 0.01,
            h: 1e-3,
            t_end: 1.0,
            depth: 0.2,
            tank_length: 0.1,
            h_over_dp: 1.2,
            compressibility: 1e-9,
            xsph: CfluidSettings::default().xsph,
            surface: SurfaceMode::OneSided,
            solver: "apgd".into(),
            max_iterations: 1000,
            tolerance_norm: ToleranceNorm::L2,
            window: 0.25,
        }
    }
}

impl CaseParams for IncompressibilityParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new(
            "tolerance",
            "1/s",
            "solver tolerance of the main run (chrono-ccp residual)",
        ),
        ParamInfo::new(
            "sweep_tolerances",
            "1/s",
            "tolerances of the table sweep (seed: 1e-1, 1e-2, 1e-6, 1e-8)",
        ),
        ParamInfo::new("spacing", "m", "particle spacing dp"),
        ParamInfo::new("h", "s", "time step"),
        ParamInfo::new("t_end", "s", "simulated time"),
        ParamInfo::new("depth", "m", "water depth"),
        ParamInfo::new("tank_length", "m", "tank length (x)"),
        ParamInfo::new("h_over_dp", "-", "smoothing length over spacing"),
        ParamInfo::new("compressibility", "1/Pa", "row compliance as 1/K"),
        ParamInfo::new("xsph", "-", "XSPH viscosity epsilon"),
        ParamInfo::new("surface", "-", "one_sided | unilateral | clamped"),
        ParamInfo::new("solver", "-", "CCP solver name (chrono-ccp)"),
        ParamInfo::new("max_iterations", "-", "iteration cap per step"),
        ParamInfo::new(
            "tolerance_norm",
            "-",
            "`l2` (Chrono's norm: solver gets tolerance/sqrt(rows)) or `rms` (chrono-ccp's)",
        ),
        ParamInfo::new(
            "window",
            "-",
            "final fraction of the run over which the density error is averaged",
        ),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            Mode::Quick => {
                self.spacing = 0.02;
                self.depth = 0.2;
                self.h = 2e-3;
                self.t_end = 0.5;
            }
            // The quick column at the seed table's step (h = 1 ms) over 0.5 s, for the
            // 20-minute budget of the default run (over the seed's 1 s it took 64 s); the
            // seed's own set-up, the earlier default (dp = 0.01 m, 1 s, ~950 s for the
            // four tolerances), is `--set spacing=0.01 --set t_end=1`.
            Mode::Default => {
                self.spacing = 0.02;
                self.t_end = 0.5;
            }
            Mode::Full => {
                self.spacing = 0.005;
                self.t_end = 2.0;
            }
        }
    }
}

/// What one run measured.
struct Outcome {
    avg_iterations: f64,
    final_density: f64,
    density_error_pct: f64,
    density_error_max_pct: f64,
    density_error_end_pct: f64,
    solver_tolerance: f64,
    max_compression_pct: f64,
    final_kinetic_energy: f64,
    specific_kinetic_energy: f64,
    steps: u64,
    wall_s: f64,
    series: Series,
}

fn simulate(
    p: &IncompressibilityParams,
    tolerance: f64,
    ctx: Option<&RunContext>,
) -> anyhow::Result<Outcome> {
    anyhow::ensure!(
        p.h > 0.0 && p.h.is_finite(),
        "parameter `h` must be > 0, got {}",
        p.h
    );
    anyhow::ensure!(
        p.t_end > 0.0,
        "parameter `t_end` must be > 0, got {}",
        p.t_end
    );
    anyhow::ensure!(
        tolerance > 0.0 && tolerance.is_finite(),
        "parameter `tolerance` must be > 0, got {tolerance}"
    );
    anyhow::ensure!(
        p.window > 0.0 && p.window <= 1.0,
        "parameter `window` must be in (0, 1], got {}",
        p.window
    );
    let dp = p.spacing;
    anyhow::ensure!(
        dp > 0.0 && dp <= p.depth / 4.0 && dp <= p.tank_length / 2.0,
        "parameter `spacing` must be in (0, min(depth/4, tank_length/2)], got {dp}"
    );
    let start = Instant::now();
    let settings = CfluidSettings {
        spacing: dp,
        h_over_dp: p.h_over_dp,
        compressibility: p.compressibility,
        xsph: p.xsph,
        surface: p.surface,
        ..CfluidSettings::default()
    };
    let rho_0 = settings.rest_density;
    let mut scene = tank_scene(
        settings,
        p.tank_length,
        1.5 * p.depth,
        [p.tank_length, p.depth],
        &p.solver,
        tolerance,
        p.max_iterations,
    )?;
    // RMS * sqrt(n) is the Euclidean norm over the n rows of the step; the count of a
    // step is known after it, so each step uses the previous step's (the first: the
    // fluid's rows; with wall-marker rows the count changes by a few rows a step)
    let l2 = p.tolerance_norm == ToleranceNorm::L2;
    let mut solver_tolerance = tolerance;
    let mut n_rows = scene.fluid()?.n_fluid();
    let n = (p.t_end / p.h).round().max(1.0) as u64;
    // steps whose start-of-step densities (the end of the previous step) are in the window
    let first_window_step = ((1.0 - p.window) * n as f64).ceil() as u64 + 1;
    let mut window = Vec::new();
    let mut iterations = 0usize;
    let mut max_compression = 0.0f64;
    let mut series = Series::new(["t", "max_compression_pct", "iterations", "kinetic_energy"]);
    let every = (n / 400).max(1);
    for step in 1..=n {
        if l2 {
            solver_tolerance = tolerance / (n_rows.max(1) as f64).sqrt();
            scene.sys.solver_mut().settings_mut().tolerance = solver_tolerance;
        }
        let report = scene.sys.step(p.h)?;
        n_rows = scene.sys.last_problem().n_rows();
        iterations += report.solve.iterations;
        let f = scene.fluid()?;
        let c = f.max_compression().max(0.0);
        max_compression = max_compression.max(c);
        if step >= first_window_step {
            window.push(c);
        }
        if step % every == 0 || step == n {
            series.push(&[
                step as f64 * p.h,
                100.0 * c,
                report.solve.iterations as f64,
                f.kinetic_energy(),
            ]);
        }
        if let Some(ctx) = ctx {
            ctx.progress_steps(step, n);
        }
    }
    let left = left_tank(scene.fluid()?, dp, p.tank_length);
    let f = scene.fluid_mut()?;
    anyhow::ensure!(left == 0, "{left} fluid particles left the tank");
    let end = f.compute_densities()?.iter().fold(rho_0, |m, r| m.max(*r)) / rho_0 - 1.0;
    window.push(end);
    let mean = window.iter().sum::<f64>() / window.len() as f64;
    let worst = window.iter().fold(0.0f64, |m, c| m.max(*c));
    let ke = f.kinetic_energy();
    let mass = f.particle_mass() * f.n_fluid() as f64;
    Ok(Outcome {
        avg_iterations: iterations as f64 / n as f64,
        final_density: rho_0 * (1.0 + mean),
        density_error_pct: 100.0 * mean,
        density_error_max_pct: 100.0 * worst,
        density_error_end_pct: 100.0 * end,
        solver_tolerance,
        max_compression_pct: 100.0 * max_compression,
        final_kinetic_energy: ke,
        specific_kinetic_energy: ke / mass,
        steps: n,
        wall_s: start.elapsed().as_secs_f64(),
        series,
    })
}

/// `1e-1` -> `1e-1` (the metric key of a tolerance).
fn tol_key(t: f64) -> String {
    format!("{t:e}")
}

fn run(p: &IncompressibilityParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    let mut out = CaseOutput::new();
    let mut table = String::new();
    let _ = writeln!(
        table,
        "| tolerance | avg iterations (seed / ours) | final density kg/m^3 (seed / ours) | density error % (seed / ours) | final KE J (seed / ours) | ours: KE J/kg | ours: error % max over window / at t_end | ours: solver RMS tolerance | ours: wall s |"
    );
    let _ = writeln!(table, "|---|---|---|---|---|---|---|---|---|");
    let mut main = None;
    let tols = p.sweep_tolerances.clone();
    for (k, &tol) in tols.iter().enumerate() {
        let o = simulate(p, tol, None)?;
        ctx.progress((k + 1) as f64 / (tols.len() + 1) as f64);
        let key = tol_key(tol);
        let seed = SEED_TABLE.iter().find(|r| (r.0 / tol - 1.0).abs() < 1e-9);
        let cell = |s: Option<f64>, ours: f64| match s {
            Some(s) => format!(
                "{} / {}",
                crate::report::fmt_num(s),
                crate::report::fmt_num(ours)
            ),
            None => format!("- / {}", crate::report::fmt_num(ours)),
        };
        let _ = writeln!(
            table,
            "| {key} | {} | {} | {} | {} | {} | {} / {} | {} | {:.2} |",
            cell(seed.map(|r| r.1), o.avg_iterations),
            cell(seed.map(|r| r.2), o.final_density),
            cell(seed.map(|r| r.3), o.density_error_pct),
            cell(seed.map(|r| r.4), o.final_kinetic_energy),
            crate::report::fmt_num(o.specific_kinetic_energy),
            crate::report::fmt_num(o.density_error_max_pct),
            crate::report::fmt_num(o.density_error_end_pct),
            crate::report::fmt_num(o.solver_tolerance),
            o.wall_s,
        );
        out.metric(format!("tol={key}.final_density"), o.final_density)
            .metric(
                format!("tol={key}.final_kinetic_energy"),
                o.final_kinetic_energy,
            )
            .metric(
                format!("tol={key}.max_compression_pct"),
                o.max_compression_pct,
            )
            .metric(
                format!("tol={key}.density_error_max_pct"),
                o.density_error_max_pct,
            )
            .metric(
                format!("tol={key}.density_error_end_pct"),
                o.density_error_end_pct,
            );
        match seed {
            Some(r) => {
                out.check(Check::below(
                    format!("tol={key}.density_error_pct"),
                    o.density_error_pct,
                    r.3,
                ))
                .check(Check::below(
                    format!("tol={key}.avg_iterations"),
                    o.avg_iterations,
                    r.1,
                ));
            }
            None => {
                out.metric(format!("tol={key}.density_error_pct"), o.density_error_pct)
                    .metric(format!("tol={key}.avg_iterations"), o.avg_iterations);
            }
        }
        out.sweep.push(SweepPoint {
            label: format!("tol={key}"),
            error: o.density_error_pct.max(1e-12),
            wall_s: o.wall_s.max(1e-9),
        });
        if (tol / p.tolerance - 1.0).abs() < 1e-9 {
            main = Some(o);
        }
    }
    let o = match main {
        Some(o) => o,
        None => simulate(p, p.tolerance, Some(ctx))?,
    };
    ctx.progress(1.0);
    out.metric("avg_iterations", o.avg_iterations)
        .metric("final_density", o.final_density)
        .metric("density_error_pct", o.density_error_pct)
        .metric("density_error_max_pct", o.density_error_max_pct)
        .metric("density_error_end_pct", o.density_error_end_pct)
        .metric("max_compression_pct", o.max_compression_pct)
        .metric("final_kinetic_energy", o.final_kinetic_energy)
        .metric("final_specific_kinetic_energy", o.specific_kinetic_energy);
    ctx.note(format!(
        "cfluid-incompressibility (dp = {} m, h = {} s, t_end = {} s, solver {}, tolerance norm {}, density error averaged over the last {} of the run): seed table beside ours\n{table}",
        p.spacing, p.h, p.t_end, p.solver, p.tolerance_norm, p.window
    ));
    std::fs::write(ctx.out_file("table.md"), &table)?;
    out.series = o.series;
    out.plot = PlotSpec::new(
        "constraint fluid at rest: compression",
        "t [s]",
        "max compression [%]",
        &["max_compression_pct"],
    );
    out.steps = o.steps;
    Ok(out)
}

/// The `cfluid-incompressibility` case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<IncompressibilityParams>::boxed(
        "cfluid-incompressibility",
        "cfluid",
        "A water column settling at rest in a tank (quasi-2D constraint fluid): the seed's incompressibility table (tolerance, avg iterations, final density, density error, final KE) beside ours.",
        run,
    )
}
