//! Running cases: selection by name, mode and `--set` overrides, timed runs with a
//! progress bar, failure capture (errors and panics), per-case artifacts, and the
//! `validate` command.

use std::io::IsTerminal;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use anyhow::{Context, bail};
use indicatif::{MultiProgress, ProgressBar, ProgressStyle};
use serde_json::Value;

use crate::case::{Case, CaseOutput, Check, Mode, PROGRESS_STEPS, RunContext};
use crate::eta::{self, Eta, Timings};
use crate::params::{Override, apply_overrides};
use crate::{budget, plot, report};

/// The outcome of one case.
#[derive(Clone, Debug)]
pub struct CaseResult {
    /// Case name.
    pub name: String,
    /// Case area.
    pub area: String,
    /// Case description.
    pub description: String,
    /// The mode of the run.
    pub mode: Mode,
    /// The parameters the case ran with (after mode and overrides).
    pub params: Value,
    /// What the run returned; `None` when it failed.
    pub output: Option<CaseOutput>,
    /// The error (or panic) text when the run failed.
    pub error: Option<String>,
    /// Wall time of `run`, in seconds.
    pub wall_s: f64,
    /// `DIR/<case>/series.csv` when written.
    pub series_csv: Option<PathBuf>,
    /// Plot files written.
    pub plots: Vec<PathBuf>,
    /// Problems that do not fail the case (a plot that could not be drawn ...).
    pub warnings: Vec<String>,
}

impl CaseResult {
    /// The checks (none when the run failed).
    pub fn checks(&self) -> &[Check] {
        self.output.as_ref().map_or(&[], |o| &o.checks)
    }

    /// Steps taken (0 when the run failed).
    pub fn steps(&self) -> u64 {
        self.output.as_ref().map_or(0, |o| o.steps)
    }

    /// Steps per second of wall time, when there were steps.
    pub fn steps_per_s(&self) -> Option<f64> {
        let steps = self.steps();
        (steps > 0 && self.wall_s > 0.0).then(|| steps as f64 / self.wall_s)
    }

    /// The run succeeded and every check passed.
    pub fn passed(&self) -> bool {
        self.error.is_none() && self.checks().iter().all(|c| c.pass)
    }
}

/// How to run a set of cases.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// The mode, applied before overrides.
    pub mode: Mode,
    /// `--set KEY=VALUE` overrides.
    pub overrides: Vec<Override>,
    /// Output directory (`DIR`); each case writes into `DIR/<case>/`.
    pub out_dir: PathBuf,
    /// Write VTK frames (`--vtk`).
    pub vtk: bool,
    /// Show progress bars (when attached to a terminal).
    pub progress: bool,
    /// Cases run at once (`--jobs`, at least 1). With more than one, each case runs on a
    /// rayon pool of its own with `threads / jobs` threads (at least one), the longest
    /// expected first; the results and the report keep the cases' order.
    pub jobs: usize,
}

/// The workspace root: the parent of this crate's manifest directory, or the current
/// directory when the binary runs elsewhere.
pub fn workspace_root() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf);
    match root {
        Some(r) if r.join("Cargo.toml").is_file() => r,
        _ => std::env::current_dir().unwrap_or_else(|_| PathBuf::from(".")),
    }
}

/// Whether progress bars should be drawn: stdout and stderr are terminals.
pub fn interactive() -> bool {
    std::io::stdout().is_terminal() && std::io::stderr().is_terminal()
}

/// The cases named in `names` (case names or area names), in the order given; all cases
/// when `names` is empty. `what` names the kind (`"case"`, `"bench"`) in errors.
pub fn select(
    all: Vec<Box<dyn Case>>,
    names: &[String],
    what: &str,
) -> anyhow::Result<Vec<Box<dyn Case>>> {
    if names.is_empty() {
        return Ok(all);
    }
    let mut order = Vec::new();
    for n in names {
        let matches: Vec<usize> = (0..all.len())
            .filter(|&i| all[i].name() == n || all[i].area() == n)
            .collect();
        if matches.is_empty() {
            if n == "granular-vs-rapier" {
                bail!(
                    "`granular-vs-rapier` needs the `rapier` feature: `cargo xtask-rapier bench granular-vs-rapier`"
                );
            }
            if all.is_empty() {
                bail!("unknown {what} `{n}`: none is registered");
            }
            let list: Vec<&str> = all.iter().map(|c| c.name()).collect();
            let mut areas: Vec<&str> = all.iter().map(|c| c.area()).collect();
            areas.dedup();
            bail!(
                "unknown {what} `{n}`; available: {} (or an area: {})",
                list.join(", "),
                areas.join(", ")
            );
        }
        order.extend(
            matches
                .into_iter()
                .filter(|i| !order.contains(i))
                .collect::<Vec<_>>(),
        );
    }
    let mut slots: Vec<Option<Box<dyn Case>>> = all.into_iter().map(Some).collect();
    Ok(order.into_iter().filter_map(|i| slots[i].take()).collect())
}

/// Applies the mode, then the overrides, to every case.
pub fn prepare(
    cases: &mut [Box<dyn Case>],
    mode: Mode,
    overrides: &[Override],
) -> anyhow::Result<()> {
    for case in cases.iter_mut() {
        case.apply_mode(mode);
    }
    apply_overrides(cases, overrides)
}

fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    let msg = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(non-string payload)".into());
    format!("panicked: {msg}")
}

fn progress_bar(prefix: String) -> ProgressBar {
    let bar = ProgressBar::new(PROGRESS_STEPS);
    let style = ProgressStyle::with_template(
        "{prefix:.bold} [{bar:30.cyan/blue}] {percent:>3}% {elapsed} (eta {eta})",
    )
    .expect("valid progress template")
    .progress_chars("=> ");
    bar.set_style(style);
    bar.set_prefix(prefix);
    bar.enable_steady_tick(Duration::from_millis(250));
    bar
}

/// Runs one case into `DIR/<case>/` and writes its artifacts (`series.csv`, plots).
/// A failing run is recorded in the result; only I/O errors on the output directory
/// are returned as errors.
pub fn run_case(case: &dyn Case, label: &str, opts: &RunOptions) -> anyhow::Result<CaseResult> {
    let bar = opts.progress.then(|| progress_bar(label.to_string()));
    run_case_with_bar(case, opts, bar)
}

/// [`run_case`] with the progress bar given (or none).
fn run_case_with_bar(
    case: &dyn Case,
    opts: &RunOptions,
    bar: Option<ProgressBar>,
) -> anyhow::Result<CaseResult> {
    let dir = opts.out_dir.join(case.name());
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    for stale in ["series.csv", "plot.png", "speed_vs_error.png"] {
        let _ = std::fs::remove_file(dir.join(stale));
    }
    let mut ctx = RunContext::new(opts.mode, &dir, opts.vtk);
    if let Some(vtk) = ctx.vtk_dir() {
        std::fs::create_dir_all(&vtk).with_context(|| format!("creating {}", vtk.display()))?;
    }
    if let Some(bar) = &bar {
        ctx = ctx.with_progress_bar(bar.clone());
    }
    let start = Instant::now();
    let outcome = catch_unwind(AssertUnwindSafe(|| case.run(&ctx)));
    let wall_s = start.elapsed().as_secs_f64();
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    let (output, error) = match outcome {
        Ok(Ok(out)) => (Some(out), None),
        Ok(Err(e)) => (None, Some(format!("{e:#}"))),
        Err(payload) => (None, Some(panic_text(payload.as_ref()))),
    };
    let mut result = CaseResult {
        name: case.name().into(),
        area: case.area().into(),
        description: case.description().into(),
        mode: opts.mode,
        params: case.params_json(),
        output,
        error,
        wall_s,
        series_csv: None,
        plots: Vec::new(),
        warnings: Vec::new(),
    };
    if let Some(out) = &result.output {
        let csv = dir.join("series.csv");
        report::write_csv(&csv, &out.series)?;
        result.series_csv = Some(csv);
        let png = dir.join("plot.png");
        match plot::plot_series(&png, case.name(), out) {
            Ok(true) => result.plots.push(png),
            Ok(false) => {}
            Err(e) => result.warnings.push(format!("plot.png: {e:#}")),
        }
        let png = dir.join("speed_vs_error.png");
        match plot::plot_sweep(&png, case.name(), &out.sweep) {
            Ok(true) => result.plots.push(png),
            Ok(false) if out.sweep.is_empty() => {}
            Ok(false) => result
                .warnings
                .push("speed_vs_error.png: no positive finite point".into()),
            Err(e) => result.warnings.push(format!("speed_vs_error.png: {e:#}")),
        }
        for (k, v) in &out.metrics {
            if !v.is_finite() {
                result
                    .warnings
                    .push(format!("metric `{k}` is not finite ({v})"));
            }
        }
    }
    Ok(result)
}

/// One line for a finished case, e.g. `[1/3] rigid-incline  PASS  0.53 s  1.9e5 steps/s`.
fn finished_line(label: &str, r: &CaseResult) -> String {
    let mut line = format!(
        "{label}  {}  {} s",
        if r.passed() { "PASS" } else { "FAIL" },
        report::fmt_sig(r.wall_s, 3)
    );
    if let Some(rate) = r.steps_per_s() {
        line += &format!("  {} steps/s", report::fmt_sig(rate, 3));
    }
    let failed = r.checks().iter().filter(|c| !c.pass).count();
    if failed > 0 {
        line += &format!("  ({failed} of {} checks failed)", r.checks().len());
    }
    if let Some(e) = &r.error {
        line += &format!("  error: {}", e.lines().next().unwrap_or(""));
    }
    line
}

/// The expected wall time of each case: the last run's in this mode, else its budget.
fn expectations(cases: &[Box<dyn Case>], mode: Mode, timings: &Timings) -> Vec<Option<f64>> {
    cases
        .iter()
        .map(|c| {
            timings
                .get(mode, c.name())
                .or_else(|| budget::budget_s(c.name(), mode))
        })
        .collect()
}

/// The overall line: cases done, time elapsed and the estimate of the time left.
fn overall_message(done: usize, total: usize, elapsed: f64, left: f64) -> String {
    format!(
        "{done}/{total} cases · {} elapsed · about {} left",
        eta::fmt_duration(elapsed),
        eta::fmt_duration(left)
    )
}

/// Runs the cases one after another, printing one line per finished case with the time
/// elapsed and an estimate of the time left ([`Eta`]); in a terminal an overall bar
/// above the case's own bar keeps that estimate current. The wall times are recorded in
/// `DIR/timings.json` for the next run's estimate.
pub fn run_all(cases: &mut [Box<dyn Case>], opts: &RunOptions) -> anyhow::Result<Vec<CaseResult>> {
    if opts.jobs > 1 && cases.len() > 1 {
        return run_jobs(cases, opts);
    }
    let width = cases.iter().map(|c| c.name().len()).max().unwrap_or(0);
    let mut timings = Timings::load(&opts.out_dir);
    let eta = Mutex::new(Eta::new(expectations(cases, opts.mode, &timings)));
    let total = cases.len();
    let run_start = Instant::now();
    let multi = opts.progress.then(MultiProgress::new);
    let overall = multi.as_ref().map(|m| {
        let bar = m.add(ProgressBar::new(total as u64));
        bar.set_style(
            ProgressStyle::with_template("{prefix:.bold} [{bar:30.green/white}] {msg}")
                .expect("valid progress template")
                .progress_chars("=> "),
        );
        bar.set_prefix("overall");
        bar
    });
    // What the ticker reads: the running case's index, start and bar.
    let current: Mutex<Option<(usize, Instant, ProgressBar)>> = Mutex::new(None);
    let stop = AtomicBool::new(false);
    let mut results = Vec::with_capacity(total);
    std::thread::scope(|scope| -> anyhow::Result<()> {
        if let Some(overall) = &overall {
            scope.spawn(|| {
                while !stop.load(Ordering::Relaxed) {
                    if let Some((i, start, bar)) = current.lock().ok().and_then(|c| c.clone()) {
                        let fraction = bar.position() as f64 / PROGRESS_STEPS as f64;
                        let elapsed = start.elapsed().as_secs_f64();
                        let left = eta
                            .lock()
                            .map_or(f64::NAN, |e| e.remaining(i, elapsed, fraction));
                        overall.set_message(overall_message(
                            i,
                            total,
                            run_start.elapsed().as_secs_f64(),
                            left,
                        ));
                    }
                    std::thread::sleep(Duration::from_millis(250));
                }
            });
        }
        let result = (|| {
            for (i, case) in cases.iter_mut().enumerate() {
                let label = format!("[{}/{}] {:<width$}", i + 1, total, case.name());
                let bar = multi.as_ref().map(|m| m.add(progress_bar(label.clone())));
                if let (Ok(mut c), Some(bar)) = (current.lock(), &bar) {
                    *c = Some((i, Instant::now(), bar.clone()));
                }
                // On a pool thread: the case's parallel loops then start from the pool
                // (chrono_core::parallel::on_worker says why).
                let r = {
                    let c: &mut Box<dyn Case> = &mut *case;
                    chrono_core::parallel::on_worker(move || {
                        run_case_with_bar(c.as_ref(), opts, bar)
                    })?
                };
                let left = {
                    let mut e = eta
                        .lock()
                        .map_err(|_| anyhow::anyhow!("estimate poisoned"))?;
                    e.finish(i, r.wall_s);
                    if i + 1 < total {
                        e.remaining(i + 1, 0.0, 0.0)
                    } else {
                        0.0
                    }
                };
                timings.set(opts.mode, case.name(), r.wall_s);
                let elapsed = run_start.elapsed().as_secs_f64();
                let line = format!(
                    "{}  · {}",
                    finished_line(&label, &r),
                    overall_message(i + 1, total, elapsed, left)
                );
                match &overall {
                    Some(o) => {
                        o.inc(1);
                        o.println(line);
                    }
                    None => println!("{line}"),
                }
                results.push(r);
            }
            Ok(())
        })();
        stop.store(true, Ordering::Relaxed);
        result
    })?;
    if let Some(o) = overall {
        o.finish_and_clear();
    }
    // The estimate of the next run; a failure to write it does not fail this one.
    if let Err(e) = timings.save(&opts.out_dir) {
        eprintln!("warning: could not write {}: {e:#}", Timings::FILE);
    }
    Ok(results)
}

/// [`run_all`] with `opts.jobs` cases at once. Why: most cases use fewer than the
/// machine's cores for part of their run (the serial parts of a step, small problems;
/// 1.0-1.8 of 2 cores measured on the largest `--quick` cases, docs/performance.md "CI
/// run time"), so two cases side by side on one thread each finish sooner than one after
/// the other on two. A case's results are bit-reproducible for its thread count, so a run
/// with `--jobs` gives the figures of a one-thread run when `threads / jobs` is 1. No
/// per-case progress bars; one line per finished case as in the serial run.
fn run_jobs(cases: &mut [Box<dyn Case>], opts: &RunOptions) -> anyhow::Result<Vec<CaseResult>> {
    use std::sync::atomic::AtomicUsize;
    let total = cases.len();
    let width = cases.iter().map(|c| c.name().len()).max().unwrap_or(0);
    let mut timings = Timings::load(&opts.out_dir);
    let expected: Vec<f64> = expectations(cases, opts.mode, &timings)
        .into_iter()
        .map(|e| e.unwrap_or(10.0))
        .collect();
    // Longest first: the last case to start is a short one, so the tail is short.
    let mut order: Vec<usize> = (0..total).collect();
    order.sort_by(|&a, &b| expected[b].total_cmp(&expected[a]).then(a.cmp(&b)));
    let jobs = opts.jobs.min(total);
    let threads = (rayon::current_num_threads() / jobs).max(1);
    // Each case is taken out once by the job that runs it (`&mut Box<dyn Case>` is `Send`).
    let slots: Vec<Mutex<Option<&mut Box<dyn Case>>>> =
        cases.iter_mut().map(|c| Mutex::new(Some(c))).collect();
    let results: Mutex<Vec<Option<CaseResult>>> = Mutex::new(vec![None; total]);
    // (cases finished, expected seconds of the cases not yet finished)
    let progress = Mutex::new((0usize, expected.iter().sum::<f64>()));
    let next = AtomicUsize::new(0);
    let run_start = Instant::now();
    let worker = || -> anyhow::Result<()> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .context("building a case's thread pool")?;
        loop {
            let k = next.fetch_add(1, Ordering::Relaxed);
            let Some(&i) = order.get(k) else {
                return Ok(());
            };
            let case = slots[i]
                .lock()
                .map_err(|_| anyhow::anyhow!("case slot poisoned"))?
                .take()
                .ok_or_else(|| anyhow::anyhow!("case {i} taken twice"))?;
            let r = pool.install(move || run_case_with_bar(case.as_ref(), opts, None))?;
            let label = format!("[{}/{}] {:<width$}", i + 1, total, r.name);
            let line = {
                let mut p = progress
                    .lock()
                    .map_err(|_| anyhow::anyhow!("progress poisoned"))?;
                p.0 += 1;
                p.1 -= expected[i];
                let left = p.1.max(0.0) / jobs as f64;
                format!(
                    "{}  · {}",
                    finished_line(&label, &r),
                    overall_message(p.0, total, run_start.elapsed().as_secs_f64(), left)
                )
            };
            println!("{line}");
            results
                .lock()
                .map_err(|_| anyhow::anyhow!("results poisoned"))?[i] = Some(r);
        }
    };
    std::thread::scope(|scope| -> anyhow::Result<()> {
        let handles: Vec<_> = (0..jobs).map(|_| scope.spawn(worker)).collect();
        for h in handles {
            h.join()
                .map_err(|p| anyhow::anyhow!("a job {}", panic_text(p.as_ref())))??;
        }
        Ok(())
    })?;
    let results: Vec<CaseResult> = results
        .into_inner()
        .map_err(|_| anyhow::anyhow!("results poisoned"))?
        .into_iter()
        .flatten()
        .collect();
    anyhow::ensure!(results.len() == total, "a case did not run");
    for r in &results {
        timings.set(opts.mode, &r.name, r.wall_s);
    }
    if let Err(e) = timings.save(&opts.out_dir) {
        eprintln!("warning: could not write {}: {e:#}", Timings::FILE);
    }
    Ok(results)
}

/// `cargo xtask validate`: selects, prepares and runs `all` (filtered by `names`),
/// writes `report.md`, `summary.json` (and `json` if given) into `opts.out_dir`, prints
/// the table. Returns whether every case passed.
pub fn validate(
    all: Vec<Box<dyn Case>>,
    names: &[String],
    opts: &RunOptions,
    json: Option<&Path>,
) -> anyhow::Result<bool> {
    let mut cases = select(all, names, "case")?;
    if cases.is_empty() {
        println!("no validation cases are registered (see xtask/src/cases/mod.rs); nothing to do");
        return Ok(true);
    }
    prepare(&mut cases, opts.mode, &opts.overrides)?;
    std::fs::create_dir_all(&opts.out_dir)
        .with_context(|| format!("creating {}", opts.out_dir.display()))?;
    let results = run_all(&mut cases, opts)?;
    let md = report::write_report_md(&opts.out_dir, "chrono-rs validation report", &results)?;
    report::write_summary(&opts.out_dir.join("summary.json"), &results)?;
    if let Some(json) = json {
        report::write_summary(json, &results)?;
    }
    println!();
    report::print_table(&results);
    report::print_sweeps(&results);
    println!();
    print!(
        "{}",
        report::text_table(report::AREA_HEADER, &report::area_rows(&results))
    );
    let failed: Vec<&str> = results
        .iter()
        .filter(|r| !r.passed())
        .map(|r| r.name.as_str())
        .collect();
    for r in results.iter().filter(|r| !r.warnings.is_empty()) {
        for w in &r.warnings {
            eprintln!("warning: {}: {w}", r.name);
        }
    }
    println!(
        "\n{} of {} cases passed; report: {}",
        results.len() - failed.len(),
        results.len(),
        md.display()
    );
    if !failed.is_empty() {
        println!("failed: {}", failed.join(", "));
    }
    Ok(failed.is_empty())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cases::testing;

    #[test]
    fn select_by_name_and_area() {
        let all = || vec![testing::decay_case(), testing::failing_case()];
        let names = |v: &[Box<dyn Case>]| v.iter().map(|c| c.name()).collect::<Vec<_>>();
        assert_eq!(
            names(&select(all(), &[], "case").unwrap()),
            ["test-decay", "test-fail"]
        );
        let pick = ["test-fail".to_string(), "test".to_string()];
        assert_eq!(
            names(&select(all(), &pick, "case").unwrap()),
            ["test-fail", "test-decay"]
        );
        let e = select(all(), &["nope".into()], "case")
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("unknown case `nope`") && e.contains("test-decay, test-fail"),
            "{e}"
        );
        let e = select(Vec::new(), &["x".into()], "bench")
            .err()
            .unwrap()
            .to_string();
        assert_eq!(e, "unknown bench `x`: none is registered");
    }
}
