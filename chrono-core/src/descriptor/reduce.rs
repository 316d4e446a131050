//! Deterministic parallel reductions.
//!
//! Floating-point addition is not associative, and rayon's adaptive splitting would make a
//! plain parallel `sum` depend on scheduling. Here the index range is cut into fixed chunks
//! of [`CHUNK`] items; each chunk is summed in order (in parallel across chunks when the
//! range is large) and the chunk sums are added in order. The result is bit-identical for
//! any thread count, sequential or parallel.
//!
//! Within a chunk the items go to [`LANES`] interleaved accumulators (item `j` of the chunk
//! to lane `j % LANES`), added as `(l0 + l1) + (l2 + l3)` at the chunk's end
//! ([`lane_sum`]): four independent addition chains instead of one, so a sum runs at the
//! adder's throughput, not its latency. Solvers that fuse their sums into other passes use
//! [`lane_sum`] over the same chunks, which keeps their bits equal to these functions'.

use rayon::prelude::*;

/// Items per chunk of a reduction.
pub const CHUNK: usize = 2048;

/// Ranges shorter than this are reduced on the calling thread (same chunking, same result).
pub const PAR_MIN: usize = 4 * CHUNK;

/// Interleaved accumulators per sum within a chunk (see the module documentation).
pub const LANES: usize = 4;

/// `K` sums `sum_{j < n} f(j)[k]` in the order of a chunk of this module: item `j` into
/// lane `j % LANES`, the lanes added as `(l0 + l1) + (l2 + l3)`.
#[inline(always)]
pub fn lane_sum<const K: usize>(n: usize, f: impl Fn(usize) -> [f64; K]) -> [f64; K] {
    let mut acc = [[0.0; K]; LANES];
    let full = n - n % LANES;
    let mut j = 0;
    while j < full {
        for (l, a) in acc.iter_mut().enumerate() {
            let v = f(j + l);
            for k in 0..K {
                a[k] += v[k];
            }
        }
        j += LANES;
    }
    for (l, a) in acc.iter_mut().enumerate().take(n - full) {
        let v = f(full + l);
        for k in 0..K {
            a[k] += v[k];
        }
    }
    let mut out = [0.0; K];
    for (k, o) in out.iter_mut().enumerate() {
        *o = (acc[0][k] + acc[1][k]) + (acc[2][k] + acc[3][k]);
    }
    out
}

/// `sum_{i < n} f(i)` in a fixed order. `partials` is scratch space (reused, so no
/// allocation once it has grown to `n / CHUNK + 1`).
pub fn sum_by(n: usize, partials: &mut Vec<f64>, f: impl Fn(usize) -> f64 + Sync) -> f64 {
    let chunks = n.div_ceil(CHUNK);
    let chunk_sum = |c: usize| {
        let (start, end) = (c * CHUNK, ((c + 1) * CHUNK).min(n));
        lane_sum::<1>(end - start, |j| [f(start + j)])[0]
    };
    if n < PAR_MIN {
        let mut total = 0.0;
        for c in 0..chunks {
            total += chunk_sum(c);
        }
        return total;
    }
    partials.clear();
    partials.resize(chunks, 0.0);
    partials
        .par_iter_mut()
        .enumerate()
        .for_each(|(c, p)| *p = chunk_sum(c));
    partials.iter().sum()
}

/// Two sums `(sum f(i).0, sum f(i).1)` in one pass, each in exactly the order of
/// [`sum_by`] (so each equals `sum_by` of its half bit for bit). `partials` is scratch
/// (`2 (n / CHUNK + 1)` once grown).
pub fn sum2_by(
    n: usize,
    partials: &mut Vec<f64>,
    f: impl Fn(usize) -> (f64, f64) + Sync,
) -> (f64, f64) {
    let chunks = n.div_ceil(CHUNK);
    let chunk_sum = |c: usize| {
        let (start, end) = (c * CHUNK, ((c + 1) * CHUNK).min(n));
        let [a, b] = lane_sum::<2>(end - start, |j| {
            let (x, y) = f(start + j);
            [x, y]
        });
        (a, b)
    };
    if n < PAR_MIN {
        let (mut a, mut b) = (0.0, 0.0);
        for c in 0..chunks {
            let (x, y) = chunk_sum(c);
            a += x;
            b += y;
        }
        return (a, b);
    }
    partials.clear();
    partials.resize(2 * chunks, 0.0);
    partials
        .par_chunks_mut(2)
        .enumerate()
        .for_each(|(c, p)| (p[0], p[1]) = chunk_sum(c));
    (
        partials.iter().step_by(2).sum(),
        partials.iter().skip(1).step_by(2).sum(),
    )
}

/// Dot product `a'b` in a fixed order (see [`sum_by`]).
pub fn dot(a: &[f64], b: &[f64], partials: &mut Vec<f64>) -> f64 {
    assert_eq!(a.len(), b.len());
    sum_by(a.len(), partials, |i| a[i] * b[i])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_result_for_any_thread_count() {
        let n = 200_003;
        let a: Vec<f64> = (0..n).map(|i| ((i as f64) * 0.37).sin() * 1e3).collect();
        let b: Vec<f64> = (0..n).map(|i| ((i as f64) * 0.11).cos()).collect();
        let mut p = Vec::new();
        let d_default = dot(&a, &b, &mut p);
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let d_one = one.install(|| dot(&a, &b, &mut Vec::new()));
        assert_eq!(d_default.to_bits(), d_one.to_bits());
        let naive: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
        assert!((d_default - naive).abs() < 1e-9 * naive.abs().max(1.0));
    }

    #[test]
    fn sum2_by_equals_two_sum_by_bit_for_bit() {
        for n in [0, 5, CHUNK + 3, PAR_MIN + 777] {
            let f = |i: usize| ((i as f64 * 0.37).sin() * 1e3, (i as f64 * 0.11).cos());
            let mut p = Vec::new();
            let (a, b) = sum2_by(n, &mut p, f);
            assert_eq!(
                a.to_bits(),
                sum_by(n, &mut p, |i| f(i).0).to_bits(),
                "n = {n}"
            );
            assert_eq!(
                b.to_bits(),
                sum_by(n, &mut p, |i| f(i).1).to_bits(),
                "n = {n}"
            );
        }
    }

    #[test]
    fn small_and_empty() {
        let mut p = Vec::new();
        assert_eq!(dot(&[], &[], &mut p), 0.0);
        assert_eq!(dot(&[1.0, 2.0], &[3.0, 4.0], &mut p), 11.0);
    }
}
