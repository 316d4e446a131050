//! A solver wrapper that saves chosen solves of a scene, problem and warm start, so that a
//! solver study can replay one step of a long simulation by itself
//! (`examples/replay_step.rs`).
//!
//! The warm start matters: a step of a running simulation starts from the previous step's
//! impulses, and a solver's cost and answer at a loose tolerance depend on it (a cold
//! replay measures another problem). Each captured solve `n` (counted from 0 over the
//! wrapper's life) writes `PREFIX_n.ccpb` ([`ProblemFile`], binary) and `PREFIX_n.warm` (the
//! warm start, `n_rows` little-endian `f64`), read back by [`load_capture`].

use std::path::{Path, PathBuf};

use chrono_core::descriptor::{CcpProblem, CcpSolver, ProblemFile, SolveStats, SolverSettings};

/// A [`CcpSolver`] that is its inner solver and saves the solves listed (see the module
/// documentation).
pub struct Capture {
    inner: Box<dyn CcpSolver>,
    at: Vec<usize>,
    prefix: PathBuf,
    solves: usize,
    failed: bool,
}

impl Capture {
    /// Wrap `inner`; save the solves whose 0-based index is in `at` to `PREFIX_n.*`.
    ///
    /// # Errors
    /// If the directory of `prefix` does not exist or cannot be written (checked now with a
    /// probe file, so that a long run does not find out at its captured step).
    pub fn new(
        inner: Box<dyn CcpSolver>,
        at: &[usize],
        prefix: impl AsRef<Path>,
    ) -> std::io::Result<Self> {
        let prefix = prefix.as_ref().to_path_buf();
        let probe = appended(&prefix, "_probe");
        std::fs::write(&probe, b"")?;
        std::fs::remove_file(&probe)?;
        let mut at = at.to_vec();
        at.sort_unstable();
        at.dedup();
        Ok(Self {
            inner,
            at,
            prefix,
            solves: 0,
            failed: false,
        })
    }

    /// Solves seen so far.
    pub fn solves(&self) -> usize {
        self.solves
    }

    fn save(&self, n: usize, problem: &CcpProblem, gamma: &[f64]) -> chrono_core::Result<()> {
        let base = appended(&self.prefix, &format!("_{n}"));
        ProblemFile::save_problem(
            problem,
            &format!("capture: solve {n} of {}", self.inner.name()),
            appended(&base, ".ccpb"),
        )?;
        let bytes: Vec<u8> = gamma.iter().flat_map(|x| x.to_le_bytes()).collect();
        let warm = appended(&base, ".warm");
        std::fs::write(&warm, bytes).map_err(|e| chrono_core::ChronoError::InvalidParameter {
            field: "capture warm start".into(),
            value: warm.display().to_string(),
            reason: e.to_string(),
        })
    }
}

/// `base` with `tail` appended to its file name (not `with_extension`, which would cut a
/// prefix that contains a dot).
fn appended(base: &Path, tail: &str) -> PathBuf {
    let mut name = base.file_name().unwrap_or_default().to_os_string();
    name.push(tail);
    base.with_file_name(name)
}

/// Load a captured solve: `base` is `PREFIX_n` (without extension).
///
/// # Errors
/// A missing or unreadable file, a problem file that does not load, or a warm start whose
/// length is not the problem's row count (naming the file).
pub fn load_capture(base: impl AsRef<Path>) -> chrono_core::Result<(CcpProblem, Vec<f64>)> {
    let base = base.as_ref();
    let problem = ProblemFile::load_problem(appended(base, ".ccpb"))?;
    let warm_path = appended(base, ".warm");
    let bad = |reason: String| chrono_core::ChronoError::InvalidParameter {
        field: "capture warm start".into(),
        value: warm_path.display().to_string(),
        reason,
    };
    let bytes = std::fs::read(&warm_path).map_err(|e| bad(e.to_string()))?;
    if bytes.len() != 8 * problem.n_rows() {
        return Err(bad(format!(
            "{} bytes, the problem has {} rows (8 bytes each)",
            bytes.len(),
            problem.n_rows()
        )));
    }
    let warm = bytes
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("chunks of 8")))
        .collect();
    Ok((problem, warm))
}

impl CcpSolver for Capture {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn settings(&self) -> &SolverSettings {
        self.inner.settings()
    }

    fn settings_mut(&mut self) -> &mut SolverSettings {
        self.inner.settings_mut()
    }

    fn solve(&mut self, problem: &CcpProblem, gamma: &mut [f64]) -> SolveStats {
        let n = self.solves;
        self.solves += 1;
        if !self.failed
            && self.at.binary_search(&n).is_ok()
            && let Err(e) = self.save(n, problem, gamma)
        {
            // The solve itself goes on; the study is told once and capturing stops.
            eprintln!("capture of solve {n} failed, capturing stopped: {e}");
            self.failed = true;
        }
        self.inner.solve(problem, gamma)
    }
}
