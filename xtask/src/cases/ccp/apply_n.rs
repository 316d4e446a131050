//! `ccp-apply-n`: throughput of `N g` (`CcpProblem::apply_n`, the unit of cost of every
//! iterative CCP solver) on a captured granular pile, in contacts/s and GB/s, against the
//! machine's memory bandwidth measured by a STREAM-like triad `a = b + s c` (McCalpin 1995)
//! with rayon over the same threads, timed alternately with the product (one of each per
//! repetition, medians of both).
//!
//! Metrics: `contacts`, `rows`, `nnz` (stored Jacobian coefficients), `apply_n_median_s`,
//! `contacts_per_s`, `bytes_per_apply_n` (the compulsory traffic,
//! `CcpProblem::apply_n_bytes`), `bytes_per_row`, `matrix_free_contacts` (triplets applied
//! from their contact frames, `CcpProblem::n_matrix_free`), `apply_n_gb_s`, `triad_gb_s`
//! (3 arrays counted, no write-allocate), `fraction_of_triad`, `threads`.

use chrono_core::descriptor::CcpWork;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::case::{Case, CaseOutput, Mode, RunContext};
use crate::params::{CaseParams, ParamCase, ParamInfo};
use chrono_ccp::testing::granular_pile;

/// Parameters of `ccp-apply-n`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ApplyNParams {
    /// Target contact count of the pile.
    pub n_contacts: usize,
    /// Settling steps before capture.
    pub settle_steps: usize,
    /// Timed repetitions (the median is reported).
    pub reps: usize,
    /// Elements per triad array (8 bytes each).
    pub triad_len: usize,
}

impl Default for ApplyNParams {
    fn default() -> Self {
        Self {
            n_contacts: 100_000,
            settle_steps: 5,
            reps: 50,
            triad_len: 1 << 23,
        }
    }
}

impl CaseParams for ApplyNParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("n_contacts", "-", "target contact count of the pile"),
        ParamInfo::new("settle_steps", "-", "settling steps before capture"),
        ParamInfo::new("reps", "-", "timed repetitions (median reported)"),
        ParamInfo::new("triad_len", "-", "elements per triad array"),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        if mode == Mode::Quick {
            self.n_contacts = 10_000;
            self.reps = 10;
            self.triad_len = 1 << 21;
        }
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The triad's arrays `a = b + s c` (`len` elements each).
pub struct Triad {
    a: Vec<f64>,
    b: Vec<f64>,
    c: Vec<f64>,
}

impl Triad {
    /// Arrays of `len` elements (written once, so their pages are mapped before timing).
    pub fn new(len: usize) -> Self {
        Self {
            a: vec![0.0; len],
            b: vec![1.0; len],
            c: vec![2.0; len],
        }
    }

    /// Seconds of one `a[i] = b[i] + s c[i]` over the arrays, in parallel.
    pub fn seconds(&mut self) -> f64 {
        let s = 3.0;
        let t0 = std::time::Instant::now();
        (self.a.par_chunks_mut(1 << 14))
            .zip(self.b.par_chunks(1 << 14))
            .zip(self.c.par_chunks(1 << 14))
            .for_each(|((a, b), c)| {
                for i in 0..a.len() {
                    a[i] = b[i] + s * c[i];
                }
            });
        let t = t0.elapsed().as_secs_f64();
        std::hint::black_box(&self.a);
        t
    }
}

fn run(p: &ApplyNParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(p.reps >= 1, "parameter `reps` must be >= 1");
    anyhow::ensure!(p.triad_len >= 1024, "parameter `triad_len` must be >= 1024");
    let (problem, gamma, _) = granular_pile(p.n_contacts, p.settle_steps, 0.002)?;
    ctx.progress(0.5);
    let m = problem.n_rows();
    let contacts = problem.sections().friction.len() / 3;
    let mut work = CcpWork::for_problem(&problem);
    let mut out_v = vec![0.0; m];
    problem.apply_n(&gamma, &mut out_v, &mut work); // warm-up
    // The product and the triad alternate, one of each per round, so both medians come
    // from the same minutes of a shared machine (its bandwidth drifts between runs).
    let mut triad = Triad::new(p.triad_len);
    triad.seconds(); // warm-up
    let (mut times, mut t_triads) = (Vec::with_capacity(p.reps), Vec::with_capacity(p.reps));
    for _ in 0..p.reps {
        let t0 = std::time::Instant::now();
        problem.apply_n(std::hint::black_box(&gamma), &mut out_v, &mut work);
        times.push(t0.elapsed().as_secs_f64());
        t_triads.push(triad.seconds());
    }
    let t = median(times);
    let bytes = problem.apply_n_bytes() as f64;
    let t_triad = median(t_triads);
    let triad_gb_s = 24.0 * p.triad_len as f64 / t_triad / 1e9;
    let gb_s = bytes / t / 1e9;
    let mut out = CaseOutput::new();
    out.metric("contacts", contacts as f64)
        .metric("rows", m as f64)
        .metric("nnz", problem.n_coefs() as f64)
        .metric("apply_n_median_s", t)
        .metric("contacts_per_s", contacts as f64 / t)
        .metric("bytes_per_apply_n", bytes)
        .metric("bytes_per_row", bytes / m.max(1) as f64)
        .metric("matrix_free_contacts", problem.n_matrix_free() as f64)
        .metric("apply_n_gb_s", gb_s)
        .metric("triad_gb_s", triad_gb_s)
        .metric("fraction_of_triad", gb_s / triad_gb_s)
        .metric("threads", rayon::current_num_threads() as f64);
    ctx.progress(1.0);
    Ok(out)
}

/// The bench.
pub fn case() -> Box<dyn Case> {
    ParamCase::<ApplyNParams>::boxed(
        "ccp-apply-n",
        "ccp",
        "Throughput of N g on a captured granular pile (contacts/s, GB/s) against a STREAM-like triad.",
        run,
    )
}
