//! The [`Case`] abstraction: one validation case (or bench) with parameters, a run and
//! its context.
//!
//! Most cases do not implement [`Case`] by hand: they write a parameter struct that
//! implements [`CaseParams`](crate::params::CaseParams) and wrap it with
//! [`ParamCase`](crate::params::ParamCase), which provides the parameter plumbing.
//! What a run returns is described in [`crate::output`].

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use indicatif::ProgressBar;
use serde::Serialize;

use crate::params::ParamInfo;

pub use crate::output::{CaseOutput, Check, CheckKind, PlotSpec, Series, SweepPoint};

/// How thorough a run is: `--quick` (smoke test, seconds), default, or `--full`
/// (the complete published setup, may take long).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// A short smoke run (`--quick`): coarse resolution, short horizon.
    Quick,
    /// The default run.
    #[default]
    Default,
    /// The complete published setup (`--full`).
    Full,
}

impl Mode {
    /// The mode selected by the `--quick` / `--full` flags (default when neither is set).
    pub fn from_flags(quick: bool, full: bool) -> Self {
        match (quick, full) {
            (true, _) => Mode::Quick,
            (false, true) => Mode::Full,
            (false, false) => Mode::Default,
        }
    }

    /// The lowercase name used in reports (`quick`, `default`, `full`).
    pub fn as_str(self) -> &'static str {
        match self {
            Mode::Quick => "quick",
            Mode::Default => "default",
            Mode::Full => "full",
        }
    }
}

impl fmt::Display for Mode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One validation case or bench.
///
/// The runner calls, in order: [`apply_mode`](Case::apply_mode), then
/// [`set_params_json`](Case::set_params_json) for `--set` overrides, then
/// [`run`](Case::run) (timed by the runner).
pub trait Case: Send {
    /// Unique kebab-case name, e.g. `"rigid-incline"`.
    fn name(&self) -> &'static str;
    /// The area the case belongs to: `"rigid"`, `"granular"`, `"sph"`, ...
    fn area(&self) -> &'static str;
    /// One or two sentences: the setup and the reference it is compared against.
    fn description(&self) -> &'static str;
    /// Name, unit and meaning of each parameter.
    fn param_info(&self) -> Vec<ParamInfo>;
    /// The current parameter values, as a JSON object.
    fn params_json(&self) -> serde_json::Value;
    /// Replaces all parameter values with `v` (a JSON object of the same shape as
    /// [`params_json`](Case::params_json)).
    fn set_params_json(&mut self, v: serde_json::Value) -> anyhow::Result<()>;
    /// Adjusts the parameters to a [`Mode`]; called before `--set` overrides.
    fn apply_mode(&mut self, mode: Mode);
    /// Runs the case. An error makes the case fail; the run of other cases continues.
    fn run(&self, ctx: &RunContext) -> anyhow::Result<CaseOutput>;
}

/// What a running case may know and use: the mode, its output directory, whether to
/// write VTK frames, and a progress reporter.
///
/// `RunContext` is `Sync`, so [`progress`](RunContext::progress) may be called from
/// rayon workers too.
#[derive(Debug)]
pub struct RunContext {
    /// The mode of this run.
    pub mode: Mode,
    /// The output directory of this case (`DIR/<case>/`); it exists when `run` starts.
    pub out_dir: PathBuf,
    /// Whether to write VTK frames into [`vtk_dir`](RunContext::vtk_dir) (`--vtk`).
    pub vtk: bool,
    bar: Option<ProgressBar>,
    last_permille: AtomicU64,
}

/// Resolution of the progress bar (positions per run).
pub(crate) const PROGRESS_STEPS: u64 = 1000;

impl RunContext {
    /// A context without a progress bar (for tests or when running a case directly).
    pub fn new(mode: Mode, out_dir: impl Into<PathBuf>, vtk: bool) -> Self {
        Self {
            mode,
            out_dir: out_dir.into(),
            vtk,
            bar: None,
            last_permille: AtomicU64::new(u64::MAX),
        }
    }

    /// Attaches a progress bar of length [`PROGRESS_STEPS`].
    pub(crate) fn with_progress_bar(mut self, bar: ProgressBar) -> Self {
        self.bar = Some(bar);
        self
    }

    /// Reports progress as a fraction in `[0, 1]` (clamped). Cheap enough to call every
    /// step: the bar is only touched when the value changes by 0.1 %.
    #[inline]
    pub fn progress(&self, fraction: f64) {
        let Some(bar) = &self.bar else { return };
        // NaN maps to 0 through the saturating cast.
        let p = (fraction.clamp(0.0, 1.0) * PROGRESS_STEPS as f64) as u64;
        if self.last_permille.swap(p, Ordering::Relaxed) != p {
            bar.set_position(p);
        }
    }

    /// Reports progress as `done` of `total` steps (see [`progress`](RunContext::progress)).
    #[inline]
    pub fn progress_steps(&self, done: u64, total: u64) {
        if total > 0 {
            self.progress(done as f64 / total as f64);
        }
    }

    /// Prints an informational line without disturbing the progress bar.
    pub fn note(&self, msg: impl AsRef<str>) {
        match &self.bar {
            Some(bar) if !bar.is_hidden() => bar.println(msg.as_ref()),
            _ => eprintln!("{}", msg.as_ref()),
        }
    }

    /// The directory for VTK frames (`DIR/<case>/vtk/`), `None` unless `--vtk` was given.
    /// The runner creates it before `run` starts.
    pub fn vtk_dir(&self) -> Option<PathBuf> {
        self.vtk.then(|| self.out_dir.join("vtk"))
    }

    /// The path of a file in this case's output directory.
    pub fn out_file(&self, name: impl AsRef<Path>) -> PathBuf {
        self.out_dir.join(name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mode_from_flags() {
        assert_eq!(Mode::from_flags(false, false), Mode::Default);
        assert_eq!(Mode::from_flags(true, false), Mode::Quick);
        assert_eq!(Mode::from_flags(false, true), Mode::Full);
        assert_eq!(Mode::Quick.to_string(), "quick");
    }

    #[test]
    fn progress_without_bar_and_with_hidden_bar_is_harmless() {
        let ctx = RunContext::new(Mode::Quick, "/nonexistent", true);
        ctx.progress(0.5);
        ctx.progress_steps(3, 0);
        assert_eq!(ctx.vtk_dir(), Some(PathBuf::from("/nonexistent/vtk")));
        let bar = ProgressBar::hidden();
        bar.set_length(PROGRESS_STEPS);
        let ctx = RunContext::new(Mode::Quick, "/x", false).with_progress_bar(bar.clone());
        ctx.progress(0.25);
        ctx.progress(f64::NAN);
        ctx.progress_steps(3, 4);
        assert_eq!(bar.position(), 750);
        assert_eq!(ctx.vtk_dir(), None);
    }
}
