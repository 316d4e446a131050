//! `ccp-solvers`: every CCP solver, cold-started, on problems captured from scenes — a
//! settled granular pile of about 1k, 10k and 100k contacts and the 5-box heavy stack — to
//! a residual of `tolerance` (1e-8 m/s) or its `apply_n` budget; and CG/MINRES on a
//! bilateral-only net of 100k rows to a relative residual of 1e-8.
//!
//! Metrics per problem and solver: `<problem>.<solver>_iters_1e-4`, `_iters_1e-6`,
//! `_apply_n_1e-4`, `_apply_n_1e-6`, `_time_1e-4`, `_time_1e-6` (s, from the solver's own
//! history clock, setup included), `_final_residual` (m/s), `_wall` (s, whole solve).
//! Metrics of a level a solver never reached within its budget are absent. The plot is residual against
//! wall time, all solvers on one figure, for the pile nearest 10k contacts (the 1k one in
//! `--quick`); `residual_<problem>.png` and `history_<problem>.csv` are written for every
//! problem, and each captured problem is saved as `<problem>.ccp` (reload it with
//! `chrono_core::descriptor::ProblemFile::load_problem`).
//!
//! Checks: on the pile nearest 10k contacts (if >= 5000 contacts) APGD needs at most 1/5 of
//! the `apply_n`-equivalents of projected Jacobi to reach 1e-6 (if Jacobi never gets there
//! its whole budget is used, a lower bound); CG and MINRES reach a relative residual of 1e-8
//! on the net; the solvers that reach 1e-7 agree on the objective to 1e-6 (relative); every
//! captured problem saved, reloaded and solved by APGD gives the same `gamma` bit for bit.

use std::fmt::Write as _;

use chrono_ccp::{CcpSolver, KrylovOptions, SolverSettings, by_name, relative_residual};
use chrono_core::descriptor::{CcpProblem, CcpWork, ProblemFile, ProblemFormat};
use serde::{Deserialize, Serialize};

use super::{LEVELS, Run};
use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::params::{CaseParams, ParamCase, ParamInfo};
use chrono_ccp::testing::{bilateral_net, granular_pile, heavy_stack};

/// Parameters of `ccp-solvers`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SolversParams {
    /// Target contact counts of the granular piles.
    pub n_contacts: Vec<usize>,
    /// Settling steps before the pile's problem is captured.
    pub settle_steps: usize,
    /// Time step of the settling, s.
    pub h: f64,
    /// Include the 5-box heavy stack.
    pub stack: bool,
    /// Solvers to compare (names of `chrono_ccp::by_name`).
    pub solvers: Vec<String>,
    /// Residual to solve to, m/s.
    pub tolerance: f64,
    /// `apply_n`-equivalents allowed per solve (the iteration cap is derived from it).
    pub apply_n_budget: usize,
    /// Wall time allowed per solve on problems of more than 100k rows, s: their iteration
    /// cap is also limited to this budget divided by twice the measured time of one
    /// `apply_n` (so the 100k-contact pile stays affordable); 0 for no limit.
    pub time_budget_s: f64,
    /// Rows of the bilateral net for CG/MINRES (0: skip).
    pub bilateral_rows: usize,
    /// Extra problems to load from files (`.ccp` binary or `.json`).
    pub problem_files: Vec<String>,
}

impl Default for SolversParams {
    fn default() -> Self {
        Self {
            n_contacts: vec![1000, 10_000, 100_000],
            settle_steps: 10,
            h: 0.002,
            stack: true,
            solvers: [
                "jacobi",
                "psor",
                "psor-sym",
                "psor-par",
                "apsor",
                "apgd",
                "bb",
                "two-phase",
            ]
            .map(String::from)
            .to_vec(),
            tolerance: 1e-8,
            apply_n_budget: 5000,
            time_budget_s: 12.0,
            bilateral_rows: 100_000,
            problem_files: Vec::new(),
        }
    }
}

impl CaseParams for SolversParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new(
            "n_contacts",
            "-",
            "target contact counts of the granular piles",
        ),
        ParamInfo::new("settle_steps", "-", "settling steps before capture"),
        ParamInfo::new("h", "s", "settling time step"),
        ParamInfo::new("stack", "-", "include the 5-box heavy stack"),
        ParamInfo::new(
            "solvers",
            "-",
            "solvers: jacobi psor psor-sym psor-par apsor apgd bb two-phase",
        ),
        ParamInfo::new("tolerance", "m/s", "residual to solve to"),
        ParamInfo::new("apply_n_budget", "-", "apply_n-equivalents per solve"),
        ParamInfo::new(
            "time_budget_s",
            "s",
            "wall time per solve (caps iterations; 0: none)",
        ),
        ParamInfo::new("bilateral_rows", "-", "rows of the CG/MINRES net (0: skip)"),
        ParamInfo::new("problem_files", "-", "extra problems from files"),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            Mode::Quick => {
                self.n_contacts = vec![1000];
                self.bilateral_rows = 20_000;
            }
            // Piles of 1k and 10k contacts and the 20k-row net, for the 20-minute budget
            // of the default run (`xtask/src/budget.rs`; the 100k pile and the 100k-row
            // net took 151 s). `--full` runs them (the earlier default).
            Mode::Default => {
                self.n_contacts = vec![1000, 10_000];
                self.bilateral_rows = 20_000;
            }
            Mode::Full => {}
        }
    }
}

/// Cost of one iteration in `apply_n`-equivalents (to turn the budget into a cap).
fn cost_per_iteration(name: &str) -> usize {
    match name {
        "psor" | "psor-par" => 2,
        "psor-sym" => 3,
        // a sweep, the momentum step and a residual check every 5 iterations
        "apsor" => 2,
        _ => 1,
    }
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Keep at most `max` records, log-spaced in the iteration number (the first and last kept).
fn downsample<T: Clone>(v: &[T], max: usize) -> Vec<T> {
    if v.len() <= max {
        return v.to_vec();
    }
    let mut idx: Vec<usize> = (0..max)
        .map(|k| ((v.len() as f64).powf(k as f64 / (max - 1) as f64) - 1.0).round() as usize)
        .collect();
    idx.dedup();
    idx.into_iter()
        .map(|i| v[i.min(v.len() - 1)].clone())
        .collect()
}

/// Residual-vs-time series of several runs (one column per solver, log10 of both).
fn residual_series(runs: &[Run]) -> Series {
    let mut cols = vec!["log10_time_s".to_string()];
    cols.extend(runs.iter().map(|r| r.solver.clone()));
    let mut s = Series::new(cols);
    for (k, run) in runs.iter().enumerate() {
        for rec in downsample(&run.stats.history, 400) {
            let mut row = vec![f64::NAN; runs.len() + 1];
            row[0] = rec.time_s.max(1e-7).log10();
            row[k + 1] = rec.residual.max(1e-300).log10();
            s.push(&row);
        }
    }
    s
}

fn history_csv(runs: &[Run]) -> String {
    let mut out = String::from("solver,iteration,apply_n,time_s,residual,objective\n");
    for run in runs {
        for r in &run.stats.history {
            let _ = writeln!(
                out,
                "{},{},{},{:e},{:e},{:.17e}",
                run.solver, r.iteration, r.apply_n, r.time_s, r.residual, r.objective
            );
        }
    }
    out
}

/// Solve one problem with every solver; record metrics; return the runs.
fn compare(
    p: &SolversParams,
    name: &str,
    problem: &CcpProblem,
    out: &mut CaseOutput,
    ctx: &RunContext,
) -> anyhow::Result<Vec<Run>> {
    let mut runs = Vec::new();
    // The measured cost of one apply_n (median of 7) turns the time budget into a cap.
    let mut budget = p.apply_n_budget;
    if p.time_budget_s > 0.0 && problem.n_rows() > 100_000 {
        let mut work = CcpWork::for_problem(problem);
        let g = vec![0.01; problem.n_rows()];
        let mut o = vec![0.0; problem.n_rows()];
        let mut t: Vec<f64> = (0..7)
            .map(|_| {
                let t0 = std::time::Instant::now();
                problem.apply_n(&g, &mut o, &mut work);
                t0.elapsed().as_secs_f64()
            })
            .collect();
        t.sort_by(f64::total_cmp);
        let by_time = (p.time_budget_s / (2.0 * t[3])) as usize;
        budget = budget.min(by_time.max(10));
    }
    out.metric(format!("{name}.apply_n_budget"), budget as f64);
    for label in &p.solvers {
        let settings = SolverSettings {
            tolerance: p.tolerance,
            max_iterations: (budget / cost_per_iteration(label)).max(1),
            record_history: true,
        };
        let mut solver =
            by_name(label, settings).map_err(|e| anyhow::anyhow!("parameter `solvers`: {e}"))?;
        let mut run = Run::solve(solver.as_mut(), problem);
        run.solver = label.clone();
        for (level, tag) in LEVELS {
            let (it, an, t) = run.reached(level);
            if it.is_finite() {
                out.metric(format!("{name}.{label}_iters_{tag}"), it);
                out.metric(format!("{name}.{label}_apply_n_{tag}"), an);
                out.metric(format!("{name}.{label}_time_{tag}"), t);
            }
        }
        out.metric(format!("{name}.{label}_final_residual"), run.stats.residual);
        out.metric(
            format!("{name}.{label}_apply_n_total"),
            run.stats.apply_n as f64,
        );
        out.metric(format!("{name}.{label}_wall"), run.wall_s);
        ctx.note(format!(
            "  {name:>12} {label:>10}: {:>6} it, {:>6} apply_n, {:.3e} m/s, {:.3} s",
            run.stats.iterations, run.stats.apply_n, run.stats.residual, run.wall_s
        ));
        runs.push(run);
    }
    // Objective agreement among the solvers that got close.
    let close: Vec<f64> = runs
        .iter()
        .filter(|r| r.stats.residual <= 1e-7)
        .map(|r| r.stats.objective)
        .collect();
    if close.len() >= 2 {
        let (lo, hi) = close
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &f| {
                (a.min(f), b.max(f))
            });
        let spread = (hi - lo) / hi.abs().max(lo.abs()).max(1e-300);
        out.check(Check::below(
            format!("{name}.objective_spread"),
            spread,
            1e-6,
        ));
    }
    std::fs::write(
        ctx.out_file(format!("history_{name}.csv")),
        history_csv(&runs),
    )?;
    let mut fig = CaseOutput::new();
    fig.series = residual_series(&runs);
    fig.plot = PlotSpec::new(
        &format!("{name}: residual against wall time"),
        "log10 wall time [s]",
        "log10 residual [m/s]",
        &[],
    );
    let _ = crate::plot::plot_series(&ctx.out_file(format!("residual_{name}.png")), name, &fig);
    Ok(runs)
}

/// Save `problem`, reload it, solve both with APGD: the number of differing bits of gamma.
fn roundtrip(name: &str, problem: &CcpProblem, ctx: &RunContext) -> anyhow::Result<f64> {
    let path = ctx.out_file(format!("{name}.ccp"));
    ProblemFile::from_problem(problem, format!("ccp-solvers capture: {name}"))
        .save(&path, ProblemFormat::Binary)?;
    let reloaded = ProblemFile::load_problem(&path)?;
    let solve = |p: &CcpProblem| {
        let s = SolverSettings {
            tolerance: 1e-8,
            max_iterations: 300,
            record_history: false,
        };
        let mut g = vec![0.0; p.n_rows()];
        chrono_ccp::Apgd::new(s).solve(p, &mut g);
        bits(&g)
    };
    let (a, b) = (solve(problem), solve(&reloaded));
    Ok(a.iter().zip(&b).filter(|(x, y)| x != y).count() as f64 + a.len().abs_diff(b.len()) as f64)
}

fn run(p: &SolversParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(
        p.tolerance.is_finite() && p.tolerance > 0.0,
        "parameter `tolerance` must be > 0, got {}",
        p.tolerance
    );
    anyhow::ensure!(
        p.apply_n_budget >= 1,
        "parameter `apply_n_budget` must be >= 1"
    );
    let mut out = CaseOutput::new();
    let mut problems: Vec<(String, CcpProblem, usize)> = Vec::new();
    for &n in &p.n_contacts {
        let t0 = std::time::Instant::now();
        let (problem, _, spheres) = granular_pile(n, p.settle_steps, p.h)?;
        let contacts = problem.sections().friction.len() / 3;
        let name = format!("pile_{n}");
        ctx.note(format!(
            "  captured {name}: {spheres} spheres, {contacts} contacts, {} rows ({:.1} s)",
            problem.n_rows(),
            t0.elapsed().as_secs_f64()
        ));
        problems.push((name, problem, contacts));
    }
    if p.stack {
        let (problem, _) = heavy_stack(5)?;
        let contacts = problem.sections().friction.len() / 3;
        problems.push(("stack_heavy".into(), problem, contacts));
    }
    for f in &p.problem_files {
        let problem = ProblemFile::load_problem(f)
            .map_err(|e| anyhow::anyhow!("parameter `problem_files`: {e}"))?;
        let stem = std::path::Path::new(f)
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("file")
            .to_string();
        let contacts = problem.sections().friction.len() / 3;
        problems.push((format!("file_{stem}"), problem, contacts));
    }
    let total = problems.len() + usize::from(p.bilateral_rows > 0);
    let mut all_runs = Vec::new();
    for (k, (name, problem, contacts)) in problems.iter().enumerate() {
        out.metric(format!("{name}.contacts"), *contacts as f64);
        out.metric(format!("{name}.rows"), problem.n_rows() as f64);
        let runs = compare(p, name, problem, &mut out, ctx)?;
        if name.starts_with("pile_") || name == "stack_heavy" {
            let diff = roundtrip(name, problem, ctx)?;
            out.check(Check::below(
                format!("{name}.file_roundtrip_bits_differ"),
                diff,
                0.0,
            ));
        }
        all_runs.push((name.clone(), *contacts, runs));
        ctx.progress_steps(k as u64 + 1, total as u64);
    }

    // APGD against projected Jacobi on the pile nearest 10k contacts.
    let pile = all_runs
        .iter()
        .filter(|(n, c, _)| n.starts_with("pile_") && *c >= 5000)
        .min_by_key(|(_, c, _)| c.abs_diff(10_000));
    if let Some((name, _, runs)) = pile {
        let find = |s: &str| runs.iter().find(|r| r.solver == s);
        if let (Some(a), Some(j)) = (find("apgd"), find("jacobi")) {
            let (_, a_n, _) = a.reached(1e-6);
            let (_, j_n, _) = j.reached(1e-6);
            let j_n = if j_n.is_finite() {
                j_n
            } else {
                j.stats.apply_n as f64
            };
            out.metric(
                format!("{name}.jacobi_reached_1e-6"),
                f64::from(u8::from(j.reached(1e-6).1.is_finite())),
            );
            out.check(Check::below(
                format!("{name}.apgd_over_jacobi_apply_n_1e-6"),
                a_n / j_n,
                0.2,
            ));
        }
    }

    // CG and MINRES on the bilateral net.
    if p.bilateral_rows > 0 {
        let net = bilateral_net(p.bilateral_rows)?;
        let name = format!("net_{}", p.bilateral_rows);
        out.metric(format!("{name}.rows"), net.n_rows() as f64);
        let mut net_runs = Vec::new();
        for label in ["cg", "minres"] {
            let settings = SolverSettings {
                tolerance: 0.0,
                max_iterations: 20_000,
                record_history: true,
            };
            let opts = KrylovOptions {
                relative_tolerance: 1e-8,
                preconditioned: true,
            };
            let mut solver: Box<dyn CcpSolver> = match label {
                "cg" => Box::new(chrono_ccp::Cg::new(settings).with_options(opts)),
                _ => Box::new(chrono_ccp::Minres::new(settings).with_options(opts)),
            };
            let run = Run::solve(solver.as_mut(), &net);
            let mut grad = vec![0.0; net.n_rows()];
            let mut work = CcpWork::for_problem(&net);
            net.gradient(&run.gamma, &mut grad, &mut work);
            let rel = relative_residual(&net, &grad, &mut work);
            out.metric(format!("{name}.{label}_iters"), run.stats.iterations as f64);
            out.metric(format!("{name}.{label}_wall"), run.wall_s);
            out.check(Check::below(
                format!("{name}.{label}_rel_residual"),
                rel,
                1e-8,
            ));
            ctx.note(format!(
                "  {name:>12} {label:>10}: {:>6} it, rel. residual {rel:.2e}, {:.3} s",
                run.stats.iterations, run.wall_s
            ));
            net_runs.push(run);
        }
        std::fs::write(
            ctx.out_file(format!("history_{name}.csv")),
            history_csv(&net_runs),
        )?;
        ctx.progress(1.0);
    }

    // The figure of the case: the pile nearest 10k contacts, else the first problem.
    let main = all_runs
        .iter()
        .filter(|(n, _, _)| n.starts_with("pile_"))
        .min_by_key(|(_, c, _)| c.abs_diff(10_000))
        .or(all_runs.first());
    if let Some((name, _, runs)) = main {
        out.series = residual_series(runs);
        out.plot = PlotSpec::new(
            &format!("{name}: residual against wall time (all solvers)"),
            "log10 wall time [s]",
            "log10 residual [m/s]",
            &[],
        );
    }
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<SolversParams>::boxed(
        "ccp-solvers",
        "ccp",
        "Every CCP solver on problems captured from a settled granular pile (1k/10k/100k contacts) and the 5-box heavy stack, to 1e-8 m/s; CG/MINRES on a 100k-row bilateral net; problem files round-trip bit for bit.",
        run,
    )
}
