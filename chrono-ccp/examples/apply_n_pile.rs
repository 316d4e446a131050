//! `N g` (`CcpProblem::apply_n`) on the captured granular pile of `ccp-apply-n`: the median
//! time of `reps` products, contacts/s, bytes per row and a fingerprint of the product's
//! bits (to compare layouts and code paths bit for bit); for profiling the product alone
//! (e.g. under callgrind or `perf record`) without building xtask.
//!
//! Run: `cargo run --release -p chrono-ccp --example apply_n_pile -- [n_contacts] [reps]`
//! (defaults: 100 000 contacts, 50 products).

use chrono_ccp::testing::granular_pile;
use chrono_core::descriptor::CcpWork;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let n_contacts: usize = a.first().map_or(Ok(100_000), |s| s.parse())?;
    let reps: usize = a.get(1).map_or(Ok(50), |s| s.parse())?;
    let (problem, gamma, _) = granular_pile(n_contacts, 5, 0.002)?;
    let m = problem.n_rows();
    let contacts = problem.sections().friction.len() / 3;
    let mut work = CcpWork::for_problem(&problem);
    let mut out = vec![0.0; m];
    problem.apply_n(&gamma, &mut out, &mut work);
    let fp = out.iter().fold(0u64, |h, x| h.rotate_left(5) ^ x.to_bits());
    let mut times = Vec::with_capacity(reps);
    for _ in 0..reps {
        let t0 = std::time::Instant::now();
        problem.apply_n(std::hint::black_box(&gamma), &mut out, &mut work);
        times.push(t0.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    let t = times[times.len() / 2];
    let bytes = problem.apply_n_bytes() as f64;
    println!(
        "contacts {contacts} rows {m} mf {} median {:.3} ms min {:.3} ms contacts/s {:.3e} \
         bytes/row {:.1} GB/s {:.2} fingerprint {fp:016x}",
        problem.n_matrix_free(),
        t * 1e3,
        times[0] * 1e3,
        contacts as f64 / t,
        bytes / m as f64,
        bytes / t / 1e9
    );
    Ok(())
}
